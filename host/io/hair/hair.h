/* hair.h: strand hair geometry: loading (cyHair .hair, TressFX 3.x/4.x .tfx, TressFX .tfxproj,
 * USC-HairSalon .data), the procedural generator, TressFX follow strands, and helpers (bounds,
 * up-axis conversion, tangents that stay finite on near-zero-length segments).
 *
 * Conventions: the first point of every strand is its root; positions are in the file's own
 * units; `radius` is a fiber RADIUS (a .hair file stores thickness, a DIAMETER, halved at load).
 * Every strand has at least 2 points and a non-zero length, and every coordinate is finite:
 * the loaders reject anything else with a one-line error naming the file and the problem
 * (docs/formats.md lists the policy). Binary layouts: ../shared/data/README.md. */
#ifndef SL_HAIR_H
#define SL_HAIR_H

#include "base/common.h"

#include <stdint.h>
#include <stdio.h>

/* Where default_radius came from (for `strandlight info` and the renderer's choice). */
enum {
    SL_RADIUS_PER_POINT = 0, /* radius[] holds per-point values (default_radius unused) */
    SL_RADIUS_HEADER = 1,    /* the file's header default (cyHair default thickness / 2) */
    SL_RADIUS_ESTIMATED = 2, /* the file has no thickness: SL_HAIR_RADIUS_SCALE x bbox diagonal */
    SL_RADIUS_PROCEDURAL = 3 /* the generator's fixed radius */
};
/* A file without thickness (TressFX, USC) gets radius = this x its bounding-box diagonal: 0.03
 * for a head of hair 60 units across, close to the generator's 0.04; thick enough to render at
 * a few pixels per strand, thin enough to look like hair. The scene's hair.radius overrides it. */
#define SL_HAIR_RADIUS_SCALE 5e-4f

typedef struct sl_hair {
    char format[64]; /* "cyHair .hair", "TressFX 3 .tfx", "TressFX 4 .tfx", "USC-HairSalon .data",
                        "TressFX project .tfxproj", "procedural (wavy)" */
    uint32_t num_strands, num_points;
    uint32_t *strand_first; /* num_strands + 1 offsets into the point arrays */
    float *pos;             /* 3 * num_points, world units of the file */
    float *radius;       /* per point fiber RADIUS, or NULL -> default_radius (.hair: DIAMETER/2) */
    float *transparency; /* per point, or NULL -> default_transparency */
    float *color;        /* 3 * num_points, or NULL -> default_color */
    float default_radius, default_transparency, default_color[3];

    /* Added fields (informational). */
    int radius_source;        /* SL_RADIUS_* */
    uint32_t dropped_strands; /* USC .data strands with 1 point, dropped as Digital Salon does */
    uint32_t guide_strands;   /* strands before follow strands were added (= num_strands if none) */
    int follow_added;         /* 1 when follow strands were added (sl_hair_add_follow, .tfxproj) */
    int color_from_file;      /* 1 when default_color is the file's colour of every strand (a
                                 .tfxproj's hairColor); material.strand_sigma_a "colors" uses it */
    char notes[256];          /* format details for `info`, e.g. "version 3.0, bothEndsImmovable" */
} sl_hair;

/* Loads a hair file, picking the parser by content ("HAIR" magic) and extension (.hair, .tfx,
 * .tfxproj, .data). On failure returns -1 with e set and *out zeroed (nothing to free).
 * Warns on stderr about dropped strands. */
int sl_hair_load(const char *path, sl_hair *out, sl_err *e);
/* The same from memory; `name` is used in messages and to pick the parser by extension. Prints
 * nothing (the fuzz targets call this). .tfxproj is not accepted here (it names other files). */
int sl_hair_load_memory(const unsigned char *data, size_t size, const char *name, sl_hair *out,
                        sl_err *e);
void sl_hair_free(sl_hair *h);

/* Writes h as a cyHair .hair file (atomically): segments, points, per-point thickness = 2 x radius
 * (the format's diameter), and transparency / colours when h has them; `info` (may be NULL) fills
 * the header's 88-byte text. A strand of more than 65536 points (the format's u16 segment count)
 * is an error naming it. sl_hair_load reads the file back to the same strands and radii. */
int sl_hair_write_cyhair(const char *path, const sl_hair *h, const char *info, sl_err *e);

/* Individual parsers (sl_hair_load_memory dispatches to them). */
int sl_hair_parse_cyhair(const unsigned char *d, size_t n, const char *name, sl_hair *out,
                         sl_err *e);
int sl_hair_parse_tfx(const unsigned char *d, size_t n, const char *name, sl_hair *out, sl_err *e);
int sl_hair_parse_usc(const unsigned char *d, size_t n, const char *name, sl_hair *out, sl_err *e);

/* Procedural hair: roots on a scalp-like cap of a sphere of radius SL_PROC_HEAD_RADIUS centred at
 * the origin (+Y up, face towards +Z left bare), strands draped under gravity around the head,
 * length about SL_PROC_LENGTH, radius SL_PROC_RADIUS. Deterministic for a given seed. */
#define SL_PROC_HEAD_RADIUS 10.0f
#define SL_PROC_LENGTH 25.0f
#define SL_PROC_RADIUS 0.04f
#define SL_PROC_MAX_STRANDS 2000000u
#define SL_PROC_MAX_POINTS 256u
enum { SL_PROC_STRAIGHT = 0, SL_PROC_WAVY = 1, SL_PROC_CURLY = 2 };
typedef struct sl_hair_procedural {
    int style; /* 0 straight 1 wavy 2 curly */
    uint32_t strands, points;
    uint32_t seed;
} sl_hair_procedural;
int sl_hair_generate(const sl_hair_procedural *p, sl_hair *out, sl_err *e);
/* "straight"/"wavy"/"curly" -> SL_PROC_*, -1 if unknown; and back. */
int sl_hair_style_from_name(const char *name);
const char *sl_hair_style_name(int style);

