/* ref_record.h: what both reference renders (pixel/fragment mode, reference.c, and the path
 * tracer, reference_path.c) record beside their EXR and key their caches by: the content hash
 * of a scene's inputs (hair, map, material, camera; not file names), the EXR's integrity record
 * in the JSON (its length and FNV-1a 64: a cached EXR that does not match is rendered again),
 * and the atomic JSON write. */
#ifndef SL_REF_RECORD_H
#define SL_REF_RECORD_H

#include "base/common.h"
#include "io/hair/hair.h"
#include "scene/camera.h"
#include "scene/material.h"
#include "scene/scene.h"

#include <cjson/cJSON.h>
#include <stdint.h>

/* FNV-1a 64 continued from h over the loaded hair (offsets, positions, radii), the decoded
 * map's pixel hash, the material's values and the camera actually used. */
uint64_t sl_ref_content_hash(uint64_t h, const sl_hair *hair, uint64_t map_hash,
                             const sl_material *m, const sl_camera *cam);

/* n doubles into the hash (settings). */
uint64_t sl_ref_hash_doubles(uint64_t h, const double *v, size_t n);

/* The EXR's digest. */
typedef struct sl_ref_digest {
    uint64_t bytes, hash;
} sl_ref_digest;

/* Adds "integrity": {"exr_bytes", "exr_fnv1a64"} to the record object ref. */
void sl_ref_integrity_add(cJSON *ref, sl_ref_digest d);
/* 1 when ref's "integrity" object is present and records d. */
int sl_ref_integrity_matches(const cJSON *ref, sl_ref_digest d);

/* Prints root (deleted here) to path atomically. Returns 0 or -1 with e set. */
int sl_ref_json_write(const char *path, cJSON *root, sl_err *e);

/* Reads and parses a JSON record of at most 1 MiB; NULL when missing or malformed. */
cJSON *sl_ref_json_read(const char *path);
/* The parse of a record already in memory (size bytes, no NUL needed); NULL when malformed.
 * No I/O: fuzzed, with the key and digest checks below, by test/fuzz/fuzz_ref_record.c. */
cJSON *sl_ref_json_parse(const void *data, size_t size);

/* Hair, camera and per-strand sigma_a through the loader `render` uses (scene_inputs.h: the
 * same framing, the same width/height overrides, 0 for the scene's, material.strand_sigma_a
 * resolved against the hair: 3 floats per strand into *strand_sa, NULL without the key; free
 * it); the hair moves into *hair. Returns 0 or -1 with e set (nothing to free then). */
int sl_ref_scene_load(const sl_scene *s, int width, int height, sl_hair *hair, sl_camera *cam,
                      float **strand_sa, sl_err *e);
/* The per-strand sigma_a (3 per strand of n, or NULL) into h (a reference's cache key). */
uint64_t sl_ref_strand_hash(uint64_t h, const float *strand_sa, uint32_t n);

/* Starts a record: a new root with the object "reference" holding "key" (16 hex digits),
 * "scene", "width" and "height"; returns root and sets *ref. */
cJSON *sl_ref_record_begin(uint64_t key, const char *scene, int w, int h, cJSON **ref);
/* 1 when the record object ref holds "key" as sl_ref_record_begin writes it. */
int sl_ref_key_matches(const cJSON *ref, uint64_t key);
/* Adds "mean_rgb" [3] and "coverage". */
void sl_ref_add_mean(cJSON *ref, const double mean_rgb[3], double coverage);

/* Writes n float planes of w x h (plane c at planes + c * w * h, named names[c]) as a float
 * EXR (sl_exr_write) and frees planes. Returns 0 or -1 with e set. */
int sl_ref_exr_write_planes(const char *path, int w, int h, const char *const *names, int n,
                            float *planes, sl_err *e);

#endif
