/**
 * @file test_cycle_stats.c
 * @brief Unit tests of the ECU's step execution-time statistics (hal/stm32f4/cycle_stats.h),
 *        which feed the CPU-load telemetry. Integer arithmetic: every check is exact.
 */
#include <stdint.h>

#include "cycle_stats.h"
#include "tv_test.h"

static void test_max_mean_and_counts_of_a_known_sequence(void)
{
    cycle_stats_t s;
    cycle_stats_init(&s, 16800u);
    cycle_stats_add(&s, 4000u, 0);
    cycle_stats_add(&s, 20000u, 0); /* over budget */
    cycle_stats_add(&s, 3001u, 1);  /* deadline missed */
    TV_CHECK_EQ_INT(s.n_steps, 3);
    TV_CHECK_EQ_INT(s.last_cycles, 3001);
    TV_CHECK_EQ_INT(s.max_cycles, 20000);
    TV_CHECK_EQ_INT(s.over_budget, 1);
    TV_CHECK_EQ_INT(s.overruns, 1);
    /* (4000 + 20000 + 3001) / 3 = 9000.33 -> 9000 */
    TV_CHECK_EQ_INT(cycle_stats_mean(&s), 9000);
}

static void test_mean_rounds_to_nearest_and_is_zero_before_the_first_step(void)
{
    cycle_stats_t s;
    cycle_stats_init(&s, 100u);
    TV_CHECK_EQ_INT(cycle_stats_mean(&s), 0);
    cycle_stats_add(&s, 1u, 0);
    cycle_stats_add(&s, 2u, 0);
    TV_CHECK_EQ_INT(cycle_stats_mean(&s), 2); /* 1.5 rounds up */
    TV_CHECK_EQ_INT(cycle_stats_mean(NULL), 0);
}

static void test_a_budget_exactly_met_is_not_over_budget(void)
{
    cycle_stats_t s;
    cycle_stats_init(&s, 16800u);
    cycle_stats_add(&s, 16800u, 0);
    TV_CHECK_EQ_INT(s.over_budget, 0);
    cycle_stats_add(&s, 16801u, 0);
    TV_CHECK_EQ_INT(s.over_budget, 1);
}

static void test_counter_wrap_inside_a_step_gives_the_true_duration(void)
{
    /* The caller passes end - start modulo 2^32: a DWT wrap inside the step is harmless. */
    const uint32_t start = 0xFFFFFF00u;
    const uint32_t end = 0x00000100u;
    cycle_stats_t s;
    cycle_stats_init(&s, 16800u);
    cycle_stats_add(&s, end - start, 0);
    TV_CHECK_EQ_INT(s.max_cycles, 0x200);
}

static void test_null_is_ignored(void)
{
    cycle_stats_init(NULL, 1u);
    cycle_stats_add(NULL, 1u, 1);
    TV_CHECK(1);
}

int main(void)
{
    TV_TEST_RUN(test_max_mean_and_counts_of_a_known_sequence);
    TV_TEST_RUN(test_mean_rounds_to_nearest_and_is_zero_before_the_first_step);
    TV_TEST_RUN(test_a_budget_exactly_met_is_not_over_budget);
    TV_TEST_RUN(test_counter_wrap_inside_a_step_gives_the_true_duration);
    TV_TEST_RUN(test_null_is_ignored);
    return tv_test_summary();
}
