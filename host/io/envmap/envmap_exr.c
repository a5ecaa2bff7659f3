/* envmap_exr.c: OpenEXR environment maps through OpenEXRCore (C), with DWAA/DWAB (which Core 3.1
 * cannot decode) handed to the C++ shim (exr_cxx_shim.h).
 *
 * Channels are matched by name (R, G, B [A ignored], or Y as grey; sl_exr_decode_rgba also
 * decodes A, for images rather than maps), in any file order; they are decoded planar to float,
 * which avoids the Core 3.1.5 bug with 4 HALF channels into interleaved float (toolchain.md
 * sec. 3). Scanline and tiled parts are read (tiled: level 0). The bytes come
 * from memory through custom read/size callbacks, and the context's error handler stores the
 * library's message instead of printing it. */
#include "io/envmap/envmap.h"
#include "io/envmap/exr_cxx_shim.h"

#include <openexr.h>

#include <stdlib.h>
#include <string.h>

typedef struct exr_mem {
    const unsigned char *data;
    size_t n;
    char msg[256]; /* last message from the library */
} exr_mem;

static int64_t mem_read(exr_const_context_t c, void *ud, void *buf, uint64_t sz, uint64_t off,
                        exr_stream_error_func_ptr_t errcb) {
    (void)c;
    (void)errcb;
    exr_mem *m = ud;
    if (off >= m->n) return 0;
    uint64_t k = m->n - off < sz ? m->n - off : sz;
    memcpy(buf, m->data + off, k);
    return (int64_t)k;
}

static int64_t mem_size(exr_const_context_t c, void *ud) {
    (void)c;
    return (int64_t)((exr_mem *)ud)->n;
}

static void quiet_handler(exr_const_context_t c, exr_result_t code, const char *msg) {
    void *ud = NULL;
    (void)code;
    if (exr_get_user_data(c, &ud) == EXR_ERR_SUCCESS && ud)
        snprintf(((exr_mem *)ud)->msg, sizeof((exr_mem *)ud)->msg, "%s", msg ? msg : "");
}

static int core_fail(sl_err *e, const char *name, const exr_mem *m, exr_result_t rv,
                     const char *what) {
    return sl_fail(e, "%s: OpenEXR: %s: %s", name, what,
                   m->msg[0] ? m->msg : exr_get_default_error_message(rv));
}

static const char *compression_name(exr_compression_t c) {
    static const char *names[] = {"NONE",  "RLE", "ZIPS", "ZIP",  "PIZ",
                                  "PXR24", "B44", "B44A", "DWAA", "DWAB"};
    return (unsigned)c < sizeof names / sizeof names[0] ? names[c] : "unknown";
}

/* The planes to decode and where they go. */
typedef struct plan {
    int nplanes;          /* 3 (R,G,B), 1 (Y), or 4 (R,G,B,A: sl_exr_decode_rgba) */
    const char *names[4]; /* file channel names */
    float *planes[4];     /* w*h each */
    /* Every other channel is decoded too, unconverted, into its own slice of this per-chunk
     * scratch (chunk_px floats per channel): Core 3.1.5 crashes on tiled parts when a channel
     * is skipped with decode_to_ptr = NULL (measured: SIGSEGV in exr_decoding_run). */
    float *scratch;
    size_t chunk_px;
    int nscratch; /* channels the scratch has room for */
} plan;

static float *plane_for(const plan *p, const char *channel_name) {
    for (int i = 0; i < p->nplanes; i++)
        if (strcmp(p->names[i], channel_name) == 0) return p->planes[i];
    return NULL;
}

/* Points the decoder's channels at the rows/columns of chunk ci (pixel origin x0, y0 relative to
 * the data window) and runs it. */
