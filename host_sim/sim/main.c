/**
 * @file main.c
 * @brief host_sim: run a scenario of the firmware application against the plant, write the
 *        CSV log and the metrics (see usage()).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

#include "cli.h"
#include "params.h"
#include "plant_params.h"
#include "rawlog_write.h"
#include "sim.h"
#include "sim_unit.h"
#include "tv_status.h"

/** Exit code for a usage error. */
#define MAIN_EXIT_USAGE 2
/** Exit code for a run or I/O failure. */
#define MAIN_EXIT_FAIL 1
/** Exit code for an invalid parameter file. */
#define MAIN_EXIT_PARAMS 3
/** Longest output path built [chars]. */
#define MAIN_PATH_MAX 4096

static const char *s_prog = "host_sim";

#define usage_error(...) cli_usage_error(s_prog, __VA_ARGS__)

/* Parameter settings and the raw-log writer (large: static). */
static params_t s_params;
static plant_config_t s_plant_cfg;
static app_config_t s_app_cfg;
static rlw_t s_raw;
static plant_fault_list_t s_faults;

/* Row callback: one raw-log record per application tick. */
typedef struct {
    rlw_t *w;
    int rc;
} raw_ctx_t;

static void raw_row(const sim_row_t *row, void *user)
{
    raw_ctx_t *c = (raw_ctx_t *)user;
    rawlog_record_t r;
    int k;
    if (c->rc != TV_OK) {
        return;
    }
    memset(&r, 0, sizeof r);
    r.t_us = row->t_us;
    r.duty = row->duty_f;
    for (k = 0; k < 4; ++k) {
        r.adc[k] = row->adc[k];
    }
    r.driver_fault = row->driver_fault;
    r.bridge_enable = row->bridge_enable ? 1u : 0u;
    for (k = 0; k < 3; ++k) {
        r.truth[k] = row->truth[k];
    }
    c->rc = rlw_put(c->w, &r);
}

/* --params-out: the filter's configuration of the run with what it learned, the stops in use at
 * the end and, when the start-up routine finished, its contact law (as app.c puts it into the
 * estimator), as a parameter file; 0 on success. */
static int write_learned_params(const char *path, const sim_options_t *opt, const sim_result_t *r, int have_params)
{
    static app_config_t cfg;
    FILE *f;
    int rc;
    if (opt->app != NULL) {
        cfg = *opt->app;
    } else {
        app_config_default(&cfg);
    }
    if (!have_params) {
        params_init(&s_params, NULL);
    }
    /* the routine's law (when it finished), then the stops in use at the end (tracked since) */
    (void)sim_apply_stop_learning(r, &cfg);
    cfg.model.phi_closed_rad = (tv_real_t)r->stop_onset_rad[0];
    cfg.model.phi_open_rad = (tv_real_t)r->stop_onset_rad[1];
    if (isfinite(r->fit_base_r_ohm) && isfinite(r->fit_base_nke_V_s)) {
        /* the fit's per-unit baseline in force at the end (given, or learned: diag.fit_base_windows) */
        cfg.diag.fit_base_r_ohm = (tv_real_t)r->fit_base_r_ohm;
        cfg.diag.fit_base_nke_V_s = (tv_real_t)r->fit_base_nke_V_s;
    }
    f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, path, strerror(errno));
        return -1;
    }
    rc = params_write(f, &cfg);
    if (fclose(f) != 0 || rc != TV_OK) {
        fprintf(stderr, "%s: write error on %s\n", s_prog, path);
        return -1;
    }
    fprintf(stderr, "wrote %s (stops %.5f / %.5f rad%s%s)\n", path, r->stop_onset_rad[0], r->stop_onset_rad[1],
            r->stop_learn_phase == (int)SL_DONE ? ", the learned contact law" : "",
            isfinite(r->fit_base_r_ohm) ? ", the fit's baseline" : "");
    return 0;
}

