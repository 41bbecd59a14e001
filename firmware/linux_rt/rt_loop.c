/**
 * @file rt_loop.c
 * @brief The periodic real-time thread (see rt_loop.h).
 */
#define _GNU_SOURCE /* CPU_SET, pthread_attr_setaffinity_np */

#include "rt_loop.h"

#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "lx_err.h"
#include "tv_status.h"

/* Stack touched before the first period, so the loop takes no page faults on it [bytes]. */
#define PREFAULT_STACK_BYTES (64u * 1024u)

static int64_t ts_ns(const struct timespec *ts)
{
    return (int64_t)ts->tv_sec * 1000000000 + (int64_t)ts->tv_nsec;
}

static void ts_add_ns(struct timespec *ts, int64_t ns)
{
    int64_t t = ts_ns(ts) + ns;
    ts->tv_sec = (time_t)(t / 1000000000);
    ts->tv_nsec = (long)(t % 1000000000);
}

static void prefault_stack(void)
{
    volatile unsigned char buf[PREFAULT_STACK_BYTES];
    size_t i;
    for (i = 0; i < sizeof buf; i += 256u) {
        buf[i] = 0u;
    }
}

static void *loop_thread(void *arg)
{
    rt_loop_t *loop = (rt_loop_t *)arg;
    const int64_t period_ns = (int64_t)loop->cfg.period_us * 1000;
    rt_loop_stats_t *st = &loop->stats;
    struct timespec next;
    prefault_stack();
    (void)clock_gettime(CLOCK_MONOTONIC, &next);
    ts_add_ns(&next, period_ns);
    while (!__atomic_load_n(&loop->stop, __ATOMIC_ACQUIRE)) {
        struct timespec now;
        struct timespec end;
        int64_t lat_ns;
        int64_t exec_ns;
        uint32_t lat_us;
        int r;
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL) == EINTR) {
        }
        (void)clock_gettime(CLOCK_MONOTONIC, &now);
        lat_ns = ts_ns(&now) - ts_ns(&next);
        if (lat_ns < 0) {
            lat_ns = 0;
        }
        if (lat_ns >= period_ns) { /* woke after whole periods: those are lost */
            const int64_t missed = lat_ns / period_ns;
            st->overruns += (uint64_t)missed;
            ts_add_ns(&next, missed * period_ns);
        }
        lat_us = (uint32_t)(lat_ns / 1000);
        st->latency_sum_us += lat_us;
        if (lat_us > st->latency_max_us) {
            st->latency_max_us = lat_us;
        }
        ++st->hist[lat_us / RT_LOOP_HIST_BIN_US < RT_LOOP_HIST_BINS ? lat_us / RT_LOOP_HIST_BIN_US
                                                                     : RT_LOOP_HIST_BINS - 1u];
        st->deadline_ns = (uint64_t)ts_ns(&next);
        r = loop->fn(loop->ctx, st);
        (void)clock_gettime(CLOCK_MONOTONIC, &end);
        exec_ns = ts_ns(&end) - ts_ns(&now);
        if ((uint32_t)(exec_ns / 1000) > st->exec_max_us) {
            st->exec_max_us = (uint32_t)(exec_ns / 1000);
        }
        ++st->ticks;
        if (r != 0) {
            loop->result = r;
            break;
        }
        if (loop->cfg.max_ticks != 0u && st->ticks >= loop->cfg.max_ticks) {
            break;
        }
        ts_add_ns(&next, period_ns);
        if (ts_ns(&end) >= ts_ns(&next)) { /* the tick ran into the next deadline */
            const int64_t missed = (ts_ns(&end) - ts_ns(&next)) / period_ns + 1;
            st->overruns += (uint64_t)missed;
            ts_add_ns(&next, missed * period_ns);
        }
    }
    __atomic_store_n(&loop->done, 1, __ATOMIC_RELEASE);
    return NULL;
}

