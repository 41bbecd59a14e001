/**
 * @file main.c
 * @brief throttle_linux: the Linux real-time controller. The same 1 kHz application step as the
 *        ECU (app_tick()), on a SCHED_FIFO thread (rt_loop), with the Linux HAL (hal_linux:
 *        sysfs PWM, IIO ADC, libgpiod GPIO, SocketCAN) and the CAN protocol (can_proto).
 *
 *   throttle_linux -c FILE [--check]
 *
 * --check loads the configuration, opens every device, puts the outputs in the safe state and
 * exits (0 when everything is in order), without starting the loop.
 *
 * Exit status: 0 after SIGINT/SIGTERM or rt.duration_s; 1 when a device could not be opened or
 * the loop could not start; 2 for a bad command line or configuration; 3 when the loop stopped
 * on a fault (rt.max_io_errors consecutive failed ticks). In every case the outputs are put in
 * the safe state (PWM 0 and disabled, bridge disabled) before the program exits.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>

#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "app_tick.h"
#include "can_proto.h"
#include "hal_linux.h"
#include "lx_config.h"
#include "rt_loop.h"
#include "tv_status.h"

/* Everything the real-time tick uses; static (no heap), touched only by the loop thread while
 * it runs. */
typedef struct {
    app_t app;
    can_proto_node_t node;
    app_output_t out;
    uint32_t max_io_errors;
    uint32_t io_error_run;
    uint64_t io_errors;
    uint64_t can_tx_errors;
    uint64_t can_rx_errors;
    int last_error;
} ctl_t;

static ctl_t s_ctl;
static rt_loop_t s_loop;

static int tick(void *vctx, const rt_loop_stats_t *st)
{
    ctl_t *c = (ctl_t *)vctx;
    hal_can_frame_t frames[CAN_PROTO_N_TX];
    hal_can_frame_t f;
    can_proto_loop_stats_t ls;
    const uint32_t steps_before = c->app.n_steps;
    int rc;
    int stepped;
    uint64_t t_us;
    size_t n;
    size_t k;
    hal_linux_set_sample_time(st->deadline_ns);
    rc = app_tick(&c->app, &c->out);
    stepped = c->app.n_steps != steps_before;
    if (rc != TV_OK) {
        ++c->io_errors;
        c->last_error = rc;
        if (++c->io_error_run >= c->max_io_errors) {
            return -1;
        }
    } else {
        c->io_error_run = 0u;
    }
    t_us = hal_time_us();
    for (k = 0; k < CAN_PROTO_RX_MAX_PER_TICK; ++k) {
        const int r = hal_can_receive(&f);
        if (r != 1) {
            if (r < 0) {
                ++c->can_rx_errors;
            }
            break;
        }
        (void)can_proto_node_receive(&c->node, &c->app, &f, t_us);
    }
    can_proto_node_update(&c->node, &c->app, stepped ? &c->out : NULL, t_us);
    ls.overruns = st->overruns > 0xFFFFFFFFu ? 0xFFFFFFFFu : (uint32_t)st->overruns;
    ls.latency_max_us = st->latency_max_us;
    ls.exec_max_us = st->exec_max_us;
    ls.sample_time_us = (uint32_t)(hal_linux_last_read_us() & 0xFFFFFFFFu);
    n = can_proto_node_transmit(&c->node, &c->app, &c->out, &ls, rc != TV_OK, t_us, frames);
    for (k = 0; k < n; ++k) {
        if (hal_can_send(&frames[k]) != TV_OK) {
            ++c->can_tx_errors;
        }
    }
    return 0;
}

static void usage(void)
{
    fprintf(stderr, "usage: throttle_linux -c CONFIG_FILE [--check]\n"
                    "  see hal/linux/README.md and firmware/linux_rt/throttle_linux.conf\n");
}

