/**
 * @file cycle_stats.c
 * @brief Step execution-time statistics (see cycle_stats.h).
 */
#include "cycle_stats.h"

#include <stddef.h>

void cycle_stats_init(cycle_stats_t *s, uint32_t budget_cycles)
{
    if (s == NULL) {
        return;
    }
    s->budget_cycles = budget_cycles;
    s->last_cycles = 0u;
    s->max_cycles = 0u;
    s->sum_cycles = 0u;
    s->n_steps = 0u;
    s->over_budget = 0u;
    s->overruns = 0u;
}

static uint32_t sat_inc(uint32_t v)
{
    return v == UINT32_MAX ? v : v + 1u;
}

void cycle_stats_add(cycle_stats_t *s, uint32_t cycles, int deadline_missed)
{
    if (s == NULL) {
        return;
    }
    s->last_cycles = cycles;
    if (cycles > s->max_cycles) {
        s->max_cycles = cycles;
    }
    if (s->n_steps == UINT32_MAX) {
        /* 49 days at 1 kHz: restart the mean rather than let it wrap. */
        s->sum_cycles = 0u;
        s->n_steps = 0u;
    }
    s->sum_cycles += cycles;
    ++s->n_steps;
    if (cycles > s->budget_cycles) {
        s->over_budget = sat_inc(s->over_budget);
    }
    if (deadline_missed) {
        s->overruns = sat_inc(s->overruns);
    }
}

uint32_t cycle_stats_mean(const cycle_stats_t *s)
{
    if (s == NULL || s->n_steps == 0u) {
        return 0u;
    }
    return (uint32_t)((s->sum_cycles + s->n_steps / 2u) / s->n_steps);
}
