/**
 * @file test_replay_params.c
 * @brief Tests of the parameter files of host_sim and replay (host_sim/replay/params.h): a written
 *        file reads back to the same configuration, and every kind of bad file is an error
 *        naming the file, the line and the key. Built for the double and the float application.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app.h"
#include "ekf.h"
#include "params.h"
#include "tv_status.h"
#include "tv_test.h"

static params_t s_p;
static char s_err[PARAMS_MSG_MAX];

/* Parse text as file "p.txt"; returns the status, message in s_err. */
static int parse(const char *text)
{
    params_init(&s_p, "p.txt");
    s_err[0] = '\0';
    return params_parse_text(&s_p, text, strlen(text), s_err, sizeof s_err);
}

static int has(const char *want)
{
    if (strstr(s_err, want) == NULL) {
        fprintf(stderr, "message '%s' lacks '%s'\n", s_err, want);
        return 0;
    }
    return 1;
}

/* Write text to a temporary file; path in out. */
static int temp_file(const char *text, size_t n, char *out, size_t cap)
{
    int fd;
    FILE *f;
    (void)snprintf(out, cap, "/tmp/tv_params_XXXXXX");
    fd = mkstemp(out);
    if (fd < 0) {
        return -1;
    }
    f = fdopen(fd, "wb");
    if (f == NULL) {
        (void)close(fd);
        return -1;
    }
    (void)fwrite(text, 1u, n, f);
    return fclose(f);
}

/* params_write() of c into buf (NUL-terminated); 0 on success, -1 when the temporary file failed. */
static int write_config(const app_config_t *c, char *buf, size_t cap)
{
    FILE *f = tmpfile();
    size_t n;
    int rc;
    if (f == NULL) {
        return -1;
    }
    rc = params_write(f, c);
    rewind(f);
    n = fread(buf, 1u, cap - 1u, f);
    buf[n] = '\0';
    (void)fclose(f);
    return rc == TV_OK ? 0 : -1;
}

static void test_written_defaults_read_back_to_the_same_configuration(void)
{
    app_config_t def;
    app_config_t got;
    char path[64];
    static char text[16384];
    app_config_default(&def);
    TV_CHECK(write_config(&def, text, sizeof text) == 0);
    TV_CHECK(temp_file(text, strlen(text), path, sizeof path) == 0);
    params_init(&s_p, path);
    TV_CHECK_EQ_INT(params_load(&s_p, path, s_err, sizeof s_err), TV_OK);
    (void)remove(path);
    got = def;
    memset(&got.model, 0, sizeof got.model); /* every model key comes from the file ... */
    got.model.Ts_s = def.model.Ts_s;         /* ... except the period, which is not a parameter */
    memset(&got.calib, 0, sizeof got.calib);
    got.calib.adc_max_counts = def.calib.adc_max_counts;
    TV_CHECK_EQ_INT(params_apply(&s_p, &got, s_err, sizeof s_err), TV_OK);
    /* %.17g of every value: the same bits (both builds); Q recomputed from the same inputs */
    TV_CHECK(memcmp(&got.model, &def.model, sizeof def.model) == 0);
    TV_CHECK(memcmp(&got.calib, &def.calib, sizeof def.calib) == 0);
    TV_CHECK(memcmp(&got.limits, &def.limits, sizeof def.limits) == 0);
    TV_CHECK(memcmp(got.ekf.Q, def.ekf.Q, sizeof def.ekf.Q) == 0);
    TV_CHECK(memcmp(got.ekf.r, def.ekf.r, sizeof def.ekf.r) == 0);
    TV_CHECK_EQ_INT(params_is_set(&s_p, "model.R_ohm"), 1);
}

