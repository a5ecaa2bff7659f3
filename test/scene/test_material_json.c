/* test_material_json.c: material JSON parsing and validation (numerics.md sec. 2): defaults, the
 * TT/TRT rules of Xu Sec. 6, melanin (d'Eon Sec. 6.1), every error with its key path, and the
 * float conversion. Expected values are written out from the spec, never taken from the code. */
#include "scene/material.h"
#include "test.h"

#include <stdio.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)

static int parse(const char *json, sl_material *m, sl_err *e) {
    return sl_material_parse(json, strlen(json), "mat.json", m, e);
}

/* The text must fail with exactly this message. */
static void expect_fail(const char *json, const char *msg) {
    sl_material m;
    sl_err e = {{0}};
    int rc = parse(json, &m, &e);
    CHECK_MSG(rc == -1, "'%s' was accepted", json);
    CHECK_MSG(strcmp(e.msg, msg) == 0, "'%s': got '%s', want '%s'", json, e.msg, msg);
}

TEST(matjson_defaults) {
    sl_material m;
    sl_err e;
    CHECK(parse("{}", &m, &e) == 0);
    CHECK(m.model == SL_MODEL_MARSCHNER && m.fresnel == SL_FRESNEL_EXACT && m.orders == 8);
    /* exact decimal defaults of numerics.md sec. 2; 1e-15 is double rounding of deg->rad */
    CHECK_NEAR(m.eta, 1.55, 0);
    CHECK_NEAR(m.alpha[0], -7.5 * DEG, 1e-15);
    CHECK_NEAR(m.alpha[1], 3.75 * DEG, 1e-15);
    CHECK_NEAR(m.alpha[2], 11.25 * DEG, 1e-15);
    CHECK_NEAR(m.beta[0], 7.5 * DEG, 1e-15);
    CHECK_NEAR(m.beta[1], 3.75 * DEG, 1e-15);
    CHECK_NEAR(m.beta[2], 15 * DEG, 1e-15);
    CHECK(m.sigma_a[0] == 0.36 && m.sigma_a[1] == 0.36 && m.sigma_a[2] == 0.36);
    CHECK(!m.sigma_a_rgb);
    CHECK(m.eccentricity == 1.0);
    CHECK_NEAR(m.caustic_width, 15 * DEG, 1e-15);
}

TEST(matjson_all_keys) {
    sl_material m;
    sl_err e = {{0}};
    const char *j = "{\"model\":\"deon\",\"eta\":1.6,\"alpha_R_deg\":-4,\"beta_R_deg\":6,"
                    "\"alpha_TT_deg\":1,\"beta_TT_deg\":2,\"alpha_TRT_deg\":3,\"beta_TRT_deg\":9,"
                    "\"sigma_a\":[0.1,0.2,0.3],\"eccentricity\":0.9,\"caustic_width_deg\":10,"
                    "\"fresnel\":\"exact\",\"orders\":12}";
    CHECK_MSG(parse(j, &m, &e) == 0, "%s", e.msg);
    CHECK(m.model == SL_MODEL_DEON && m.orders == 12 && m.eta == 1.6);
    CHECK_NEAR(m.alpha[0], -4 * DEG, 1e-15);
    CHECK_NEAR(m.alpha[1], 1 * DEG, 1e-15);
    CHECK_NEAR(m.alpha[2], 3 * DEG, 1e-15);
    CHECK_NEAR(m.beta[0], 6 * DEG, 1e-15);
    CHECK_NEAR(m.beta[1], 2 * DEG, 1e-15);
    CHECK_NEAR(m.beta[2], 9 * DEG, 1e-15);
    CHECK(m.sigma_a[0] == 0.1 && m.sigma_a[1] == 0.2 && m.sigma_a[2] == 0.3 && m.sigma_a_rgb);
    CHECK(m.eccentricity == 0.9);
    CHECK_NEAR(m.caustic_width, 10 * DEG, 1e-15);
}

