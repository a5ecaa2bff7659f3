/* image_write.c: EXR output through OpenEXRCore and tone-mapped sRGB PNG output through
 * stb_image_write, both written atomically (see image_write.h for the exact transforms). */
#include "io/image/image_write.h"
#include "base/output_set.h"

#include <openexr.h>
#include <stb/stb_image_write.h>

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define HALF_MAX 65504.0f

static void exr_quiet(exr_const_context_t c, exr_result_t code, const char *msg) {
    (void)c;
    (void)code;
    (void)msg; /* the return code is reported instead */
}

/* OpenEXRCore's write callback on a descriptor (user data: the int fd): all of sz at offset. */
static int64_t exr_write_fd(exr_const_context_t ctx, void *user, const void *buf, uint64_t sz,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
    int fd = *(const int *)user;
    const char *p = buf;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t k = pwrite(fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) {
            if (error_cb) error_cb(ctx, EXR_ERR_WRITE_IO, "write failed: %s", strerror(errno));
            return -1;
        }
        done += (uint64_t)k;
    }
    return (int64_t)sz;
}

static int check_channels(const char *path, int w, int h, const sl_exr_channel *ch, int nch,
                          sl_err *e) {
    if (w < 1 || h < 1 || w > 1 << 20 || h > 1 << 20 || (long long)w * h > (1LL << 31) / 4)
        return sl_fail(e, "%s: cannot write a %d x %d image", path, w, h);
    if (nch < 1 || nch > 1024 || !ch)
        return sl_fail(e, "%s: need 1..1024 channels, got %d", path, nch);
    for (int i = 0; i < nch; i++) {
        if (!ch[i].name || !ch[i].name[0] || strlen(ch[i].name) > 255)
            return sl_fail(e, "%s: channel %d: name must be 1..255 bytes", path, i);
        if (!ch[i].data) return sl_fail(e, "%s: channel %s: no data", path, ch[i].name);
        for (int j = 0; j < i; j++)
            if (strcmp(ch[i].name, ch[j].name) == 0)
                return sl_fail(e, "%s: channel %s given twice", path, ch[i].name);
    }
    return 0;
}

/* Depth is always stored as FLOAT: half's 11-bit mantissa would quantise a view depth of 120 to
 * steps of 0.06 (docs/frame.md, "Outputs"). */
static int channel_is_float(const sl_exr_channel *c, int use_float) {
    return use_float || strcmp(c->name, "Z") == 0;
}

/* Encodes every chunk; the part header is already written. */
static exr_result_t write_chunks(exr_context_t ctx, int w, int h, const sl_exr_channel *ch, int nch,
                                 int use_float) {
    int32_t lpc = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lpc);
    if (rv != EXR_ERR_SUCCESS) return rv;
    float *scratch = sl_malloc((size_t)nch * (size_t)lpc * (size_t)w * sizeof(float));
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int first = 1;
    for (int y = 0; y < h && rv == EXR_ERR_SUCCESS; y += lpc) {
        exr_chunk_info_t ci;
        rv = exr_write_scanline_chunk_info(ctx, 0, y, &ci);
        if (rv != EXR_ERR_SUCCESS) break;
        rv = first ? exr_encoding_initialize(ctx, 0, &ci, &enc)
                   : exr_encoding_update(ctx, 0, &ci, &enc);
        if (rv != EXR_ERR_SUCCESS) break;
        int lines = ci.height;
        for (int c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *cc = &enc.channels[c];
            int k = 0;
            while (k < nch && strcmp(ch[k].name, cc->channel_name) != 0)
                k++;
            if (k == nch) {
                rv = EXR_ERR_INVALID_ARGUMENT;
                break;
            }
            const float *src = ch[k].data + (size_t)y * (size_t)w;
            if (!channel_is_float(&ch[k], use_float)) { /* clamp to the half range: no finite
                                                          value becomes Inf */
                float *dst = scratch + (size_t)k * (size_t)lpc * (size_t)w;
                for (size_t i = 0; i < (size_t)lines * (size_t)w; i++) {
                    float v = src[i];
                    dst[i] = v > HALF_MAX && isfinite(v)    ? HALF_MAX
                             : v < -HALF_MAX && isfinite(v) ? -HALF_MAX
                                                            : v;
                }
                src = dst;
            }
            cc->encode_from_ptr = (const uint8_t *)src;
            cc->user_pixel_stride = (int32_t)sizeof(float);
            cc->user_line_stride = (int32_t)sizeof(float) * w;
            cc->user_bytes_per_element = (int16_t)sizeof(float);
            cc->user_data_type = EXR_PIXEL_FLOAT;
        }
        if (rv != EXR_ERR_SUCCESS) break;
        rv = exr_encoding_choose_default_routines(ctx, 0, &enc);
        first = 0;
        if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctx, 0, &enc);
    }
    exr_encoding_destroy(ctx, &enc);
    free(scratch);
    return rv;
}

