/* lobes_json.c: reads and writes SRBF lobe files (see lobes_json.h). */
#include "lighting/lobes_json.h"

#include "base/json_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

double sl_lobe_integral(double lambda) {
    /* 2 pi integral_{-1}^{1} exp(2 (t - 1) / l2) dt = pi l2 (1 - exp(-4 / l2)), written with
     * x = 4 / l2 so that neither end overflows: broad lobes (x -> 0, l2 may be Inf) tend to
     * 4 pi (1 - exp(-x)) / x -> 4 pi, narrow ones to pi l2; expm1 keeps both limits exact. */
    double x = 4.0 / (lambda * lambda);
    if (x > 1.0) return -M_PI * lambda * lambda * expm1(-x);
    return x > 0 ? -4.0 * M_PI * expm1(-x) / x : 4.0 * M_PI;
}

void sl_lobes_free(sl_lobes *l) {
    if (!l) return;
    free(l->lobe);
    free(l->fit_json);
    memset(l, 0, sizeof *l);
}

/* Checks one lobe; `name` and `idx` are for messages. Normalises a nearly unit dir in place. */
static int check_lobe(sl_lobe *lb, const char *name, int idx, sl_err *e) {
    double n = sqrt(lb->dir[0] * lb->dir[0] + lb->dir[1] * lb->dir[1] + lb->dir[2] * lb->dir[2]);
    if (!isfinite(n) || fabs(n - 1.0) > 1e-3)
        return sl_fail(e, "%s: lobes[%d].dir: expected a unit vector (length %.6g)", name, idx, n);
    for (int k = 0; k < 3; k++)
        lb->dir[k] /= n;
    if (!isfinite(lb->lambda) || !(lb->lambda > 0))
        return sl_fail(e, "%s: lobes[%d].lambda: expected a positive number", name, idx);
    for (int k = 0; k < 3; k++)
        if (!isfinite(lb->rgb[k]) || lb->rgb[k] < 0)
            return sl_fail(e, "%s: lobes[%d].rgb[%d]: expected a finite number >= 0", name, idx, k);
    return 0;
}

int sl_lobes_parse(const char *text, size_t len, const char *name, sl_lobes *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    out->rel_l2 = out->lobe_conv_rel_l2 = -1;
    cJSON *root = sl_json_parse(text, len, name, e);
    if (!root) return -1;
    int rc = -1;
    sl_json_ctx top = {name, ""};
    static const char *const top_keys[] = {"lobes", "fit", NULL};
    static const char *const lobe_keys[] = {"dir", "lambda", "rgb", NULL};
    if (!cJSON_IsObject(root)) {
        sl_fail(e, "%s: expected a JSON object with a \"lobes\" array", name);
        goto done;
    }
    if (sl_json_check_keys(&top, root, top_keys, e)) goto done;
    const cJSON *arr = cJSON_GetObjectItemCaseSensitive(root, "lobes");
    if (!arr) {
        sl_fail(e, "%s: lobes: missing", name);
        goto done;
    }
    if (!cJSON_IsArray(arr)) {
        sl_fail(e, "%s: lobes: expected an array", name);
        goto done;
    }
    int n = cJSON_GetArraySize(arr);
    if (n < 1) {
        sl_fail(e, "%s: lobes: expected at least one lobe", name);
        goto done;
    }
    if (n > SL_LOBES_MAX) {
        sl_fail(e, "%s: lobes: %d lobes, at most %d supported", name, n, SL_LOBES_MAX);
        goto done;
    }
    out->lobe = sl_calloc((size_t)n, sizeof *out->lobe);
    int i = 0;
    for (const cJSON *it = arr->child; it; it = it->next, i++) {
        char prefix[64];
        snprintf(prefix, sizeof prefix, "lobes[%d]", i);
        sl_json_ctx c = {name, prefix};
        if (!cJSON_IsObject(it)) {
            sl_fail(e, "%s: %s: expected an object", name, prefix);
            goto done;
        }
        sl_lobe *lb = &out->lobe[i];
        if (sl_json_check_keys(&c, it, lobe_keys, e) ||
            sl_json_vec(&c, it, "dir", 1, 3, lb->dir, e) ||
            sl_json_number(&c, it, "lambda", 1, &lb->lambda, e) ||
            sl_json_vec(&c, it, "rgb", 1, 3, lb->rgb, e) || check_lobe(lb, name, i, e))
            goto done;
    }
    out->count = n;
    const cJSON *fit = NULL;
    if (sl_json_object(&top, root, "fit", 0, &fit, e)) goto done;
    if (fit) {
        out->fit_json = cJSON_PrintUnformatted(fit);
        const cJSON *h = cJSON_GetObjectItemCaseSensitive(fit, "map_hash");
        if (cJSON_IsString(h) && h->valuestring)
            snprintf(out->map_hash, sizeof out->map_hash, "%s", h->valuestring);
        const cJSON *r = cJSON_GetObjectItemCaseSensitive(fit, "rel_l2");
        if (cJSON_IsNumber(r)) out->rel_l2 = r->valuedouble;
        r = cJSON_GetObjectItemCaseSensitive(fit, "lobe_conv_rel_l2");
        if (cJSON_IsNumber(r)) out->lobe_conv_rel_l2 = r->valuedouble;
    }
    rc = 0;
done:
    cJSON_Delete(root);
    if (rc) sl_lobes_free(out);
    return rc;
}

