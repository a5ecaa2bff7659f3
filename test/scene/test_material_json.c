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
    /* positive, but 0 once in radians (found by fuzz_material: it was accepted with beta 0) */
    expect_fail("{\"beta_TT_deg\": 1e-323}", "mat.json: beta_TT_deg: must be > 0 (too small)");
    expect_fail("{\"model\": \"chiang\", \"roughness\": 1e-300}",
                "mat.json: roughness: too small (the longitudinal variance underflows to 0)");
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
    expect_fail("{\"model\": \"kajiya\"}",
                "mat.json: model: expected \"marschner\", \"deon\" or \"chiang\"");
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

/* Cycles' Principled Hair mappings (numerics.md sec. 3), values computed by hand:
 *  melanin 0.5, redness 0.3: q = -ln(1 - 0.5) = 0.693147181, eumelanin q 0.7 = 0.485203026,
 *  pheomelanin q 0.3 = 0.207944154, sigma_a = eu (0.506, 0.841, 1.653) + pheo (0.343, 0.733,
 *  1.924) = (0.245512731 + 0.071324845, 0.408055745 + 0.152423065, 0.802040603 + 0.400084552)
 *  = (0.316837576, 0.560478810, 1.202125155);
 *  a tint of 0.5 (red) at radial roughness 0.3: 5.969 - 0.215 (0.3) + 2.532 (0.09) - 10.73 (0.027)
 *  + 5.574 (0.0081) + 0.245 (0.00243) = 5.88841475, (ln 0.5 / 5.88841475)^2 = 0.0138565189;
 *  roughness 0.3: 0.726 (0.3) + 0.812 (0.09) + 3.7 (0.3^20 = 3.49e-11) = 0.290880000129,
 *  v = 0.0846111745 (TT v/4 = 0.0211527936, TRT 4v = 0.338444698);
 *  radial roughness 0.3: sqrt(pi/8) (0.265 (0.3) + 1.194 (0.09) + 5.372 (0.3^22 = 3.1e-12))
 *  = 0.626657069 (0.18696) = 0.117159806;
 *  coat 0.9: R's roughness 0.3 (1 - 0.9) = 0.03: (0.0217800 + 0.000730800)^2 = 0.000506736;
 *  melanin 1 is clamped: q = -ln(1e-4) = 9.21034037. */
TEST(matjson_chiang_mappings) {
    sl_chiang c;
    memset(&c, 0, sizeof c);
    c.melanin = 0.5;
    c.melanin_redness = 0.3;
    c.tint[0] = c.tint[1] = c.tint[2] = 1.0;
    c.radial_roughness = 0.3;
    double sa[3];
    sl_chiang_sigma_a_rgb(&c, sa);
    CHECK_NEAR(sa[0], 0.316837576, 1e-9);
    CHECK_NEAR(sa[1], 0.560478810, 1e-9);
    CHECK_NEAR(sa[2], 1.202125155, 1e-9);
    c.tint[0] = 0.5;
    sl_chiang_sigma_a_rgb(&c, sa);
    CHECK_NEAR(sa[0], 0.316837576 + 0.0138565189, 1e-9);
    CHECK_NEAR(sa[1], 0.560478810, 1e-9);
    c.tint[0] = 1.0;
    c.melanin = 1.0;
    c.melanin_redness = 0.0;
    sl_chiang_sigma_a_rgb(&c, sa);
    CHECK_NEAR(sa[0], 9.21034037 * 0.506, 1e-7);
    CHECK_NEAR(sl_chiang_variance(0.3), 0.0846111745, 1e-10);
    CHECK_NEAR(sl_chiang_variance(0.03), 0.000506736, 1e-9);
    CHECK_NEAR(sl_chiang_logistic_scale(0.3), 0.117159806, 1e-9);
    /* radial roughness 1: sqrt(pi/8) (0.265 + 1.194 + 5.372) = 0.626657069 (6.831) = 4.28069444 */
    CHECK_NEAR(sl_chiang_logistic_scale(1.0), 4.28069444, 1e-8);
}

/* The derived fields of a parsed chiang material: lobes in d'Eon form (theta_o - 2 alpha[p]:
 * R shifted by -2 offset, TT by +offset, TRT by +4 offset), v_p = beta[p]^2, s, orders 2,
 * sigma_a from melanin (rgb) unless given. */