int sl_exr_write_temp(const char *path, int w, int h, const sl_exr_channel *ch, int nch,
                      int use_float, sl_atomic_file *af, sl_err *e) {
    memset(af, 0, sizeof *af);
    if (check_channels(path, w, h, ch, nch, e)) return -1;
    if (strlen(path) + 64 >= sizeof af->path) return sl_fail(e, "%s: path too long", path);
    if (sl_make_parent_dirs(path, e)) return -1;
    snprintf(af->path, sizeof af->path, "%s", path);
    char *tmp = af->tmp_path;
    int fd = sl_temp_create(path, tmp, sizeof af->tmp_path, e);
    if (fd < 0) {
        tmp[0] = 0;
        return -1;
    }
    /* OpenEXRCore writes through our descriptor (write_fn): the temporary was created here with
     * O_EXCL | O_NOFOLLOW, never reopened by name. */
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_quiet;
    init.user_data = &fd;
    init.write_fn = exr_write_fd;
    exr_context_t ctx = NULL;
    const char *stage = "cannot create file";
    exr_result_t rv = exr_start_write(&ctx, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS) {
        int part = 0;
        stage = "header";
        rv = exr_add_part(ctx, "main", EXR_STORAGE_SCANLINE, &part);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_initialize_required_attr_simple(ctx, 0, w, h, EXR_COMPRESSION_ZIP);
        for (int i = 0; i < nch && rv == EXR_ERR_SUCCESS; i++)
            rv = exr_add_channel(ctx, 0, ch[i].name,
                                 channel_is_float(&ch[i], use_float) ? EXR_PIXEL_FLOAT
                                                                     : EXR_PIXEL_HALF,
                                 EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
        if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
        if (rv == EXR_ERR_SUCCESS) {
            stage = "writing pixels";
            rv = write_chunks(ctx, w, h, ch, nch, use_float);
        }
    }
    exr_result_t frv = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
    if (rv == EXR_ERR_SUCCESS && frv != EXR_ERR_SUCCESS) {
        rv = frv;
        stage = "finishing file";
    }
    /* on disk before any rename (output_set.h) */
    if (rv == EXR_ERR_SUCCESS && fsync(fd) != 0 && errno != EINVAL) {
        rv = EXR_ERR_WRITE_IO;
        stage = "flushing file";
    }
    if (close(fd) != 0 && rv == EXR_ERR_SUCCESS) {
        rv = EXR_ERR_WRITE_IO;
        stage = "closing file";
    }
    if (rv != EXR_ERR_SUCCESS) {
        remove(tmp);
        tmp[0] = 0;
        return sl_fail(e, "%s: cannot write OpenEXR (%s): %s", path, stage,
                       exr_get_default_error_message(rv));
    }
    return 0;
}

int sl_exr_write(const char *path, int w, int h, const sl_exr_channel *ch, int nch, int use_float,
                 sl_err *e) {
    sl_atomic_file af;
    if (sl_exr_write_temp(path, w, h, ch, nch, use_float, &af, e)) return -1;
    sl_atomic_file *set[1] = {&af};
    return sl_output_set_commit(set, 1, e);
}

float sl_tonemap_srgb(float x) {
    if (!(x > 0.0f)) return 0.0f; /* negative and NaN */
    double t;
    if (isinf(x)) {
        t = 1.0;
    } else {
        double v = x;
        t = v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14); /* Narkowicz 2015 */
        if (t > 1.0) t = 1.0;
    }
    double s = t <= 0.0031308 ? 12.92 * t : 1.055 * pow(t, 1.0 / 2.4) - 0.055;
    return (float)(s < 0 ? 0 : s > 1 ? 1 : s);
}

static unsigned char to_byte(double v) {
    if (!(v > 0)) return 0;
    if (v >= 1) return 255;
    return (unsigned char)lround(v * 255.0);
}

typedef struct png_buf {
    unsigned char *data;
    size_t n, cap;
} png_buf;

static void png_collect(void *ctx, void *data, int size) {
    png_buf *b = ctx;
    if (size <= 0) return;
    if (b->n + (size_t)size > b->cap) {
        b->cap = (b->n + (size_t)size) * 2;
        b->data = sl_realloc(b->data, b->cap);
    }
    memcpy(b->data + b->n, data, (size_t)size);
    b->n += (size_t)size;
}

int sl_png_write_temp(const char *path, int w, int h, const float *rgba, float exposure,
                      sl_atomic_file *af, sl_err *e) {
    memset(af, 0, sizeof *af);
    if (w < 1 || h < 1 || w > 1 << 16 || h > 1 << 16 || !rgba)
        return sl_fail(e, "%s: cannot write a %d x %d PNG", path, w, h);
    if (!isfinite(exposure)) return sl_fail(e, "%s: exposure must be finite", path);
    size_t np = (size_t)w * (size_t)h;
    unsigned char *px = sl_malloc(np * 4);
    double scale = exp2((double)exposure);
    for (size_t i = 0; i < np; i++) {
        const float *p = rgba + 4 * i;
        float a = p[3];
        double inv = a > 0.0f && isfinite(a) ? 1.0 / a : 1.0;
        for (int c = 0; c < 3; c++)
            px[4 * i + c] = to_byte(sl_tonemap_srgb((float)(p[c] * inv * scale)));
        px[4 * i + 3] = to_byte(a);
    }
    png_buf b = {NULL, 0, 0};
    int ok = stbi_write_png_to_func(png_collect, &b, w, h, 4, px, w * 4);
    free(px);
    if (!ok || b.n == 0) {
        free(b.data);
        return sl_fail(e, "%s: PNG encoding failed", path);
    }
    if (sl_atomic_open(af, path, e)) {
        free(b.data);
        return -1;
    }
    fwrite(b.data, 1, b.n, af->fp);
    free(b.data);
    return sl_atomic_finish(af, e);
}

int sl_png_write(const char *path, int w, int h, const float *rgba, float exposure, sl_err *e) {
    sl_atomic_file af;
    if (sl_png_write_temp(path, w, h, rgba, exposure, &af, e)) return -1;
    sl_atomic_file *set[1] = {&af};
    return sl_output_set_commit(set, 1, e);
}
