/**
 * @file plant.c
 * @brief High-fidelity throttle-valve plant for the host simulation (see plant.h for the model,
 *        the integration scheme and the sensor transfer functions).
 */
#include "plant.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "tv_paper.h"
#include "tv_status.h"

/** pi (C99 has no M_PI). */
#define PLANT_PI 3.14159265358979323846
/** Remainders of a time step below this fraction of a sub-step are rounding, not time. */
#define PLANT_TIME_SNAP_FRAC 1e-9
/** 2^-53: turns the top 53 bits of a 64-bit random word into a double in [0, 1). */
#define PLANT_TWO_POW_M53 (1.0 / 9007199254740992.0)

/* ------------------------------------------------------------------------------------------ */
/* Noise: splitmix64 seeding xoshiro256** (Blackman and Vigna), Box-Muller normals.            */
/* ------------------------------------------------------------------------------------------ */

static uint64_t plant_splitmix64(uint64_t *x)
{
    uint64_t z = (*x += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

static uint64_t plant_rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

static uint64_t plant_rng_next(uint64_t s[4])
{
    const uint64_t result = plant_rotl(s[1] * 5u, 7) * 9u;
    const uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = plant_rotl(s[3], 45);
    return result;
}

/** Standard normal N(0, 1). Box-Muller without rejection: a fixed cost, no data-dependent loop. */
static double plant_gauss(plant_t *p)
{
    double u1;
    double u2;
    double r;
    if (p->gauss_has_spare) {
        p->gauss_has_spare = 0;
        return p->gauss_spare;
    }
    /* u1 in (0, 1] so that log(u1) is finite; u2 in [0, 1). */
    u1 = ((double)(plant_rng_next(p->rng_s) >> 11) + 1.0) * PLANT_TWO_POW_M53;
    u2 = (double)(plant_rng_next(p->rng_s) >> 11) * PLANT_TWO_POW_M53;
    r = sqrt(-2.0 * log(u1));
    p->gauss_spare = r * sin(2.0 * PLANT_PI * u2);
    p->gauss_has_spare = 1;
    return r * cos(2.0 * PLANT_PI * u2);
}

/* ------------------------------------------------------------------------------------------ */
/* Configuration                                                                               */
/* ------------------------------------------------------------------------------------------ */

void plant_config_default(plant_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->R_ohm = TV_PAPER_R_OHM;
    cfg->L_H = TV_PAPER_L_H;
    cfg->Ke_V_s_rad = TV_PAPER_KE_V_S_RAD;
    cfg->Kt_Nm_A = TV_PAPER_KT_NM_A;
    cfg->J_kg_m2 = TV_PAPER_J_KG_M2;
    cfg->n_gear = TV_PAPER_N_GEAR;
    cfg->Mc_Nm = TV_PAPER_MC_NM;
    cfg->Ms_Nm = TV_PAPER_MS_NM;
    cfg->ws_rad_s = TV_PAPER_WS_RAD_S;
    cfg->Kv_Nm_s_rad = TV_PAPER_KV_NM_S_RAD;
    cfg->M0_Nm = TV_PAPER_M0_NM;
    cfg->c_Nm_rad = TV_PAPER_C_NM_RAD;
    cfg->limp_home_width_rad = 1e-4;
    cfg->phi_closed_rad = -0.10;
    cfg->phi_open_rad = -0.10 + 84.0 * PLANT_PI / 180.0;
    cfg->stop_k_Nm_rad = 2.0e5;
    cfg->stop_exponent = 1.5;
    cfg->stop_lambda_Nm_s_rad = 2.865e4;
    cfg->substeps_per_ms = 50;
    cfg->supply_V = 13.5;
    cfg->diode_drop_V = 0.7;
    cfg->pwm_ripple = 0;
    cfg->pwm_frequency_Hz = 20000.0;
    cfg->current_offset_V = 1.65;
    cfg->current_gain_V_A = 0.1;
    cfg->current_noise_A = 0.01;
    cfg->tps_supply_V = 5.0;
    cfg->tps_offset_frac = 0.10;
    cfg->tps_span_frac = 0.80;
    cfg->tps_ref_closed_rad = cfg->phi_closed_rad;
    cfg->tps_ref_open_rad = cfg->phi_open_rad;
    cfg->angle_noise_rad = 1e-4;
    cfg->tps_noise_V = 0.0;
    cfg->tps_divider_gain = 0.66;
    cfg->supply_divider_gain = 1.0 / 6.0;
    cfg->supply_noise_V = 0.01;
    cfg->adc_ref_V = 3.3;
    cfg->adc_bits = 12;
}

/* A double field: non-finite -> TV_ERR_NONFINITE, range condition false -> TV_ERR_CONFIG. */
#define PLANT_CHECK_REAL(field, cond)                                                         \
    do {                                                                                      \
        if (!isfinite(cfg->field)) {                                                          \
            *st = TV_ERR_NONFINITE;                                                           \
            return #field;                                                                    \
        }                                                                                     \
        if (!(cond)) {                                                                        \
            *st = TV_ERR_CONFIG;                                                              \
            return #field;                                                                    \
        }                                                                                     \
    } while (0)

/* An int field: range condition false -> TV_ERR_CONFIG. */
#define PLANT_CHECK_INT(field, cond)                                                          \
    do {                                                                                      \
        if (!(cond)) {                                                                        \
            *st = TV_ERR_CONFIG;                                                              \
            return #field;                                                                    \
        }                                                                                     \
    } while (0)

static const char *plant_config_check_impl(const plant_config_t *cfg, int *st)
{
    double h_s;
    double omega_rad_s;
    *st = TV_ERR_CONFIG;
    PLANT_CHECK_REAL(R_ohm, cfg->R_ohm >= 0.0 && cfg->R_ohm <= 1e4);
    PLANT_CHECK_REAL(L_H, cfg->L_H > 0.0 && cfg->L_H <= 10.0);
    PLANT_CHECK_REAL(Ke_V_s_rad, cfg->Ke_V_s_rad >= 0.0 && cfg->Ke_V_s_rad <= 10.0);
    PLANT_CHECK_REAL(Kt_Nm_A, cfg->Kt_Nm_A >= 0.0 && cfg->Kt_Nm_A <= 10.0);
    PLANT_CHECK_REAL(J_kg_m2, cfg->J_kg_m2 > 0.0 && cfg->J_kg_m2 <= 10.0);
    PLANT_CHECK_REAL(n_gear, cfg->n_gear > 0.0 && cfg->n_gear <= 1e4);
    PLANT_CHECK_REAL(Mc_Nm, cfg->Mc_Nm >= 0.0 && cfg->Mc_Nm <= 1e3);
    PLANT_CHECK_REAL(Ms_Nm, cfg->Ms_Nm >= cfg->Mc_Nm && cfg->Ms_Nm <= 1e3);
    PLANT_CHECK_REAL(ws_rad_s, cfg->ws_rad_s > 0.0 && cfg->ws_rad_s <= 1e4);
    PLANT_CHECK_REAL(Kv_Nm_s_rad, cfg->Kv_Nm_s_rad >= 0.0 && cfg->Kv_Nm_s_rad <= 1e3);
    PLANT_CHECK_REAL(M0_Nm, cfg->M0_Nm >= 0.0 && cfg->M0_Nm <= 1e3);
    PLANT_CHECK_REAL(c_Nm_rad, cfg->c_Nm_rad >= 0.0 && cfg->c_Nm_rad <= 1e3);
    PLANT_CHECK_REAL(limp_home_width_rad,
                     cfg->limp_home_width_rad > 0.0 && cfg->limp_home_width_rad <= 0.1);
    PLANT_CHECK_REAL(phi_closed_rad, cfg->phi_closed_rad < 0.0 && cfg->phi_closed_rad >= -1.0);
    PLANT_CHECK_REAL(phi_open_rad, cfg->phi_open_rad > 0.0 && cfg->phi_open_rad <= 3.0);
    PLANT_CHECK_REAL(stop_k_Nm_rad, cfg->stop_k_Nm_rad >= 0.0 && cfg->stop_k_Nm_rad <= 1e9);
    PLANT_CHECK_REAL(stop_exponent, cfg->stop_exponent >= 1.0 && cfg->stop_exponent <= 3.0);
    PLANT_CHECK_REAL(stop_lambda_Nm_s_rad,
                     cfg->stop_lambda_Nm_s_rad >= 0.0 && cfg->stop_lambda_Nm_s_rad <= 1e9);
    PLANT_CHECK_INT(substeps_per_ms, cfg->substeps_per_ms >= PLANT_SUBSTEPS_PER_MS_MIN &&
                                         cfg->substeps_per_ms <= PLANT_SUBSTEPS_PER_MS_MAX);
    PLANT_CHECK_REAL(supply_V, cfg->supply_V > 0.0 && cfg->supply_V <= 100.0);
    PLANT_CHECK_REAL(diode_drop_V, cfg->diode_drop_V >= 0.0 && cfg->diode_drop_V <= 5.0);
    PLANT_CHECK_INT(pwm_ripple, cfg->pwm_ripple == 0 || cfg->pwm_ripple == 1);
    PLANT_CHECK_REAL(pwm_frequency_Hz,
                     cfg->pwm_frequency_Hz >= 100.0 && cfg->pwm_frequency_Hz <= 1e6);
    PLANT_CHECK_REAL(current_offset_V, fabs(cfg->current_offset_V) <= 100.0);
    PLANT_CHECK_REAL(current_gain_V_A,
                     cfg->current_gain_V_A != 0.0 && fabs(cfg->current_gain_V_A) <= 100.0);
    PLANT_CHECK_REAL(current_noise_A, cfg->current_noise_A >= 0.0 && cfg->current_noise_A <= 100.0);
    PLANT_CHECK_REAL(tps_supply_V, cfg->tps_supply_V > 0.0 && cfg->tps_supply_V <= 100.0);
    PLANT_CHECK_REAL(tps_offset_frac, cfg->tps_offset_frac >= 0.0 && cfg->tps_offset_frac < 1.0);
    PLANT_CHECK_REAL(tps_span_frac, cfg->tps_span_frac > 0.0 &&
                                        cfg->tps_offset_frac + cfg->tps_span_frac <= 1.0);
    PLANT_CHECK_REAL(tps_ref_closed_rad, cfg->tps_ref_closed_rad >= -1.0 && cfg->tps_ref_closed_rad <= 1.0);
    PLANT_CHECK_REAL(tps_ref_open_rad, cfg->tps_ref_open_rad > cfg->tps_ref_closed_rad && cfg->tps_ref_open_rad <= 3.0);
    PLANT_CHECK_REAL(angle_noise_rad, cfg->angle_noise_rad >= 0.0 && cfg->angle_noise_rad <= 1.0);
    PLANT_CHECK_REAL(tps_noise_V, cfg->tps_noise_V >= 0.0 && cfg->tps_noise_V <= 100.0);
    PLANT_CHECK_REAL(tps_divider_gain, cfg->tps_divider_gain > 0.0 && cfg->tps_divider_gain <= 1.0);
    PLANT_CHECK_REAL(supply_divider_gain,
                     cfg->supply_divider_gain > 0.0 && cfg->supply_divider_gain <= 1.0);
    PLANT_CHECK_REAL(supply_noise_V, cfg->supply_noise_V >= 0.0 && cfg->supply_noise_V <= 100.0);
    PLANT_CHECK_REAL(adc_ref_V, cfg->adc_ref_V > 0.0 && cfg->adc_ref_V <= 100.0);
    PLANT_CHECK_INT(adc_bits, cfg->adc_bits >= 8 && cfg->adc_bits <= 16);

    /* Stability of the explicit parts of the scheme (see plant.h): h * omega bounded for the
       detent + spring, for the contact stiffness at the deepest allowed penetration, and for
       the electromechanical (current <-> velocity) oscillation. */
    h_s = 1e-3 / (double)cfg->substeps_per_ms;
    omega_rad_s = sqrt((cfg->M0_Nm / cfg->limp_home_width_rad + cfg->c_Nm_rad) / cfg->J_kg_m2);
    PLANT_CHECK_REAL(limp_home_width_rad, h_s * omega_rad_s <= PLANT_STABILITY_H_OMEGA_MAX);
    omega_rad_s = sqrt(cfg->stop_exponent * cfg->stop_k_Nm_rad *
                       pow(PLANT_STATE_PENETRATION_MAX_RAD, cfg->stop_exponent - 1.0) /
                       cfg->J_kg_m2);
    PLANT_CHECK_REAL(stop_k_Nm_rad, h_s * omega_rad_s <= PLANT_STABILITY_H_OMEGA_MAX);
    omega_rad_s = cfg->n_gear * sqrt(cfg->Ke_V_s_rad * cfg->Kt_Nm_A / (cfg->L_H * cfg->J_kg_m2));
    PLANT_CHECK_INT(substeps_per_ms, h_s * omega_rad_s <= PLANT_STABILITY_H_OMEGA_MAX);
    *st = TV_OK;
    return NULL;
}

#undef PLANT_CHECK_REAL
#undef PLANT_CHECK_INT

const char *plant_config_check(const plant_config_t *cfg, int *status)
{
    int st = TV_OK;
    const char *bad;
    if (cfg == NULL) {
        if (status != NULL) {
            *status = TV_ERR_NULL;
        }
        return "cfg";
    }
    bad = plant_config_check_impl(cfg, &st);
    if (status != NULL) {
        *status = st;
    }
    return bad;
}

/** Armature zero-order-hold coefficients over hs: a = exp(-R hs / L), b = (1 - a) / R. */
static void plant_zoh(const plant_config_t *cfg, double hs, double *a, double *b_A_V)
{
    const double x = cfg->R_ohm * hs / cfg->L_H;
    *a = exp(-x);
    /* expm1 keeps b accurate when R hs / L is small; R = 0 is the limit hs / L. */
    *b_A_V = cfg->R_ohm > 0.0 ? -expm1(-x) / cfg->R_ohm : hs / cfg->L_H;
}

int plant_init(plant_t *plant, const plant_config_t *cfg, uint64_t seed)
{
    int st = TV_OK;
    uint64_t sm = seed;
    int k;
    if (plant == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    if (plant_config_check_impl(cfg, &st) != NULL) {
        return st;
    }
    plant->cfg = *cfg;
    plant->cfg_nominal = *cfg;
    plant_faults_none(&plant->faults);
    plant->tps_stuck_V[0] = plant->tps_stuck_V[1] = 0.0;
    plant->tps_stuck_held[0] = plant->tps_stuck_held[1] = 0;
    plant->h_s = 1e-3 / (double)cfg->substeps_per_ms;
    plant_zoh(cfg, 0.5 * plant->h_s, &plant->a_half, &plant->b_half_A_V);
    plant->current_A = 0.0;
    plant->velocity_rad_s = 0.0;
    plant->angle_rad = 0.0;
    plant->duty = 0.0;
    plant->enable = 0;
    plant->substeps_done = 0u;
    plant->frac_s = 0.0;
    plant->mean_bridge_V = 0.0;
    for (k = 0; k < 4; ++k) {
        plant->rng_s[k] = plant_splitmix64(&sm);
    }
    sm = seed ^ UINT64_C(0x5EED0FA17D1A6000); /* the fault draws: a stream of their own */
    for (k = 0; k < 4; ++k) {
        plant->fault_rng_s[k] = plant_splitmix64(&sm);
    }
    plant->gauss_spare = 0.0;
    plant->gauss_has_spare = 0;
    return TV_OK;
}

void plant_faults_none(plant_faults_t *f)
{
    if (f == NULL) {
        return;
    }
    memset(f, 0, sizeof *f);
    f->friction_factor = 1.0;
    f->spring_factor = 1.0;
    f->resistance_factor = 1.0;
}

/* TV_OK, TV_ERR_NONFINITE or TV_ERR_RANGE for the fields of *f against plant.h's ranges. */
static int plant_faults_check(const plant_faults_t *f, const plant_config_t *nom)
{
    const double v[] = {f->friction_factor,  f->jam_Nm,          f->spring_factor,    f->resistance_factor,
                        f->short_fraction,   f->supply_drop_V,   f->current_offset_A, f->current_gain_err,
                        f->tps_offset_V[0],  f->tps_offset_V[1], f->tps_gain_err[0],  f->tps_gain_err[1],
                        f->tps_dropout_prob[0], f->tps_dropout_prob[1]};
    size_t k;
    int ch;
    for (k = 0; k < sizeof v / sizeof v[0]; ++k) {
        if (!isfinite(v[k])) {
            return TV_ERR_NONFINITE;
        }
    }
    if (f->friction_factor < 0.1 || f->friction_factor > 100.0 || f->jam_Nm < 0.0 || f->jam_Nm > 1e3 ||
        f->spring_factor < 0.0 || f->spring_factor > 10.0 || f->resistance_factor < 0.1 ||
        f->resistance_factor > 100.0 || f->short_fraction < 0.0 || f->short_fraction > 0.95 ||
        (f->winding_open != 0 && f->winding_open != 1) || f->bridge_lost < -1 || f->bridge_lost > 1 ||
        f->supply_drop_V < 0.0 || !(f->supply_drop_V < nom->supply_V) || fabs(f->current_offset_A) > 100.0 ||
        !(f->current_gain_err > -1.0) || f->current_gain_err > 10.0) {
        return TV_ERR_RANGE;
    }
    for (ch = 0; ch < 2; ++ch) {
        if (fabs(f->tps_offset_V[ch]) > nom->tps_supply_V || !(f->tps_gain_err[ch] > -1.0) ||
            f->tps_gain_err[ch] > 10.0 || (f->tps_stuck[ch] != 0 && f->tps_stuck[ch] != 1) ||
            f->tps_dropout_prob[ch] < 0.0 || f->tps_dropout_prob[ch] > 1.0) {
            return TV_ERR_RANGE;
        }
    }
    return TV_OK;
}

int plant_set_faults(plant_t *plant, const plant_faults_t *faults)
{
    plant_config_t c;
    const plant_config_t *nom;
    const char *bad;
    int st = TV_OK;
    int ch;
    if (plant == NULL || faults == NULL) {
        return TV_ERR_NULL;
    }
    nom = &plant->cfg_nominal;
    st = plant_faults_check(faults, nom);
    if (st != TV_OK) {
        return st;
    }
    c = *nom;
    {
        const double keep = 1.0 - faults->short_fraction;
        c.Mc_Nm = nom->Mc_Nm * faults->friction_factor;
        c.Ms_Nm = nom->Ms_Nm * faults->friction_factor;
        c.M0_Nm = nom->M0_Nm * faults->spring_factor;
        c.c_Nm_rad = nom->c_Nm_rad * faults->spring_factor;
        c.R_ohm = nom->R_ohm * faults->resistance_factor * keep;
        c.Kt_Nm_A = nom->Kt_Nm_A * keep;
        c.Ke_V_s_rad = nom->Ke_V_s_rad * keep;
        c.L_H = nom->L_H * keep * keep;
        c.supply_V = nom->supply_V - faults->supply_drop_V;
    }
    bad = plant_config_check_impl(&c, &st);
    if (bad != NULL) {
        return st;
    }
    if (faults->jam_Nm > 0.0 && !(plant->faults.jam_Nm > 0.0)) {
        plant->velocity_rad_s = 0.0; /* the plate is blocked where it is */
    }
    for (ch = 0; ch < 2; ++ch) {
        if (!faults->tps_stuck[ch]) {
            plant->tps_stuck_held[ch] = 0;
        }
    }
    plant->cfg = c;
    plant->faults = *faults;
    plant_zoh(&c, 0.5 * plant->h_s, &plant->a_half, &plant->b_half_A_V);
    return TV_OK;
}

int plant_set_bridge(plant_t *plant, double duty, int enable)
{
    if (plant == NULL) {
        return TV_ERR_NULL;
    }
    if (!isfinite(duty)) {
        return TV_ERR_NONFINITE;
    }
    if (duty < -1.0 || duty > 1.0) {
        return TV_ERR_RANGE;
    }
    plant->duty = duty;
    plant->enable = enable != 0;
    return TV_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* Integration                                                                                 */
/* ------------------------------------------------------------------------------------------ */

/** On-time of the centred pulse, accumulated from the start of a PWM period up to t >= 0. */
static double plant_pwm_on_cumulative(double t_s, double period_s, double d)
{
    const double k = floor(t_s / period_s);
    const double local_s = t_s - k * period_s;
    double in_period_s = local_s - 0.5 * (1.0 - d) * period_s;
    if (in_period_s < 0.0) {
        in_period_s = 0.0;
    }
    if (in_period_s > d * period_s) {
        in_period_s = d * period_s;
    }
    return k * d * period_s + in_period_s;
}

/**
 * Mean bridge voltage over [t0, t0 + hs] with the bridge enabled: duty * Vs (averaged mode) or
 * sign(duty) * Vs times the exact on-time fraction of centre-aligned PWM (ripple mode).
 */
static double plant_enabled_voltage(const plant_t *p, double t0_s, double hs)
{
    const plant_config_t *cfg = &p->cfg;
    double period_s;
    double local0_s;
    double d;
    double on_s;
    if ((p->faults.bridge_lost > 0 && p->duty > 0.0) || (p->faults.bridge_lost < 0 && p->duty < 0.0)) {
        return 0.0; /* that direction is lost: both low sides on, 0 V */
    }
    if (!cfg->pwm_ripple) {
        return p->duty * cfg->supply_V;
    }
    d = fabs(p->duty);
    period_s = 1.0 / cfg->pwm_frequency_Hz;
    /* Work relative to the start of the PWM period holding t0 to keep the numbers small. */
    local0_s = t0_s - floor(t0_s / period_s) * period_s;
    if (local0_s < 0.0) {
        local0_s = 0.0;
    }
    on_s = plant_pwm_on_cumulative(local0_s + hs, period_s, d) -
           plant_pwm_on_cumulative(local0_s, period_s, d);
    if (on_s < 0.0) {
        on_s = 0.0;
    }
    if (on_s > hs) {
        on_s = hs;
    }
    return (p->duty < 0.0 ? -cfg->supply_V : cfg->supply_V) * (on_s / hs);
}

/**
 * Armature over a time slice hs starting at t0_s, from current i0 with the plate velocity held
 * at w: exact zero-order-hold solution (a, b_A_V are the coefficients for hs). Enabled bridge:
 * the mean bridge voltage over the slice. Disabled bridge: the diode complementarity law of
 * plant.h, with the zero crossing located exactly. Writes the integral of the terminal voltage
 * over the slice [V s] and returns the new current.
 */
static double plant_armature(const plant_t *p, double i0, double w, double hs, double a,
                             double b_A_V, double t0_s, double *u_int_V_s)
{
    const plant_config_t *cfg = &p->cfg;
    const double emf_V = cfg->Ke_V_s_rad * cfg->n_gear * w;
    const double clamp_V = cfg->supply_V + 2.0 * cfg->diode_drop_V;
    double u_V;
    double drive_V;
    double i1;
    double t_zero_s;
    if (p->enable) {
        u_V = plant_enabled_voltage(p, t0_s, hs);
        *u_int_V_s = u_V * hs;
        return a * i0 + b_A_V * (u_V - emf_V);
    }
    if (i0 == 0.0) {
        /* Open winding: diodes block while |back-EMF| <= Vs + 2 Vd; the terminals float at
           the back-EMF and the current stays exactly 0. */
        if (fabs(emf_V) <= clamp_V) {
            *u_int_V_s = emf_V * hs;
            return 0.0;
        }
        /* Generator mode: the current flows against the EMF through the diodes. */
        u_V = emf_V > 0.0 ? clamp_V : -clamp_V;
        *u_int_V_s = u_V * hs;
        return b_A_V * (u_V - emf_V);
    }
    u_V = i0 > 0.0 ? -clamp_V : clamp_V;
    drive_V = u_V - emf_V;
    i1 = a * i0 + b_A_V * drive_V;
    if ((i0 > 0.0 && i1 > 0.0) || (i0 < 0.0 && i1 < 0.0)) {
        *u_int_V_s = u_V * hs;
        return i1;
    }
    /* The current reaches zero inside the slice; the diodes stop it there. Exact crossing
       time of i(t) = i_inf + (i0 - i_inf) exp(-R t / L), i_inf = drive / R (linear if R = 0). */
    if (cfg->R_ohm > 0.0) {
        t_zero_s = cfg->L_H / cfg->R_ohm * log1p(-i0 * cfg->R_ohm / drive_V);
    } else {
        t_zero_s = -cfg->L_H * i0 / drive_V;
    }
    if (!(t_zero_s >= 0.0)) {
        t_zero_s = 0.0;
    }
    if (t_zero_s > hs) {
        t_zero_s = hs;
    }
    *u_int_V_s = u_V * t_zero_s + emf_V * (hs - t_zero_s);
    return 0.0;
}

/** Solve A(w) = y for the velocity (see plant_kick): A strictly increasing, piecewise linear. */
static double plant_solve_velocity(double y, double s1, double beta_P_k, double beta_P_lambda,
                                   double w_kink, int contact)
{
    if (contact < 0) {
        /* closed stop: A(w) = (s1 + b P lambda) w - b P k for w <= k / lambda, s1 w beyond */
        if (beta_P_lambda > 0.0 && y > s1 * w_kink) {
            return y / s1;
        }
        return (y + beta_P_k) / (s1 + beta_P_lambda);
    }
    if (contact > 0) {
        /* open stop: A(w) = (s1 + b P lambda) w + b P k for w >= -k / lambda, s1 w below */
        if (beta_P_lambda > 0.0 && y < -s1 * w_kink) {
            return y / s1;
        }
        return (y - beta_P_k) / (s1 + beta_P_lambda);
    }
    return y / s1;
}

/** Stribeck friction level g(w) = Mc + (Ms - Mc) exp(-|w| / ws) [N m], plus a jam's holding torque. */
static double plant_friction_level(const plant_t *p, double w_rad_s)
{
    const plant_config_t *cfg = &p->cfg;
    return cfg->Mc_Nm + (cfg->Ms_Nm - cfg->Mc_Nm) * exp(-fabs(w_rad_s) / cfg->ws_rad_s) + p->faults.jam_Nm;
}

/**
 * Velocity kick over hs at angle phi with motor current i (see plant.h, step 2): solves
 *   (w1 - w0) J / hs = n Kt i - Mspring(phi) - Kv (w0 + w1) / 2 - Mcoul + Mstop(phi, w1),
 *   Mcoul in g Sign(w1),
 * exactly (A(w) = (1 + hs Kv / 2J) w - (hs/J) Mstop(phi, w) is strictly increasing and piecewise
 * linear). The friction level g is first taken at w0 (so a plate at rest breaks away exactly
 * when the net torque exceeds Ms); when the plate slides through the whole kick it is
 * re-evaluated at the mean velocity of the first solution (second order in smooth sliding).
 */
static double plant_kick(const plant_t *p, double w0, double phi, double i_A, double hs)
{
    const plant_config_t *cfg = &p->cfg;
    const double beta = hs / cfg->J_kg_m2;
    const double half_visc = 0.5 * beta * cfg->Kv_Nm_s_rad;
    const double s1 = 1.0 + half_visc;
    double detent;
    double z;
    double a0;
    double beta_P_k = 0.0;
    double beta_P_lambda = 0.0;
    double w_kink = 0.0;
    double w1 = 0.0;
    int contact = 0;
    int pass;

    detent = phi / cfg->limp_home_width_rad;
    if (detent > 1.0) {
        detent = 1.0;
    }
    if (detent < -1.0) {
        detent = -1.0;
    }
    /* velocity after the smooth, explicit torques (motor, springs, half of viscous) */
    z = w0 * (1.0 - half_visc) +
        beta * (cfg->n_gear * cfg->Kt_Nm_A * i_A - cfg->M0_Nm * detent - cfg->c_Nm_rad * phi);
    if (phi < cfg->phi_closed_rad) {
        contact = -1;
    } else if (phi > cfg->phi_open_rad) {
        contact = 1;
    }
    if (contact != 0) {
        const double pen_rad = contact < 0 ? cfg->phi_closed_rad - phi : phi - cfg->phi_open_rad;
        const double pe = pow(pen_rad, cfg->stop_exponent);
        beta_P_k = beta * pe * cfg->stop_k_Nm_rad;
        beta_P_lambda = beta * pe * cfg->stop_lambda_Nm_s_rad;
        if (cfg->stop_lambda_Nm_s_rad > 0.0) {
            w_kink = cfg->stop_k_Nm_rad / cfg->stop_lambda_Nm_s_rad;
        }
    }
    /* A(0) = -(hs/J) Mstop(phi, 0): the static contact torque */
    a0 = contact < 0 ? -beta_P_k : (contact > 0 ? beta_P_k : 0.0);
    for (pass = 0; pass < 2; ++pass) {
        const double w_level = pass == 0 ? w0 : 0.5 * (w0 + w1);
        const double friction = beta * plant_friction_level(p, w_level);
        if (fabs(z - a0) <= friction) {
            w1 = 0.0; /* sticks: friction absorbs the whole impulse */
        } else if (z - a0 > friction) {
            w1 = plant_solve_velocity(z - friction, s1, beta_P_k, beta_P_lambda, w_kink, contact);
            if (w1 < 0.0) {
                w1 = 0.0; /* rounding only: A is increasing, so the exact root is positive */
            }
        } else {
            w1 = plant_solve_velocity(z + friction, s1, beta_P_k, beta_P_lambda, w_kink, contact);
            if (w1 > 0.0) {
                w1 = 0.0;
            }
        }
        /* refine only while sliding the whole kick in one direction */
        if (!(w0 * w1 > 0.0)) {
            break;
        }
    }
    return w1;
}

/**
 * One sub-step of length hs (<= h) starting at plant time t0_s; a_half, b_half are the armature
 * ZOH coefficients for hs / 2. Strang splitting: armature half-slice with w0, mechanics by
 * drift (hs/2) - kick (hs) - drift (hs/2) with the mid-slice current, armature half-slice with
 * w1. Returns the integral of the bridge voltage over the sub-step [V s].
 */
static double plant_substep(plant_t *p, double hs, double a_half, double b_half_A_V, double t0_s)
{
    const plant_config_t *cfg = &p->cfg;
    const double half_s = 0.5 * hs;
    const double w0 = p->velocity_rad_s;
    double u_int_a;
    double u_int_b;
    double i_mid;
    double phi_mid;
    double w1;

    if (p->faults.winding_open) {
        /* open winding: no current whatever the bridge does; the terminals float at the
           back-EMF (trapezoid over the sub-step) */
        phi_mid = p->angle_rad + half_s * w0;
        w1 = plant_kick(p, w0, phi_mid, 0.0, hs);
        p->angle_rad = phi_mid + half_s * w1;
        p->velocity_rad_s = w1;
        p->current_A = 0.0;
        return cfg->Ke_V_s_rad * cfg->n_gear * half_s * (w0 + w1);
    }
    i_mid = plant_armature(p, p->current_A, w0, half_s, a_half, b_half_A_V, t0_s, &u_int_a);
    phi_mid = p->angle_rad + half_s * w0;
    w1 = plant_kick(p, w0, phi_mid, i_mid, hs);
    p->angle_rad = phi_mid + half_s * w1;
    p->velocity_rad_s = w1;
    p->current_A =
        plant_armature(p, i_mid, w1, half_s, a_half, b_half_A_V, t0_s + half_s, &u_int_b);
    return u_int_a + u_int_b;
}

/** Partial sub-step of length hs (< h) at time t0_s, with its own ZOH coefficients. */
static double plant_partial_substep(plant_t *p, double hs, double t0_s)
{
    double a;
    double b_A_V;
    plant_zoh(&p->cfg, 0.5 * hs, &a, &b_A_V);
    return plant_substep(p, hs, a, b_A_V, t0_s);
}

int plant_advance(plant_t *plant, double dt_s)
{
    double h_s;
    double snap_s;
    double remaining_s;
    double u_int_V_s = 0.0;
    double q;
    double r_s;
    uint64_t n_full;
    uint64_t k;
    plant_state_t saved;
    uint64_t saved_steps;
    double saved_frac_s;
    if (plant == NULL) {
        return TV_ERR_NULL;
    }
    if (!isfinite(dt_s)) {
        return TV_ERR_NONFINITE;
    }
    if (dt_s < 0.0 || dt_s > PLANT_ADVANCE_MAX_S) {
        return TV_ERR_RANGE;
    }
    if (dt_s == 0.0) {
        return TV_OK;
    }
    saved.current_A = plant->current_A;
    saved.velocity_rad_s = plant->velocity_rad_s;
    saved.angle_rad = plant->angle_rad;
    saved_steps = plant->substeps_done;
    saved_frac_s = plant->frac_s;

    h_s = plant->h_s;
    snap_s = PLANT_TIME_SNAP_FRAC * h_s;
    remaining_s = dt_s;

    /* 1. complete a partially done sub-step, staying on the time grid */
    if (plant->frac_s > 0.0) {
        const double t0_s = (double)plant->substeps_done * h_s + plant->frac_s;
        const double to_grid_s = h_s - plant->frac_s;
        if (remaining_s < to_grid_s - snap_s) {
            u_int_V_s += plant_partial_substep(plant, remaining_s, t0_s);
            plant->frac_s += remaining_s;
            remaining_s = 0.0;
        } else {
            u_int_V_s += plant_partial_substep(plant, to_grid_s, t0_s);
            plant->substeps_done += 1u;
            plant->frac_s = 0.0;
            remaining_s -= to_grid_s;
            if (remaining_s < 0.0) {
                remaining_s = 0.0;
            }
        }
    }

    /* 2. whole sub-steps (at most PLANT_ADVANCE_MAX_S / h of them) */
    q = remaining_s / h_s;
    n_full = (uint64_t)floor(q + PLANT_TIME_SNAP_FRAC);
    r_s = remaining_s - (double)n_full * h_s;
    if (r_s < snap_s) {
        r_s = 0.0;
    }
    if (r_s >= h_s) {
        r_s = h_s * (1.0 - PLANT_TIME_SNAP_FRAC); /* rounding guard; cannot occur for q >= 0 */
    }
    for (k = 0u; k < n_full; ++k) {
        const double t0_s = (double)plant->substeps_done * h_s;
        u_int_V_s += plant_substep(plant, h_s, plant->a_half, plant->b_half_A_V, t0_s);
        plant->substeps_done += 1u;
    }

    /* 3. remainder */
    if (r_s > 0.0) {
        u_int_V_s += plant_partial_substep(plant, r_s, (double)plant->substeps_done * h_s);
        plant->frac_s = r_s;
    }

    if (!isfinite(plant->current_A) || !isfinite(plant->velocity_rad_s) ||
        !isfinite(plant->angle_rad) || !isfinite(u_int_V_s)) {
        plant->current_A = saved.current_A;
        plant->velocity_rad_s = saved.velocity_rad_s;
        plant->angle_rad = saved.angle_rad;
        plant->substeps_done = saved_steps;
        plant->frac_s = saved_frac_s;
        return TV_ERR_NUMERIC;
    }
    plant->mean_bridge_V = u_int_V_s / dt_s;
    return TV_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* Sensors and accessors                                                                       */
/* ------------------------------------------------------------------------------------------ */

/** Round to nearest and saturate to 0 .. 2^bits - 1 (NaN maps to 0). */
static uint16_t plant_quantise(double pin_V, double counts_per_V, double max_counts)
{
    const double q = floor(pin_V * counts_per_V + 0.5);
    if (!(q > 0.0)) {
        return 0u;
    }
    if (q > max_counts) {
        return (uint16_t)max_counts;
    }
    return (uint16_t)q;
}

static double plant_clamp(double x, double lo, double hi)
{
    if (x < lo) {
        return lo;
    }
    if (x > hi) {
        return hi;
    }
    return x;
}

int plant_sample(plant_t *plant, plant_adc_t *out)
{
    const plant_config_t *cfg;
    double n_i_A;
    double n_phi_rad;
    double n_e1_V;
    double n_e2_V;
    double n_s_V;
    double full_scale;
    double counts_per_V;
    double max_counts;
    if (plant == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    cfg = &plant->cfg;
    /* Always five draws in this order, whatever the sigmas. */
    n_i_A = cfg->current_noise_A * plant_gauss(plant);
    n_phi_rad = cfg->angle_noise_rad * plant_gauss(plant);
    n_e1_V = cfg->tps_noise_V * plant_gauss(plant);
    n_e2_V = cfg->tps_noise_V * plant_gauss(plant);
    n_s_V = cfg->supply_noise_V * plant_gauss(plant);

    full_scale = (double)(1L << cfg->adc_bits);
    counts_per_V = full_scale / cfg->adc_ref_V;
    max_counts = full_scale - 1.0;

    out->t_s = plant_time_s(plant);
    {
        const plant_faults_t *f = &plant->faults;
        double track_V[2];
        double x;
        int ch;
        out->current_pin_V = cfg->current_offset_V + cfg->current_gain_V_A * (1.0 + f->current_gain_err) *
                                                         (plant->current_A + n_i_A + f->current_offset_A);
        x = (plant->angle_rad + n_phi_rad - cfg->tps_ref_closed_rad) /
            (cfg->tps_ref_open_rad - cfg->tps_ref_closed_rad);
        track_V[0] = cfg->tps_supply_V * (cfg->tps_offset_frac + cfg->tps_span_frac * x);
        track_V[1] = cfg->tps_supply_V * (1.0 - cfg->tps_offset_frac - cfg->tps_span_frac * x);
        n_e1_V += f->tps_offset_V[0];
        n_e2_V += f->tps_offset_V[1];
        track_V[0] = plant_clamp(track_V[0] * (1.0 + f->tps_gain_err[0]) + n_e1_V, 0.0, cfg->tps_supply_V);
        track_V[1] = plant_clamp(track_V[1] * (1.0 + f->tps_gain_err[1]) + n_e2_V, 0.0, cfg->tps_supply_V);
        for (ch = 0; ch < 2; ++ch) {
            if (f->tps_stuck[ch]) {
                if (!plant->tps_stuck_held[ch]) {
                    plant->tps_stuck_V[ch] = track_V[ch];
                    plant->tps_stuck_held[ch] = 1;
                }
                track_V[ch] = plant->tps_stuck_V[ch];
            }
            if (f->tps_dropout_prob[ch] > 0.0 &&
                (double)(plant_rng_next(plant->fault_rng_s) >> 11) * PLANT_TWO_POW_M53 < f->tps_dropout_prob[ch]) {
                track_V[ch] = 0.0; /* the wiper lost contact: the pull-down reads 0 V */
            }
        }
        out->tps1_pin_V = cfg->tps_divider_gain * track_V[0];
        out->tps2_pin_V = cfg->tps_divider_gain * track_V[1];
    }
    out->supply_pin_V = cfg->supply_divider_gain * (cfg->supply_V + n_s_V);

    out->current_counts = plant_quantise(out->current_pin_V, counts_per_V, max_counts);
    out->tps1_counts = plant_quantise(out->tps1_pin_V, counts_per_V, max_counts);
    out->tps2_counts = plant_quantise(out->tps2_pin_V, counts_per_V, max_counts);
    out->supply_counts = plant_quantise(out->supply_pin_V, counts_per_V, max_counts);
    return TV_OK;
}

int plant_truth(const plant_t *plant, plant_state_t *out)
{
    if (plant == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    out->current_A = plant->current_A;
    out->velocity_rad_s = plant->velocity_rad_s;
    out->angle_rad = plant->angle_rad;
    return TV_OK;
}

int plant_bridge_voltage(const plant_t *plant, double *mean_V)
{
    if (plant == NULL || mean_V == NULL) {
        return TV_ERR_NULL;
    }
    *mean_V = plant->mean_bridge_V;
    return TV_OK;
}

double plant_time_s(const plant_t *plant)
{
    if (plant == NULL) {
        return 0.0;
    }
    return (double)plant->substeps_done * plant->h_s + plant->frac_s;
}

int plant_set_state(plant_t *plant, const plant_state_t *state)
{
    if (plant == NULL || state == NULL) {
        return TV_ERR_NULL;
    }
    if (!isfinite(state->current_A) || !isfinite(state->velocity_rad_s) ||
        !isfinite(state->angle_rad)) {
        return TV_ERR_NONFINITE;
    }
    if (fabs(state->current_A) > PLANT_STATE_CURRENT_MAX_A ||
        fabs(state->velocity_rad_s) > PLANT_STATE_VELOCITY_MAX_RAD_S ||
        state->angle_rad < plant->cfg.phi_closed_rad - PLANT_STATE_PENETRATION_MAX_RAD ||
        state->angle_rad > plant->cfg.phi_open_rad + PLANT_STATE_PENETRATION_MAX_RAD) {
        return TV_ERR_RANGE;
    }
    plant->current_A = state->current_A;
    plant->velocity_rad_s = state->velocity_rad_s;
    plant->angle_rad = state->angle_rad;
    return TV_OK;
}
