/**
 * @file tv_param_table.c
 * @brief The parameter table (see tv_param_table.h).
 */
#include "tv_param_table.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "tv_model.h"

static const tvp_desc_t s_table[TVP_COUNT] = {
    {"model.R_ohm", "ohm", 0.0, 1000.0, TVP_LO_OPEN, "armature resistance"},
    {"model.L_H", "H", 0.0, 10.0, TVP_LO_OPEN, "armature inductance"},
    {"model.Ke_V_s_rad", "V s/rad", 0.0, 10.0, 0u, "back-EMF constant (motor side)"},
    {"model.Kt_Nm_A", "N m/A", 0.0, 10.0, 0u, "torque constant (motor side)"},
    {"model.J_kg_m2", "kg m^2", 0.0, 10.0, TVP_LO_OPEN, "inertia at the plate"},
    {"model.n_gear", "-", 0.0, 1000.0, TVP_LO_OPEN, "gear ratio motor : plate"},
    {"model.Mc_Nm", "N m", 0.0, 100.0, 0u, "Coulomb friction (<= Ms)"},
    {"model.M0_Nm", "N m", 0.0, 100.0, 0u, "limp-home spring preload"},
    {"model.c_Nm_rad", "N m/rad", 0.0, 1000.0, 0u, "spring rate"},
    {"model.Kv_Nm_s_rad", "N m s/rad", 0.0, 100.0, 0u, "viscous friction"},
    {"model.Ms_Nm", "N m", 0.0, 100.0, 0u, "static friction (>= Mc)"},
    {"model.ws_rad_s", "rad/s", 0.0, 1000.0, TVP_LO_OPEN, "Stribeck velocity"},
    {"model.phi_closed_rad", "rad", -1.0, 0.0, TVP_HI_OPEN, "closed hard stop (below limp-home)"},
    {"model.phi_open_rad", "rad", 0.0, 2.5, TVP_LO_OPEN, "open hard stop"},
    {"model.k_stop_Nm_rad", "N m/rad", 0.0, 10000000.0, 0u, "stop contact stiffness"},
    {"model.d_stop_Nm_s_rad", "N m s/rad", 0.0, 1.0e7, 0u, "stop contact damping"},
    {"model.stop_exponent", "-", 0.0, 3.0, 0u, "stop contact law: 0 = Kelvin-Voigt, 1..3 = Hunt-Crossley exponent (k in N m/rad^e, damping in N m s/rad^(e+1))"},
    {"model.e_phi_rad", "rad", 0.0, 0.1, TVP_LO_OPEN, "smoothing width of the preload sign"},
    {"model.e_w_rad_s", "rad/s", 0.0, 10.0, TVP_LO_OPEN, "smoothing width of |w| in the Stribeck term"},
    {"model.substeps", "-", 1.0, (double)TVM_SUBSTEPS_MAX, TVP_INTEGER, "sub-steps of the prediction map per period"},
    {"ekf.qu_V2_s", "V^2 s", 0.0, 1000.0, 0u, "armature voltage noise density (Q)"},
    {"ekf.qT_Nm2_s", "N^2 m^2 s", 0.0, 1000.0, 0u, "plate torque noise density (Q)"},
    {"ekf.r_current_A2", "A^2", 0.0, 1000.0, TVP_LO_OPEN, "current measurement VARIANCE"},
    {"ekf.r_velocity_rad2_s2", "(rad/s)^2", 0.0, 1000000.0, TVP_LO_OPEN, "differentiated-velocity measurement VARIANCE"},
    {"ekf.r_angle_rad2", "rad^2", 0.0, 1.0, TVP_LO_OPEN, "angle measurement VARIANCE"},
    {"ekf.contact_band_rad", "rad", 0.0, 0.5, 0u, "band around each stop where the contact law is uncertain (0 = off)"},
    {"ekf.qc_Nm2_s", "N^2 m^2 s", 0.0, 1000.0, 0u, "contact torque-noise density added in that band"},
    {"ekf.stop_learn_margin_rad", "rad", 0.0, 0.5, 0u, "stops move out to where the plate is seen beyond them by this (0 = fixed)"},
    {"ekf.qd_contact_Nm2_s", "N^2 m^2 s", 0.0, 1.0e6, 0u, "contact-torque state: random-walk density in the contact band (0 with qd_free = no state)"},
    {"ekf.qd_free_Nm2_s", "N^2 m^2 s", 0.0, 1000.0, 0u, "contact-torque state: random-walk density away from the stops"},
    {"ekf.d_tau_s", "s", 0.0, 10.0, TVP_LO_OPEN, "contact-torque state: decay time outside the contact band"},
    {"ekf.contact_nis_gate", "-", 0.0, 1000.0, 0u, "in the contact band, an angle innovation beyond this NIS inflates the covariance until it fits (0 = off)"},
    {"ekf.contact_w_coupling", "-", 0.0, 1.0, 0u, "that inflation's velocity coupling (1 = a white torque over the period); the impact learning lowers it where the angle correction overshoots the rebound"},
    {"ekf.qT_rel_s", "s", 0.0, 1.0, 0u, "model-torque noise: torque-noise density added per N^2 m^2 of the model's torque magnitude (0 = off)"},
    {"ekf.impact_timing", "-", 0.0, 10.0, 0u, "velocity variance added when a prediction enters a stop, in units of (h / J M)^2, M the largest stop torque of its sub-steps: the stop torque starts up to one sub-step late (0 = off)"},
    {"impact_learn.enable", "-", 0.0, 1.0, TVP_INTEGER, "1: the stops' contact damping and stiffness are learned from impacts in service (impact_learn.h)"},
    {"impact_learn.gain", "-", 0.0, 1.0, TVP_LO_OPEN, "impact learning: low-pass gain per impact"},
    {"stop_learn.e_min", "-", 1.0, 3.0, 0u, "start-up stop learning: smallest contact-law exponent its fit searches (stop_learn.h)"},
    {"stop_learn.e_max", "-", 1.0, 3.0, 0u, "start-up stop learning: largest exponent (= e_min: the exponent fixed, e.g. identify's)"},
    {"stop_learn.lambda_per_k_s_rad", "s/rad", 0.0, 10.0, 0u, "start-up stop learning: contact damping lambda = this x the learned k"},
    {"stop_learn.k_min_Nm_rad", "N m/rad", 0.0, 1.0e7, TVP_LO_OPEN, "start-up stop learning: least stiffness it fits, as a secant at 2.5 mrad"},
    {"stop_learn.k_max_Nm_rad", "N m/rad", 0.0, 1.0e7, TVP_LO_OPEN, "start-up stop learning: largest stiffness (secant at 2.5 mrad; the model's stability cap)"},
    {"ekf.qr_ohm2_s", "ohm^2/s", 0.0, 100.0, 0u, "winding-resistance error state: random-walk density (0 = no such state)"},
    {"ekf.r_sigma0_ohm", "ohm", 0.0, 100.0, 0u, "winding-resistance error state: initial standard deviation"},
    {"ekf.dr_abs_max_ohm", "ohm", 0.0, 100.0, TVP_LO_OPEN, "winding-resistance error state: bound on its magnitude"},
    {"ekf.dr_excite_A", "A", 0.0, 50.0, 0u, "winding-resistance error state: updated only while |current| is at least this"},
    {"ekf.qf_1_s", "1/s", 0.0, 100.0, 0u, "relative friction error state: random-walk density (0 = no such state)"},
    {"ekf.f_sigma0", "-", 0.0, 10.0, 0u, "relative friction error state: initial standard deviation"},
    {"ekf.f_abs_max", "-", 0.0, 1.0, TVP_LO_OPEN | TVP_HI_OPEN, "relative friction error state: bound on its magnitude"},
    {"ekf.f_excite_rad_s", "rad/s", 0.0, 500.0, 0u, "relative friction error state: updated only while |velocity| is at least this"},
    {"ekf.qm_1_s", "1/s", 0.0, 100.0, 0u, "relative spring-preload error state: random-walk density (0 = no such state)"},
    {"ekf.m_sigma0", "-", 0.0, 10.0, 0u, "relative spring-preload error state: initial standard deviation"},
    {"ekf.m_abs_max", "-", 0.0, 1.0, TVP_LO_OPEN | TVP_HI_OPEN, "relative spring-preload error state: bound on its magnitude"},
    {"ekf.nis_inflate_alpha", "-", 0.0, 1.0, 0u, "consistency-driven inflation: low-pass gain of the average NIS per correction (0 = off)"},
    {"ekf.nis_inflate_threshold", "-", 0.0, 1000.0, TVP_LO_OPEN, "consistency-driven inflation: average NIS above which Q is scaled by (average / this)^2"},
    {"ekf.nis_inflate_max", "-", 1.0, 1.0e6, 0u, "consistency-driven inflation: largest factor on Q"},
    {"ekf.white_threshold", "-", 0.0, 1.0e6, 0u, "whiteness-driven inflation: the angle innovations' squared mean, in multiples of what white noise gives, above which Q's plate block is scaled by the ratio (0 = off, the default; trained setting 16)"},
    {"ekf.stuck_q_min", "-", 0.0, 1.0, TVP_LO_OPEN, "stuck-plate noise: factor on the plate's process noise where static friction holds the plate with a reserve of at least stuck_hold_frac (1 = off)"},
    {"ekf.stuck_hold_frac", "-", 0.0, 1.0, TVP_LO_OPEN, "stuck-plate noise: friction reserve (1 - net torque / breakaway) from which stuck_q_min applies"},
    {"diag.identified", "-", 0.0, 1.0, TVP_INTEGER, "1: the model is this unit's own (identify writes it): the diagnostic bounds judge friction and preload relative to it (diag_detect_config_identified())"},
    {"diag.r_fit_high_frac", "-", 1.0, 3.0, TVP_LO_OPEN, "P2101 from the voltage equation's fit: its R above this times the model's (at the winding's known temperature) in 3 windows in a row fails P2101; the margin above the units' spread must hold the temperature reading's error (default 1.25)"},
    {"diag.friction_high_rel", "-", 0.0, 3.0, TVP_LO_OPEN, "P2119 when the adapted friction level 1 + f reads above this for 95 checks in a row (default 1.7, the class's spread; 1.15 with diag.identified; population --friction-baseline learns a unit's own)"},
    {"diag.friction_fast_high", "-", 0.0, 3.0, TVP_LO_OPEN, "P2119 when the torque signature's friction reads above this with the adapted level at least diag.friction_fast_level_min (default 1.7; 1.15 with diag.identified)"},
    {"diag.friction_fast_level_min", "-", 0.0, 3.0, TVP_LO_OPEN, "the adapted friction level the signature's reading needs beside it (default 1.3; 1.1 with diag.identified)"},
    {"diag.fit_base_r_ohm", "ohm", 0.0, 1000.0, 0u, "the fit's per-unit baseline: the unit's winding resistance at 20 degC as the voltage equation's fit read it healthy (0 = none; host_sim prints the learned one and --params-out writes it); with it the fit's checks judge R and n Ke relative to the unit's own values"},
    {"diag.fit_base_nke_V_s", "V*s/rad", 0.0, 100.0, 0u, "the fit's per-unit baseline: the unit's back-EMF constant at the plate, n Ke, as the fit read it healthy (0 = none; both or neither)"},
    {"diag.fit_base_windows", "windows", 0.0, 65535.0, TVP_INTEGER, "learn the fit's baseline as the mean of this many of its windows in service (temperature known, no code pending or confirmed); 0 = do not learn (the default)"},
    {"diag.r_fit_base_high_frac", "-", 1.0, 3.0, TVP_LO_OPEN, "with a baseline: P2101 when the fit's R reads above this times the baseline's (at the known temperature) in 3 windows in a row (default 1.10)"},
    {"diag.gain_fit_base_max", "-", 0.0, 1.0, TVP_LO_OPEN | TVP_HI_OPEN, "with a baseline: P1A04 (current-sensor gain) when the fit's R reads below this times the baseline's with n Ke intact, in 5 windows in a row (default 0.97)"},
    {"calib.current_offset_counts", "counts", 0.0, 65535.0, 0u, "current channel at 0 A"},
    {"calib.current_A_per_count", "A/count", -1.0, 1.0, TVP_NONZERO, "current sense gain"},
    {"calib.tps1_counts_at_zero", "counts", -1000000.0, 1000000.0, 0u, "track 1 at limp-home"},
    {"calib.tps1_rad_per_count", "rad/count", 0.0, 1.0, TVP_LO_OPEN, "track 1 gain (rising)"},
    {"calib.tps2_counts_at_zero", "counts", -1000000.0, 1000000.0, 0u, "track 2 at limp-home"},
    {"calib.tps2_rad_per_count", "rad/count", -1.0, 0.0, TVP_HI_OPEN, "track 2 gain (falling)"},
    {"calib.supply_V_per_count", "V/count", 0.0, 1.0, TVP_LO_OPEN, "supply divider and ADC"},
    {"limits.current_min_counts", "counts", 0.0, 65535.0, TVP_INTEGER, "lowest plausible current count (< max)"},
    {"limits.current_max_counts", "counts", 0.0, 65535.0, TVP_INTEGER, "highest plausible current count"},
    {"limits.tps_min_counts", "counts", 0.0, 65535.0, TVP_INTEGER, "lowest plausible track count (< max)"},
    {"limits.tps_max_counts", "counts", 0.0, 65535.0, TVP_INTEGER, "highest plausible track count"},
    {"limits.tps_disagree_max_rad", "rad", 0.0, 3.2, TVP_LO_OPEN, "largest plausible track disagreement"},
    {"limits.supply_min_V", "V", 0.0, 1000.0, TVP_LO_OPEN, "lowest plausible supply (< max)"},
    {"limits.supply_max_V", "V", 0.0, 1000.0, TVP_LO_OPEN, "highest plausible supply"},
    {"limits.debounce_trip", "samples", 1.0, 65535.0, TVP_INTEGER, "consecutive failures that latch a fault"},
    {"limits.max_gap_periods", "periods", 1.0, (double)APP_MAX_GAP_PERIODS, TVP_INTEGER, "largest gap one step predicts across"},
};

