/**
 * @file sim_tracking.c
 * @brief Tracking figures of a closed-loop run (see sim_tracking.h).
 */
#include "sim_tracking.h"

#include <math.h>
#include <string.h>

void sim_tracking_init(sim_tracking_t *tk)
{
    memset(tk, 0, sizeof *tk);
}

/* Mean of the last min(n, SIM_TRK_SS_SAMPLES) values of the ring; NaN when n == 0. */
static double ring_mean(const double ring[SIM_TRK_SS_SAMPLES], uint32_t n)
{
    const uint32_t m = n < (uint32_t)SIM_TRK_SS_SAMPLES ? n : (uint32_t)SIM_TRK_SS_SAMPLES;
    double sum = 0.0;
    uint32_t k;
    /* cppcheck's value flow sees only the zeroed struct of sim_tracking_init(), not the samples
     * sim_tracking_add() counts: a false "always true/false" */
    // cppcheck-suppress knownConditionTrueFalse
    if (m == 0u) {
        return (double)NAN;
    }
    // cppcheck-suppress knownConditionTrueFalse
    for (k = 0; k < m; ++k) {
        sum += ring[k];
    }
    return sum / (double)m;
}

/* Close the open segment: its figures into step[] and the worst-case summary. */
static void close_segment(sim_tracking_t *tk)
{
    sim_trk_step_t s;
    if (!tk->active) {
        return;
    }
    tk->active = 0;
    s.t_step_s = tk->t_step;
    s.from_rad = tk->r0;
    s.to_rad = tk->r1;
    s.overshoot_pct = 100.0 * (tk->max_over > 0.0 ? tk->max_over : 0.0) / fabs(tk->r1 - tk->r0);
    s.settled = tk->t_out < tk->t_last ? 1.0 : 0.0;
    s.settling_s = (tk->t_out > tk->t_step ? tk->t_out : tk->t_step) - tk->t_step;
    s.ss_error_rad = ring_mean(tk->ring, tk->ring_n);
    if (tk->n_steps < SIM_TRK_MAX_STEPS) {
        tk->step[tk->n_steps] = s;
    }
    ++tk->n_steps;
    tk->worst_overshoot_pct = s.overshoot_pct > tk->worst_overshoot_pct ? s.overshoot_pct : tk->worst_overshoot_pct;
    tk->worst_settling_s = s.settling_s > tk->worst_settling_s ? s.settling_s : tk->worst_settling_s;
    tk->worst_ss_error_rad = s.ss_error_rad > tk->worst_ss_error_rad ? s.ss_error_rad : tk->worst_ss_error_rad;
}

void sim_tracking_add(sim_tracking_t *tk, double t_s, double target_rad, double angle_rad)
{
    double e;
    if (!(target_rad == target_rad)) {
        close_segment(tk);
        tk->have_target = 0;
        return;
    }
    /* a target that moves by less than a step (a ramp) ends the step being scored: its figures
     * are those up to where the target started to move; a ramp is scored by the RMS error */
    if (tk->have_target && target_rad != tk->last_target && fabs(target_rad - tk->last_target) <= SIM_TRK_STEP_MIN_RAD) {
        close_segment(tk);
    }
    /* a step: the target moved, or the first target, away from where the plate is */
    if (tk->have_target ? fabs(target_rad - tk->last_target) > SIM_TRK_STEP_MIN_RAD
                        : fabs(target_rad - angle_rad) > SIM_TRK_STEP_MIN_RAD) {
        close_segment(tk);
        tk->active = 1;
        tk->r0 = tk->have_target ? tk->last_target : angle_rad;
        tk->r1 = target_rad;
        tk->t_step = t_s;
        tk->t_out = t_s;
        tk->max_over = 0.0;
        tk->band = 0.02 * fabs(tk->r1 - tk->r0) > SIM_TRK_BAND_MIN_RAD ? 0.02 * fabs(tk->r1 - tk->r0)
                                                                       : SIM_TRK_BAND_MIN_RAD;
        tk->ring_n = 0u;
    }
    tk->have_target = 1;
    tk->last_target = target_rad;
    e = angle_rad - target_rad;
    tk->sse += e * e;
    ++tk->n;
    if (tk->active) {
        const double over = (angle_rad - tk->r1) * (tk->r1 > tk->r0 ? 1.0 : -1.0);
        tk->max_over = over > tk->max_over ? over : tk->max_over;
        if (fabs(e) > tk->band) {
            tk->t_out = t_s;
        }
        tk->t_last = t_s;
        tk->ring[tk->ring_n % SIM_TRK_SS_SAMPLES] = fabs(e);
        ++tk->ring_n;
    }
}

void sim_tracking_finish(sim_tracking_t *tk)
{
    close_segment(tk);
    tk->rms_error_rad = tk->n > 0u ? sqrt(tk->sse / (double)tk->n) : (double)NAN;
}
