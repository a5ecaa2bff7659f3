/* test_scene.c: scene-file validation (scene.md): defaults, path resolution, and an error that
 * names the file and the key path for each kind of mistake. */
#include "scene/scene.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

static int parse(const char *text, sl_scene *s, sl_err *e) {
    return sl_scene_parse(text, strlen(text), "dir/scene.json", s, e);
}

static const char *MINIMAL = "{\"hair\":{\"procedural\":{\"style\":\"curly\",\"strands\":10}},"
                             "\"environment\":{\"file\":\"maps/a.hdr\"}}";

TEST(scene_minimal_defaults_and_paths) {
    sl_scene *s = calloc(1, sizeof *s);
    sl_err e;
    CHECK(parse(MINIMAL, s, &e) == 0);
    CHECK(s->hair_procedural && s->proc_style == 2 && s->proc_strands == 10);
    CHECK(strcmp(s->env_file, "dir/maps/a.hdr") == 0);
    CHECK(s->width == 720 && s->height == 480 && s->lobes == 40 && !s->has_eye);
    CHECK_NEAR(s->material.eta, 1.55, 0);
    free(s);
}

TEST(scene_full_example_parses) {
    const char *text =
        "{\"hair\":{\"file\":\"models/straight.hair\",\"up\":\"z\",\"radius\":0.05,"
        "\"tfx_follow\":{\"per_guide\":4,\"root_radius\":0.4,\"tip_spread\":5.0}},"
        "\"material\":{\"eta\":1.6},"
        "\"environment\":{\"file\":\"maps/forest.hdr\",\"lobes\":\"/abs/f.lobes.json\","
        "\"rotation_deg\":30,\"intensity\":2},"
        "\"camera\":{\"eye\":[0,0,120],\"target\":[0,0,0],\"up\":[0,1,0],\"fov_deg\":30},"
        "\"image\":{\"width\":64,\"height\":32},"
        "\"quality\":{\"lobes\":40,\"layers\":4,\"segments_m\":4,\"kappa\":0.5,\"voxels\":64,"
        "\"multiple_scattering\":\"off\",\"oit_layers\":8,\"shading_rate\":\"auto\","
        "\"shadow_size\":256},"
        "\"output\":{\"exr\":\"out/frame.exr\",\"png\":\"out/frame.png\",\"aovs\":[\"R\",\"TT\"]}}";
    sl_scene *s = calloc(1, sizeof *s);
    sl_err e = {{0}};
    int rc = parse(text, s, &e);
    CHECK_MSG(rc == 0, "%s", e.msg);
    CHECK(strcmp(s->hair_file, "dir/models/straight.hair") == 0 && s->up_z);
    CHECK(strcmp(s->env_lobes, "/abs/f.lobes.json") == 0);
    CHECK(s->has_eye && s->eye[2] == 120 && s->has_follow && s->follow_per_guide == 4);
    CHECK(s->multiple_scattering == SL_MS_OFF && s->num_aovs == 2 && s->shadow_size == 256);
    CHECK_NEAR(s->material.eta, 1.6, 0);
    CHECK(strcmp(s->out_exr, "dir/out/frame.exr") == 0);
    free(s);
}

/* Each bad scene must fail with exactly this message (file + key path + problem). */
TEST(scene_errors_name_file_and_key) {
    static const struct {
        const char *text, *msg;
    } cases[] = {
        {"{", "dir/scene.json: invalid JSON near line 1"},
        {"[]", "dir/scene.json: expected a JSON object at the top level"},
        {"{}\n\n x", "dir/scene.json: invalid JSON near line 3"},
        {"{\"environment\":{\"file\":\"a.hdr\"}}", "dir/scene.json: hair: missing"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},\"colour\":1}",
         "dir/scene.json: colour: unknown key"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"camera\":{\"fov_deg\":\"wide\"}}",
         "dir/scene.json: camera.fov_deg: expected a number"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"camera\":{\"eye\":[0,0]}}",
         "dir/scene.json: camera.eye: expected an array of 3 numbers"},
        {"{\"hair\":{\"file\":\"a.hair\",\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"}}",
         "dir/scene.json: hair: give exactly one of 'file' and 'procedural'"},
        {"{\"hair\":{\"procedural\":{\"style\":\"frizzy\"}},\"environment\":{\"file\":\"a.hdr\"}}",
         "dir/scene.json: hair.procedural.style: expected \"straight\", \"wavy\" or \"curly\""},
        {"{\"hair\":{\"procedural\":{\"strands\":1.5}},\"environment\":{\"file\":\"a.hdr\"}}",
         "dir/scene.json: hair.procedural.strands: expected an integer"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{}}",
         "dir/scene.json: environment: give 'file' and/or 'lobes'"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"image\":{\"width\":0}}",
         "dir/scene.json: image.width: must be in [1, 16384]"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"quality\":{\"multiple_scattering\":\"maybe\"}}",
         "dir/scene.json: quality.multiple_scattering: expected \"on\", \"off\" or \"auto\""},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"quality\":{\"shadow_size\":8}}",
         "dir/scene.json: quality.shadow_size: must be in [16, 8192]"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"quality\":{\"shading_refine\":1.01}}",
         "dir/scene.json: quality.shading_refine: must be 0 (off) or in [1.05, 1000]"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"quality\":{\"sharp_shadows\":3}}",
         "dir/scene.json: quality.sharp_shadows: must be in [0, 2]"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"output\":{\"aovs\":[\"R\",\"XYZ\"]}}",
         "dir/scene.json: output.aovs[1]: unknown AOV \"XYZ\" (known: R TT TRT MS depth shadow "
         "lobes alpha)"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"camera\":{\"eye\":[0,0,5],\"target\":[0,0,5]}}",
         "dir/scene.json: camera.eye: must differ from camera.target"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"material\":{\"eta\":0.9}}",
         "dir/scene.json: material.eta"},
        /* duplicate keys: cJSON would keep the first, Python and JavaScript the last */
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"quality\":{\"lobes\":4,\"layers\":4,\"lobes\":8}}",
         "dir/scene.json: quality.lobes: duplicate key"},
        {"{\"hair\":{\"procedural\":{}},\"hair\":{\"procedural\":{}},"
         "\"environment\":{\"file\":\"a.hdr\"}}",
         "dir/scene.json: hair: duplicate key"},
        {"{\"hair\":{\"procedural\":{}},\"environment\":{\"file\":\"a.hdr\"},"
         "\"x\":[1,{\"a\":1,\"a\":2}]}",
         "dir/scene.json: x[1].a: duplicate key"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sl_scene *s = calloc(1, sizeof *s);
        sl_err e = {{0}};
        int rc = parse(cases[i].text, s, &e);
        CHECK_MSG(rc == -1, "case %zu accepted", i);
        CHECK_MSG(strncmp(e.msg, cases[i].msg, strlen(cases[i].msg)) == 0,
                  "case %zu: got '%s', want '%s'", i, e.msg, cases[i].msg);
        free(s);
    }
}