static exr_result_t decode_chunk(exr_context_t ctx, exr_decode_pipeline_t *dec, int *first,
                                 const exr_chunk_info_t *ci, const plan *p, int w, int x0, int y0) {
    exr_result_t rv =
        *first ? exr_decoding_initialize(ctx, 0, ci, dec) : exr_decoding_update(ctx, 0, ci, dec);
    if (rv != EXR_ERR_SUCCESS) return rv;
    *first = 0;
    for (int c = 0; c < dec->channel_count; c++) {
        exr_coding_channel_info_t *ch = &dec->channels[c];
        float *pl = plane_for(p, ch->channel_name);
        if (!pl) {
            if (c >= p->nscratch || (size_t)ch->width * (size_t)ch->height > p->chunk_px ||
                ch->bytes_per_element > 4 || ch->bytes_per_element < 1)
                return EXR_ERR_CORRUPT_CHUNK;
            ch->decode_to_ptr = (uint8_t *)(p->scratch + p->chunk_px * (size_t)c);
            ch->user_pixel_stride = ch->bytes_per_element;
            ch->user_line_stride = ch->bytes_per_element * (ch->width > 0 ? ch->width : 1);
            ch->user_bytes_per_element = ch->bytes_per_element;
            ch->user_data_type = ch->data_type;
            continue;
        }
        ch->decode_to_ptr = (uint8_t *)(pl + (size_t)y0 * (size_t)w + (size_t)x0);
        ch->user_pixel_stride = (int32_t)sizeof(float);
        ch->user_line_stride = (int32_t)sizeof(float) * w;
        ch->user_bytes_per_element = (int16_t)sizeof(float);
        ch->user_data_type = EXR_PIXEL_FLOAT;
    }
    rv = exr_decoding_choose_default_routines(ctx, 0, dec);
    if (rv != EXR_ERR_SUCCESS) return rv;
    return exr_decoding_run(ctx, 0, dec);
}

static exr_result_t read_scanlines(exr_context_t ctx, const exr_attr_box2i_t *dw, const plan *p,
                                   int nchannels, int w, int h, exr_mem *m, const char *name,
                                   sl_err *e) {
    int32_t lpc = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lpc);
    if (rv != EXR_ERR_SUCCESS || lpc < 1) return rv ? rv : EXR_ERR_INVALID_ATTR;
    plan q = *p;
    q.chunk_px = (size_t)w * (size_t)(lpc < h ? lpc : h);
    q.scratch = sl_malloc(q.chunk_px * (size_t)nchannels * sizeof(float));
    q.nscratch = nchannels;
    p = &q;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int first = 1;
    for (int64_t y = dw->min.y; y <= dw->max.y; y += lpc) {
        exr_chunk_info_t ci;
        rv = exr_read_scanline_chunk_info(ctx, 0, (int)y, &ci);
        if (rv != EXR_ERR_SUCCESS) break;
        int64_t y0 = (int64_t)ci.start_y - dw->min.y;
        if (y0 < 0 || ci.height < 1 || y0 + ci.height > h || ci.width != w) {
            sl_fail(e, "%s: OpenEXR: chunk at line %d has an inconsistent size", name, (int)y);
            rv = EXR_ERR_CORRUPT_CHUNK;
            break;
        }
        rv = decode_chunk(ctx, &dec, &first, &ci, p, w, 0, (int)y0);
        if (rv != EXR_ERR_SUCCESS) break;
    }
    if (rv != EXR_ERR_SUCCESS && !e->msg[0]) core_fail(e, name, m, rv, "decoding");
    exr_decoding_destroy(ctx, &dec);
    free(q.scratch);
    return rv;
}

