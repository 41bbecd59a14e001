/**
 * @file impact_learn.h
 * @brief Impact learning: the stops' contact damping (and, where the sensor resolves it, their
 *        stiffness) from the plate's impacts in service. Pure C99, no heap, no globals; float and
 *        double builds.
 *
 * Why (README "Stop contact", measured): the start-up routine (stop_learn.h) fits the contact
 * law from rest angles under static torques of at most 1.2 N m, which press a stiff stop by less
 * than one count of the angle sensor (0.45 mrad): its stiffness is then a bound, and its damping
 * is a fixed ratio of it (lambda_per_k_s_rad). At an impact what matters is the restitution: the
 * population's stops rebound with 0.05 .. 0.85 of the impact speed; a model whose stop rebounds
 * with 0.5 where the unit's is nearly plastic put the velocity estimate 4.5 rad/s off at every
 * impact, which made the filter worse than differentiating the angle on two units.
 *
 * Law. The model's Hunt-Crossley stop (tv_model.h, stop_exponent e >= 1) has the torque
 * p^e (k + d dp/dt) with d = alpha k. Free of other torques, an impact at speed v_in leaves at
 * v_out = r v_in where r depends on alpha v_in alone (the energy balance of the compression and
 * restitution phases integrated in closed form: x - ln(1 + x) = -r x - ln(1 - r x), x = alpha
 * v_in), and the deepest penetration follows from
 *   k p_max^(e+1) / (e + 1) = J (x - ln(1 + x)) / alpha^2   (+ the work P p_max of a torque P
 *                                                          pressing into the stop).
 * The damping is learned from what the estimator's corrections say about the model's rebound
 * (not from the physical restitution: a model whose stop is softer than the unit's, because the
 * sensor cannot resolve its stiffness, predicts the best velocity with more damping than the
 * unit has; measured), the stiffness from the deepest measured penetration where the sensor
 * resolves it.
 *
 * Measurement of one impact (il_step(), per sample, after the estimator's correction):
 *   1. armed when the estimate moves toward a stop at |w| >= v_min_rad_s and the onset lies
 *      within |w| Ts + arm_margin_rad of it: v_in = |w| (the estimate before the impact is
 *      good: the plate flew freely);
 *   2. contact: the samples whose measured angle lies beyond the onset (none for a stiff stop:
 *      it rebounds within a sample) are counted, their deepest penetration p_max kept, and the
 *      net torque the model puts into the stop (motor, springs) averaged over the samples
 *      whose estimate still moves into it (P: the compression's; over the whole impact the
 *      back-EMF's braking on the way in and its push on the way out cancelled, and the stiffness
 *      came out too high: 9 - 25 % on units whose true law it was given, measured);
 *   3. the impact is over when the estimate moves away from the stop and the measured angle is
 *      outside the onset (a contact seen, or a reversal within one sample of an estimate still
 *      moving in at half the impact speed or more: no drive does that), and abandoned when the
 *      plate stays near the stop for contact_max samples (it rests) or never reaches it; over
 *      the impact and the settle samples after it, the estimator's velocity corrections
 *      (posterior - prior) are summed as speed away from the stop: dw (the whole window: after a
 *      rebound the model lacked, the contact inflation corrects first upward and then back
 *      down; the sum is the net error. The samples after the impact alone were tried: their sign
 *      is the overshoot's, which drove a bouncy unit's damping to the bound, measured on
 *      population unit 1007). At the sample that ends the impact the estimate's speed away from
 *      the stop before (w_prior_end) and after (w_end) its correction are kept, and the measured
 *      angles of it and the next IL_FIT_N - 1 samples;
 *   4. the damping ratio, bounded to alpha_min .. alpha_max and by a factor of 2 per impact:
 *      - an impact over within a sample (fewer than two samples beyond the onset: a stop the
 *        sensor cannot resolve): the rebound seen in HINDSIGHT, w_fit, the speed at the ending
 *        sample of the quadratic least-squares fit through those IL_FIT_N angles (free flight
 *        under a nearly constant torque), against the model's own rebound there, the prior:
 *        alpha <- alpha exp(gain (w_prior_end - w_fit) / (IL_REST_SENS v_in)). IL_REST_SENS is
 *        the restitution's sensitivity to ln alpha (about 0.25 for the laws learned at 12 V).
 *        The correction sum dw cannot serve there: a model whose rebound is too fast gets an
 *        upward correction at the impact's sample and downward ones after, which nearly cancel
 *        (unit 1014: dw / v_in -0.13 while its prior rebound was 2.5x the unit's).
 *        The estimator's velocity coupling of the contact inflation (ekf_config_t::
 *        contact_w_coupling) learns from the same sample: the correction it made, w_end -
 *        w_prior_end, against the one that would have reached w_fit: coupling <- coupling
 *        rho^IL_COUPLING_GAIN, rho = (w_fit - w_prior_end) / (w_end - w_prior_end) clipped to
 *        0.25 .. 2, bounded to IL_COUPLING_MIN .. 1, and only when the correction was at least
 *        0.05 v_in;
 *      - a resolved impact: alpha <- alpha exp(-gain dw / v_in): corrections that keep taking
 *        away-speed the model's rebound gave mean too little damping;
 *      and, when p_max >= p_min_rad over at least two samples, k <- k (k_obs / k)^gain with k_obs
 *      from the penetration relation, bounded as a secant stiffness at IL_P_REF_RAD to
 *      k_sec_min .. k_sec_max (the start-up routine's bounds).
 * The application then gives the estimator the law (k, e, alpha k), ekf_set_contact_law(), and
 * the coupling, ekf_set_contact_w_coupling().
 *
 * Not run for a Kelvin-Voigt model (stop_exponent 0: the stops were never learned; its damping
 * is not a ratio of its stiffness) nor while the start-up routine runs.
 *
 * Cost: per sample a few comparisons and sums; per impact one exp and, for k, one log, one
 * exp and two powers.
 */
