/**
 * @file qemu_bench.c
 * @brief Instruction-count benchmark of the application step and of the EKF step on the
 *        Cortex-M4F build, in QEMU mps2-an386 (tools/m4f/bench_qemu.sh drives it).
 *
 *   qemu_bench gen OUT STEPS   write the scenario of tvlog_gen.h (plant in closed loop) to OUT;
 *                              run WITHOUT instruction logging (the plant is not measured)
 *   qemu_bench run IN          replay IN; each app_step() is bracketed by marker functions,
 *                              then the same filter step (ekf_predict, ekf_correct on a copy of
 *                              the filter as it was before the step) is bracketed again; run
 *                              with QEMU's "-d in_asm,exec,nochain" log, from which
 *                              tools/m4f/count_insns.py counts the instructions executed
 *                              between each pair of markers outside this file's main()
 *
 * Markers: bench_app_<category>() before an application step (its category: the mode, or
 * "safe" with latched faults, or "gap" when samples were lost before it), bench_pred() /
 * bench_corr() before ekf_predict / ekf_correct, bench_end() after each. After the replay, two
 * costs the stream does not reach: bench_pred_hc() before ekf_predict with a learned
 * Hunt-Crossley contact law and the plate in contact (pressed against the open stop, and an
 * impact into it), bench_fit() before each period of the start-up stop learning's fitting stage
 * (sl_step() in stage 3: SL_FIT_PER_STEP exponents of the joint contact-law fit per period). Distinct bodies keep
 * the compiler from merging them (identical-code folding would give them one address).
 */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "app.h"
#include "ekf.h"
#include "semihost.h"
#include "stop_learn.h"
#include "startup.h"
#include "tv_status.h"
#include "tvlog.h"
#include "tvlog_gen.h"

#define MAX_RECORDS 8000u

static tvlog_gen_t s_gen;
static app_t s_app;
static ekf_t s_shadow;
static uint8_t s_in[MAX_RECORDS * TVLOG_IN_BYTES];
static char s_cmdline[512];

/** Written by the markers (volatile: each marker is a real store at a distinct address). */
volatile uint32_t g_bench_mark;

#define MARKER(name, value)                                                                        \
    __attribute__((noinline)) void name(void);                                                     \
    __attribute__((noinline)) void name(void) { g_bench_mark = (value); }
MARKER(bench_app_off, 0x10u)
MARKER(bench_app_sine, 0x11u)
MARKER(bench_app_steps, 0x12u)
MARKER(bench_app_chirp, 0x13u)
MARKER(bench_app_position, 0x14u)
MARKER(bench_app_safe, 0x15u)
MARKER(bench_app_gap, 0x16u)
MARKER(bench_pred, 0x20u)
MARKER(bench_corr, 0x21u)
MARKER(bench_pred_hc, 0x22u)
MARKER(bench_fit, 0x23u)
MARKER(bench_end, 0x30u)

void startup_fault_hook(uint32_t exception_number)
{
    sh_puts("qemu_bench: fault, exception ");
    sh_put_u32(exception_number);
    sh_puts("\n");
    sh_exit(3);
}

static void fail(const char *what)
{
    sh_puts("qemu_bench: ");
    sh_puts(what);
    sh_puts("\n");
    sh_exit(2);
}

static uint32_t parse_u32(const char *s)
{
    uint32_t v = 0u;
    while (*s >= '0' && *s <= '9') {
        v = 10u * v + (uint32_t)(*s++ - '0');
    }
    return v;
}

static int gen(const char *path, uint32_t steps)
{
    uint8_t hdr[TVLOG_HEADER_BYTES];
    uint32_t written = 0u;
    tvlog_in_t r;
    int rc;
    const int32_t fd = sh_open(path, SH_MODE_WB);
    if (fd < 0 || tvlog_gen_init(&s_gen, steps, 20240501u) != 0) {
        fail("gen: cannot open the output or initialise");
    }
    /* The record count goes in the header, known only at the end: collect, then write. */
    while ((rc = tvlog_gen_next(&s_gen, &r)) >= 0) {
        if (rc == 1) {
            if (written >= MAX_RECORDS) {
                fail("gen: too many steps");
            }
            tvlog_in_encode(&s_in[written * TVLOG_IN_BYTES], &r);
            ++written;
        }
    }
    if (rc != -1) {
        fail("gen: plant failed");
    }
    tvlog_header_encode(hdr, TVLOG_MAGIC_IN, written, TVLOG_IN_BYTES);
    if (sh_write(fd, hdr, sizeof hdr) != 0 || sh_write(fd, s_in, written * TVLOG_IN_BYTES) != 0) {
        fail("gen: write failed");
    }
    (void)sh_close(fd);
    sh_puts("qemu_bench: generated ");
    sh_put_u32(written);
    sh_puts(" records\n");
    return 0;
}