static exr_result_t read_tiles(exr_context_t ctx, const plan *p, int nchannels, int w, int h,
                               exr_mem *m, const char *name, sl_err *e) {
    int32_t tw = 0, th = 0;
    exr_result_t rv = exr_get_tile_sizes(ctx, 0, 0, 0, &tw, &th);
    if (rv != EXR_ERR_SUCCESS || tw < 1 || th < 1) {
        if (!rv) rv = EXR_ERR_INVALID_ATTR;
        core_fail(e, name, m, rv, "tile description");
        return rv;
    }
    plan q = *p;
    q.chunk_px = (size_t)(tw < w ? tw : w) * (size_t)(th < h ? th : h);
    q.scratch = sl_malloc(q.chunk_px * (size_t)nchannels * sizeof(float));
    q.nscratch = nchannels;
    p = &q;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int first = 1;
    int nx = (int)(((int64_t)w + tw - 1) / tw), ny = (int)(((int64_t)h + th - 1) / th);
    for (int ty = 0; ty < ny && rv == EXR_ERR_SUCCESS; ty++) {
        for (int tx = 0; tx < nx; tx++) {
            exr_chunk_info_t ci;
            rv = exr_read_tile_chunk_info(ctx, 0, tx, ty, 0, 0, &ci);
            if (rv != EXR_ERR_SUCCESS) break;
            int64_t x0 = (int64_t)tx * tw, y0 = (int64_t)ty * th;
            if (ci.width < 1 || ci.height < 1 || x0 + ci.width > w || y0 + ci.height > h) {
                sl_fail(e, "%s: OpenEXR: tile (%d, %d) has an inconsistent size", name, tx, ty);
                rv = EXR_ERR_CORRUPT_CHUNK;
                break;
            }
            rv = decode_chunk(ctx, &dec, &first, &ci, p, w, (int)x0, (int)y0);
            if (rv != EXR_ERR_SUCCESS) break;
        }
    }
    if (rv != EXR_ERR_SUCCESS && !e->msg[0]) core_fail(e, name, m, rv, "decoding");
    exr_decoding_destroy(ctx, &dec);
    free(q.scratch);
    return rv;
}

/* ---- Header walk for the C++ reader ----
 * Imf::InputFile allocates from header fields before it checks them against the file: an opaque
 * or string attribute's declared size (new[] of up to 2 GB), a preview image's width x height,
 * the line/tile offset table from the data window and tile description. OpenEXRCore bounds these
 * by the file size, but the C++ parser walks the bytes differently (a known fixed-size type is
 * read at its fixed size whatever size the file declares), so the two can disagree about where
 * attributes start. So before the C++ library sees a file, the header is walked here exactly as
 * the C++ reader walks it (OpenEXR 3.1 Header::readFrom), and refused unless every size it will
 * allocate from fits in the file and its data window is the one Core read. */

static uint32_t rd32(const unsigned char *d) {
    return (uint32_t)d[0] | (uint32_t)d[1] << 8 | (uint32_t)d[2] << 16 | (uint32_t)d[3] << 24;
}

/* Bytes C++ reads for a known fixed-size attribute type; 0 when variable-size, -1 if unknown. */
static int fixed_type_size(const char *t) {
    static const struct {
        const char *name;
        int size;
    } types[] = {{"box2i", 16},      {"box2f", 16},
                 {"compression", 1}, {"lineOrder", 1},
                 {"envmap", 1},      {"deepImageState", 1},
                 {"float", 4},       {"double", 8},
                 {"int", 4},         {"v2i", 8},
                 {"v2f", 8},         {"v2d", 16},
                 {"v3i", 12},        {"v3f", 12},
                 {"v3d", 24},        {"m33f", 36},
                 {"m33d", 72},       {"m44f", 64},
                 {"m44d", 128},      {"chromaticities", 32},
                 {"rational", 8},    {"keycode", 28},
                 {"timecode", 8},    {"tiledesc", 9},
                 {"string", 0},      {"stringvector", 0},
                 {"floatvector", 0}, {"chlist", 0},
                 {"preview", 0}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(t, types[i].name) == 0) return types[i].size;
    return -1;
}

/* Length of the NUL-terminated name at d[0..avail) (at most 255 characters, as in C++), or -1. */
static int name_len(const unsigned char *d, size_t avail) {
    for (size_t i = 0; i < avail && i < 256; i++)
        if (!d[i]) return (int)i;
    return -1;
}

/* A printable copy of a header name for messages (hostile bytes become '?'). */
static const char *printable(const char *in, char *buf, size_t n) {
    size_t i = 0;
    for (; in[i] && i + 1 < n; i++)
        buf[i] = in[i] >= 0x20 && in[i] < 0x7f ? in[i] : '?';
    buf[i] = 0;
    return buf;
}

/* Offset table entries a tiled part has, rounding level sizes up (an upper bound for either
 * rounding mode). Level counts are capped at 32 per axis (dimensions are < 2^31). */