const tvp_desc_t *tvp_desc(int id)
{
    return id >= 0 && id < (int)TVP_COUNT ? &s_table[id] : NULL;
}

int tvp_find(const char *key)
{
    int k;
    if (key == NULL) {
        return -1;
    }
    for (k = 0; k < (int)TVP_COUNT; ++k) {
        if (strcmp(key, s_table[k].key) == 0) {
            return k;
        }
    }
    return -1;
}

int tvp_check(int id, double v)
{
    const tvp_desc_t *d = tvp_desc(id);
    if (d == NULL) {
        return -4;
    }
    if (!(v == v) || v - v != 0.0) {
        return -1;
    }
    if ((d->flags & TVP_INTEGER) != 0u && v != floor(v)) { /* floor: no conversion of huge values */
        return -3;
    }
    if (((d->flags & TVP_LO_OPEN) != 0u ? !(v > d->lo) : !(v >= d->lo)) ||
        ((d->flags & TVP_HI_OPEN) != 0u ? !(v < d->hi) : !(v <= d->hi)) ||
        ((d->flags & TVP_NONZERO) != 0u && v == 0.0)) {
        return -2;
    }
    return 0;
}

void tvp_range_text(int id, char *out, size_t cap)
{
    const tvp_desc_t *d = tvp_desc(id);
    if (out == NULL || cap == 0u) {
        return;
    }
    if (d == NULL) {
        out[0] = '\0';
        return;
    }
    (void)snprintf(out, cap, "%s%.9g, %.9g%s%s%s", (d->flags & TVP_LO_OPEN) != 0u ? "(" : "[", d->lo, d->hi,
                   (d->flags & TVP_HI_OPEN) != 0u ? ")" : "]", (d->flags & TVP_INTEGER) != 0u ? ", an integer" : "",
                   (d->flags & TVP_NONZERO) != 0u ? ", not 0" : "");
}