/* Xu 2011 Sec. 6: TT/TRT follow R unless given; an explicit one is kept. */
TEST(matjson_tt_trt_follow_r) {
    sl_material m;
    sl_err e;
    CHECK(parse("{\"alpha_R_deg\": 4, \"beta_R_deg\": 10}", &m, &e) == 0);
    CHECK_NEAR(m.alpha[1], -2 * DEG, 1e-15);
    CHECK_NEAR(m.alpha[2], -6 * DEG, 1e-15);
    CHECK_NEAR(m.beta[1], 5 * DEG, 1e-15);
    CHECK_NEAR(m.beta[2], 20 * DEG, 1e-15);
    CHECK(parse("{\"alpha_R_deg\": 4, \"beta_TRT_deg\": 3}", &m, &e) == 0);
    CHECK_NEAR(m.alpha[2], -6 * DEG, 1e-15);
    CHECK_NEAR(m.beta[2], 3 * DEG, 1e-15);
    CHECK_NEAR(m.beta[1], 3.75 * DEG, 1e-15); /* from the default beta_R */
}

TEST(matjson_melanin) {
    sl_material m;
    sl_err e;
    CHECK(parse("{\"melanin\": {\"eumelanin\": 2, \"pheomelanin\": 0.5}}", &m, &e) == 0);
    /* d'Eon 2011 Sec. 6.1: 2*(0.419,0.697,1.37) + 0.5*(0.187,0.4,1.05) */
    CHECK_NEAR(m.sigma_a[0], 0.9315, 1e-15);
    CHECK_NEAR(m.sigma_a[1], 1.594, 1e-15);
    CHECK_NEAR(m.sigma_a[2], 3.265, 1e-15);
    CHECK(m.sigma_a_rgb);
    CHECK(parse("{\"melanin\": {\"pheomelanin\": 1}}", &m, &e) == 0);
    CHECK_NEAR(m.sigma_a[2], 1.05, 1e-15);
    CHECK(parse("{\"sigma_a\": 0.5}", &m, &e) == 0);
    CHECK(m.sigma_a[0] == 0.5 && m.sigma_a[2] == 0.5 && !m.sigma_a_rgb);
}

TEST(matjson_errors) {
    expect_fail("{\"beta_R_deg\": 0}", "mat.json: beta_R_deg: must be > 0");
    expect_fail("{\"beta_TT_deg\": -1}", "mat.json: beta_TT_deg: must be > 0");
    expect_fail("{\"beta_TRT_deg\": 0}", "mat.json: beta_TRT_deg: must be > 0");
    expect_fail("{\"eta\": 1}", "mat.json: eta: must be > 1");
    expect_fail("{\"eta\": \"1.5\"}", "mat.json: eta: expected a number");
    expect_fail("{\"eta\": true}", "mat.json: eta: expected a number");
    expect_fail("{\"eta\": 1e999}", "mat.json: eta: must be a finite number");
    expect_fail("{\"alpha_R_deg\": -1e999}", "mat.json: alpha_R_deg: must be a finite number");
    expect_fail("{\"sigma_a\": -0.1}", "mat.json: sigma_a: must be >= 0");
    expect_fail("{\"sigma_a\": [0.1, -0.2, 0.3]}", "mat.json: sigma_a[1]: must be >= 0");
    expect_fail("{\"sigma_a\": [0.1, 0.2]}",
                "mat.json: sigma_a: expected a number or an array of 3 numbers [r, g, b]");
    expect_fail("{\"sigma_a\": [0.1, \"x\", 0.2]}", "mat.json: sigma_a[1]: expected a number");
    expect_fail("{\"sigma_a\": 0.2, \"melanin\": {\"eumelanin\": 1}}",
                "mat.json: melanin: cannot be given together with sigma_a (choose one)");
    expect_fail("{\"melanin\": {\"eumelanin\": -1}}", "mat.json: melanin.eumelanin: must be >= 0");
    expect_fail("{\"melanin\": {\"blonde\": 1}}", "mat.json: melanin.blonde: unknown key");
    expect_fail("{\"melanin\": 3}", "mat.json: melanin: expected an object");
    expect_fail("{\"eccentricity\": 0}", "mat.json: eccentricity: must be > 0");
    expect_fail("{\"caustic_width_deg\": 0}", "mat.json: caustic_width_deg: must be > 0");
    expect_fail("{\"orders\": 1}", "mat.json: orders: must be an integer >= 2");
    expect_fail("{\"orders\": 2.5}", "mat.json: orders: must be an integer >= 2");
    expect_fail("{\"orders\": 257}",
                "mat.json: orders: must be at most 256 (the float backends allow at most 32; the "
                "orders above are still counted, in f_rest)");
    expect_fail("{\"model\": \"kajiya\"}", "mat.json: model: expected \"marschner\" or \"deon\"");
    expect_fail("{\"fresnel\": 1}", "mat.json: fresnel: expected \"exact\" or \"schlick\"");
    expect_fail("{\"model\": \"deon\", \"fresnel\": \"schlick\"}",
                "mat.json: fresnel: \"schlick\" is not allowed with model \"deon\" (d'Eon always "
                "uses exact Fresnel)");
    expect_fail("{\"fresnel\": \"schlick\", \"model\": \"deon\"}",
                "mat.json: fresnel: \"schlick\" is not allowed with model \"deon\" (d'Eon always "
                "uses exact Fresnel)");
    expect_fail("{\"etaa\": 1.5}", "mat.json: etaa: unknown key");
    expect_fail("{\"eta\": 1.5, \"eta\": 1.6}", "mat.json: eta: duplicate key");
    expect_fail("[1, 2]", "mat.json: expected a JSON object at the top level");
}

