/* fuzz_ref_record.c: libFuzzer target for the cached reference records (`<exr>.json` beside a
 * reference EXR, verify/reference/ref_record.h): the parse (sl_ref_json_parse; sl_ref_json_read
 * is it plus the file read) and the two checks that decide a cache hit, sl_ref_key_matches and
 * sl_ref_integrity_matches, on the "reference" object of the input.
 * Checks: when "key" is 16 lowercase hex digits, the record matches that key and not the key
 * with its lowest bit flipped; any other "key" matches neither 0 nor the input's hash; when
 * "integrity" holds a 16-hex-digit exr_fnv1a64 and an integer exr_bytes below 2^53, the record
 * matches that digest and not one byte more; and a record written for the input's hash by
 * sl_ref_record_begin + sl_ref_integrity_add reads back as matching (the writer and the reader
 * agree). The input is an exact-size copy (no NUL), so ASan catches a read past its end.
 * ref_record.c also holds the scene loading and the EXR writer of the references; those are
 * stubs here (a trap: the parser must not call them), which keeps the scene, hair and image
 * code out of this target. Seeds: test/fuzz/corpus/fuzz_ref_record/.
 */
// clang-format off
/* FUZZ_SOURCES: host/verify/reference/ref_record.c host/base/common.c */
// clang-format on
#include "io/image/image_write.h"
#include "scene/scene_inputs.h"
#include "verify/reference/ref_record.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int sl_scene_inputs_from_scene(const sl_scene *s, const sl_scene_inputs_opts *o,
                               sl_scene_inputs *in, sl_err *e) {
    (void)s, (void)o, (void)in, (void)e;
    __builtin_trap();
}
void sl_scene_inputs_free(sl_scene_inputs *in) {
    (void)in;
    __builtin_trap();
}
int sl_exr_write(const char *path, int w, int h, const sl_exr_channel *ch, int nch, int use_float,
                 sl_err *e) {
    (void)path, (void)w, (void)h, (void)ch, (void)nch, (void)use_float, (void)e;
    __builtin_trap();
}

/* 16 lowercase hex digits, as the writer prints a 64-bit value. */
static int hex16(const cJSON *s, uint64_t *out) {
    if (!cJSON_IsString(s) || strlen(s->valuestring) != 16) return 0;
    uint64_t v = 0;
    for (int i = 0; i < 16; i++) {
        char c = s->valuestring[i];
        int d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
        if (d < 0) return 0;
        v = v << 4 | (uint64_t)d;
    }
    *out = v;
    return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    uint64_t h = sl_hash64(text, size, 0);
    cJSON *root = sl_ref_json_parse(text, size);
    if (root) {
        const cJSON *ref = cJSON_GetObjectItemCaseSensitive(root, "reference");
        uint64_t key;
        if (hex16(cJSON_GetObjectItemCaseSensitive(ref, "key"), &key)) {
            if (!sl_ref_key_matches(ref, key) || sl_ref_key_matches(ref, key ^ 1)) __builtin_trap();
        } else if (sl_ref_key_matches(ref, 0) || sl_ref_key_matches(ref, h)) {
            __builtin_trap();
        }
        const cJSON *in = cJSON_GetObjectItemCaseSensitive(ref, "integrity");
        const cJSON *b = cJSON_GetObjectItemCaseSensitive(in, "exr_bytes");
        sl_ref_digest d;
        if (hex16(cJSON_GetObjectItemCaseSensitive(in, "exr_fnv1a64"), &d.hash) &&
            cJSON_IsNumber(b) && b->valuedouble >= 0 && b->valuedouble < 9007199254740992.0 &&
            b->valuedouble == floor(b->valuedouble)) {
            d.bytes = (uint64_t)b->valuedouble;
            sl_ref_digest d1 = {d.bytes + 1, d.hash};
            if (!sl_ref_integrity_matches(ref, d) || sl_ref_integrity_matches(ref, d1))
                __builtin_trap();
        }
        cJSON_Delete(root);
    }
    /* writer -> reader, for a key and digest from this input */
    cJSON *wref;
    cJSON *w = sl_ref_record_begin(h, "fuzz.json", 1, 1, &wref);
    sl_ref_digest wd = {size, h ^ 0x5a5a5a5a5a5a5a5aull};
    sl_ref_integrity_add(wref, wd);
    char *printed = cJSON_PrintUnformatted(w);
    cJSON_Delete(w);
    cJSON *back = printed ? sl_ref_json_parse(printed, strlen(printed)) : NULL;
    const cJSON *bref = cJSON_GetObjectItemCaseSensitive(back, "reference");
    if (!back || !sl_ref_key_matches(bref, h) || !sl_ref_integrity_matches(bref, wd))
        __builtin_trap();
    cJSON_Delete(back);
    free(printed);
    free(text);
    return 0;
}