int sl_lobes_load(const char *path, sl_lobes *out, sl_err *e) {
    unsigned char *data;
    size_t size;
    memset(out, 0, sizeof *out);
    if (sl_read_file(path, &data, &size, (size_t)256 << 20, e)) return -1;
    int rc = sl_lobes_parse((const char *)data, size, path, out, e);
    free(data);
    return rc;
}

char *sl_lobes_format(const sl_lobes *l, const char *name, size_t *len, sl_err *e) {
    if (l->count < 1) {
        sl_fail(e, "%s: no lobes to write", name);
        return NULL;
    }
    for (int i = 0; i < l->count; i++) {
        sl_lobe tmp = l->lobe[i];
        if (check_lobe(&tmp, name, i, e)) return NULL;
    }
    cJSON *fit = NULL;
    if (l->fit_json) {
        fit = cJSON_Parse(l->fit_json);
        if (!fit || !cJSON_IsObject(fit)) {
            cJSON_Delete(fit);
            sl_fail(e, "%s: internal: the \"fit\" record is not a JSON object", name);
            return NULL;
        }
    }
    char *text = NULL;
    size_t n = 0;
    FILE *fp = open_memstream(&text, &n);
    if (!fp) {
        cJSON_Delete(fit);
        sl_fail(e, "%s: out of memory", name);
        return NULL;
    }
    /* One lobe per line: easy to read and to diff. %.17g round-trips doubles exactly. */
    fprintf(fp, "{\n  \"lobes\": [\n");
    for (int i = 0; i < l->count; i++) {
        const sl_lobe *b = &l->lobe[i];
        fprintf(fp,
                "    {\"dir\": [%.17g, %.17g, %.17g], \"lambda\": %.17g, \"rgb\": [%.9g, %.9g, "
                "%.9g]}%s\n",
                b->dir[0], b->dir[1], b->dir[2], b->lambda, b->rgb[0], b->rgb[1], b->rgb[2],
                i + 1 < l->count ? "," : "");
    }
    fprintf(fp, "  ]");
    if (fit) {
        char *txt = cJSON_Print(fit);
        /* Indent the pretty-printed object by two spaces to sit inside the top level. */
        fprintf(fp, ",\n  \"fit\": ");
        for (const char *c = txt; *c; c++) {
            fputc(*c, fp);
            if (*c == '\n') fputs("  ", fp);
        }
        free(txt);
        cJSON_Delete(fit);
    }
    fprintf(fp, "\n}\n");
    int bad = ferror(fp);
    if (fclose(fp) != 0 || bad) {
        free(text);
        sl_fail(e, "%s: out of memory", name);
        return NULL;
    }
    *len = n;
    return text;
}

int sl_lobes_save(const char *path, const sl_lobes *l, sl_err *e) {
    size_t n = 0;
    char *text = sl_lobes_format(l, path, &n, e);
    if (!text) return -1;
    sl_atomic_file af;
    if (sl_make_parent_dirs(path, e) || sl_atomic_open(&af, path, e)) {
        free(text);
        return -1;
    }
    if (fwrite(text, 1, n, af.fp) != n) {
        free(text);
        sl_atomic_abort(&af);
        return sl_fail(e, "%s: write error", path);
    }
    free(text);
    return sl_atomic_commit(&af, e);
}
