/* path_noise.c: see path_noise.h. */
#include "verify/reference/path_noise.h"

#include <math.h>
#include <stdlib.h>

double sl_path_noise(const slref_path_accum *a, int block) {
    double ne = a->n[0], no = a->n[1], n = ne + no;
    if (ne < 1 || no < 1) return NAN;
    if (block < 1) block = 1;
    double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
    long hair = 0;
    for (int by = 0; by < a->h; by += block)
        for (int bx = 0; bx < a->w; bx += block) {
            double A[4] = {0, 0, 0, 0}, B[4] = {0, 0, 0, 0};
            int cnt = 0;
            for (int y = by; y < by + block && y < a->h; y++)
                for (int x = bx; x < bx + block && x < a->w; x++, cnt++) {
                    size_t i = (size_t)y * a->w + x;
                    for (int c = 0; c < 4; c++)
                        A[c] += a->half[0][4 * i + c], B[c] += a->half[1][4 * i + c];
                }
            if (!(A[3] + B[3] > 0)) continue; /* no ray of the block hit a fiber */
            hair++;
            for (int c = 0; c < 3; c++) {
                double ma = A[c] / ne / cnt, mb = B[c] / no / cnt, mf = (A[c] + B[c]) / n / cnt;
                num[c] += (ma - mb) * (ma - mb) * ne * no / (n * n);
                den[c] += mf * mf;
            }
        }
    if (hair == 0) return NAN;
    double r = 0;
    for (int c = 0; c < 3; c++)
        r += (den[c] > 0 ? sqrt(num[c] / den[c]) : 0.0) / 3.0;
    return r;
}
