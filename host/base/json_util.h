/* json_util.h: typed access to cJSON objects with errors that name the file and the key path
 * ("scene.json: camera.fov_deg: expected a number"). Used by the scene and material loaders. */
#ifndef SL_JSON_UTIL_H
#define SL_JSON_UTIL_H

#include "base/common.h"

#include <cjson/cJSON.h>

typedef struct sl_json_ctx {
    const char *file;   /* for messages */
    const char *prefix; /* key path of the object being read, "" at the top */
} sl_json_ctx;

/* Builds "prefix.key" (or "key" at the top) into out. */
void sl_json_path(const sl_json_ctx *c, const char *key, char *out, size_t n);
/* Fails on any key of obj not in the NULL-terminated list `allowed`. obj must be an object. */
int sl_json_check_keys(const sl_json_ctx *c, const cJSON *obj, const char *const *allowed,
                       sl_err *e);
/* Reads obj[key] if present (returns 0 and leaves *out when absent unless required). */
int sl_json_number(const sl_json_ctx *c, const cJSON *obj, const char *key, int required,
                   double *out, sl_err *e);
int sl_json_int(const sl_json_ctx *c, const cJSON *obj, const char *key, int required, long lo,
                long hi, long *out, sl_err *e);
int sl_json_string(const sl_json_ctx *c, const cJSON *obj, const char *key, int required,
                   char *out, size_t n, sl_err *e);
/* A fixed-length array of numbers, e.g. [x, y, z]. */
int sl_json_vec(const sl_json_ctx *c, const cJSON *obj, const char *key, int required, int len,
                double *out, sl_err *e);
/* obj[key] must be an object when present; *child = NULL when absent. */
int sl_json_object(const sl_json_ctx *c, const cJSON *obj, const char *key, int required,
                   const cJSON **child, sl_err *e);
/* Parses text; a syntax error names the line: "x.json: invalid JSON near line 3"; a key given twice
 * in one object names its path: "x.json: quality.lobes: duplicate key". */
cJSON *sl_json_parse(const char *text, size_t len, const char *file, sl_err *e);

#endif