static void test_values_comments_and_q_recomputation(void)
{
    app_config_t c;
    tv_real_t Q[TVM_NX][TVM_NX];
    TV_CHECK_EQ_INT(parse("# a comment\n\n  model.L_H = 0.003   # trailing comment\r\n"
                          "ekf.qu_V2_s=1e-5\nekf.r_angle_rad2 = 4e-8\nlimits.debounce_trip = 3\n"),
                    TV_OK);
    app_config_default(&c);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK(c.model.L_H == (tv_real_t)0.003 && c.ekf.r[EKF_CH_ANGLE] == (tv_real_t)4e-8 && c.limits.debounce_trip == 3u);
    TV_CHECK_EQ_INT(ekf_q_from_spectral(&c.model, (tv_real_t)1e-5, EKF_DEFAULT_QT_NM2_S, Q), TV_OK);
    TV_CHECK(memcmp(Q, c.ekf.Q, sizeof Q) == 0); /* Q follows the new L and qu */
    /* command-line overrides replace a file's value */
    TV_CHECK_EQ_INT(params_set(&s_p, "ekf.r_angle_rad2", 9e-8, s_err, sizeof s_err), TV_OK);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK(c.ekf.r[EKF_CH_ANGLE] == (tv_real_t)9e-8);
    TV_CHECK_EQ_INT(params_set(&s_p, "ekf.r_angle_rad2", -1.0, s_err, sizeof s_err), TV_ERR_RANGE);
    TV_CHECK(has("command line: ekf.r_angle_rad2 = -1 is out of range"));
    TV_CHECK_EQ_INT(params_set(&s_p, "nope", 1.0, s_err, sizeof s_err), TV_ERR_FORMAT);
}

/* A model-only file applied on top of one that set the densities (population --params, then
 * identify's file of the unit) rebuilds Q from those densities, not from the defaults, and
 * params_write() writes the densities in force: before, the first file's qu and qT were lost
 * without a word, and the written file named them while the filter ran the defaults. */
static void test_densities_survive_a_later_model_file(void)
{
    app_config_t c;
    tv_real_t Q[TVM_NX][TVM_NX];
    char buf[16384];
    app_config_default(&c);
    TV_CHECK_EQ_INT(parse("ekf.qu_V2_s = 1e-6\nekf.qT_Nm2_s = 2e-6\n"), TV_OK);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK_EQ_INT(parse("model.R_ohm = 5\nmodel.J_kg_m2 = 0.002\n"), TV_OK);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK(c.model.R_ohm == (tv_real_t)5.0 && c.model.J_kg_m2 == (tv_real_t)0.002);
    TV_CHECK_EQ_INT(ekf_q_from_spectral(&c.model, (tv_real_t)1e-6, (tv_real_t)2e-6, Q), TV_OK);
    TV_CHECK(memcmp(Q, c.ekf.Q, sizeof Q) == 0);
    TV_CHECK(c.ekf.qu_V2_s == (tv_real_t)1e-6 && c.ekf.qT_Nm2_s == (tv_real_t)2e-6);
    /* the written file reads back to the same densities and Q */
    TV_CHECK_EQ_INT(write_config(&c, buf, sizeof buf), 0);
    TV_CHECK_EQ_INT(parse(buf), TV_OK);
    {
        app_config_t back;
        app_config_default(&back);
        TV_CHECK_EQ_INT(params_apply(&s_p, &back, s_err, sizeof s_err), TV_OK);
        TV_CHECK(back.ekf.qu_V2_s == c.ekf.qu_V2_s && back.ekf.qT_Nm2_s == c.ekf.qT_Nm2_s);
        TV_CHECK(memcmp(back.ekf.Q, c.ekf.Q, sizeof Q) == 0);
    }
}

/* diag.identified = 1 (what identify writes) puts the bounds of diag_detect_config_identified() in
 * force, = 0 the class's; the written file says which; anything but 0 or 1 is refused. The bound
 * values are written out here (diag_detect.h's documentation), not taken from the code. */
static void test_diag_identified_selects_the_unit_model_bounds(void)
{
    app_config_t c;
    char buf[16384];
    app_config_default(&c);
    TV_CHECK(c.diag.identified == 0u && c.diag.friction_high_rel == (tv_real_t)1.7 &&
             c.diag.friction_fast_high == (tv_real_t)1.7);
    TV_CHECK_EQ_INT(parse("diag.identified = 1\n"), TV_OK);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK(c.diag.identified == 1u);
    TV_CHECK(c.diag.friction_high_rel == (tv_real_t)1.15 && c.diag.friction_fast_high == (tv_real_t)1.15 &&
             c.diag.friction_fast_level_min == (tv_real_t)1.1 && c.diag.preload_fast_low == (tv_real_t)0.7 &&
             c.diag.preload_fast_friction_max == (tv_real_t)1.3);
    /* the written configuration names it, and reads back to the same bounds */
    TV_CHECK(write_config(&c, buf, sizeof buf) == 0);
    TV_CHECK(strstr(buf, "\ndiag.identified = 1 ") != NULL);
    /* 0 restores the class's bounds */
    TV_CHECK_EQ_INT(parse("diag.identified = 0\n"), TV_OK);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK(c.diag.identified == 0u && c.diag.friction_high_rel == (tv_real_t)1.7 &&
             c.diag.friction_fast_high == (tv_real_t)1.7 && c.diag.preload_fast_low == (tv_real_t)0.5);
    TV_CHECK_EQ_INT(parse("diag.identified = 2\n"), TV_ERR_RANGE);
    TV_CHECK(has("p.txt:1: diag.identified = 2 is out of range, allowed [0, 1]"));
    TV_CHECK_EQ_INT(parse("diag.identified = 0.5\n"), TV_ERR_FORMAT);
}