static void usage(FILE *f)
{
    int k;
    fprintf(f,
            "usage: %s [--scenario NAME] [--duration S] [--warmup S] [--seed N] [--mc N] [--setup 2|3]\n"
            "          [--qu X] [--qT X] [--r-current X] [--r-angle X] [--r-velocity X]\n"
            "          [--pwm-ripple] [--drop-every N] [--out DIR] [--params FILE] [--params-out FILE] [--print-params]\n"
            "          [--raw-log PATH [--raw-format csv|bin]] [--plant-params FILE] [--print-plant-params]\n"
            "          [--plant-class a|b] [--unit ID [--spread stops|all]]\n"
            "          [--fault KIND[:MAGNITUDE]@T_S[:RAMP_S] ...] [--events FILE]\n"
            "          [--winding-temp DEGC] [--temp-reading plant|none|DEGC] [--help]\n"
            "\n"
            "Runs the firmware's 1 kHz application (double build) against the high-fidelity plant.\n"
            "With no arguments: the paper's experiment (paper_sine, 2 s, seed 1) into out/.\n"
            "\n"
            "  --scenario NAME   one of (default paper_sine):\n",
            s_prog);
    for (k = 0; k < (int)SIM_SCN_COUNT; ++k) {
        fprintf(f, "                      %-14s %s\n", sim_scenario_name((sim_scenario_t)k),
                sim_scenario_description((sim_scenario_t)k));
    }
    fprintf(f,
            ""
            "  --duration S      simulated time [s], 0 < S <= %g (default: the scenario's)\n"
            "  --warmup S        first run S s of normal excitation (a 6 V, 1 Hz open-loop sine),\n"
            "                    0 <= S <= 60 (default 0), then the scenario, whose time and\n"
            "                    scoring count from its start (--fault onsets and the CSV's t_s\n"
            "                    from the run's); population's all_varied_adapted runs are\n"
            "                    --warmup 5. Not with stuck_release or stop_learn, which start\n"
            "                    from a given plate state\n"
            "  --seed N          plant noise seed, unsigned integer (default 1)\n"
            "  --mc N            Monte Carlo over N seeds (--seed, --seed + 1, ...), 1 <= N <= %u;\n"
            "                    writes <scenario>_mc_metrics.txt/.json instead of the CSV\n"
            "  --setup 2|3       application filter measurements: 2 = current + angle (default),\n"
            "                    3 = the paper's current + differentiated velocity + angle\n"
            "  --qu X            voltage process-noise density [V^2 s], >= 0 (default %g)\n"
            "  --qT X            torque process-noise density [N^2 m^2 s], >= 0 (default %g)\n"
            "  --r-current X     current measurement noise VARIANCE [A^2], > 0\n"
            "  --r-angle X       angle measurement noise VARIANCE [rad^2], > 0\n"
            "  --r-velocity X    differentiated-velocity noise VARIANCE [(rad/s)^2], > 0 (setup 3)\n"
            "  --pwm-ripple      the plant resolves the 20 kHz PWM switching\n"
            "  --drop-every N    skip every N-th application tick (missing samples), N >= 2\n"
            "  --out DIR         output directory, created if missing (default out)\n"
            "  --params FILE     application parameters (model, noise, calibration, limits) as\n"
            "                    key = value lines (host_sim/replay/params.h; the plant keeps its own)\n"
            "  --print-params    print the parameter file of the defaults (with --params: of the\n"
            "                    result) and exit\n"
            "  --raw-log PATH    also write the raw ADC stream the application read (counts, duty,\n"
            "                    driver fault, bridge enable, plant truth) for replay\n"
            "  --raw-format F    csv (default) or bin (TVRAWLOG), host_sim/replay/LOG_FORMATS.md\n"
            "  --plant-params FILE  the PLANT's own parameters (plant.FIELD = value lines,\n"
            "                    host_sim/plant/plant_params.h): a unit that differs from the filter's\n"
            "                    model (--params sets the filter's)\n"
            "  --print-plant-params  print the plant parameter file of the defaults (with\n"
            "                    --plant-params: of that file; with --unit: of the drawn unit) and exit\n"
            "  --plant-class a|b the throttle class (host_sim/plant/plant_draw.h): a = the paper's,\n"
            "                    b = a low-resistance motor; the filter runs on the class's nominal model\n"
            "  --unit ID         a random unit of that class, drawn from the documented ranges\n"
            "                    (the same ID is always the same unit); the ECU is calibrated for it\n"
            "  --spread S        what --unit varies: stops (stops, contact, sensor front end) or all\n"
            "                    (default: also motor, friction, springs)\n"
            "  --fault SPEC      inject a fault (repeatable, up to %u): KIND:MAGNITUDE@T_S, or\n"
            "                    KIND@T_S for a kind without a magnitude; :RAMP_S after the time\n"
            "                    makes it a drift reaching MAGNITUDE at T_S + RAMP_S, e.g.\n"
            "                    friction_high:2@1.5 (Mc, Ms x2 from 1.5 s), tps1_offset:1@0.5:0.2.\n"
            "                    Kinds (host_sim/plant/plant_fault.h):\n",
            SIM_DURATION_MAX_S, SIM_MC_SEEDS_MAX, (double)EKF_DEFAULT_QU_V2_S, (double)EKF_DEFAULT_QT_NM2_S,
            PLANT_FAULT_LIST_MAX);
    for (k = 0; k < (int)PLANT_FAULT_KIND_COUNT; ++k) {
        fprintf(f, "                      %-24s %s\n", plant_fault_kind_name((plant_fault_kind_t)k),
                plant_fault_kind_help((plant_fault_kind_t)k));
    }
    fprintf(f, "%s", CLI_TEMP_HELP);
    fprintf(f,
            "  --events FILE     write the diagnostic events (firmware/diag/diag.h) as CSV:\n"
            "                    t_us,status,fault_class,dtc, status pending|confirmed|healed\n"
            "  --params-out FILE after the run, write the filter's parameter file with what it\n"
            "                    learned: the stops in use (start-up routine, online tracking)\n"
            "                    and, after stop_learn, the contact law; the fit's per-unit\n"
            "                    baseline when there is one (diag.fit_base_*: learned with\n"
            "                    diag.fit_base_windows > 0 and --temp-reading) (the host's\n"
            "                    persistence; --params FILE reads it back)\n"
            "Outputs: DIR/<scenario>.csv, DIR/<scenario>_metrics.txt, DIR/<scenario>_metrics.json.\n"
            "Exit codes: 0 ok; 1 run or I/O failure; 2 usage error; 3 parameter file invalid.\n");
}