TEST(matjson_invalid_json_line) {
    expect_fail("{\n  \"eta\": 1.5,\n  \"beta_R_deg\": ,\n}", "mat.json: invalid JSON near line 3");
    expect_fail("", "mat.json: invalid JSON near line 1");
    expect_fail("{\"eta\": NaN}", "mat.json: invalid JSON near line 1");
    expect_fail("{}\n\nx", "mat.json: invalid JSON near line 3 (text after the object)");
    sl_material m;
    sl_err e;
    CHECK(parse("{}\n\n  \n", &m, &e) == 0); /* trailing whitespace is fine */
}

/* The scene loader's form: errors carry the "material." key prefix. */
TEST(matjson_key_prefix) {
    cJSON *o = cJSON_Parse("{\"eta\": 0.9}");
    sl_material m;
    sl_err e = {{0}};
    CHECK(sl_material_from_json(o, "scene.json", "material", &m, &e) == -1);
    CHECK_MSG(strcmp(e.msg, "scene.json: material.eta: must be > 1") == 0, "%s", e.msg);
    cJSON_Delete(o);
    o = cJSON_Parse("{\"melanin\": {\"pheomelanin\": -2}}");
    CHECK(sl_material_from_json(o, "scene.json", "material", &m, &e) == -1);
    CHECK_MSG(strcmp(e.msg, "scene.json: material.melanin.pheomelanin: must be >= 0") == 0, "%s",
              e.msg);
    cJSON_Delete(o);
    o = cJSON_Parse("7");
    CHECK(sl_material_from_json(o, "scene.json", "material", &m, &e) == -1);
    CHECK_MSG(strcmp(e.msg, "scene.json: material: expected an object") == 0, "%s", e.msg);
    cJSON_Delete(o);
}

TEST(matjson_load_file) {
    char path[4200];
    snprintf(path, sizeof path, "%s/mat_ok.json", sl_test_tmpdir());
    FILE *fp = fopen(path, "w");
    CHECK(fp != NULL);
    if (!fp) return;
    fputs("{\"eta\": 1.7, \"sigma_a\": [0, 1, 2]}\n", fp);
    fclose(fp);
    sl_material m;
    sl_err e = {{0}};
    CHECK_MSG(sl_material_load(path, &m, &e) == 0, "%s", e.msg);
    CHECK(m.eta == 1.7 && m.sigma_a[2] == 2);
    snprintf(path, sizeof path, "%s/does_not_exist.json", sl_test_tmpdir());
    CHECK(sl_material_load(path, &m, &e) == -1);
    CHECK_MSG(strstr(e.msg, "does_not_exist.json") != NULL, "%s", e.msg);
}

TEST(matjson_to_fiber) {
    sl_material m;
    sl_err e;
    CHECK(parse("{\"model\":\"deon\",\"orders\":5,\"sigma_a\":[0.25,0.5,2]}", &m, &e) == 0);
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 2, &fp);
    CHECK(fp.model == 1 && fp.orders == 5 && fp.fresnel == 0);
    CHECK(fp.sigma_a == 2.0f);
    CHECK(fp.eta == 1.55f);
    CHECK(fp.alpha[0] == (float)(-7.5 * DEG) && fp.beta[2] == (float)(15 * DEG));
    CHECK(fp.caustic_width == (float)(15 * DEG) && fp.eccentricity == 1.0f);
    sl_material_to_fiber(&m, 1, &fp);
    CHECK(fp.sigma_a == 0.5f);
}