/* diag.r_fit_high_frac: the fit's P2101 bound (default 1.25, diag_detect.h), set and written back
 * whatever diag.identified says (the identified bounds leave it alone); 1 and above 3 refused. */
static void test_diag_fit_resistance_bound(void)
{
    app_config_t c;
    char buf[16384];
    app_config_default(&c);
    TV_CHECK(c.diag.r_fit_high_frac == (tv_real_t)1.25);
    TV_CHECK_EQ_INT(parse("diag.identified = 1\ndiag.r_fit_high_frac = 1.375\n"), TV_OK);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK(c.diag.identified == 1u && c.diag.r_fit_high_frac == (tv_real_t)1.375);
    TV_CHECK(write_config(&c, buf, sizeof buf) == 0);
    TV_CHECK(strstr(buf, "\ndiag.r_fit_high_frac = 1.375 ") != NULL);
    TV_CHECK_EQ_INT(parse("diag.r_fit_high_frac = 1\n"), TV_ERR_RANGE);
    TV_CHECK(has("p.txt:1: diag.r_fit_high_frac = 1 is out of range, allowed (1, 3]"));
    TV_CHECK_EQ_INT(parse("diag.r_fit_high_frac = 3.5\n"), TV_ERR_RANGE);
}

/* The friction check's bounds (diag.friction_high_rel, friction_fast_high, friction_fast_level_min;
 * population --friction-baseline learns a unit's own): defaults 1.7 / 1.7 / 1.3; applied after
 * diag.identified, whose 1.15 / 1.15 / 1.1 they amend; a bound below 1 (a unit whose friction
 * reads below its model's) accepted and taken by app_init(); 0 and above 3 refused. */
static void test_diag_friction_bound_keys(void)
{
    app_config_t c;
    static app_t a;
    char buf[16384];
    app_config_default(&c);
    TV_CHECK(c.diag.friction_high_rel == (tv_real_t)1.7 && c.diag.friction_fast_high == (tv_real_t)1.7 &&
             c.diag.friction_fast_level_min == (tv_real_t)1.3);
    TV_CHECK_EQ_INT(parse("diag.identified = 1\ndiag.friction_high_rel = 0.875\n"), TV_OK);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    /* the identified set's signature bounds, the adapted level's amended */
    TV_CHECK(c.diag.identified == 1u && c.diag.friction_high_rel == (tv_real_t)0.875 &&
             c.diag.friction_fast_high == (tv_real_t)1.15 && c.diag.friction_fast_level_min == (tv_real_t)1.1);
    TV_CHECK_EQ_INT(parse("diag.friction_high_rel = 1.25\ndiag.friction_fast_high = 1.375\ndiag.friction_fast_level_min = 1.125\n"),
                    TV_OK);
    app_config_default(&c);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK(c.diag.identified == 0u && c.diag.friction_high_rel == (tv_real_t)1.25 &&
             c.diag.friction_fast_high == (tv_real_t)1.375 && c.diag.friction_fast_level_min == (tv_real_t)1.125);
    TV_CHECK_EQ_INT(app_init(&a, &c), TV_OK);
    TV_CHECK(write_config(&c, buf, sizeof buf) == 0);
    TV_CHECK(strstr(buf, "\ndiag.friction_high_rel = 1.25 ") != NULL && strstr(buf, "\ndiag.friction_fast_high = 1.375 ") != NULL &&
             strstr(buf, "\ndiag.friction_fast_level_min = 1.125 ") != NULL);
    c.diag.friction_high_rel = (tv_real_t)0.875;
    TV_CHECK_EQ_INT(app_init(&a, &c), TV_OK);
    TV_CHECK_EQ_INT(parse("diag.friction_high_rel = 0\n"), TV_ERR_RANGE);
    TV_CHECK(has("p.txt:1: diag.friction_high_rel = 0 is out of range, allowed (0, 3]"));
    TV_CHECK_EQ_INT(parse("diag.friction_fast_high = 3.5\n"), TV_ERR_RANGE);
}