static FILE *open_out(const char *dir, const char *scn, const char *suffix, char *path, size_t cap)
{
    FILE *f;
    const int n = snprintf(path, cap, "%s/%s%s", dir, scn, suffix);
    if (n < 0 || (size_t)n >= cap) {
        fprintf(stderr, "%s: output path too long: %s/%s%s\n", s_prog, dir, scn, suffix);
        return NULL;
    }
    f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, path, strerror(errno));
    }
    return f;
}

static int close_out(FILE *f, const char *path)
{
    if (fclose(f) != 0) {
        fprintf(stderr, "%s: error writing %s\n", s_prog, path);
        return -1;
    }
    return 0;
}

/* Monte Carlo progress on stderr: a rewritten line on a terminal, every 10 % otherwise. */
static void progress(uint32_t done, uint32_t n, void *user)
{
    (void)user;
    if (isatty(fileno(stderr))) {
        fprintf(stderr, "\rmonte carlo: %lu / %lu runs", (unsigned long)done, (unsigned long)n);
        if (done == n) {
            fputc('\n', stderr);
        }
    } else if (done == n || (uint64_t)done * 10u / n != (uint64_t)(done - 1u) * 10u / n) {
        fprintf(stderr, "monte carlo: %lu / %lu runs\n", (unsigned long)done, (unsigned long)n);
    }
    fflush(stderr);
}

