/* json_util.c: see json_util.h. */
#include "base/json_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void sl_json_path(const sl_json_ctx *c, const char *key, char *out, size_t n) {
    if (c->prefix && c->prefix[0])
        snprintf(out, n, "%s.%s", c->prefix, key);
    else
        snprintf(out, n, "%s", key);
}

int sl_json_check_keys(const sl_json_ctx *c, const cJSON *obj, const char *const *allowed,
                       sl_err *e) {
    for (const cJSON *it = obj->child; it; it = it->next) {
        int ok = 0;
        for (const char *const *a = allowed; *a; a++)
            if (it->string && strcmp(it->string, *a) == 0) ok = 1;
        if (!ok) {
            char p[512];
            sl_json_path(c, it->string ? it->string : "?", p, sizeof p);
            return sl_fail(e, "%s: %s: unknown key", c->file, p);
        }
    }
    return 0;
}

static const cJSON *get(const sl_json_ctx *c, const cJSON *obj, const char *key, int required,
                        sl_err *e, int *missing) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    *missing = 0;
    if (!v) {
        *missing = 1;
        if (required) {
            char p[512];
            sl_json_path(c, key, p, sizeof p);
            sl_fail(e, "%s: %s: missing", c->file, p);
        }
    }
    return v;
}

int sl_json_number(const sl_json_ctx *c, const cJSON *obj, const char *key, int required,
                   double *out, sl_err *e) {
    int missing;
    const cJSON *v = get(c, obj, key, required, e, &missing);
    if (missing) return required ? -1 : 0;
    char p[512];
    sl_json_path(c, key, p, sizeof p);
    if (!cJSON_IsNumber(v)) return sl_fail(e, "%s: %s: expected a number", c->file, p);
    if (!isfinite(v->valuedouble)) return sl_fail(e, "%s: %s: not a finite number", c->file, p);
    *out = v->valuedouble;
    return 0;
}

int sl_json_int(const sl_json_ctx *c, const cJSON *obj, const char *key, int required, long lo,
                long hi, long *out, sl_err *e) {
    double d = 0;
    int missing;
    get(c, obj, key, 0, e, &missing);
    if (missing && !required) return 0;
    if (sl_json_number(c, obj, key, required, &d, e)) return -1;
    char p[512];
    sl_json_path(c, key, p, sizeof p);
    if (d != floor(d)) return sl_fail(e, "%s: %s: expected an integer", c->file, p);
    if (d < (double)lo || d > (double)hi)
        return sl_fail(e, "%s: %s: must be in [%ld, %ld]", c->file, p, lo, hi);
    *out = (long)d;
    return 0;
}

int sl_json_string(const sl_json_ctx *c, const cJSON *obj, const char *key, int required, char *out,
                   size_t n, sl_err *e) {
    int missing;
    const cJSON *v = get(c, obj, key, required, e, &missing);
    if (missing) return required ? -1 : 0;
    char p[512];
    sl_json_path(c, key, p, sizeof p);
    if (!cJSON_IsString(v) || !v->valuestring)
        return sl_fail(e, "%s: %s: expected a string", c->file, p);
    if (strlen(v->valuestring) >= n) return sl_fail(e, "%s: %s: string too long", c->file, p);
    snprintf(out, n, "%s", v->valuestring);
    return 0;
}

int sl_json_vec(const sl_json_ctx *c, const cJSON *obj, const char *key, int required, int len,
                double *out, sl_err *e) {
    int missing;
    const cJSON *v = get(c, obj, key, required, e, &missing);
    if (missing) return required ? -1 : 0;
    char p[512];
    sl_json_path(c, key, p, sizeof p);
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != len)
        return sl_fail(e, "%s: %s: expected an array of %d numbers", c->file, p, len);
    int i = 0;
    for (const cJSON *it = v->child; it; it = it->next, i++) {
        if (!cJSON_IsNumber(it) || !isfinite(it->valuedouble))
            return sl_fail(e, "%s: %s[%d]: expected a finite number", c->file, p, i);
        out[i] = it->valuedouble;
    }
    return 0;
}

int sl_json_object(const sl_json_ctx *c, const cJSON *obj, const char *key, int required,
                   const cJSON **child, sl_err *e) {
    int missing;
    const cJSON *v = get(c, obj, key, required, e, &missing);
    *child = NULL;
    if (missing) return required ? -1 : 0;
    char p[512];
    sl_json_path(c, key, p, sizeof p);
    if (!cJSON_IsObject(v)) return sl_fail(e, "%s: %s: expected an object", c->file, p);
    *child = v;
    return 0;
}

static int cmp_key(const void *a, const void *b) {
    const cJSON *x = *(const cJSON *const *)a, *y = *(const cJSON *const *)b;
    return strcmp(x->string ? x->string : "", y->string ? y->string : "");
}

/* The first key that appears twice in one object of the tree below v, as its key path (e.g.
 * "quality.lobes", "lobes[3].dir"), or 0 when there is none. cJSON keeps both copies and its
 * lookups return the first while Python and JavaScript keep the last: a duplicate is an error, not
 * a guess. Sorted per object (n log n), so a huge object costs no quadratic time. */
static int find_duplicate(const cJSON *v, const char *path, char *out, size_t n, int depth) {
    if (depth > 64) return 0; /* cJSON itself refuses deeper nesting */
    size_t count = 0;
    for (const cJSON *it = v->child; it; it = it->next)
        count++;
    if (cJSON_IsObject(v) && count > 1) {
        const cJSON **keys = malloc(count * sizeof *keys);
        if (keys) {
            size_t i = 0;
            for (const cJSON *it = v->child; it; it = it->next)
                keys[i++] = it;
            qsort(keys, count, sizeof *keys, cmp_key);
            for (i = 1; i < count; i++)
                if (cmp_key(&keys[i - 1], &keys[i]) == 0) {
                    const char *k = keys[i]->string ? keys[i]->string : "";
                    snprintf(out, n, "%s%s%s", path, path[0] ? "." : "", k);
                    free(keys);
                    return 1;
                }
            free(keys);
        }
    }
    size_t idx = 0;
    for (const cJSON *it = v->child; it; it = it->next, idx++) {
        if (!it->child) continue;
        char sub[512];
        if (cJSON_IsObject(v))
            snprintf(sub, sizeof sub, "%s%s%s", path, path[0] ? "." : "",
                     it->string ? it->string : "");
        else
            snprintf(sub, sizeof sub, "%s[%zu]", path, idx);
        if (find_duplicate(it, sub, out, n, depth + 1)) return 1;
    }
    return 0;
}

cJSON *sl_json_parse(const char *text, size_t len, const char *file, sl_err *e) {
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    /* Text after the JSON value ("{} x") is an error too (cJSON's own check wants a NUL). */
    if (root) {
        const char *p = end;
        while (p < text + len && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r'))
            p++;
        if (p < text + len && *p) {
            cJSON_Delete(root);
            root = NULL;
            end = p;
        }
    }
    if (!root) {
        int line = 1;
        const char *stop = end ? end : text;
        for (const char *p = text; p < stop && p < text + len; p++)
            if (*p == '\n') line++;
        sl_fail(e, "%s: invalid JSON near line %d", file, line);
        return NULL;
    }
    char dup[512];
    if (find_duplicate(root, "", dup, sizeof dup, 0)) {
        cJSON_Delete(root);
        sl_fail(e, "%s: %s: duplicate key", file, dup);
        return NULL;
    }
    return root;
}
