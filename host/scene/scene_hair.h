/* scene_hair.h: the scene's hair as every pass sees it: the file (up axis converted to +Y,
 * TressFX guides densified by hair.tfx_follow unless a .tfxproj already did) or the procedural
 * generator, with hair.radius overriding the file's thickness. */
#ifndef SL_SCENE_HAIR_H
#define SL_SCENE_HAIR_H

#include "io/hair/hair.h"
#include "scene/scene.h"

int sl_scene_load_hair(const sl_scene *s, sl_hair *h, sl_err *e);

#endif