static double tile_count(int64_t w, int64_t h, int64_t tx, int64_t ty, int mode) {
    double total = 0;
    int nlx = 1, nly = 1;
    if (mode == 1 || mode == 2) {
        while (nlx < 32 && (1LL << (nlx - 1)) < w)
            nlx++;
        while (nly < 32 && (1LL << (nly - 1)) < h)
            nly++;
        if (mode == 1) nlx = nly = nlx > nly ? nlx : nly; /* MIPMAP: max(w, h) levels */
    }
    for (int lx = 0; lx < nlx; lx++)
        for (int ly = 0; ly < nly; ly++) {
            if (mode == 1 && lx != ly) continue; /* MIPMAP: the diagonal only */
            int64_t lw = (w + (1LL << lx) - 1) >> lx, lh = (h + (1LL << ly) - 1) >> ly;
            total += (double)((lw + tx - 1) / tx) * (double)((lh + ty - 1) / ty);
        }
    return total;
}

/* Walks the header as Imf::InputFile will; 0 when every size it allocates from fits the file
 * and its data window equals core_dw, else -1 with a message naming the problem. */
static int cxx_header_ok(const unsigned char *d, size_t n, const exr_attr_box2i_t *core_dw,
                         const char *name, sl_err *e) {
    if (n < 8) return sl_fail(e, "%s: OpenEXR: truncated header", name);
    uint32_t flags = rd32(d + 4) & ~0xffu;
    if (flags & 0x1800u)
        return sl_fail(e, "%s: OpenEXR: multi-part or deep DWA files are not supported", name);
    size_t p = 8;
    int have_dw = 0, have_tiles = 0, tmode = 0, lines = 1;
    int32_t dwv[4] = {0, 0, 0, 0};
    uint32_t tx = 0, ty = 0;
    for (;;) {
        int ln = name_len(d + p, n - p);
        if (ln < 0) return sl_fail(e, "%s: OpenEXR: unterminated attribute name in header", name);
        const char *an = (const char *)d + p;
        p += (size_t)ln + 1;
        if (ln == 0) break;
        char pn[48], pt[40];
        printable(an, pn, sizeof pn);
        int lt = name_len(d + p, n - p);
        if (lt < 0 || n - p - (size_t)lt - 1 < 4)
            return sl_fail(e, "%s: OpenEXR: attribute %s: truncated type or size", name, pn);
        const char *type = (const char *)d + p;
        printable(type, pt, sizeof pt);
        p += (size_t)lt + 1;
        int32_t size = (int32_t)rd32(d + p);
        p += 4;
        size_t left = n - p;
        if (size < 0 || (size_t)size > left)
            return sl_fail(e,
                           "%s: OpenEXR: attribute %s declares %ld bytes but only %zu remain "
                           "in the file",
                           name, pn, (long)size, left);
        const unsigned char *v = d + p;
        int fixed = fixed_type_size(type);
        if (fixed > 0 && size != fixed)
            return sl_fail(e, "%s: OpenEXR: attribute %s of type %s has size %ld, not %d", name, pn,
                           pt, (long)size, fixed);
        if (strcmp(type, "preview") == 0) {
            /* C++ allocates width x height RGBA8 pixels before reading them. */
            if (size < 8 || (double)rd32(v) * (double)rd32(v + 4) * 4.0 + 8.0 != (double)size)
                return sl_fail(e, "%s: OpenEXR: preview %s does not match its size", name, pn);
        } else if (strcmp(type, "chlist") == 0) {
            /* C++ reads entries up to the empty name, not by size: they must end at size. */
            size_t q = 0;
            for (;;) {
                int cl = name_len(v + q, (size_t)size - q);
                if (cl < 0) return sl_fail(e, "%s: OpenEXR: bad channel list", name);
                q += (size_t)cl + 1;
                if (cl == 0) break;
                if ((size_t)size - q < 16) return sl_fail(e, "%s: OpenEXR: bad channel list", name);
                q += 16;
            }
            if (q != (size_t)size) return sl_fail(e, "%s: OpenEXR: bad channel list", name);
        } else if (strcmp(type, "idmanifest") == 0) {
            return sl_fail(e, "%s: OpenEXR: attribute type %s is not supported", name, pt);
        }
        if (strcmp(an, "dataWindow") == 0 && strcmp(type, "box2i") == 0) {
            for (int k = 0; k < 4; k++)
                dwv[k] = (int32_t)rd32(v + 4 * k);
            have_dw = 1;
        } else if (strcmp(an, "tiles") == 0 && strcmp(type, "tiledesc") == 0) {
            tx = rd32(v);
            ty = rd32(v + 4);
            tmode = v[8] & 0xf;
            have_tiles = 1;
        } else if (strcmp(an, "compression") == 0 && strcmp(type, "compression") == 0) {
            /* Lines per chunk as C++ sees them: NONE RLE ZIPS 1, ZIP PXR24 16, DWAB 256,
             * PIZ B44 B44A DWAA 32 (OpenEXR file layout). */
            static const int lpb[10] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
            lines = v[0] < 10 ? lpb[v[0]] : 1;
        }
        p += (size_t)size;
    }
    if (!have_dw || dwv[0] != core_dw->min.x || dwv[1] != core_dw->min.y ||
        dwv[2] != core_dw->max.x || dwv[3] != core_dw->max.y)
        return sl_fail(e, "%s: OpenEXR: the C++ reader would see a different data window", name);
    int64_t w = (int64_t)dwv[2] - dwv[0] + 1, h = (int64_t)dwv[3] - dwv[1] + 1;
    size_t left = n - p;
    double entries;
    if (flags & 0x200u) {
        if (!have_tiles || tx < 1 || ty < 1 || tx > SL_ENVMAP_MAX_DIM || ty > SL_ENVMAP_MAX_DIM ||
            tmode > 2)
            return sl_fail(e, "%s: OpenEXR: bad tile description", name);
        /* A tile buffer larger than the image (C++ allocates one per thread) is refused. */
        if ((double)tx * ty > (double)w * h && (double)tx * ty > 65536.0)
            return sl_fail(e, "%s: OpenEXR: tiles of %u x %u for a %lld x %lld image", name, tx, ty,
                           (long long)w, (long long)h);
        entries = tile_count(w, h, tx, ty, tmode);
    } else {
        entries = (double)((h + lines - 1) / lines);
    }
    if (entries * 8.0 > (double)left)
        return sl_fail(e, "%s: OpenEXR: offset table of %.0f chunks does not fit in the file", name,
                       entries);
    return 0;
}