int rt_loop_start(rt_loop_t *loop, const rt_loop_config_t *cfg, rt_loop_tick_fn fn, void *ctx, char *err,
                  size_t err_len)
{
    pthread_attr_t attr;
    int rc;
    if (loop == NULL || cfg == NULL || fn == NULL) {
        lx_err_set(err, err_len, "rt_loop_start: NULL argument");
        return TV_ERR_NULL;
    }
    memset(loop, 0, sizeof *loop);
    if (cfg->period_us == 0u) {
        lx_err_set(err, err_len, "rt_loop: period 0");
        return TV_ERR_CONFIG;
    }
    if (cfg->priority < 0 || cfg->priority > sched_get_priority_max(SCHED_FIFO)) {
        lx_err_set(err, err_len, "rt.priority = %d: outside 0..%d", cfg->priority, sched_get_priority_max(SCHED_FIFO));
        return TV_ERR_CONFIG;
    }
    if (cfg->cpu < -1 || (cfg->cpu >= 0 && cfg->cpu >= (int)sysconf(_SC_NPROCESSORS_CONF))) {
        lx_err_set(err, err_len, "rt.cpu = %d: this machine has CPUs 0..%ld", cfg->cpu, sysconf(_SC_NPROCESSORS_CONF) - 1);
        return TV_ERR_CONFIG;
    }
    loop->cfg = *cfg;
    loop->fn = fn;
    loop->ctx = ctx;
    if (cfg->lock_memory && mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
        lx_err_set(err, err_len,
                "rt.lock_memory = 1: mlockall failed: %s (needs root, CAP_IPC_LOCK or a memlock limit: "
                "ulimit -l unlimited)",
                strerror(errno));
        return TV_ERR_IO;
    }
    (void)pthread_attr_init(&attr);
    if (cfg->priority > 0) {
        struct sched_param sp;
        memset(&sp, 0, sizeof sp);
        sp.sched_priority = cfg->priority;
        (void)pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
        (void)pthread_attr_setschedpolicy(&attr, SCHED_FIFO);
        (void)pthread_attr_setschedparam(&attr, &sp);
    }
    if (cfg->cpu >= 0) {
        cpu_set_t set;
        CPU_ZERO(&set);
        CPU_SET((size_t)cfg->cpu, &set);
        (void)pthread_attr_setaffinity_np(&attr, sizeof set, &set);
    }
    rc = pthread_create(&loop->thread, &attr, loop_thread, loop);
    (void)pthread_attr_destroy(&attr);
    if (rc != 0) {
        if (rc == EPERM && cfg->priority > 0) {
            lx_err_set(err, err_len,
                    "rt.priority = %d: not allowed to create a SCHED_FIFO thread (%s): run as root, with "
                    "CAP_SYS_NICE, or raise the rtprio limit (see hal/linux/README.md)",
                    cfg->priority, strerror(rc));
        } else if (cfg->cpu >= 0) {
            lx_err_set(err, err_len, "rt.cpu = %d: cannot start the loop thread there: %s", cfg->cpu, strerror(rc));
        } else {
            lx_err_set(err, err_len, "rt_loop: pthread_create: %s", strerror(rc));
        }
        return TV_ERR_IO;
    }
    loop->started = 1;
    return TV_OK;
}

void rt_loop_request_stop(rt_loop_t *loop)
{
    if (loop != NULL) {
        __atomic_store_n(&loop->stop, 1, __ATOMIC_RELEASE);
    }
}

int rt_loop_is_done(rt_loop_t *loop)
{
    return loop != NULL && __atomic_load_n(&loop->done, __ATOMIC_ACQUIRE);
}

int rt_loop_join(rt_loop_t *loop)
{
    if (loop == NULL) {
        return TV_ERR_NULL;
    }
    if (!loop->started) {
        return TV_ERR_CONFIG;
    }
    (void)pthread_join(loop->thread, NULL);
    loop->started = 0;
    return loop->result;
}

uint32_t rt_loop_latency_quantile_us(const rt_loop_stats_t *stats, double q)
{
    uint64_t total = 0u;
    uint64_t acc = 0u;
    uint32_t b;
    if (stats == NULL) {
        return 0u;
    }
    for (b = 0; b < RT_LOOP_HIST_BINS; ++b) {
        total += stats->hist[b];
    }
    if (total == 0u) {
        return 0u;
    }
    for (b = 0; b < RT_LOOP_HIST_BINS; ++b) {
        acc += stats->hist[b];
        if ((double)acc >= q * (double)total) {
            return b + 1u < RT_LOOP_HIST_BINS ? (b + 1u) * RT_LOOP_HIST_BIN_US : stats->latency_max_us;
        }
    }
    return stats->latency_max_us;
}