/* The contact costs the replayed stream (the model's Kelvin-Voigt stops) does not reach. */
static void bench_contact(void)
{
    static ekf_t tmpl;
    static ekf_t e;
    /* rest angles of a learned law at the routine's four net torques (values of a training unit) */
    static const tv_real_t a[2][SL_LEVELS] = {{TV_R(-0.1046), TV_R(-0.1037), TV_R(-0.1030), TV_R(-0.1019)},
                                              {TV_R(1.3707), TV_R(1.3698), TV_R(1.3691), TV_R(1.3680)}};
    static sl_t sl;
    tvm_params_t p;
    ekf_config_t c;
    sl_config_t slc;
    int n;
    tvm_params_default(&p);
    p.stop_exponent = TV_R(1.25);
    p.k_stop_Nm_rad = TV_R(2.0e4);
    p.d_stop_Nm_s_rad = TV_R(0.16) * p.k_stop_Nm_rad;
    ekf_config_default(&c, EKF_SETUP_CURRENT_ANGLE);
    if (ekf_init(&tmpl, &p, &c) != TV_OK) {
        fail("bench_contact: ekf_init failed");
    }
    for (n = 0; n < 100; ++n) {
        e = tmpl;
        /* even: pressed 1 mrad into the open stop under 10 V; odd: 2 mrad short of it at 10 rad/s */
        e.x[TVM_I] = TV_R(2.0);
        e.x[TVM_W] = (n & 1) != 0 ? TV_R(10.0) : TV_R(0.0);
        e.x[TVM_PHI] = p.phi_open_rad + ((n & 1) != 0 ? TV_R(-0.002) : TV_R(0.001));
        bench_pred_hc();
        (void)ekf_predict(&e, TV_R(10.0));
        bench_end();
    }
    /* the routine as stop_measured() leaves it when the open stop's last level is measured */
    sl_config_default(&slc);
    tvm_params_default(&p);
    if (sl_start(&sl, &slc, &p) != TV_OK) {
        fail("bench_contact: sl_start failed");
    }
    memcpy(sl.rest_rad, a, sizeof sl.rest_rad);
    sl.phase = SL_OPEN;
    sl.phi_closed_rad = a[0][SL_LEVELS - 1u];
    sl.phi_open_rad = a[1][SL_LEVELS - 1u];
    sl.n_phase = 1u;
    sl.stage = 3u;
    sl.fit_g = 0u;
    sl.fit_sse_best = TV_R(-1.0);
    for (n = 0; n < 100 && sl.phase == SL_OPEN; ++n) {
        bench_fit();
        (void)sl_step(&sl, sl.phi_open_rad);
        bench_end();
    }
    if (sl.phase != SL_DONE) {
        fail("bench_contact: the fitting stage did not end in SL_DONE");
    }
}

static int run(const char *path)
{
    uint8_t hdr[TVLOG_HEADER_BYTES];
    uint32_t n = 0u;
    uint32_t k;
    uint64_t last_t = 0u;
    const int32_t fd = sh_open(path, SH_MODE_RB);
    if (fd < 0 || sh_read(fd, hdr, sizeof hdr) != (int32_t)sizeof hdr ||
        tvlog_header_decode(hdr, TVLOG_MAGIC_IN, TVLOG_IN_BYTES, &n) != 0 || n > MAX_RECORDS ||
        sh_read(fd, s_in, n * TVLOG_IN_BYTES) != (int32_t)(n * TVLOG_IN_BYTES)) {
        fail("run: cannot read the input");
    }
    (void)sh_close(fd);
    if (tvlog_replay_init(&s_app, 0) != 0) {
        fail("run: app_init failed");
    }
    for (k = 0u; k < n; ++k) {
        tvlog_in_t rec;
        app_input_t in;
        app_output_t out;
        tv_real_t u;
        tvlog_in_decode(&s_in[k * TVLOG_IN_BYTES], &rec);
        tvlog_apply_cmd(&s_app, &rec);
        memcpy(in.adc, rec.adc, sizeof in.adc);
        in.t_us = rec.t_us;
        in.driver_fault = rec.driver_fault;
        s_shadow = s_app.ekf;
        u = s_app.u_applied_V;

        if (k > 0u && rec.t_us - last_t > 1500u) {
            bench_app_gap();
        } else if (s_app.faults != 0u) {
            bench_app_safe();
        } else {
            switch (s_app.cfg.control.mode) {
            case APP_MODE_SINE: bench_app_sine(); break;
            case APP_MODE_STEPS: bench_app_steps(); break;
            case APP_MODE_CHIRP: bench_app_chirp(); break;
            case APP_MODE_POSITION: bench_app_position(); break;
            case APP_MODE_OFF:
            default: bench_app_off(); break;
            }
        }
        app_step(&s_app, &in, &out);
        bench_end();
        last_t = rec.t_us;

        /* The filter step the application just did, again on the copy: one prediction and one
         * correction (steps after a gap predict several times: not an EKF step). */
        if (out.missing_samples == 0u && out.innov.n_used > 0u) {
            ekf_meas_t meas;
            ekf_innov_t innov;
            memcpy(meas.z, out.z, sizeof meas.z);
            bench_pred();
            (void)ekf_predict(&s_shadow, u);
            bench_end();
            bench_corr();
            (void)ekf_correct(&s_shadow, &meas, &innov);
            bench_end();
        }
    }
    bench_contact();
    sh_puts("qemu_bench: ");
    sh_put_u32(n);
    sh_puts(" steps replayed; stack high-water ");
    sh_put_u32(startup_stack_high_water_bytes());
    sh_puts(" of ");
    sh_put_u32(startup_stack_size_bytes());
    sh_puts(" bytes\n");
    return 0;
}

int main(void)
{
    char *argv[4];
    uint32_t argc;
    if (sh_get_cmdline(s_cmdline, sizeof s_cmdline) != 0) {
        fail("no command line");
    }
    argc = sh_split_words(s_cmdline, argv, 4u);
    if (argc == 4u && strcmp(argv[1], "gen") == 0) {
        sh_exit(gen(argv[2], parse_u32(argv[3])));
    }
    if (argc == 3u && strcmp(argv[1], "run") == 0) {
        sh_exit(run(argv[2]));
    }
    fail("usage: qemu_bench gen OUT STEPS | run IN");
    return 2;
}
