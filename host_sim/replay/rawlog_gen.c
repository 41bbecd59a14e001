/**
 * @file rawlog_gen.c
 * @brief rawlog_gen: write a long raw ADC log of the high-fidelity plant (host_sim/plant/plant.h)
 *        driven open loop, streaming (constant memory whatever the length), for the replay
 *        throughput benchmark and for tests. See usage().
 *
 * The drive repeats a 10 s programme: 4 s of the paper's 12 V / 5 Hz sine, 4 s of a 1 -> 20 Hz
 * chirp of 10 V, 2 s with the bridge disabled (the plate returns to limp-home). The duty is
 * u / 13.5 V (the plant's nominal supply) as float, like the application's.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "params.h"
#include "plant.h"
#include "rawlog_write.h"
#include "tv_status.h"

static const char *s_prog = "rawlog_gen";
static rlw_t s_writer;
static plant_t s_plant;
static char s_outbuf[262144];

/* Longest log written [s] (a day). */
#define GEN_SECONDS_MAX 86400.0
#define GEN_PI 3.14159265358979323846

static void usage(FILE *f)
{
    fprintf(f,
            "usage: %s --seconds S -o FILE [--format csv|bin] [--seed N] [--truth] [--block-records N]\n"
            "Writes S seconds (0 < S <= %g) of a 1 kHz raw ADC log of the simulated plant, driven open\n"
            "loop (sine, chirp, bridge off, repeating every 10 s), in CSV (default) or binary.\n",
            s_prog, GEN_SECONDS_MAX);
}

/* Duty of the drive programme at t [s], and the enable. */
static float drive(double t_s, int *enable)
{
    const double tau = fmod(t_s, 10.0);
    double u_V;
    *enable = 1;
    if (tau < 4.0) {
        u_V = 12.0 * sin(2.0 * GEN_PI * 5.0 * tau);
    } else if (tau < 8.0) {
        const double c = tau - 4.0;
        u_V = 10.0 * sin(2.0 * GEN_PI * (1.0 * c + (20.0 - 1.0) * c * c / (2.0 * 4.0)));
    } else {
        *enable = 0;
        return 0.0f;
    }
    return (float)(u_V / 13.5);
}

int main(int argc, char **argv)
{
    double seconds = 0.0;
    const char *path = NULL;
    rlr_format_t format = RLR_FMT_CSV;
    unsigned long long seed = 1u;
    unsigned long block_records = RAWLOG_BLOCK_RECORDS_DEFAULT;
    int truth = 0;
    plant_config_t pc;
    app_calib_t cal;
    tvm_params_t mp;
    rawlog_header_t h;
    FILE *f;
    uint64_t n;
    uint64_t k;
    int rc;
    int a;

    for (a = 1; a < argc; ++a) {
        const char *o = argv[a];
        const char *v = a + 1 < argc ? argv[a + 1] : NULL;
        char *end = NULL;
        if (strcmp(o, "--help") == 0) {
            usage(stdout);
            return 0;
        }
        if (strcmp(o, "--truth") == 0) {
            truth = 1;
            continue;
        }
        if (v == NULL) {
            usage(stderr);
            return 2;
        }
        ++a;
        errno = 0;
        if (strcmp(o, "--seconds") == 0) {
            seconds = strtod(v, &end);
            if (end == v || *end != '\0' || !(seconds > 0.0) || seconds > GEN_SECONDS_MAX) {
                fprintf(stderr, "%s: --seconds %s: not in (0, %g]\n", s_prog, v, GEN_SECONDS_MAX);
                return 2;
            }
        } else if (strcmp(o, "-o") == 0) {
            path = v;
        } else if (strcmp(o, "--format") == 0) {
            if (rlr_format_from_name(v, &format) != TV_OK || format == RLR_FMT_AUTO) {
                fprintf(stderr, "%s: --format %s: not csv or bin\n", s_prog, v);
                return 2;
            }
        } else if (strcmp(o, "--seed") == 0) {
            seed = strtoull(v, &end, 10);
            if (end == v || *end != '\0' || errno != 0) {
                fprintf(stderr, "%s: --seed %s: not an unsigned integer\n", s_prog, v);
                return 2;
            }
        } else if (strcmp(o, "--block-records") == 0) {
            block_records = strtoul(v, &end, 10);
            if (end == v || *end != '\0' || block_records < 1u || block_records > RAWLOG_BLOCK_RECORDS_MAX) {
                fprintf(stderr, "%s: --block-records %s: not in 1..%u\n", s_prog, v, RAWLOG_BLOCK_RECORDS_MAX);
                return 2;
            }
        } else {
            usage(stderr);
            return 2;
        }
    }
    if (path == NULL || !(seconds > 0.0)) {
        usage(stderr);
        return 2;
    }
    plant_config_default(&pc);
    rc = plant_init(&s_plant, &pc, (uint64_t)seed);
    if (rc != TV_OK) {
        fprintf(stderr, "%s: plant_init: %s\n", s_prog, tv_status_str(rc));
        return 1;
    }
    tvm_params_default(&mp);
    app_calib_default(&cal, &mp);
    rawlog_header_default(&h);
    h.flags = truth ? RAWLOG_FLAG_TRUTH : 0u;
    h.records_per_block = (uint16_t)block_records;
    h.adc_bits = (uint8_t)pc.adc_bits;
    params_calib_to_header(&cal, &h);
    f = fopen(path, format == RLR_FMT_BIN ? "wb" : "w");
    if (f == NULL) {
        fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, path, strerror(errno));
        return 1;
    }
    (void)setvbuf(f, s_outbuf, _IOFBF, sizeof s_outbuf);
    rc = rlw_open(&s_writer, f, format, &h, "generated by rawlog_gen: plant driven open loop (sine, chirp, bridge off)");
    n = (uint64_t)floor(seconds * 1000.0 + 0.5);
    for (k = 0; rc == TV_OK && k < n; ++k) {
        rawlog_record_t r;
        plant_adc_t adc;
        plant_state_t st;
        int en = 0;
        memset(&r, 0, sizeof r);
        rc = plant_sample(&s_plant, &adc);
        if (rc != TV_OK) {
            break;
        }
        (void)plant_truth(&s_plant, &st);
        r.t_us = k * 1000u;
        r.adc[0] = adc.current_counts;
        r.adc[1] = adc.tps1_counts;
        r.adc[2] = adc.tps2_counts;
        r.adc[3] = adc.supply_counts;
        r.duty = drive((double)k * 1e-3, &en);
        r.bridge_enable = (uint8_t)en;
        r.truth[0] = st.current_A;
        r.truth[1] = st.velocity_rad_s;
        r.truth[2] = st.angle_rad;
        rc = rlw_put(&s_writer, &r);
        if (rc == TV_OK) {
            rc = plant_set_bridge(&s_plant, (double)r.duty, en);
        }
        if (rc == TV_OK) {
            rc = plant_advance(&s_plant, 1e-3);
        }
    }
    if (rc != TV_OK) {
        fprintf(stderr, "%s: failed at sample %llu: %s\n", s_prog, (unsigned long long)k, tv_status_str(rc));
    }
    if (rlw_close(&s_writer) != TV_OK || fclose(f) != 0) {
        fprintf(stderr, "%s: writing %s failed\n", s_prog, path);
        return 1;
    }
    if (rc != TV_OK) {
        return 1;
    }
    fprintf(stderr, "%s: wrote %s: %llu samples (%.3f s) in %s\n", s_prog, path, (unsigned long long)n,
            (double)n * 1e-3, rlr_format_name(format));
    return 0;
}
