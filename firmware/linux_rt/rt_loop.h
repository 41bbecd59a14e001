/**
 * @file rt_loop.h
 * @brief The periodic real-time thread of the Linux controller: mlockall(), a SCHED_FIFO thread
 *        (optionally pinned to one CPU) that wakes on clock_nanosleep(CLOCK_MONOTONIC,
 *        TIMER_ABSTIME) every period, runs one tick, and keeps the statistics a real-time
 *        loop is judged by: wake-up latency (worst, mean, histogram), execution time, overruns.
 *
 * Timing of one period: the thread sleeps until the absolute deadline d; it wakes at w >= d
 * (latency w - d) and runs the tick until e. The next deadline is d + period. A period whose
 * deadline has already passed when the thread would sleep for it (e >= d + period), or that
 * passed while the thread was waking (w - d >= period), is not run: it counts as an overrun and
 * the schedule moves on by whole periods, keeping its phase (the application predicts across
 * the missing samples).
 */
#ifndef RT_LOOP_H
#define RT_LOOP_H

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Latency histogram: RT_LOOP_HIST_BINS bins of RT_LOOP_HIST_BIN_US, the last one open-ended. */
#define RT_LOOP_HIST_BINS 200u
#define RT_LOOP_HIST_BIN_US 10u

/** Loop settings. */
typedef struct {
    int priority;       /**< SCHED_FIFO priority 1..99; 0 = SCHED_OTHER (no real-time guarantee) */
    int cpu;            /**< CPU to pin the thread to; -1 = not pinned */
    int lock_memory;    /**< 1: mlockall(MCL_CURRENT | MCL_FUTURE) before starting */
    uint32_t period_us; /**< period [us], > 0 */
    uint64_t max_ticks; /**< stop after this many ticks; 0 = until rt_loop_request_stop() */
} rt_loop_config_t;

/** Statistics, updated by the loop thread after each tick. */
typedef struct {
    uint64_t deadline_ns;    /**< CLOCK_MONOTONIC deadline of the period being run [ns] */
    uint64_t ticks;          /**< ticks run */
    uint64_t overruns;       /**< periods not run (deadline already passed) */
    uint64_t latency_sum_us; /**< sum of wake-up latencies [us] */
    uint32_t latency_max_us; /**< worst wake-up latency [us] */
    uint32_t exec_max_us;    /**< worst tick execution time [us] */
    uint32_t hist[RT_LOOP_HIST_BINS]; /**< wake-up latency histogram */
} rt_loop_stats_t;

/**
 * The work of one period, called on the real-time thread.
 * @return 0 to continue; > 0 to stop cleanly; < 0 to stop because of a fault.
 */
typedef int (*rt_loop_tick_fn)(void *ctx, const rt_loop_stats_t *stats);

/** A running loop. Treat the fields as private. */
typedef struct {
    rt_loop_config_t cfg;
    rt_loop_tick_fn fn;
    void *ctx;
    pthread_t thread;
    int started;
    int stop;   /**< set by rt_loop_request_stop() (atomic access) */
    int done;   /**< set by the thread when it ends (atomic access) */
    int result; /**< what ended it: 0 (stop request / max ticks), the tick's return value otherwise */
    rt_loop_stats_t stats;
} rt_loop_t;

/**
 * Lock memory (if configured) and start the thread.
 * @param err receives a message naming the rt.* key and value on error
 * @return 0; TV_ERR_NULL; TV_ERR_CONFIG (bad period / priority / cpu); TV_ERR_IO (mlockall,
 *         scheduling or thread creation refused: not privileged, no such CPU).
 */
int rt_loop_start(rt_loop_t *loop, const rt_loop_config_t *cfg, rt_loop_tick_fn fn, void *ctx, char *err,
                  size_t err_len);

/** Ask the thread to stop after its current tick (async-signal-safe: a single atomic store). */
void rt_loop_request_stop(rt_loop_t *loop);

/** 1 once the thread has ended. */
int rt_loop_is_done(rt_loop_t *loop);

/**
 * Wait for the thread to end.
 * @return the loop's result (see rt_loop_t::result); TV_ERR_NULL; TV_ERR_CONFIG if not started.
 */
int rt_loop_join(rt_loop_t *loop);

/** Latency below which a fraction q (0..1) of the ticks woke, from the histogram [us]. */
uint32_t rt_loop_latency_quantile_us(const rt_loop_stats_t *stats, double q);

#ifdef __cplusplus
}
#endif

#endif /* RT_LOOP_H */
