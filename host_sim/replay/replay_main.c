/**
 * @file replay_main.c
 * @brief replay: run a logged raw ADC stream through the firmware's application step and
 *        write the estimates as CSV (see usage() and host_sim/replay/replay.h).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "diag_csv.h"
#include "params.h"
#include "replay.h"
#include "tv_status.h"

static const char *s_prog = "replay";

#define usage_error(...) cli_usage_error(s_prog, __VA_ARGS__)

/* The reader and the parameters are large: static, one run per process. */
static rlr_t s_reader;
static params_t s_params;
static char s_outbuf[262144];

static void usage(FILE *f)
{
    fprintf(f,
            "usage: %s [options] [LOG | -]\n"
            "\n"
            "Replays a raw ADC log (CSV or binary TVRAWLOG, host_sim/replay/LOG_FORMATS.md; '-' or no LOG: stdin)\n"
            "through the firmware's own application step (%s build): count calibration, plausibility checks\n"
            "and EKF, with the logged duty (APP_MODE_EXTERNAL). Writes one CSV line per sample: estimates,\n"
            "their standard deviations, innovations, NIS, fault flags.\n"
            "\n"
            "  --format auto|csv|bin   input format (default auto: the TVRAWLOG magic means binary)\n"
            "  -o, --out FILE|-        output CSV (default stdout)\n"
            "  --setup 2|3             measurements: 2 = current + angle (default), 3 = the paper's current +\n"
            "                          differentiated velocity + angle\n"
            "  --params FILE           parameter file (key = value; --print-params shows every key)\n"
            "  --qu X, --qT X          process-noise densities [V^2 s], [N^2 m^2 s], >= 0 (Q recomputed)\n"
            "  --r-current X           current measurement VARIANCE [A^2], > 0\n"
            "  --r-angle X             angle measurement VARIANCE [rad^2], > 0\n"
            "  --r-velocity X          differentiated-velocity VARIANCE [(rad/s)^2], > 0\n"
            "                          (these override the parameter file)\n"
            "  --start S, --stop S     replay only the samples with start <= t_us / 1e6 <= stop [s]\n"
            "  --on-error stop|skip    stop at the first bad input (default), or skip it, count it, go on\n"
            "  --max-messages N        messages printed per kind of error (default %u)\n"
            "  --wide                  also measurements, supply voltage, innovation sigmas\n"
            "  --events FILE           write the diagnostic events (firmware/diag/diag.h) as CSV:\n"
            "                          t_us,status,fault_class,dtc (status pending|confirmed|healed)\n"
            "  --winding-temp C        the winding's temperature during the log [degC], -40 .. 180, told to\n"
            "                          the application (the CAN command's WindingTemp): the resistance\n"
            "                          check refers R (at 20 degC) to it (default: unknown)\n"
            "  --parse-only            read and validate the log only (no estimator, no output)\n"
            "  --timing                print timing (share outside the estimator) and peak RSS at the end\n"
            "  --quiet                 no summary on stderr (errors are still printed)\n"
            "  --print-params          print the default parameter file and exit\n"
            "  --help                  this text\n"
            "\n"
            "A progress line is shown on stderr when stderr is a terminal.\n"
            "Exit codes: 0 ok; 1 I/O error; 2 usage; 3 parameter file invalid; 4 configuration rejected\n"
            "(sample rate not 1000 Hz, calibration unusable); input errors (first one, or fatal):\n"
            "5 empty input, 6 bad header/metadata, 7 bad magic, 8 unsupported version, 9 line too long,\n"
            "10 wrong column count, 11 not a number, 12 non-finite value, 13 value out of range,\n"
            "14 timestamp going backwards, 15 repeated timestamp, 16 CRC mismatch, 17 bad block header,\n"
            "18 truncated input; 19 finished with --on-error skip after skipping input.\n",
            s_prog, TV_REAL_IS_DOUBLE ? "double" : "float", REPLAY_MESSAGES_DEFAULT);
}

