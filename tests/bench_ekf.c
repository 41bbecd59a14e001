/**
 * @file bench_ekf.c
 * @brief Workload for instruction counting: `bench_ekf <filter|full> <steps> [2|3]`.
 *
 * Runs <steps> EKF cycles on the paper's 12 V / 5 Hz trajectory inside bench_run(), which
 * tools/bench_callgrind.sh counts with `valgrind --tool=callgrind --toggle-collect=bench_run`
 * (instruction counts are repeatable; wall time on a shared machine is not). Inputs and
 * measurements are prepared before bench_run() so only the filter is counted.
 *   filter: covariance propagation with a fixed Jacobian (ekf_propagate) + correction: the
 *           filter arithmetic alone;
 *   full:   ekf_predict (model map + analytic Jacobian + propagation) + correction.
 * The optional last argument picks 2 measurements (current + angle, default) or 3 (the paper's
 * current + velocity + angle).
 * Prints a checksum of the final state so the work cannot be optimised away.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ekf.h"

#define BENCH_MAX_STEPS 20000

static tv_real_t s_u[BENCH_MAX_STEPS];
static ekf_meas_t s_z[BENCH_MAX_STEPS];

__attribute__((noinline)) static double bench_run(ekf_t *f, int full, long steps, tv_real_t F[TVM_NX][TVM_NX])
{
    long k;
    double acc = 0.0;
    ekf_innov_t out;
    for (k = 0; k < steps; ++k) {
        if (full) {
            (void)ekf_predict(f, s_u[k]);
        } else {
            (void)ekf_propagate(f, f->x, F);
        }
        (void)ekf_correct(f, &s_z[k], &out);
        acc += (double)out.nis_total;
    }
    return acc;
}

int main(int argc, char **argv)
{
    tvm_params_t p;
    ekf_config_t cfg;
    tvm_t m;
    ekf_t f;
    tv_real_t x[TVM_NX] = {TV_R(0.0), TV_R(0.0), TV_R(0.0)};
    tv_real_t F[TVM_NX][TVM_NX];
    long steps;
    long k;
    int full;
    double acc;
    char *end = NULL;
    int nmeas = 2;
    if ((argc != 3 && argc != 4) || (strcmp(argv[1], "filter") != 0 && strcmp(argv[1], "full") != 0) ||
        (argc == 4 && strcmp(argv[3], "2") != 0 && strcmp(argv[3], "3") != 0)) {
        fprintf(stderr, "usage: %s <filter|full> <steps 1..%d> [2|3]\n", argv[0], BENCH_MAX_STEPS);
        return 2;
    }
    if (argc == 4) {
        nmeas = argv[3][0] - '0';
    }
    full = strcmp(argv[1], "full") == 0;
    steps = strtol(argv[2], &end, 10);
    if (end == argv[2] || *end != '\0' || steps < 1 || steps > BENCH_MAX_STEPS) {
        fprintf(stderr, "%s: steps must be 1..%d, got '%s'\n", argv[0], BENCH_MAX_STEPS, argv[2]);
        return 2;
    }
    tvm_params_default(&p);
    ekf_config_default(&cfg, nmeas == 3 ? EKF_SETUP_PAPER_3MEAS : EKF_SETUP_CURRENT_ANGLE);
    if (tvm_init(&m, &p) != 0 || ekf_init(&f, &p, &cfg) != 0) {
        fprintf(stderr, "%s: init failed\n", argv[0]);
        return 1;
    }
    for (k = 0; k < steps; ++k) {
        s_u[k] = (tv_real_t)(12.0 * sin(2.0 * 3.14159265358979323846 * 5.0 * (double)k * 1e-3));
        tvm_step(&m, x, s_u[k], x, F);
        s_z[k].z[EKF_CH_CURRENT] = x[0] + TV_R(0.003);
        s_z[k].z[EKF_CH_VELOCITY] = x[1];
        s_z[k].z[EKF_CH_ANGLE] = x[2] - TV_R(5e-5);
    }
    /* A representative Jacobian for the filter-only mode: the map's at the last state. */
    acc = bench_run(&f, full, steps, F);
    printf("bench_ekf %s %s meas=%d steps=%ld checksum=%.9g x=(%.6g, %.6g, %.6g)\n", TV_REAL_IS_DOUBLE ? "f64" : "f32",
           argv[1], nmeas, steps, acc, (double)f.x[0], (double)f.x[1], (double)f.x[2]);
    return 0;
}