/* Picks the planes to decode from the channel list; fills the names/format fields of out. With
 * a layer (an image's AOV, e.g. "MS"), its LAYER.R, LAYER.G, LAYER.B are the colour planes (A
 * stays A; no grey form). */
static int make_plan(const exr_attr_chlist_t *chl, const char *name, int with_alpha,
                     const char *layer, plan *p, sl_envmap *out, const char **type_word,
                     const char **layout, sl_err *e) {
    int idx[5] = {-1, -1, -1, -1, -1}; /* R G B A Y */
    char wb[3][80];
    const char *want[5] = {"R", "G", "B", "A", layer ? "" : "Y"};
    for (int k = 0; layer && k < 3; k++) {
        snprintf(wb[k], sizeof wb[k], "%s.%c", layer, "RGB"[k]);
        want[k] = wb[k];
    }
    size_t used = 0;
    out->channel_names[0] = 0;
    for (int i = 0; i < chl->num_channels; i++) {
        const char *cn = chl->entries[i].name.str;
        for (int k = 0; k < 5; k++)
            if (strcmp(cn, want[k]) == 0) idx[k] = i;
        int len = (int)strlen(cn);
        if (used + (size_t)len + 5 < sizeof out->channel_names) {
            used += (size_t)snprintf(out->channel_names + used, sizeof out->channel_names - used,
                                     "%s%s", i ? "," : "", cn);
        } else if (used + 4 < sizeof out->channel_names && !strstr(out->channel_names, "...")) {
            used += (size_t)snprintf(out->channel_names + used, sizeof out->channel_names - used,
                                     ",...");
        }
    }
    out->channels = chl->num_channels;
    int grey = !(idx[0] >= 0 && idx[1] >= 0 && idx[2] >= 0);
    if (layer && (grey || idx[3] < 0))
        return sl_fail(e, "%s: OpenEXR: need channels %s, %s, %s and A, the file has %s", name,
                       want[0], want[1], want[2],
                       out->channel_names[0] ? out->channel_names : "none");
    if (grey && idx[4] < 0)
        return sl_fail(e, "%s: OpenEXR: unsupported channel set (%s): need R,G,B[,A] or Y", name,
                       out->channel_names[0] ? out->channel_names : "none");
    if (with_alpha && (grey || idx[3] < 0))
        return sl_fail(e, "%s: OpenEXR: need channels R, G, B and A, the file has %s", name,
                       out->channel_names[0] ? out->channel_names : "none");
    int sel[4] = {idx[0], idx[1], idx[2], idx[3]};
    p->nplanes = grey ? 1 : with_alpha ? 4 : 3;
    if (grey) sel[0] = idx[4];
    int nhalf = 0;
    for (int i = 0; i < p->nplanes; i++) {
        const exr_attr_chlist_entry_t *c = &chl->entries[sel[i]];
        if (c->x_sampling != 1 || c->y_sampling != 1)
            return sl_fail(e, "%s: OpenEXR: channel %s is subsampled (%d x %d), not supported",
                           name, c->name.str, c->x_sampling, c->y_sampling);
        if (c->pixel_type != EXR_PIXEL_HALF && c->pixel_type != EXR_PIXEL_FLOAT)
            return sl_fail(e, "%s: OpenEXR: channel %s is not half or float", name, c->name.str);
        nhalf += c->pixel_type == EXR_PIXEL_HALF;
        p->names[i] = c->name.str;
    }
    *layout = grey ? (idx[3] >= 0 ? "YA" : "Y") : (idx[3] >= 0 ? "RGBA" : "RGB");
    *type_word = nhalf == p->nplanes ? "half" : nhalf == 0 ? "float" : "mixed half/float";
    return 0;
}

