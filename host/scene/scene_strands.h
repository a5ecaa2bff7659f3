/* scene_strands.h: per-strand absorption overrides of a scene (`material.strand_sigma_a`,
 * docs/formats.md): "colors" (from the hair file's per-point colours) or a CSV file
 * `strand,sigma_a_r,sigma_a_g,sigma_a_b` (header line, one row per overridden strand; strands
 * without a row keep the material's sigma_a). The renderer takes the result with
 * sl_renderer_set_strand_sigma_a (host/plan/frame.h); the viewer saves paint with the writer.
 *
 *   float *sa;                       (3 per strand: sigma_a r g b per unit fiber radius)
 *   if (sl_scene_strand_sigma_a(&scene, &hair, &sa, &e)) ...   sa == NULL: the key is absent
 *   sl_renderer_set_strand_sigma_a(&r, sa, hair.num_strands, &e); free(sa);
 *   sl_strand_sigma_a_write_csv("paint.csv", sa, n, base, &e);  (rows only where sa != base) */
#ifndef SL_SCENE_STRANDS_H
#define SL_SCENE_STRANDS_H

#include "io/hair/hair.h"
#include "scene/scene.h"

/* Resolves s->strand_sigma_a against the hair h: *out = 3 x h->num_strands floats (malloc; the
 * caller frees), or NULL when the scene has no such key. Errors: a hair file without per-point
 * colours ("colors"), a missing or malformed CSV (one line naming the file and line). */
int sl_scene_strand_sigma_a(const sl_scene *s, const sl_hair *h, float **out, sl_err *e);

/* Writes the CSV form atomically: a header and one row for each strand whose sigma_a differs
 * from base (exact float comparison), values printed so that they read back bit-exact. */
int sl_strand_sigma_a_write_csv(const char *path, const float *sa, uint32_t n, const float base[3],
                                sl_err *e);

/* Reads the CSV form for a hair of n strands: *out = 3 n floats, base where no row is given.
 * `name` is used in messages (the path as the user wrote it). */
int sl_strand_sigma_a_read_csv(const char *path, uint32_t n, const float base[3], float **out,
                               sl_err *e);
/* The same from memory (tests, fuzzing). */
int sl_strand_sigma_a_parse_csv(const char *text, size_t len, const char *name, uint32_t n,
                                const float base[3], float **out, sl_err *e);

/* "colors": each strand's mean per-point colour mapped to sigma_a per channel by Chiang et al.
 * 2016 Eq. 9 (the inverse of their colour fit), with their azimuthal roughness beta_n taken
 * equal to the longitudinal beta_m that reproduces the material's R width (see
 * sl_chiang_beta_m). A hair without a per-point colour array uses the file's one colour (a
 * .tfxproj's hairColor, h->color_from_file); error when it has neither. */
int sl_strand_sigma_a_from_colors(const sl_hair *h, const sl_material *m, float **out, sl_err *e);

/* Chiang et al. 2016 Eq. 9: sigma_a (per unit fiber radius, as pbrt and numerics.md) of a hair
 * whose multiply-scattered colour is c in (0, 1], for azimuthal roughness beta_n in [0, 1].
 * c is clamped to [1e-4, 1]; c = 1 gives 0. */
double sl_chiang_sigma_a(double c, double beta_n);
/* Chiang et al. 2016 Eq. 7 inverted: the roughness beta_m in [0, 1] whose longitudinal standard
 * deviation 0.726 b + 0.812 b^2 + 3.7 b^20 equals sd (radians); clamped to [0, 1]. */
double sl_chiang_beta_m(double sd);

#endif