#ifndef IMPACT_LEARN_H
#define IMPACT_LEARN_H

#include <stdint.h>

#include "tv_model.h"
#include "tv_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Penetration at which the stiffness bounds are secant stiffnesses [rad] (as stop_learn.h's). */
#define IL_P_REF_RAD TV_R(0.0025)

/** Measured angles after an impact whose quadratic fit gives the rebound seen in hindsight (the
 *  ending sample and IL_FIT_N - 1 settle samples: il_config_t::settle >= IL_FIT_N - 1). */
#define IL_FIT_N 4

/** The restitution's sensitivity to ln alpha, |dr / d ln alpha| (r = v_out / v_in of the law
 *  free of other torques): ((1 - r x) / (1 + x) - r^2) / r with x = alpha v_in; 0.25 at the
 *  learned ratio 0.21 and 12 rad/s (r 0.35), used as a constant [-]. */
#define IL_REST_SENS TV_R(0.25)

/** Low-pass gain of the contact inflation's velocity coupling per impact [-], and its lower bound. */
#define IL_COUPLING_GAIN TV_R(0.5)
#define IL_COUPLING_MIN TV_R(0.05)

/** Configuration. Units SI. */
typedef struct {
    uint8_t enable;          /**< 1 (default): learn; 0: the law stays as given. It was off while the 70 s
                                  healthy soak confirmed P1A04 (current-sensor bias) with it on (all_varied
                                  unit 1016, paper sine: impact innovations in P1A04's window); P1A04 now
                                  skips them, and the soak has no false alarm either way (README "Impact
                                  learning") */
    tv_real_t v_min_rad_s;   /**< least impact speed learned from, > 0; default 6 (a second, slow bounce
                                  of a plate pushed back into the stop is not an impact of its own) */
    tv_real_t arm_margin_rad; /**< armed within |w| Ts + this of an onset, > 0; default 0.002 */
    uint16_t contact_max;    /**< samples near the stop after which the impact is abandoned, 2..1000; default 30 */
    uint16_t settle;         /**< samples after the impact before it is learned from, IL_FIT_N - 1..20; default 3 */
    tv_real_t gain;          /**< log-domain low-pass gain per impact, (0, 1]; default 0.3 */
    tv_real_t alpha_min;     /**< damping ratio bounds [s/rad], 0 < min < max; default 0.04 */
    tv_real_t alpha_max;     /**< default 0.8: restitution at a 10 rad/s impact from about 0.9 down
                                  to 0.1, the span of throttle stops (host_sim/plant/plant_draw.h) with
                                  a margin; within it the model's explicit sub-steps stay stable at the
                                  stiffness bound */
    tv_real_t p_min_rad;     /**< least measured penetration for a stiffness update, > 0; default 0.0015 (3 counts) */
    tv_real_t k_sec_min;     /**< stiffness bounds as secant stiffness at IL_P_REF_RAD [N m/rad], 0 < min < max; default 100 */
    tv_real_t k_sec_max;     /**< default 1e4 (stop_learn.h's k_max: the model's contact stays stable) */
} il_config_t;

