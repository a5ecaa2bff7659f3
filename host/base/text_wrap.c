/* text_wrap.c: see text_wrap.h. */
#include "base/text_wrap.h"

#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

int sl_term_width(FILE *f) {
    if (!isatty(fileno(f))) return 0;
    struct winsize ws;
    if (ioctl(fileno(f), TIOCGWINSZ, &ws) == 0 && ws.ws_col >= 60) return ws.ws_col;
    return 100;
}

void sl_put_wrapped(FILE *f, const char *text, int col, int indent, int width) {
    if (width <= 0 || col + (int)strlen(text) <= width) {
        fputs(text, f);
        return;
    }
    const char *p = text;
    while (*p) {
        int room = width - col;
        if (room < 20) room = 20;
        int n = (int)strlen(p);
        if (n <= room) {
            fputs(p, f);
            break;
        }
        int cut = room;
        while (cut > 0 && p[cut] != ' ')
            cut--;
        if (cut == 0) cut = room; /* one long word: cut it */
        fprintf(f, "%.*s\n%*s", cut, p, indent, "");
        p += cut;
        while (*p == ' ')
            p++;
        col = indent;
    }
}
