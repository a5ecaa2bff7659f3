/* test_envfit_json.c: the lobes JSON reader/writer (numerics.md sec. 4 layout). */
#include "lighting/lobes_json.h"
#include "test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int parse(const char *txt, sl_lobes *l, sl_err *e) {
    return sl_lobes_parse(txt, strlen(txt), "t.json", l, e);
}

TEST(lobes_json_round_trip) {
    sl_lobe lb[2] = {{{0, 1, 0}, 0.25, {1.5, 2.5, 3.5}},
                     {{0.6, 0, -0.8}, 0.003125, {30000, 1e-7, 0}}};
    sl_lobes l = {2,  lb, "{\"map_hash\":\"00ff\",\"rel_l2\":0.125,\"settings\":{\"lobes\":2}}",
                  "", 0,  0};
    char path[4096];
    snprintf(path, sizeof path, "%s/lobes_rt.json", sl_test_tmpdir());
    sl_err e;
    CHECK(sl_lobes_save(path, &l, &e) == 0);
    sl_lobes r;
    CHECK(sl_lobes_load(path, &r, &e) == 0);
    CHECK(r.count == 2);
    for (int j = 0; j < 2 && r.count == 2; j++) {
        for (int k = 0; k < 3; k++)
            CHECK(r.lobe[j].dir[k] == lb[j].dir[k]); /* %.17g: exact */
        CHECK(r.lobe[j].lambda == lb[j].lambda);
        for (int k = 0; k < 3; k++)
            CHECK_REL(r.lobe[j].rgb[k], lb[j].rgb[k], 1e-8); /* %.9g */
    }
    CHECK(strcmp(r.map_hash, "00ff") == 0);
    CHECK(r.rel_l2 == 0.125);
    CHECK(r.fit_json && strstr(r.fit_json, "\"settings\""));
    sl_lobes_free(&r);
}

TEST(lobes_json_errors_name_the_key) {
    struct {
        const char *txt, *want;
    } cs[] = {
        {"[1,2]", "t.json: expected a JSON object"},
        {"{\"lobes\": []}", "lobes: expected at least one lobe"},
        {"{\"fit\": {}}", "lobes: missing"},
        {"{\"lobes\": [{\"dir\": [0,1,0], \"lambda\": 0.1, \"rgb\": [1,1,1], \"x\": 1}]}",
         "lobes[0].x: unknown key"},
        {"{\"lobes\": [{\"dir\": [0,2,0], \"lambda\": 0.1, \"rgb\": [1,1,1]}]}",
         "lobes[0].dir: expected a unit vector"},
        {"{\"lobes\": [{\"dir\": [0,1,0], \"lambda\": 0.1, \"rgb\": [1,1,1]}, {\"dir\": [0,1,0], "
         "\"lambda\": 0, \"rgb\": [1,1,1]}]}",
         "lobes[1].lambda: expected a positive number"},
        {"{\"lobes\": [{\"dir\": [0,1,0], \"lambda\": 0.1, \"rgb\": [1,-1,1]}]}",
         "lobes[0].rgb[1]: expected a finite number >= 0"},
        {"{\"lobes\": [{\"dir\": [0,1], \"lambda\": 0.1, \"rgb\": [1,1,1]}]}",
         "lobes[0].dir: expected an array of 3 numbers"},
        {"{\"lobes\": [{\"lambda\": 0.1, \"rgb\": [1,1,1]}]}", "lobes[0].dir: missing"},
        {"{\"lobes\": [\n{\"dir\": [0,1,0] \"lambda\": 0.1}]}", "invalid JSON near line 2"},
        {"{\"lobes\": [{\"dir\": [0,1,0], \"lambda\": 0.1, \"rgb\": [1,1,1]}], \"fit\": 3}",
         "fit: expected an object"},
    };
    for (size_t i = 0; i < sizeof cs / sizeof cs[0]; i++) {
        sl_lobes l;
        sl_err e = {{0}};
        CHECK_MSG(parse(cs[i].txt, &l, &e) == -1, "case %zu accepted", i);
        CHECK_MSG(strstr(e.msg, cs[i].want) != NULL, "case %zu: '%s' lacks '%s'", i, e.msg,
                  cs[i].want);
        CHECK(strchr(e.msg, '\n') == NULL);
    }
    /* A nearly unit dir (printing round-off) is normalised, not rejected. */
    sl_lobes l;
    sl_err e;
    CHECK(parse("{\"lobes\": [{\"dir\": [0, 1.0004, 0], \"lambda\": 0.1, \"rgb\": [1,1,1]}]}", &l,
                &e) == 0);
    CHECK(l.count == 1 && l.lobe[0].dir[1] == 1.0);
    CHECK(l.rel_l2 == -1 && l.fit_json == NULL);
    sl_lobes_free(&l);
    CHECK(sl_lobes_load("/nonexistent/lobes.json", &l, &e) == -1);
    CHECK(strstr(e.msg, "/nonexistent/lobes.json") != NULL);
}

TEST(lobes_json_integral) {
    /* pi l^2 (1 - exp(-4/l^2)); broad limit 4 pi (1 - ...) -> as lambda grows, 4 pi. */
    CHECK_REL(sl_lobe_integral(0.1), M_PI * 0.01, 1e-12);
    CHECK_REL(sl_lobe_integral(1.0), M_PI * (1 - exp(-4.0)), 1e-12);
    CHECK_REL(sl_lobe_integral(1e4), 4 * M_PI, 1e-6);
}

/* The lobe integral stays finite at both ends of the double range (a lobes file may say
 * "lambda": 1e308): broad lobes tend to 4 pi, narrow ones to pi lambda^2. */
TEST(lobes_integral_extreme_lambda) {
    CHECK_REL(sl_lobe_integral(1e308), 4 * M_PI, 1e-12);
    CHECK_REL(sl_lobe_integral(1e6), 4 * M_PI * (1 - 2e-12), 1e-12);
    CHECK_REL(sl_lobe_integral(2.0), M_PI * 4 * (1 - exp(-1.0)), 1e-12);
    CHECK_REL(sl_lobe_integral(1e-150), M_PI * 1e-300, 1e-12);
}
