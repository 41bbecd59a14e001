/**
 * @file cycle_stats.h
 * @brief Execution-time statistics of the control step from DWT cycle counts: last, worst
 *        case, mean, steps over budget, missed deadlines. Pure C (host-tested); the ECU feeds
 *        it from the 1 kHz interrupt.
 */
#ifndef CYCLE_STATS_H
#define CYCLE_STATS_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Statistics since cycle_stats_init(). */
typedef struct {
    uint32_t budget_cycles; /**< cycles a step may take (10 % of the core at 1 kHz) */
    uint32_t last_cycles;   /**< the most recent step [cycles] */
    uint32_t max_cycles;    /**< worst step [cycles] */
    uint64_t sum_cycles;    /**< sum over all steps [cycles] (for the mean) */
    uint32_t n_steps;       /**< steps counted */
    uint32_t over_budget;   /**< steps that took more than budget_cycles */
    uint32_t overruns;      /**< steps still running when the next period began (deadline missed) */
} cycle_stats_t;

/** Start over with a budget [cycles]. Does nothing when s is NULL. */
void cycle_stats_init(cycle_stats_t *s, uint32_t budget_cycles);

/**
 * Count one step.
 * @param cycles           its duration: end - start of the 32-bit cycle counter (modulo 2^32,
 *                         so a counter wrap inside the step is harmless)
 * @param deadline_missed  nonzero when the next period had already started at its end
 */
void cycle_stats_add(cycle_stats_t *s, uint32_t cycles, int deadline_missed);

/** Mean cycles per step, rounded to nearest; 0 before the first step. */
uint32_t cycle_stats_mean(const cycle_stats_t *s);

#ifdef __cplusplus
}
#endif

#endif /* CYCLE_STATS_H */