int main(int argc, char **argv)
{
    sim_options_t opt;
    const char *out_dir = "out";
    unsigned long long mc = 0u;
    int k;
    int rc;
    char path[MAIN_PATH_MAX];
    const char *scn;
    const char *params_path = NULL;
    const char *raw_path = NULL;
    const char *events_path = NULL;
    const char *params_out = NULL;
    rlr_format_t raw_format = RLR_FMT_CSV;
    int print_params = 0;
    int print_plant_params = 0;
    const char *plant_params_path = NULL;
    plant_class_t plant_class = PLANT_CLASS_A;
    plant_spread_t spread = PLANT_SPREAD_ALL;
    int class_given = 0;
    int unit_given = 0;
    int spread_given = 0;
    uint64_t unit_id = 0u;
    cli_noise_overrides_t ov;
    cli_temps_t temps;
    static const char *const takes_value[] = {"--scenario", "--duration", "--warmup", "--seed", "--mc", "--setup", "--qu", "--qT",
                                              "--r-current", "--r-angle", "--r-velocity", "--drop-every", "--out",
                                              "--params", "--raw-log", "--raw-format", "--plant-params", "--plant-class",
                                              "--unit", "--spread", "--fault", "--events", "--params-out",
                                              "--winding-temp", "--temp-reading", NULL};

    sim_options_default(&opt);
    memset(&ov, 0, sizeof ov);
    cli_temps_default(&temps);
    for (k = 1; k < argc; ++k) {
        const char *a = argv[k];
        const char *v = k + 1 < argc ? argv[k + 1] : NULL;
        double d = 0.0;
        unsigned long long u = 0u;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        }
        if (strcmp(a, "--pwm-ripple") == 0) {
            opt.pwm_ripple = 1;
            continue;
        }
        if (strcmp(a, "--print-params") == 0) {
            print_params = 1;
            continue;
        }
        if (strcmp(a, "--print-plant-params") == 0) {
            print_plant_params = 1;
            continue;
        }
        if (cli_option_value(s_prog, a, v, takes_value) != 0 || v == NULL) { /* (v: for the analyser) */
            return CLI_EXIT_USAGE;
        }
        ++k;
        if (strcmp(a, "--scenario") == 0) {
            if (sim_scenario_from_name(v, &opt.scenario) != TV_OK) {
                return usage_error("option %s: unknown scenario '%s'", a, v);
            }
        } else if (strcmp(a, "--params") == 0) {
            params_path = v;
        } else if (strcmp(a, "--events") == 0) {
            if (*v == '\0') {
                return usage_error("option %s: empty path", a);
            }
            events_path = v;
        } else if (strcmp(a, "--params-out") == 0) {
            params_out = v;
        } else if (strcmp(a, "--fault") == 0) {
            char msg[PLANT_FAULT_MSG_MAX];
            if (plant_fault_list_add(&s_faults, v, msg, sizeof msg) != TV_OK) {
                return usage_error("option %s: %s", a, msg);
            }
            opt.faults = &s_faults;
        } else if (strcmp(a, "--plant-params") == 0) {
            plant_params_path = v;
        } else if (strcmp(a, "--plant-class") == 0) {
            if (plant_class_from_name(v, &plant_class) != TV_OK) {
                return usage_error("option %s: '%s' is not a or b", a, v);
            }
            class_given = 1;
        } else if (strcmp(a, "--spread") == 0) {
            if (plant_spread_from_name(v, &spread) != TV_OK) {
                return usage_error("option %s: '%s' is not none, stops or all", a, v);
            }
            spread_given = 1;
        } else if (strcmp(a, "--unit") == 0) {
            const int prc = cli_parse_u64(v, &u);
            if (prc != 0) {
                return usage_error("option %s: '%s' is not an unsigned integer%s", a, v, prc == -2 ? " (too large)" : "");
            }
            unit_id = (uint64_t)u;
            unit_given = 1;
        } else if (strcmp(a, "--raw-log") == 0) {
            if (*v == '\0') {
                return usage_error("option %s: empty path", a);
            }
            raw_path = v;
        } else if (strcmp(a, "--raw-format") == 0) {
            if (rlr_format_from_name(v, &raw_format) != TV_OK || raw_format == RLR_FMT_AUTO) {
                return usage_error("option %s: '%s' is not csv or bin", a, v);
            }
        } else if (strcmp(a, "--out") == 0) {
            if (*v == '\0') {
                return usage_error("option %s: empty directory name", a);
            }
            out_dir = v;
        } else if (strcmp(a, "--seed") == 0 || strcmp(a, "--mc") == 0 || strcmp(a, "--setup") == 0 ||
                   strcmp(a, "--drop-every") == 0) {
            const int prc = cli_parse_u64(v, &u);
            if (prc == -2) {
                return usage_error("option %s: %s is out of range (too large)", a, v);
            }
            if (prc != 0) {
                return usage_error("option %s: '%s' is not an unsigned integer", a, v);
            }
            if (strcmp(a, "--seed") == 0) {
                opt.seed = (uint64_t)u;
            } else if (strcmp(a, "--mc") == 0) {
                if (u < 1u || u > SIM_MC_SEEDS_MAX) {
                    return usage_error("option %s: %s is out of range (1 .. 100000)", a, v);
                }
                mc = u;
            } else if (strcmp(a, "--setup") == 0) {
                if (u != 2u && u != 3u) {
                    return usage_error("option %s: %s is not 2 or 3", a, v);
                }
                opt.setup = u == 2u ? EKF_SETUP_CURRENT_ANGLE : EKF_SETUP_PAPER_3MEAS;
            } else {
                if (u < 2u || u > 1000000u) {
                    return usage_error("option %s: %s is out of range (2 .. 1000000)", a, v);
                }
                opt.drop_tick_every = (uint32_t)u;
            }
        } else if (cli_noise_index(a) >= 0) {
            rc = cli_noise_set(s_prog, &ov, a, v);
            if (rc != 0) {
                return rc;
            }
        } else if (cli_is_temp_option(a)) {
            rc = cli_temp_set(s_prog, &temps, a, v);
            if (rc != 0) {
                return rc;
            }
        } else if (strcmp(a, "--warmup") == 0) {
            if (cli_parse_double(v, &d) != 0) {
                return usage_error("option %s: '%s' is not a finite number", a, v);
            }
            if (!(d >= 0.0) || d > SIM_WARMUP_MAX_S) {
                return usage_error("option %s: %s is out of range (0 <= S <= %g)", a, v, SIM_WARMUP_MAX_S);
            }
            opt.warmup_s = d;
        } else {
            if (cli_parse_double(v, &d) != 0) {
                return usage_error("option %s: '%s' is not a finite number", a, v);
            }
            if (!(d > 0.0) || d > SIM_DURATION_MAX_S) {
                return usage_error("option %s: %s is out of range (0 < S <= 600)", a, v);
            }
            opt.duration_s = d;
        }
    }
    if (opt.warmup_s > 0.0 && !sim_scenario_takes_warmup(opt.scenario)) {
        return usage_error("option --warmup: scenario %s starts from a given plate state; it takes no warm-up",
                           sim_scenario_name(opt.scenario));
    }
    /* the noise overrides; a density not given keeps its default */
    if (ov.given[CLI_NOISE_QU] || ov.given[CLI_NOISE_QT]) {
        opt.q_override = 1;
        if (ov.given[CLI_NOISE_QU]) {
            opt.qu_V2_s = ov.value[CLI_NOISE_QU];
        }
        if (ov.given[CLI_NOISE_QT]) {
            opt.qT_Nm2_s = ov.value[CLI_NOISE_QT];
        }
    }
    if (ov.given[CLI_NOISE_R_CURRENT]) {
        opt.r_current_A2 = ov.value[CLI_NOISE_R_CURRENT];
    }
    if (ov.given[CLI_NOISE_R_ANGLE]) {
        opt.r_angle_rad2 = ov.value[CLI_NOISE_R_ANGLE];
    }
    if (ov.given[CLI_NOISE_R_VELOCITY]) {
        opt.r_velocity_rad2_s2 = ov.value[CLI_NOISE_R_VELOCITY];
    }
    opt.winding_temp_C = temps.winding_C;
    opt.temp_reading = cli_temp_told(&temps, &opt.temp_reading_C);
    if (spread_given && !unit_given) {
        return usage_error("--spread needs --unit ID (the unit it draws)");
    }
    if (unit_given && plant_params_path != NULL) {
        return usage_error("--unit draws the plant; it cannot be combined with --plant-params");
    }
    if (class_given || unit_given) {
        /* a unit of the population: its own plant, the ECU calibrated for it, the filter on its
         * class's nominal model (sim_unit.h); --params still applies on top */
        rc = unit_given ? plant_draw(plant_class, spread, unit_id, &s_plant_cfg)
                        : plant_class_nominal(plant_class, &s_plant_cfg);
        if (rc == TV_OK) {
            rc = sim_app_config_for_unit(plant_class, &s_plant_cfg, &s_app_cfg);
        }
        if (rc != TV_OK) {
            fprintf(stderr, "%s: unit %llu of class %s: %s\n", s_prog, (unsigned long long)unit_id,
                    plant_class_name(plant_class), tv_status_str(rc));
            return MAIN_EXIT_FAIL;
        }
        opt.plant = &s_plant_cfg;
        opt.app = &s_app_cfg;
    }
    if (plant_params_path != NULL || print_plant_params) {
        /* the plant's own parameters: the simulated unit may differ from the filter's model */
        if (opt.plant == NULL) {
            plant_config_default(&s_plant_cfg);
        }
        if (plant_params_path != NULL) {
            char err[PLANT_PARAMS_MSG_MAX];
            rc = plant_params_load(plant_params_path, &s_plant_cfg, err, sizeof err);
            if (rc != TV_OK) {
                fprintf(stderr, "%s: %s\n", s_prog, err);
                return rc == TV_ERR_IO ? MAIN_EXIT_FAIL : MAIN_EXIT_PARAMS;
            }
        }
        if (print_plant_params) {
            return plant_params_write(stdout, &s_plant_cfg) == TV_OK ? 0 : MAIN_EXIT_FAIL;
        }
        opt.plant = &s_plant_cfg;
    }
    if (params_path != NULL || print_params) {
        char err[PARAMS_MSG_MAX];
        params_init(&s_params, params_path);
        if (params_path != NULL) {
            rc = params_load(&s_params, params_path, err, sizeof err);
            if (rc != TV_OK) {
                fprintf(stderr, "%s: %s\n", s_prog, err);
                return rc == TV_ERR_IO ? MAIN_EXIT_FAIL : MAIN_EXIT_PARAMS;
            }
        }
        if (opt.app == NULL) {
            app_config_default(&s_app_cfg);
        }
        rc = params_apply(&s_params, &s_app_cfg, err, sizeof err);
        if (rc != TV_OK) {
            fprintf(stderr, "%s: %s\n", s_prog, err);
            return MAIN_EXIT_PARAMS;
        }
        if (print_params) {
            return params_write(stdout, &s_app_cfg) == TV_OK ? 0 : MAIN_EXIT_FAIL;
        }
        opt.app = &s_app_cfg;
    }
    if (raw_path != NULL && mc > 0u) {
        return usage_error("--raw-log writes one run; it cannot be combined with --mc");
    }
    if (events_path != NULL && mc > 0u) {
        return usage_error("--events writes one run; it cannot be combined with --mc");
    }
    if (params_out != NULL && mc > 0u) {
        return usage_error("--params-out writes what one run learned; it cannot be combined with --mc");
    }
    if (cli_make_dirs(out_dir) != 0) {
        fprintf(stderr, "%s: cannot create output directory %s: %s\n", s_prog, out_dir, strerror(errno));
        return MAIN_EXIT_FAIL;
    }
    scn = sim_scenario_name(opt.scenario);

    if (mc > 0u) {
        sim_mc_result_t m;
        FILE *f;
        rc = sim_monte_carlo(&opt, (uint32_t)mc, progress, NULL, &m);
        if (rc != TV_OK) {
            fprintf(stderr, "%s: Monte Carlo failed: %s\n", s_prog, tv_status_str(rc));
            return MAIN_EXIT_FAIL;
        }
        (void)sim_mc_print(stdout, &m);
        f = open_out(out_dir, scn, "_mc_metrics.txt", path, sizeof path);
        if (f == NULL) {
            return MAIN_EXIT_FAIL;
        }
        rc = sim_mc_print(f, &m);
        if (close_out(f, path) != 0 || rc != TV_OK) {
            return MAIN_EXIT_FAIL;
        }
        fprintf(stderr, "wrote %s\n", path);
        f = open_out(out_dir, scn, "_mc_metrics.json", path, sizeof path);
        if (f == NULL) {
            return MAIN_EXIT_FAIL;
        }
        rc = sim_mc_json(f, &m);
        if (close_out(f, path) != 0 || rc != TV_OK) {
            return MAIN_EXIT_FAIL;
        }
        fprintf(stderr, "wrote %s\n", path);
        return 0;
    }

    {
        sim_result_t r;
        FILE *raw = NULL;
        raw_ctx_t raw_ctx;
        FILE *f = open_out(out_dir, scn, ".csv", path, sizeof path);
        if (f == NULL) {
            return MAIN_EXIT_FAIL;
        }
        raw_ctx.w = &s_raw;
        raw_ctx.rc = TV_OK;
        if (raw_path != NULL) {
            rawlog_header_t h;
            const app_calib_t *c = opt.app != NULL ? &opt.app->calib : NULL;
            app_config_t def;
            plant_config_t pc;
            if (c == NULL) {
                app_config_default(&def);
                c = &def.calib;
            }
            if (opt.plant != NULL) {
                pc = *opt.plant;
            } else {
                plant_config_default(&pc);
            }
            rawlog_header_default(&h);
            h.flags = RAWLOG_FLAG_TRUTH;
            h.adc_bits = (uint8_t)pc.adc_bits;
            params_calib_to_header(c, &h);
            raw = fopen(raw_path, raw_format == RLR_FMT_BIN ? "wb" : "w");
            if (raw == NULL) {
                fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, raw_path, strerror(errno));
                (void)fclose(f);
                return MAIN_EXIT_FAIL;
            }
            rc = rlw_open(&s_raw, raw, raw_format, &h, "written by host_sim (the application's ADC reads, duty and plant truth)");
            if (rc != TV_OK) {
                fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, raw_path, tv_status_str(rc));
                (void)fclose(raw);
                (void)fclose(f);
                return MAIN_EXIT_FAIL;
            }
            opt.row_fn = raw_row;
            opt.row_user = &raw_ctx;
        }
        opt.csv = f;
        if (events_path != NULL) {
            opt.events = fopen(events_path, "w");
            if (opt.events == NULL) {
                fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, events_path, strerror(errno));
                (void)fclose(f);
                if (raw != NULL) {
                    (void)fclose(raw);
                }
                return MAIN_EXIT_FAIL;
            }
        }
        rc = sim_run(&opt, &r);
        if (close_out(f, path) != 0) {
            return MAIN_EXIT_FAIL;
        }
        if (opt.events != NULL) {
            if (close_out(opt.events, events_path) != 0) {
                return MAIN_EXIT_FAIL;
            }
            fprintf(stderr, "wrote %s (%lu events)\n", events_path, (unsigned long)r.dtc_events);
        }
        if (raw != NULL) {
            const int wrc = rlw_close(&s_raw);
            if (fclose(raw) != 0 || wrc != TV_OK || raw_ctx.rc != TV_OK) {
                fprintf(stderr, "%s: error writing %s: %s\n", s_prog, raw_path,
                        tv_status_str(raw_ctx.rc != TV_OK ? raw_ctx.rc : TV_ERR_IO));
                return MAIN_EXIT_FAIL;
            }
        }
        if (rc != TV_OK) {
            fprintf(stderr, "%s: run failed: %s%s\n", s_prog, tv_status_str(rc),
                    rc == TV_ERR_CONFIG && opt.faults != NULL ? " (or a --fault the unit cannot take, e.g. a supply sag above its supply)" : "");
            return MAIN_EXIT_FAIL;
        }
        fprintf(stderr, "wrote %s\n", path);
        if (raw != NULL) {
            fprintf(stderr, "wrote %s (%s, %llu records)\n", raw_path, rlr_format_name(raw_format),
                    (unsigned long long)s_raw.records);
        }
        if (params_out != NULL && write_learned_params(params_out, &opt, &r, params_path != NULL) != 0) {
            return MAIN_EXIT_FAIL;
        }
        (void)sim_result_print(stdout, &r);
        f = open_out(out_dir, scn, "_metrics.txt", path, sizeof path);
        if (f == NULL) {
            return MAIN_EXIT_FAIL;
        }
        rc = sim_result_print(f, &r);
        if (close_out(f, path) != 0 || rc != TV_OK) {
            return MAIN_EXIT_FAIL;
        }
        fprintf(stderr, "wrote %s\n", path);
        f = open_out(out_dir, scn, "_metrics.json", path, sizeof path);
        if (f == NULL) {
            return MAIN_EXIT_FAIL;
        }
        rc = sim_result_json(f, &r);
        if (close_out(f, path) != 0 || rc != TV_OK) {
            return MAIN_EXIT_FAIL;
        }
        fprintf(stderr, "wrote %s\n", path);
    }
    return 0;
}