static void summary(const rt_loop_stats_t *st, const ctl_t *c)
{
    const can_proto_rx_stats_t *rx = &c->node.stats;
    printf("throttle_linux: ticks %llu, overruns %llu, wake-up latency mean %.1f us, p99 <= %u us, "
           "p99.9 <= %u us, max %u us, exec max %u us\n",
           (unsigned long long)st->ticks, (unsigned long long)st->overruns,
           st->ticks > 0u ? (double)st->latency_sum_us / (double)st->ticks : 0.0,
           (unsigned)rt_loop_latency_quantile_us(st, 0.99), (unsigned)rt_loop_latency_quantile_us(st, 0.999),
           (unsigned)st->latency_max_us, (unsigned)st->exec_max_us);
    printf("throttle_linux: faults 0x%02x, io errors %llu, can tx errors %llu, can rx errors %llu; commands "
           "accepted %u, rejected: crc %u, dlc %u, repeated %u, sequence %u, range %u, unknown %u; timeouts %u\n",
           (unsigned)c->app.faults, (unsigned long long)c->io_errors, (unsigned long long)c->can_tx_errors,
           (unsigned long long)c->can_rx_errors, (unsigned)rx->accepted, (unsigned)rx->crc, (unsigned)rx->dlc,
           (unsigned)rx->repeated, (unsigned)rx->sequence, (unsigned)rx->range, (unsigned)rx->unknown,
           (unsigned)rx->timeouts);
}