TEST(matjson_chiang_derived) {
    sl_material m;
    sl_err e = {{0}};
    CHECK_MSG(parse("{\"model\": \"chiang\", \"melanin\": 0.5, \"melanin_redness\": 0.3, "
                    "\"coat\": 0.9, \"offset_deg\": -5}",
                    &m, &e) == 0,
              "%s", e.msg);
    CHECK(m.model == SL_MODEL_CHIANG && m.orders == 2 && m.sigma_a_rgb);
    CHECK(m.fresnel == SL_FRESNEL_EXACT && m.eta == 1.55);
    CHECK_NEAR(m.alpha[0], -5 * DEG, 1e-15);
    CHECK_NEAR(m.alpha[1], 2.5 * DEG, 1e-15);
    CHECK_NEAR(m.alpha[2], 10 * DEG, 1e-15);
    CHECK_NEAR(m.beta[0] * m.beta[0], 0.000506736, 1e-9);
    CHECK_NEAR(m.beta[1] * m.beta[1], 0.0211527936, 1e-10);
    CHECK_NEAR(m.beta[2] * m.beta[2], 0.338444698, 1e-9);
    CHECK_NEAR(m.logistic_s, 0.117159806, 1e-9);
    CHECK_NEAR(m.sigma_a[2], 1.202125155, 1e-9);
    /* defaults: melanin 0.8, redness 1 (pheomelanin only: q = ln 5 = 1.60943791), offset 2 deg */
    CHECK(parse("{\"model\": \"chiang\"}", &m, &e) == 0);
    CHECK_NEAR(m.sigma_a[0], 1.60943791 * 0.343, 1e-8);
    CHECK_NEAR(m.alpha[0], 2 * DEG, 1e-15);
    CHECK(parse("{\"model\": \"chiang\", \"sigma_a\": 0.7}", &m, &e) == 0);
    CHECK(!m.sigma_a_rgb && m.sigma_a[0] == 0.7 && m.sigma_a[2] == 0.7);
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    CHECK(fp.model == 2 && fp.orders == 2);
    CHECK_NEAR(fp.logistic_s, 0.117159806, 1e-7);
}

TEST(matjson_chiang_errors) {
    expect_fail("{\"model\": \"chiang\", \"melanin_red\": 1}",
                "mat.json: melanin_red: unknown key");
    expect_fail("{\"model\": \"chiang\", \"melanin\": 1.5}",
                "mat.json: melanin: must be in [0, 1]");
    expect_fail("{\"model\": \"chiang\", \"melanin_redness\": -0.1}",
                "mat.json: melanin_redness: must be in [0, 1]");
    expect_fail("{\"model\": \"chiang\", \"roughness\": 0}",
                "mat.json: roughness: must be in (0, 1]");
    expect_fail("{\"model\": \"chiang\", \"radial_roughness\": 1.2}",
                "mat.json: radial_roughness: must be in (0, 1]");
    expect_fail("{\"model\": \"chiang\", \"coat\": 1}", "mat.json: coat: must be in [0, 1)");
    expect_fail("{\"model\": \"chiang\", \"offset_deg\": 50}",
                "mat.json: offset_deg: must be in [-45, 45]");
    expect_fail("{\"model\": \"chiang\", \"tint\": [1, 0, 1]}",
                "mat.json: tint[1]: must be in (0, 1]");
    expect_fail("{\"model\": \"chiang\", \"tint\": [1, 1]}",
                "mat.json: tint: expected an array of 3 numbers [r, g, b] in (0, 1]");
    expect_fail("{\"model\": \"chiang\", \"roughness\": \"a\"}",
                "mat.json: roughness: expected a number");
    expect_fail("{\"model\": \"chiang\", \"eta\": 1}", "mat.json: eta: must be > 1");
    expect_fail("{\"model\": \"chiang\", \"sigma_a\": 1, \"melanin\": 0.5}",
                "mat.json: melanin: cannot be given together with sigma_a (choose one)");
    expect_fail("{\"model\": \"chiang\", \"sigma_a\": 1, \"tint\": [1, 1, 1]}",
                "mat.json: tint: cannot be given together with sigma_a (choose one)");
    expect_fail("{\"model\": \"chiang\", \"melanin\": {\"eumelanin\": 1}}",
                "mat.json: melanin: expected a number in [0, 1] with model \"chiang\" (the "
                "eumelanin / pheomelanin object is for marschner and deon)");
    expect_fail("{\"model\": \"chiang\", \"alpha_R_deg\": 3}",
                "mat.json: alpha_R_deg: not a key of model \"chiang\" (its keys: melanin, "
                "melanin_redness, tint, roughness, radial_roughness, coat, offset_deg, eta, "
                "sigma_a)");
    expect_fail("{\"model\": \"deon\", \"coat\": 0.5}",
                "mat.json: coat: is a key of model \"chiang\" only");
    expect_fail("{\"radial_roughness\": 0.5}",
                "mat.json: radial_roughness: is a key of model \"chiang\" only");
}