/* sl_envmap_decode_exr, and with with_alpha the A plane too, into *alpha (w*h, caller frees). */
static int decode_exr(const unsigned char *data, size_t n, const char *name, int force_cxx,
                      int with_alpha, const char *layer, sl_envmap *out, float **alpha, sl_err *e) {
    sl_err local;
    if (!e) e = &local;
    memset(out, 0, sizeof *out);
    e->msg[0] = 0;
    exr_mem m = {data, n, {0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet_handler;
    init.user_data = &m;
    init.read_fn = mem_read;
    init.size_fn = mem_size;
    init.max_image_width = init.max_image_height = SL_ENVMAP_MAX_DIM;
    init.max_tile_width = init.max_tile_height = SL_ENVMAP_MAX_DIM;
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    exr_context_t ctx = NULL;
    exr_result_t rv = exr_start_read(&ctx, name, &init);
    if (rv != EXR_ERR_SUCCESS) {
        core_fail(e, name, &m, rv, "cannot read header");
        exr_finish(&ctx);
        return -1;
    }
    int rc = -1;
    float *planes = NULL;
    int nparts = 0;
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *chl = NULL;
    exr_compression_t comp;
    if ((rv = exr_get_count(ctx, &nparts)) || nparts < 1 ||
        (rv = exr_get_storage(ctx, 0, &storage)) || (rv = exr_get_data_window(ctx, 0, &dw)) ||
        (rv = exr_get_channels(ctx, 0, &chl)) || (rv = exr_get_compression(ctx, 0, &comp)) ||
        !chl) {
        core_fail(e, name, &m, rv ? rv : EXR_ERR_MISSING_REQ_ATTR, "header");
        goto done;
    }
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED) {
        sl_fail(e, "%s: OpenEXR: deep images are not supported", name);
        goto done;
    }
    int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
    /* Deflate packs at most ~1032 bytes into one; 16384 pixels per byte leaves room for DWA. */
    if (!sl_envmap_size_ok(w, h, n, 16384.0)) {
        sl_fail(e, "%s: OpenEXR: implausible data window %lld x %lld for a %zu-byte file", name,
                (long long)w, (long long)h, n);
        goto done;
    }
    plan p;
    const char *type_word = "", *layout = "";
    if (make_plan(chl, name, with_alpha, layer, &p, out, &type_word, &layout, e)) goto done;
    /* decode limits from the header (envmap.h): every channel of the file is decompressed,
     * the planes chosen are kept as floats, then copied out (RGB, alpha, the caller's RGBA) */
    double raw_px = 0;
    for (int i = 0; i < chl->num_channels; i++) {
        const exr_attr_chlist_entry_t *c = &chl->entries[i];
        double sub = (double)(c->x_sampling > 0 ? c->x_sampling : 1) *
                     (double)(c->y_sampling > 0 ? c->y_sampling : 1);
        raw_px += (c->pixel_type == EXR_PIXEL_HALF ? 2.0 : 4.0) / sub;
    }
    double out_px = 4.0 * p.nplanes + 12.0 + (with_alpha ? 4.0 + 16.0 : 0.0);
    if (!sl_decode_budget_ok(name, "OpenEXR", w, h, raw_px, out_px, n, e)) goto done;
    size_t np = (size_t)w * (size_t)h;
    planes = sl_calloc(np * (size_t)p.nplanes, sizeof(float));
    for (int i = 0; i < p.nplanes; i++)
        p.planes[i] = planes + np * (size_t)i;

    int dwa = comp == EXR_COMPRESSION_DWAA || comp == EXR_COMPRESSION_DWAB;
    int use_cxx = force_cxx || dwa;
    if (!use_cxx) {
        int nc = chl->num_channels;
        rv = storage == EXR_STORAGE_TILED
                 ? read_tiles(ctx, &p, nc, (int)w, (int)h, &m, name, e)
                 : read_scanlines(ctx, &dw, &p, nc, (int)w, (int)h, &m, name, e);
        if (rv == EXR_ERR_FEATURE_NOT_IMPLEMENTED) {
            use_cxx = 1; /* something Core cannot decode: try the C++ library */
            e->msg[0] = 0;
        } else if (rv != EXR_ERR_SUCCESS) {
            goto done;
        }
    }
    if (use_cxx) {
        char msg[512];
        if (cxx_header_ok(data, n, &dw, name, e)) goto done;
        if (sl_exrcxx_read_planes(data, n, (int)w, (int)h, p.nplanes, p.names, p.planes, msg,
                                  sizeof msg)) {
            sl_fail(e, "%s: OpenEXR (C++): %s", name, msg);
            goto done;
        }
    }
    out->rgb = sl_malloc(np * 3 * sizeof(float));
    for (size_t i = 0; i < np; i++)
        for (int c = 0; c < 3; c++)
            out->rgb[3 * i + c] = p.planes[p.nplanes >= 3 ? c : 0][i];
    if (with_alpha) {
        *alpha = sl_malloc(np * sizeof(float));
        memcpy(*alpha, p.planes[3], np * sizeof(float));
    }
    out->width = (int)w;
    out->height = (int)h;
    snprintf(out->format, sizeof out->format, "OpenEXR %s %s (%s%s)", type_word, layout,
             compression_name(comp), storage == EXR_STORAGE_TILED ? ", tiled" : "");
    rc = 0;
done:
    free(planes);
    exr_finish(&ctx);
    return rc;
}

int sl_envmap_decode_exr(const unsigned char *data, size_t n, const char *name, int force_cxx,
                         sl_envmap *out, sl_err *e) {
    return decode_exr(data, n, name, force_cxx, 0, NULL, out, NULL, e);
}

int sl_exr_decode_rgba(const unsigned char *data, size_t n, const char *name, int *w, int *h,
                       float **rgba, sl_err *e) {
    return sl_exr_decode_layer_rgba(data, n, name, NULL, w, h, rgba, e);
}

int sl_exr_decode_layer_rgba(const unsigned char *data, size_t n, const char *name,
                             const char *layer, int *w, int *h, float **rgba, sl_err *e) {
    sl_envmap m;
    float *alpha = NULL;
    *rgba = NULL;
    *w = *h = 0;
    if (decode_exr(data, n, name, 0, 1, layer, &m, &alpha, e)) return -1;
    size_t np = (size_t)m.width * (size_t)m.height;
    *rgba = sl_malloc(4 * np * sizeof(float));
    for (size_t i = 0; i < np; i++) {
        for (int c = 0; c < 3; c++)
            (*rgba)[4 * i + c] = m.rgb[3 * i + c];
        (*rgba)[4 * i + 3] = alpha[i];
    }
    *w = m.width;
    *h = m.height;
    free(alpha);
    sl_envmap_free(&m);
    return 0;
}