int main(int argc, char **argv)
{
    static lx_config_t cfg;
    app_config_t acfg;
    rt_loop_config_t lc;
    char err[LX_ERR_LEN];
    const char *path = NULL;
    int check_only = 0;
    sigset_t sigs;
    int i;
    int rc;
    int result;
    int exit_code = 0;

    for (i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "-c") == 0 && i + 1 < argc) {
            path = argv[++i];
        } else if (strcmp(argv[i], "--check") == 0) {
            check_only = 1;
        } else {
            usage();
            return 2;
        }
    }
    if (path == NULL) {
        usage();
        return 2;
    }
    if (lx_config_load(path, &cfg, err, sizeof err) != TV_OK) {
        fprintf(stderr, "throttle_linux: %s\n", err);
        return 2;
    }
    if (cfg.app_stops_file[0] != '\0') {
        /* the stops learned before (written at the last clean stop); none yet is no error */
        errno = 0;
        if (lx_config_overlay_model_file(cfg.app_stops_file, &cfg, err, sizeof err) == TV_OK) {
            printf("throttle_linux: stops and contact law from %s\n", cfg.app_stops_file);
        } else if (errno == ENOENT) {
            printf("throttle_linux: %s does not exist yet: the model's stops until the start-up routine learns them\n",
                   cfg.app_stops_file);
        } else {
            fprintf(stderr, "throttle_linux: %s\n", err);
            return 2;
        }
    }
    app_config_default(&acfg);
    lx_config_apply_app(&cfg, &acfg);
    rc = app_init(&s_ctl.app, &acfg);
    if (rc != TV_OK) {
        fprintf(stderr, "throttle_linux: %s: the application refused the app.* / calib.* / adc.max_counts values (%s)\n",
                path, tv_status_str(rc));
        return 2;
    }
    rc = can_proto_node_init(&s_ctl.node, &cfg.can, &s_ctl.app);
    if (rc != TV_OK) {
        fprintf(stderr, "throttle_linux: %s: can.* values refused (%s)\n", path, tv_status_str(rc));
        return 2;
    }
    s_ctl.max_io_errors = cfg.rt_max_io_errors;

    /* SIGINT/SIGTERM are taken synchronously by this thread (sigtimedwait below); blocked
     * before the loop thread exists, so it inherits the mask and never sees them. */
    sigemptyset(&sigs);
    sigaddset(&sigs, SIGINT);
    sigaddset(&sigs, SIGTERM);
    (void)pthread_sigmask(SIG_BLOCK, &sigs, NULL);

    (void)hal_linux_configure(&cfg.dev);
    if (hal_init() != TV_OK) {
        fprintf(stderr, "throttle_linux: %s\n", hal_linux_error());
        return 1;
    }
    if (check_only) {
        rc = hal_linux_safe_state();
        hal_linux_close();
        printf("throttle_linux: %s: configuration and devices OK%s\n", path, rc == TV_OK ? "" : " (safe state write failed)");
        return rc == TV_OK ? 0 : 1;
    }

    lc.priority = cfg.rt_priority;
    lc.cpu = cfg.rt_cpu;
    lc.lock_memory = cfg.rt_lock_memory;
    lc.period_us = APP_PERIOD_US;
    lc.max_ticks = (uint64_t)cfg.rt_duration_s * (1000000u / APP_PERIOD_US);
    if (rt_loop_start(&s_loop, &lc, tick, &s_ctl, err, sizeof err) != TV_OK) {
        hal_linux_close();
        fprintf(stderr, "throttle_linux: %s\n", err);
        return 1;
    }
    printf("throttle_linux: running (%s, period %u us, priority %d, cpu %d); SIGINT/SIGTERM stop it\n", path,
           (unsigned)APP_PERIOD_US, cfg.rt_priority, cfg.rt_cpu);
    printf("throttle_linux: clock: TV_TIME.SampleTime 0 = CLOCK_MONOTONIC %llu ns\n",
           (unsigned long long)hal_linux_t0_ns());
    fflush(stdout);
    for (;;) {
        const struct timespec wait = {0, 20000000L};
        const int sig = sigtimedwait(&sigs, NULL, &wait);
        if (sig == SIGINT || sig == SIGTERM) {
            printf("throttle_linux: %s, stopping\n", sig == SIGINT ? "SIGINT" : "SIGTERM");
            break;
        }
        if (rt_loop_is_done(&s_loop)) {
            break;
        }
    }
    rt_loop_request_stop(&s_loop);
    result = rt_loop_join(&s_loop);
    if (hal_linux_safe_state() != TV_OK) {
        fprintf(stderr, "throttle_linux: %s\n", hal_linux_error());
        exit_code = 3;
    }
    hal_linux_close();
    if (result < 0) {
        fprintf(stderr, "throttle_linux: stopped after %u consecutive failed ticks (last: %s); outputs safe\n",
                (unsigned)s_ctl.io_error_run, tv_status_str(s_ctl.last_error));
        exit_code = 3;
    }
    if (cfg.app_stops_file[0] != '\0') {
        /* the stops in use now (learned, then tracked in service), and the fit's baseline when there
         * is one (given or learned), for the next start */
        const tvm_params_t *mp = &s_ctl.app.ekf.model.p;
        if (lx_config_write_stops(cfg.app_stops_file, (double)mp->phi_closed_rad, (double)mp->phi_open_rad,
                                  (double)mp->k_stop_Nm_rad, (double)mp->stop_exponent, (double)mp->d_stop_Nm_s_rad,
                                  (double)s_ctl.app.fit_base_r_ohm, (double)s_ctl.app.fit_base_nke_V_s, err,
                                  sizeof err) == TV_OK) {
            printf("throttle_linux: stops written to %s (closed %.5f rad, open %.5f rad)\n", cfg.app_stops_file,
                   (double)mp->phi_closed_rad, (double)mp->phi_open_rad);
            if (s_ctl.app.fit_base_r_ohm > TV_R(0.0)) {
                printf("throttle_linux: the fit's baseline written there too (R %.5g ohm at 20 degC, n Ke %.5g V s/rad)\n",
                       (double)s_ctl.app.fit_base_r_ohm, (double)s_ctl.app.fit_base_nke_V_s);
            }
        } else {
            fprintf(stderr, "throttle_linux: %s\n", err);
            exit_code = exit_code == 0 ? 1 : exit_code;
        }
    }
    summary(&s_loop.stats, &s_ctl);
    printf("throttle_linux: outputs in the safe state (PWM 0 and disabled, bridge disabled)\n");
    return exit_code;
}