/* The fit's per-unit baseline (diag.fit_base_*, diag_detect.h): none and not learned by default,
 * bounds 1.10 and 0.97; set, applied after diag.identified (which leaves them alone), written back;
 * a negative value, a fractional window count and bounds on the wrong side of 1 are refused; the
 * baseline needs both values (app_init() refuses R alone). */
static void test_diag_fit_baseline_keys(void)
{
    app_config_t c;
    static app_t a;
    char buf[16384];
    app_config_default(&c);
    TV_CHECK(c.diag.fit_base_r_ohm == TV_R(0.0) && c.diag.fit_base_nke_V_s == TV_R(0.0) && c.diag.fit_base_windows == 0u);
    TV_CHECK(c.diag.r_fit_base_high_frac == (tv_real_t)1.10 && c.diag.gain_fit_base_max == (tv_real_t)0.97);
    TV_CHECK_EQ_INT(parse("diag.identified = 1\ndiag.fit_base_r_ohm = 4.375\ndiag.fit_base_nke_V_s = 0.625\n"
                          "diag.fit_base_windows = 24\ndiag.r_fit_base_high_frac = 1.125\ndiag.gain_fit_base_max = 0.9375\n"),
                    TV_OK);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK(c.diag.identified == 1u && c.diag.fit_base_r_ohm == (tv_real_t)4.375 && c.diag.fit_base_nke_V_s == (tv_real_t)0.625);
    TV_CHECK(c.diag.fit_base_windows == 24u && c.diag.r_fit_base_high_frac == (tv_real_t)1.125 &&
             c.diag.gain_fit_base_max == (tv_real_t)0.9375);
    TV_CHECK_EQ_INT(app_init(&a, &c), TV_OK);
    c.diag.fit_base_nke_V_s = TV_R(0.0);
    TV_CHECK_EQ_INT(app_init(&a, &c), TV_ERR_CONFIG);
    c.diag.fit_base_nke_V_s = (tv_real_t)0.625;
    TV_CHECK(write_config(&c, buf, sizeof buf) == 0);
    TV_CHECK(strstr(buf, "\ndiag.fit_base_r_ohm = 4.375 ") != NULL && strstr(buf, "\ndiag.fit_base_nke_V_s = 0.625 ") != NULL);
    TV_CHECK(strstr(buf, "\ndiag.fit_base_windows = 24 ") != NULL && strstr(buf, "\ndiag.gain_fit_base_max = 0.9375 ") != NULL);
    TV_CHECK_EQ_INT(parse("diag.fit_base_r_ohm = -1\n"), TV_ERR_RANGE);
    TV_CHECK(has("p.txt:1: diag.fit_base_r_ohm = -1 is out of range"));
    TV_CHECK_EQ_INT(parse("diag.fit_base_windows = 2.5\n"), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(parse("diag.r_fit_base_high_frac = 1\n"), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(parse("diag.gain_fit_base_max = 1\n"), TV_ERR_RANGE);
}

/* The start-up stop learning's contact-law keys (what identify writes to keep an identified law):
 * applied to app_config_t::stop_learn, written back, out-of-range values and the cross-field
 * rules (e_min <= e_max, k_min < k_max) refused naming both keys. */
static void test_stop_learn_keys(void)
{
    app_config_t c;
    app_config_default(&c);
    TV_CHECK(c.stop_learn.e_min == TV_R(1.0) && c.stop_learn.e_max == TV_R(2.0));
    TV_CHECK_EQ_INT(parse("stop_learn.e_min = 1.3\nstop_learn.e_max = 1.3\nstop_learn.lambda_per_k_s_rad = 0.2\n"
                          "stop_learn.k_min_Nm_rad = 1500\nstop_learn.k_max_Nm_rad = 1530\n"),
                    TV_OK);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
    TV_CHECK(c.stop_learn.e_min == (tv_real_t)1.3 && c.stop_learn.e_max == (tv_real_t)1.3 &&
             c.stop_learn.lambda_per_k_s_rad == (tv_real_t)0.2 && c.stop_learn.k_min == (tv_real_t)1500 &&
             c.stop_learn.k_max == (tv_real_t)1530);
    {
        static char buf[16384];
        TV_CHECK(write_config(&c, buf, sizeof buf) == 0);
        TV_CHECK(strstr(buf, "\nstop_learn.e_min = ") != NULL && strstr(buf, "\nstop_learn.k_max_Nm_rad = ") != NULL);
        /* and reads back to the same */
        TV_CHECK_EQ_INT(parse(buf), TV_OK);
        app_config_default(&c);
        TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_OK);
        TV_CHECK(c.stop_learn.e_min == (tv_real_t)1.3 && c.stop_learn.k_min == (tv_real_t)1500 &&
                 c.stop_learn.k_max == (tv_real_t)1530 && c.stop_learn.lambda_per_k_s_rad == (tv_real_t)0.2);
    }
    TV_CHECK_EQ_INT(parse("stop_learn.e_min = 1.5\nstop_learn.e_max = 1.2\n"), TV_OK);
    app_config_default(&c);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_ERR_RANGE);
    TV_CHECK(has("p.txt: stop_learn.e_min (p.txt:1) = 1.5 must be <= stop_learn.e_max (p.txt:2) = 1.2"));
    TV_CHECK_EQ_INT(parse("stop_learn.k_min_Nm_rad = 2e4\n"), TV_OK);
    app_config_default(&c);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_ERR_RANGE);
    TV_CHECK(has("p.txt: stop_learn.k_min_Nm_rad (p.txt:1) = 20000 must be < stop_learn.k_max_Nm_rad (default) = 10000"));
    TV_CHECK_EQ_INT(parse("stop_learn.e_max = 3.5\n"), TV_ERR_RANGE);
    TV_CHECK(has("p.txt:1: stop_learn.e_max = 3.5 is out of range"));
}