/* TressFX follow strands (AMD's viewer, TressFXAssetLoader::GenerateFollowHairs): each guide
 * gets per_guide offset copies. The offset is random in the plane normal to the guide's root
 * segment, uniform in the disc of radius root_radius, and at point k of n it is scaled by
 * 1 + tip_spread * k / (n - 1) (AMD divides by n; see docs/formats.md). Strands come out
 * guide-major (guide, its follows, next guide ...) as in AMD's viewer. Per-point arrays are
 * copied from the guide. per_guide = 0 changes nothing. */
#define SL_FOLLOW_MAX_PER_GUIDE 64
#define SL_HAIR_MAX_POINTS 400000000u /* 4.8 GB of positions: refuse rather than swap */
typedef struct sl_hair_follow {
    int per_guide;
    float root_radius, tip_spread;
    uint32_t seed;
} sl_hair_follow;
int sl_hair_add_follow(sl_hair *h, const sl_hair_follow *f, sl_err *e);

/* TressFX .tfxproj: `<file>.tfx <followPerGuide> <followRadius> <tipSeparation> <file>.tfxsim
 * <group>` lines (one per hair group) and `hairColor r g b`; other keys are ignored. */
#define SL_TFXPROJ_MAX_GROUPS 16
typedef struct sl_tfxproj_group {
    char tfx_path[4096]; /* resolved against the project's directory */
    char name[64];
    sl_hair_follow follow;
} sl_tfxproj_group;
typedef struct sl_tfxproj {
    int num_groups;
    sl_tfxproj_group groups[SL_TFXPROJ_MAX_GROUPS];
    int has_color;
    float hair_color[3];
} sl_tfxproj;
int sl_tfxproj_parse(const char *text, size_t len, const char *path, sl_tfxproj *p, sl_err *e);
int sl_tfxproj_read(const char *path, sl_tfxproj *p, sl_err *e);
/* The first group's follow settings and .tfx path (the optional helper of the API sketch). */
int sl_tfxproj_load(const char *path, sl_hair_follow *f, char *tfx_path, size_t n, sl_err *e);
/* Loads every group of a project into one sl_hair; with_follow adds each group's follow strands
 * (seed = 1 + group index). */
int sl_hair_load_tfxproj(const char *path, int with_follow, sl_hair *out, sl_err *e);

/* Geometry helpers. */
void sl_hair_z_up_to_y_up(sl_hair *h); /* (x, y, z) -> (x, z, -y): rotation by -90 deg about X */
void sl_hair_bounds(const sl_hair *h, float lo[3], float hi[3]); /* zeros when empty */
/* Unit direction of segment `seg` (points seg -> seg+1) of strand `strand`, always finite: a
 * segment shorter than a few float ulps of its coordinates (its direction would be rounding
 * noise) takes the nearest usable segment's direction along the strand, else +Y. */
void sl_hair_tangent(const sl_hair *h, uint32_t strand, uint32_t seg, float t[3]);
/* 1 when segment `seg` of `strand` has a usable direction of its own (see sl_hair_tangent). */
int sl_hair_segment_usable(const sl_hair *h, uint32_t strand, uint32_t seg);
/* Unit tangent at a point: the normalized sum of the adjacent segments' tangents (one segment at
 * the ends), always finite. */
void sl_hair_point_tangent(const sl_hair *h, uint32_t strand, uint32_t point, float t[3]);

/* Checks an sl_hair's invariants (offsets, >= 2 points, finite values, non-zero length, ranges);
 * used by every loader and the generator. Messages start with `name`. */
int sl_hair_validate(const sl_hair *h, const char *name, sl_err *e);

/* `strandlight info` for a hair file (.hair, .tfx, .tfxproj, .data). */
int sl_hair_info(const char *path, FILE *out, sl_err *e);
/* True when path looks like a hair file by extension. */
int sl_hair_is_hair_path(const char *path);

/* Small deterministic PRNG (splitmix64) for the generator and follow strands: no rand(). */
typedef struct sl_hair_rng {
    uint64_t s;
} sl_hair_rng;
static inline uint64_t sl_hair_rng_next(sl_hair_rng *r) {
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
/* Uniform in [0, 1) with 24 random bits (exactly representable as float). */
static inline float sl_hair_rng_float(sl_hair_rng *r) {
    return (float)(sl_hair_rng_next(r) >> 40) * (1.0f / 16777216.0f);
}

/* Internal helpers shared by the parsers (hair.c). */
/* Allocates strand_first (num_strands + 1) and pos (3 * num_points) and sets the counts. */
void sl_hair_alloc(sl_hair *h, uint32_t num_strands, uint32_t num_points);
/* Little-endian reads from an unaligned byte buffer (memcpy). */
uint32_t sl_rd_u32(const unsigned char *p);
float sl_rd_f32(const unsigned char *p);
/* Appends src's strands to dst (per-point arrays are materialized where only one side has
 * them and the defaults differ). */
int sl_hair_append(sl_hair *dst, const sl_hair *src, sl_err *e);
/* Sets default_radius = SL_HAIR_RADIUS_SCALE x bbox diagonal (radius_source ESTIMATED). */
void sl_hair_estimate_radius(sl_hair *h);

#endif
