/* env_lighting.h: the SRBF lobes a scene is lit by. A scene names a lobes file (written by
 * `strandlight fit`) and/or an environment map; with only a map, the lobes are fitted on the fly
 * (quality.lobes of them) and cached on disk by the map's hash and the fit settings, so the next
 * render of the same map starts at once. */
#ifndef SL_ENV_LIGHTING_H
#define SL_ENV_LIGHTING_H

#include "lighting/envfit.h"
#include "io/envmap/envmap.h"
#include "lighting/lobes_json.h"
#include "scene/scene.h"

/* The JSON "fit" record written beside fitted lobes: map hash, settings, achieved errors. */
char *sl_envfit_record(const char *map_path, const sl_envmap *m, const sl_envfit_settings *s,
                       int clamp, const sl_envfit_report *r, int count);

/* Loads environment.lobes, or fits quality.lobes lobes to environment.file (cached). Rotation
 * and intensity are NOT applied here (see sl_lobes_transform). */
int sl_scene_lobes(const sl_scene *s, int clamp_nonfinite, sl_lobes *out, sl_err *e);

/* Applies environment.rotation_deg (about +Y) and intensity to lobes in place. */
void sl_lobes_transform(sl_lobes *l, double rotation_deg, double intensity);

#endif