static void test_unknown_key_is_an_error_naming_file_line_and_key(void)
{
    TV_CHECK_EQ_INT(parse("model.R_ohm = 4\nmodel.R_Ohm = 4\n"), TV_ERR_FORMAT);
    TV_CHECK(has("p.txt:2: unknown key 'model.R_Ohm'"));
}

static void test_missing_value_is_an_error(void)
{
    TV_CHECK_EQ_INT(parse("\nmodel.J_kg_m2 =   \n"), TV_ERR_FORMAT);
    TV_CHECK(has("p.txt:2: key 'model.J_kg_m2' has no value"));
    TV_CHECK_EQ_INT(parse("model.J_kg_m2 = # only a comment\n"), TV_ERR_FORMAT);
    TV_CHECK(has("p.txt:1: key 'model.J_kg_m2' has no value"));
    TV_CHECK_EQ_INT(parse("model.J_kg_m2\n"), TV_ERR_FORMAT);
    TV_CHECK(has("p.txt:1: expected 'key = value'"));
    TV_CHECK_EQ_INT(parse(" = 3\n"), TV_ERR_FORMAT);
    TV_CHECK(has("p.txt:1: missing key"));
}

static void test_duplicate_key_is_an_error(void)
{
    TV_CHECK_EQ_INT(parse("ekf.qT_Nm2_s = 1e-6\n# x\nekf.qT_Nm2_s = 2e-6\n"), TV_ERR_FORMAT);
    TV_CHECK(has("p.txt:3: duplicate key 'ekf.qT_Nm2_s' (first set on line 1)"));
}