int main(int argc, char **argv)
{
    replay_options_t opt;
    replay_stats_t st;
    rlr_format_t format = RLR_FMT_AUTO;
    const char *in_path = NULL;
    const char *out_path = NULL;
    const char *events_path = NULL;
    const char *params_path = NULL;
    int quiet = 0;
    int print_params = 0;
    int k;
    int rc;
    FILE *in;
    FILE *out = NULL;
    char err[PARAMS_MSG_MAX];
    /* overrides, applied after the file */
    cli_noise_overrides_t ov;
    static const char *const takes_value[] = {"--format", "-o", "--out", "--setup", "--params", "--qu", "--qT",
                                              "--r-current", "--r-angle", "--r-velocity", "--start", "--stop",
                                              "--on-error", "--max-messages", "--events", "--winding-temp", NULL};

    replay_options_default(&opt);
    memset(&ov, 0, sizeof ov);
    for (k = 1; k < argc; ++k) {
        const char *a = argv[k];
        const char *v = k + 1 < argc ? argv[k + 1] : NULL;
        double d = 0.0;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return RLR_EXIT_OK;
        }
        if (strcmp(a, "--wide") == 0) {
            opt.wide = 1;
            continue;
        }
        if (strcmp(a, "--parse-only") == 0) {
            opt.parse_only = 1;
            continue;
        }
        if (strcmp(a, "--timing") == 0) {
            opt.timing = 1;
            continue;
        }
        if (strcmp(a, "--quiet") == 0) {
            quiet = 1;
            continue;
        }
        if (strcmp(a, "--print-params") == 0) {
            print_params = 1;
            continue;
        }
        if (strcmp(a, "-") == 0 || a[0] != '-') {
            if (cli_set_input(s_prog, &in_path, a) != 0) {
                return CLI_EXIT_USAGE;
            }
            continue;
        }
        if (cli_option_value(s_prog, a, v, takes_value) != 0 || v == NULL) { /* (v: for the analyser) */
            return CLI_EXIT_USAGE;
        }
        ++k;
        if (strcmp(a, "--format") == 0) {
            if (rlr_format_from_name(v, &format) != TV_OK) {
                return usage_error("option %s: '%s' is not auto, csv or bin", a, v);
            }
        } else if (strcmp(a, "-o") == 0 || strcmp(a, "--out") == 0) {
            out_path = v;
        } else if (strcmp(a, "--winding-temp") == 0) {
            if (cli_parse_temp(v, &d) != 0) {
                return usage_error("option %s: '%s' is not a temperature in -40 .. 180 degC", a, v);
            }
            opt.temp_known = 1;
            opt.winding_temp_C = d;
        } else if (strcmp(a, "--events") == 0) {
            if (*v == '\0') {
                return usage_error("option %s: empty path", a);
            }
            events_path = v;
        } else if (strcmp(a, "--params") == 0) {
            params_path = v;
        } else if (strcmp(a, "--setup") == 0) {
            if (strcmp(v, "2") == 0) {
                opt.setup = EKF_SETUP_CURRENT_ANGLE;
            } else if (strcmp(v, "3") == 0) {
                opt.setup = EKF_SETUP_PAPER_3MEAS;
            } else {
                return usage_error("option %s: '%s' is not 2 or 3", a, v);
            }
        } else if (strcmp(a, "--on-error") == 0) {
            if (cli_on_error(s_prog, a, v, &opt.skip_errors) != 0) {
                return CLI_EXIT_USAGE;
            }
        } else if (cli_noise_index(a) >= 0) {
            rc = cli_noise_set(s_prog, &ov, a, v);
            if (rc != 0) {
                return rc;
            }
        } else {
            if (cli_parse_double(v, &d) != 0) {
                return usage_error("option %s: '%s' is not a finite number", a, v);
            }
            if (strcmp(a, "--start") == 0 || strcmp(a, "--stop") == 0) {
                if (d < 0.0) {
                    return usage_error("option %s: %s is negative", a, v);
                }
                if (strcmp(a, "--start") == 0) {
                    opt.has_start = 1;
                    opt.start_s = d;
                } else {
                    opt.has_stop = 1;
                    opt.stop_s = d;
                }
            } else {
                if (d < 0.0 || d > 1e9 || d != (double)(long)d) {
                    return usage_error("option %s: '%s' is not an integer in 0..1e9", a, v);
                }
                opt.max_messages = (unsigned)d;
            }
        }
    }
    if (opt.has_start && opt.has_stop && opt.stop_s < opt.start_s) {
        return usage_error("--stop is before --start");
    }

    params_init(&s_params, params_path != NULL ? params_path : "command line");
    if (params_path != NULL) {
        rc = params_load(&s_params, params_path, err, sizeof err);
        if (rc != TV_OK) {
            fprintf(stderr, "%s: %s\n", s_prog, err);
            return rc == TV_ERR_IO ? RLR_EXIT_IO : RLR_EXIT_PARAMS;
        }
    }
    for (k = 0; k < (int)CLI_NOISE_N; ++k) {
        if (ov.given[k]) {
            rc = params_set(&s_params, cli_noise_param_key((cli_noise_t)k), ov.value[k], err, sizeof err);
            if (rc != TV_OK) {
                return usage_error("%s", err);
            }
        }
    }
    opt.params = &s_params;
    opt.params_name = params_path;

    {
        /* Cross-field rules (e.g. Mc <= Ms) are checked here, before any input is read, so an
         * invalid parameter file exits 3 as it does in host_sim, whatever the log holds. */
        app_config_t cfg;
        app_config_default(&cfg);
        rc = params_apply(&s_params, &cfg, err, sizeof err);
        if (rc != TV_OK) {
            fprintf(stderr, "%s: %s\n", s_prog, err);
            return RLR_EXIT_PARAMS;
        }
        if (print_params) {
            return params_write(stdout, &cfg) == TV_OK ? RLR_EXIT_OK : RLR_EXIT_IO;
        }
    }

    if (!opt.parse_only && cli_refuse_output_is_input(s_prog, in_path, out_path)) {
        return RLR_EXIT_USAGE;
    }
    in = cli_open_input(s_prog, &in_path);
    if (in == NULL) {
        return RLR_EXIT_IO;
    }
    if (!opt.parse_only) {
        if (out_path == NULL || strcmp(out_path, "-") == 0) {
            out = stdout;
            out_path = "<stdout>";
        } else {
            out = fopen(out_path, "w");
            if (out == NULL) {
                fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, out_path, strerror(errno));
                if (in != stdin) {
                    (void)fclose(in);
                }
                return RLR_EXIT_IO;
            }
        }
        (void)setvbuf(out, s_outbuf, _IOFBF, sizeof s_outbuf);
    }
    if (events_path != NULL && !opt.parse_only) {
        if (cli_same_file(in_path, events_path)) {
            fprintf(stderr, "%s: the events file %s is the input log: refusing to overwrite it\n", s_prog, events_path);
            rc = RLR_EXIT_USAGE;
        } else {
            opt.events = fopen(events_path, "w");
            rc = opt.events != NULL && diag_csv_header(opt.events) == TV_OK ? RLR_EXIT_OK : RLR_EXIT_IO;
            if (rc != RLR_EXIT_OK) {
                fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, events_path, strerror(errno));
            }
        }
        if (rc != RLR_EXIT_OK) {
            if (opt.events != NULL) {
                (void)fclose(opt.events);
            }
            if (in != stdin) {
                (void)fclose(in);
            }
            if (out != NULL && out != stdout) {
                (void)fclose(out);
            }
            return rc;
        }
    }
    opt.out = out;
    opt.diag = stderr;
    opt.progress = isatty(fileno(stderr)) && !quiet;

    rc = rlr_open_file(&s_reader, in, in_path, format, 0u);
    if (rc != TV_OK) {
        fprintf(stderr, "%s: %s\n", s_prog, rlr_message(&s_reader));
        rc = rlr_exit_code(rlr_error(&s_reader));
    } else {
        (void)replay_run(&s_reader, &opt, &st);
        if (!quiet || opt.timing) {
            replay_print_summary(stderr, &s_reader, &st, &opt);
        }
        rc = replay_exit_code(&st);
    }
    if (in != stdin) {
        (void)fclose(in);
    }
    if (opt.events != NULL && fclose(opt.events) != 0 && rc == RLR_EXIT_OK) {
        fprintf(stderr, "%s: error writing %s\n", s_prog, events_path);
        rc = RLR_EXIT_IO;
    }
    if (out != NULL && out != stdout) {
        if (fclose(out) != 0 && rc == RLR_EXIT_OK) {
            fprintf(stderr, "%s: error writing %s\n", s_prog, out_path);
            rc = RLR_EXIT_IO;
        }
    } else if (out != NULL && fflush(out) != 0 && rc == RLR_EXIT_OK) {
        rc = RLR_EXIT_IO;
    }
    return rc;
}