/** Phases of one impact. */
typedef enum { IL_IDLE = 0, IL_ARMED = 1, IL_AFTER = 2 } il_phase_t;

/** State. */
typedef struct {
    il_config_t cfg;
    il_phase_t phase;
    uint8_t stop;            /**< 0 closed, 1 open: the stop of the impact under way */
    uint16_t n;              /**< samples since armed (IL_ARMED) or since the impact ended (IL_AFTER) */
    uint16_t n_contact;      /**< samples with the measured angle beyond the onset */
    tv_real_t v_in;          /**< impact speed [rad/s] */
    tv_real_t p_max;         /**< deepest measured penetration [rad] */
    tv_real_t pen_last;      /**< the last sample's measured penetration [rad] (< 0: outside the onset) */
    tv_real_t pen_before;    /**< the penetration of the sample before the deepest [rad] */
    tv_real_t pen_after;     /**< ... and of the sample after it [rad] (valid when have_after) */
    uint8_t have_after;      /**< 1: pen_after holds the sample after the deepest */
    tv_real_t push_sum;      /**< sum of the net torque into the stop over the impact's compression [N m] */
    tv_real_t push_n;        /**< samples in push_sum (those with the estimate still moving into the stop) */
    tv_real_t dw_sum;        /**< sum of the estimator's velocity corrections away from the stop [rad/s] */
    tv_real_t toward_last;   /**< the estimate's speed into the stop at the previous sample [rad/s] */
    tv_real_t w_end;         /**< the estimate's speed away from the stop at the sample that ended the impact [rad/s] */
    tv_real_t w_prior_end;   /**< ... its prediction, before that sample's correction [rad/s] */
    tv_real_t phi_after[IL_FIT_N]; /**< measured angles from that sample on, as distance away from the stop's side [rad] */
    /* results */
    tv_real_t alpha;         /**< learned damping ratio d / k [s/rad] (valid when n_learned > 0) */
    tv_real_t k;             /**< learned stiffness [N m/rad^e] (the law's, updated when resolvable) */
    tv_real_t coupling;      /**< learned velocity coupling of the contact inflation [-] (ekf_config_t::contact_w_coupling) */
    tv_real_t rebound_err_last; /**< the last impact's rebound error relative to the impact speed [-]: (w_fit - w_prior_end) / v_in
                                     for one over within a sample, dw / v_in for a resolved one */
    uint32_t n_learned;      /**< impacts learned from */
    uint32_t n_k;            /**< of which updated the stiffness */
    uint32_t n_abandoned;    /**< impacts armed but not learned from (rest, no reversal, invalid angle) */
} il_t;

/** Defaults as documented at il_config_t. */
void il_config_default(il_config_t *cfg);

/** @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE; TV_ERR_CONFIG (a value outside its documented range). */
int il_config_check(const il_config_t *cfg);

/**
 * Start from the model's law (k_stop, d_stop: alpha = d / k). Counters at 0.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (configuration invalid, or a law without stiffness).
 */
int il_reset(il_t *il, const il_config_t *cfg, const tvm_params_t *model);

/**
 * One sample after the estimator's correction. model: the estimator's model (onsets, springs,
 * n Kt, J, the law in use); phi_meas: the measured angle, phi_valid 0 when there is none (an
 * impact under way is abandoned); x: the corrected estimate (i, w, phi); w_prior: the velocity
 * the estimator predicted for this sample, before the correction [rad/s].
 * @return 1 when an impact was learned from and the law changed (il->k, il->alpha: the
 *         application gives the estimator k, the model's exponent and alpha k), 0 otherwise.
 */
int il_step(il_t *il, const tvm_params_t *model, tv_real_t phi_meas, int phi_valid, const tv_real_t x[TVM_NX],
            tv_real_t w_prior);

#ifdef __cplusplus
}
#endif

#endif /* IMPACT_LEARN_H */