static void test_out_of_range_values_are_errors(void)
{
    TV_CHECK_EQ_INT(parse("model.R_ohm = 0\n"), TV_ERR_RANGE);
    TV_CHECK(has("p.txt:1: model.R_ohm = 0 is out of range, allowed (0, 1000]"));
    TV_CHECK_EQ_INT(parse("model.phi_closed_rad = 0.1\n"), TV_ERR_RANGE);
    TV_CHECK(has("model.phi_closed_rad = 0.1 is out of range, allowed [-1, 0)"));
    TV_CHECK_EQ_INT(parse("calib.current_A_per_count = 0\n"), TV_ERR_RANGE);
    TV_CHECK(has("not 0"));
    TV_CHECK_EQ_INT(parse("model.substeps = 51\n"), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(parse("model.substeps = 2.5\n"), TV_ERR_FORMAT);
    TV_CHECK(has("model.substeps = 2.5 is not an integer"));
    TV_CHECK_EQ_INT(parse("ekf.r_current_A2 = -1e-4\n"), TV_ERR_RANGE);
}

static void test_non_numbers_and_non_finite_values_are_errors(void)
{
    TV_CHECK_EQ_INT(parse("model.Kv_Nm_s_rad = fast\n"), TV_ERR_FORMAT);
    TV_CHECK(has("p.txt:1: model.Kv_Nm_s_rad = fast is not a number"));
    TV_CHECK_EQ_INT(parse("model.Kv_Nm_s_rad = 0.01 0.02\n"), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(parse("model.Kv_Nm_s_rad = nan\n"), TV_ERR_NONFINITE);
    TV_CHECK(has("p.txt:1: model.Kv_Nm_s_rad = nan is not finite"));
    TV_CHECK_EQ_INT(parse("model.Kv_Nm_s_rad = 1e999\n"), TV_ERR_NONFINITE);
}

static void test_cross_field_rules_name_both_keys(void)
{
    app_config_t c;
    TV_CHECK_EQ_INT(parse("model.Mc_Nm = 0.2\nmodel.Ms_Nm = 0.1\n"), TV_OK);
    app_config_default(&c);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_ERR_RANGE);
    TV_CHECK(has("model.Mc_Nm (p.txt:1) = 0.2 must be <= model.Ms_Nm (p.txt:2) = 0.1"));
    TV_CHECK_EQ_INT(parse("limits.supply_max_V = 5\n"), TV_OK);
    app_config_default(&c);
    TV_CHECK_EQ_INT(params_apply(&s_p, &c, s_err, sizeof s_err), TV_ERR_RANGE);
    TV_CHECK(has("limits.supply_min_V (default) = 8 must be < limits.supply_max_V (p.txt:1) = 5"));
}

static void test_long_lines_nul_bytes_and_missing_files_are_errors(void)
{
    static char text[4096];
    char path[64];
    memset(text, ' ', sizeof text);
    memcpy(text, "model.R_ohm = 4", 15);
    text[sizeof text - 1u] = '\n';
    params_init(&s_p, "p.txt");
    TV_CHECK_EQ_INT(params_parse_text(&s_p, text, sizeof text, s_err, sizeof s_err), TV_ERR_FORMAT);
    TV_CHECK(has("p.txt:1: line longer than 1024 bytes"));
    TV_CHECK(temp_file(text, sizeof text, path, sizeof path) == 0);
    params_init(&s_p, path);
    TV_CHECK_EQ_INT(params_load(&s_p, path, s_err, sizeof s_err), TV_ERR_FORMAT);
    TV_CHECK(has(":1: line longer than 1024 bytes"));
    (void)remove(path);
    TV_CHECK(temp_file("model.R_ohm = 4\0 junk\n", 22u, path, sizeof path) == 0);
    params_init(&s_p, path);
    TV_CHECK_EQ_INT(params_load(&s_p, path, s_err, sizeof s_err), TV_ERR_FORMAT);
    TV_CHECK(has(":1: NUL byte in the line"));
    (void)remove(path);
    params_init(&s_p, "/nonexistent/p.txt");
    TV_CHECK_EQ_INT(params_load(&s_p, "/nonexistent/p.txt", s_err, sizeof s_err), TV_ERR_IO);
    TV_CHECK(has("/nonexistent/p.txt: cannot open"));
}

int main(void)
{
    TV_TEST_RUN(test_written_defaults_read_back_to_the_same_configuration);
    TV_TEST_RUN(test_values_comments_and_q_recomputation);
    TV_TEST_RUN(test_densities_survive_a_later_model_file);
    TV_TEST_RUN(test_diag_identified_selects_the_unit_model_bounds);
    TV_TEST_RUN(test_diag_fit_resistance_bound);
    TV_TEST_RUN(test_diag_friction_bound_keys);
    TV_TEST_RUN(test_diag_fit_baseline_keys);
    TV_TEST_RUN(test_stop_learn_keys);
    TV_TEST_RUN(test_unknown_key_is_an_error_naming_file_line_and_key);
    TV_TEST_RUN(test_missing_value_is_an_error);
    TV_TEST_RUN(test_duplicate_key_is_an_error);
    TV_TEST_RUN(test_out_of_range_values_are_errors);
    TV_TEST_RUN(test_non_numbers_and_non_finite_values_are_errors);
    TV_TEST_RUN(test_cross_field_rules_name_both_keys);
    TV_TEST_RUN(test_long_lines_nul_bytes_and_missing_files_are_errors);
    return tv_test_summary();
}
