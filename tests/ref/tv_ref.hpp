/**
 * @file tv_ref.hpp
 * @brief Independent C++/Eigen reference of the throttle-valve prediction map and EKF, used only by
 *        tests (tests/test_eigen_crosscheck*.cpp) and by the benchmark tests/bench_ref.cpp.
 *
 * Written from the specifications in the doc comments of firmware/estimator/tv_model.h and firmware/estimator/ekf.h,
 * NOT from firmware/estimator/tv_model.c or firmware/estimator/ekf.c, so that it checks the C code instead of
 * repeating it. Differences from the C code by construction:
 *   - everything is double and Eigen fixed-size matrices (Matrix3d, Vector3d, RowVector3d);
 *   - the map is one template, step<S>(), evaluated with S = double for values and with
 *     S = Eigen::AutoDiffScalar<Eigen::Vector3d> for the Jacobian: there is no hand-derived
 *     derivative anywhere in this file;
 *   - the correction is written in matrix form: H a RowVector3d, K = P H^T / s, Joseph form
 *     (I - K H) P (I - K H)^T + K r K^T, then P = (P + P^T) / 2.
 *
 * Branches of the piecewise-smooth map (stick/slip, stop contact) are decided on the value
 * (val()) of the scalar, so AutoDiff returns the derivative of the branch taken. step() can
 * record the smallest relative distance to a branch boundary met along the way (BranchTrace):
 * tests use it to tell a rounding-induced branch straddle from a real disagreement.
 */
#ifndef TV_REF_HPP
#define TV_REF_HPP

#include <Eigen/Dense>
#include <unsupported/Eigen/AutoDiff>

#include <algorithm>
#include <cmath>
#include <limits>

namespace tvref {

/** Scalar for forward-mode AD with respect to the 3 states. */
typedef Eigen::AutoDiffScalar<Eigen::Vector3d> Ad;

/** Value of a scalar (double or AD). */
inline double val(double v) { return v; }
/** Value of an AD scalar. */
template <class D> inline double val(const Eigen::AutoDiffScalar<D>& v) { return v.value(); }

/**
 * Model parameters, SI, plate side. Defaults are those documented at tvm_params_default() in
 * firmware/estimator/tv_model.h: paper Table 1 plus the project's stop, smoothing and sub-step choices.
 */
struct Params {
    double R_ohm = 4.3;
    double L_H = 0.002;
    double Ke_V_s_rad = 0.017;
    double Kt_Nm_A = 0.017;
    double J_kg_m2 = 0.0016;
    double n_gear = 40.0;
    double Mc_Nm = 0.2;
    double M0_Nm = 0.25;
    double c_Nm_rad = 0.059;
    double Kv_Nm_s_rad = 0.01;
    double Ms_Nm = 0.3;
    double ws_rad_s = 1.0;
    double phi_closed_rad = -0.10;
    /* tv_model.h: "phi_closed + 84 deg = 1.3660766 rad" (exactly 1.36607657167..., the
     * documented number is that rounded to 7 decimals; the documented number is the default) */
    double phi_open_rad = 1.3660766;
    double k_stop_Nm_rad = 1.0e4;
    double d_stop_Nm_s_rad = 2.4;
    double e_phi_rad = 1.0e-4;
    double e_w_rad_s = 1.0e-3;
    double Ts_s = 1.0e-3;
    int substeps = 10;
};

/**
 * What one evaluation of the map met, over all its sub-steps. Diagnostics for tests only; the
 * map does not depend on it.
 *
 * min_margin: smallest relative distance to a branch boundary (1 = far from every boundary,
 * 0 = exactly on one), each measured against the magnitudes that set the rounding error of the
 * quantity compared:
 *   stick/slip:      ||z| - D| / max(|w|, |(h/J) T|, D)
 *   contact law:     |k p -/+ d w| / (k |p| + d |w|)     while penetrating
 *   contact onset:   |p| / max(|phi|, |phi_stop|)        (p = penetration)
 * mag: per state, the largest sum of absolute values of the terms that form its new value in a
 * sub-step (current: a|i| + b|u| + b Ke n |w|; velocity: |w| + (h/J) sum|torque terms| + D;
 * angle: |phi| + h |w1|). Rounding error in x_next is a small multiple of eps * mag.
 */
struct BranchTrace {
    double min_margin = 1.0;
    double mag[3] = {0.0, 0.0, 0.0};
    void see(double m)
    {
        if (m < min_margin) {
            min_margin = m;
        }
    }
    void mag_see(int k, double m)
    {
        if (m > mag[k]) {
            mag[k] = m;
        }
    }
};

/** Relative distance |a - b| / max(|a|, |b|), 1 when both are zero. */
inline double rel_gap(double a, double b)
{
    const double s = std::max(std::fabs(a), std::fabs(b));
    return s > 0.0 ? std::fabs(a - b) / s : 1.0;
}

/**
 * Hard-stop torque [N m], positive = opening (Kelvin-Voigt, no adhesion), tv_model.h:
 *   p_lo = phi_closed - phi > 0:  +max(0, k p_lo - d w)
 *   p_hi = phi - phi_open   > 0:  -max(0, k p_hi + d w)
 */
template <class S> S stop_torque(const Params& p, const S& phi, const S& w, BranchTrace* tr)
{
    const S p_lo = p.phi_closed_rad - phi;
    const S p_hi = phi - p.phi_open_rad;
    if (tr) {
        tr->see(std::fabs(val(p_lo)) / std::max(std::fabs(val(phi)), std::fabs(p.phi_closed_rad)));
        tr->see(std::fabs(val(p_hi)) / std::max(std::fabs(val(phi)), std::fabs(p.phi_open_rad)));
    }
    if (val(p_lo) > 0.0) {
        const S f = p.k_stop_Nm_rad * p_lo - p.d_stop_Nm_s_rad * w;
        if (tr) {
            tr->see(rel_gap(p.k_stop_Nm_rad * val(p_lo), p.d_stop_Nm_s_rad * val(w)));
        }
        if (val(f) > 0.0) {
            return f;
        }
        return S(0.0);
    }
    if (val(p_hi) > 0.0) {
        const S f = p.k_stop_Nm_rad * p_hi + p.d_stop_Nm_s_rad * w;
        if (tr) {
            tr->see(rel_gap(p.k_stop_Nm_rad * val(p_hi), -p.d_stop_Nm_s_rad * val(w)));
        }
        if (val(f) > 0.0) {
            return S(-f);
        }
        return S(0.0);
    }
    return S(0.0);
}

/** Friction level g(w) = Mc + (Ms - Mc) exp(-|w|_e / ws), |w|_e = sqrt(w^2 + e_w^2) - e_w. */
template <class S> S friction_level(const Params& p, const S& w)
{
    using std::exp;
    using std::sqrt;
    const S w_abs_e = S(sqrt(w * w + p.e_w_rad_s * p.e_w_rad_s)) - p.e_w_rad_s;
    return S(p.Mc_Nm + (p.Ms_Nm - p.Mc_Nm) * S(exp(S(-w_abs_e / p.ws_rad_s))));
}

/** Smoothed limp-home preload sign sp(phi) = phi / sqrt(phi^2 + e_phi^2). */
template <class S> S preload_sign(const Params& p, const S& phi)
{
    using std::sqrt;
    return S(phi / S(sqrt(phi * phi + p.e_phi_rad * p.e_phi_rad)));
}

/**
 * One sub-step of length h = Ts / N of the discrete map (tv_model.h), written from the spec:
 *   i1   = a i + b (u - Ke n w),        a = exp(-R h / L), b = (1 - a) / R
 *   T    = n Kt i1 - M0 sp(phi) - c phi + Mstop(phi, w)
 *   z    = w + (h / J) T
 *   D    = (h / J) g(w)
 *   w1   = kappa sgn(z) max(|z| - D, 0),  kappa = 1 / (1 + h Kv / J)
 *   phi1 = phi + h w1
 */
template <class S>
Eigen::Matrix<S, 3, 1> substep(const Params& p, const Eigen::Matrix<S, 3, 1>& x, double u_V,
                               BranchTrace* tr = nullptr)
{
    using std::exp;
    const double h = p.Ts_s / p.substeps;
    const double a = exp(-p.R_ohm * h / p.L_H);
    const double b = (1.0 - a) / p.R_ohm;
    const double kappa = 1.0 / (1.0 + h * p.Kv_Nm_s_rad / p.J_kg_m2);
    const double h_over_J = h / p.J_kg_m2;

    const S i = x(0);
    const S w = x(1);
    const S phi = x(2);

    const S i1 = a * i + b * S(u_V - p.Ke_V_s_rad * p.n_gear * w);
    const S M_motor = p.n_gear * p.Kt_Nm_A * i1;
    const S M_preload = p.M0_Nm * preload_sign(p, phi);
    const S M_spring = p.c_Nm_rad * phi;
    const S M_stop = stop_torque(p, phi, w, tr);
    const S T = M_motor - M_preload - M_spring + M_stop;
    const S z = w + h_over_J * T;
    const S D = h_over_J * friction_level(p, w);
    if (tr) {
        const double hT = h_over_J * std::fabs(val(T));
        tr->see(std::fabs(std::fabs(val(z)) - val(D)) /
                std::max(std::max(std::fabs(val(w)), hT), val(D)));
        tr->mag_see(0, a * std::fabs(val(i)) + b * std::fabs(u_V) +
                           b * p.Ke_V_s_rad * p.n_gear * std::fabs(val(w)));
        tr->mag_see(1, std::fabs(val(w)) +
                           h_over_J * (std::fabs(val(M_motor)) + std::fabs(val(M_preload)) +
                                       std::fabs(val(M_spring)) + std::fabs(val(M_stop))) +
                           val(D));
    }
    S w1;
    if (val(z) > val(D)) {
        w1 = kappa * S(z - D);
    } else if (val(z) < -val(D)) {
        w1 = kappa * S(z + D);
    } else {
        w1 = S(0.0); /* stuck: the friction impulse stops the plate; derivative zero */
    }
    const S phi1 = phi + h * w1;
    if (tr) {
        tr->mag_see(2, std::fabs(val(phi)) + h * std::fabs(val(w1)));
    }

    Eigen::Matrix<S, 3, 1> x1;
    x1 << i1, w1, phi1;
    return x1;
}

/** The discrete map x(k+1) = f(x(k), u) over Ts: N sub-steps with u held. */
template <class S>
Eigen::Matrix<S, 3, 1> step(const Params& p, const Eigen::Matrix<S, 3, 1>& x, double u_V,
                            BranchTrace* tr)
{
    Eigen::Matrix<S, 3, 1> xs = x;
    for (int k = 0; k < p.substeps; ++k) {
        xs = substep<S>(p, xs, u_V, tr);
    }
    return xs;
}

/**
 * How firmly static friction holds the plate over one step (tv_model.h tvm_step_aug_peak()'s
 * hold_frac): 1 - |z| / D of the last sub-step when no sub-step slipped, else -1; z and D as
 * substep() forms them, each sub-step from the previous one's state.
 */
inline double hold_fraction(const Params& p, const Eigen::Vector3d& x, double u_V)
{
    const double h = p.Ts_s / p.substeps;
    const double a = std::exp(-p.R_ohm * h / p.L_H);
    const double b = (1.0 - a) / p.R_ohm;
    const double h_over_J = h / p.J_kg_m2;
    Eigen::Vector3d xs = x;
    double frac = -1.0;
    for (int k = 0; k < p.substeps; ++k) {
        const double i1 = a * xs(0) + b * (u_V - p.Ke_V_s_rad * p.n_gear * xs(1));
        const double T = p.n_gear * p.Kt_Nm_A * i1 - p.M0_Nm * preload_sign(p, xs(2)) - p.c_Nm_rad * xs(2) +
                         stop_torque<double>(p, xs(2), xs(1), nullptr);
        const double z = xs(1) + h_over_J * T;
        const double D = h_over_J * friction_level(p, xs(1));
        if (std::fabs(z) > D) {
            return -1.0;
        }
        frac = 1.0 - std::fabs(z) / D;
        xs = substep<double>(p, xs, u_V);
    }
    return frac;
}

/** The largest |M_stop| over the sub-steps of one step, each at the sub-step's start state. */
inline double peak_stop_torque(const Params& p, const Eigen::Vector3d& x, double u_V)
{
    Eigen::Vector3d xs = x;
    double peak = 0.0;
    for (int k = 0; k < p.substeps; ++k) {
        peak = std::max(peak, std::fabs(stop_torque<double>(p, xs(2), xs(1), nullptr)));
        xs = substep<double>(p, xs, u_V);
    }
    return peak;
}

/** The discrete map x(k+1) = f(x(k), u) over Ts (no branch trace). */
template <class S>
Eigen::Matrix<S, 3, 1> step(const Params& p, const Eigen::Matrix<S, 3, 1>& x, double u_V)
{
    return step<S>(p, x, u_V, nullptr);
}

/** Seed an AD state vector: derivative of x_j with respect to x_j is 1. */
inline Eigen::Matrix<Ad, 3, 1> ad_seed(const Eigen::Vector3d& x)
{
    Eigen::Matrix<Ad, 3, 1> xa;
    for (int j = 0; j < 3; ++j) {
        xa(j) = Ad(x(j), Eigen::Vector3d::Unit(j));
    }
    return xa;
}

/** Values and derivatives of an AD state vector. */
inline void ad_split(const Eigen::Matrix<Ad, 3, 1>& ya, Eigen::Vector3d* y, Eigen::Matrix3d* F)
{
    for (int r = 0; r < 3; ++r) {
        if (y) {
            (*y)(r) = ya(r).value();
        }
        if (F) {
            /* a constant result (e.g. a stuck velocity) may carry an empty/zero derivative */
            if (ya(r).derivatives().size() == 3) {
                F->row(r) = ya(r).derivatives().transpose();
            } else {
                F->row(r).setZero();
            }
        }
    }
}

/** Jacobian df/dx of the map at (x, u) by forward-mode automatic differentiation; optional f. */
inline Eigen::Matrix3d jacobian_ad(const Params& p, const Eigen::Vector3d& x, double u_V,
                                   Eigen::Vector3d* x_next = nullptr, BranchTrace* tr = nullptr)
{
    Eigen::Matrix3d F;
    ad_split(step<Ad>(p, ad_seed(x), u_V, tr), x_next, &F);
    return F;
}

/**
 * Componentwise rounding-error scale of the chain-rule product F = J_N ... J_1:
 * B = |J_N| ... |J_1| with the sub-step Jacobians J_k from AD along the double trajectory.
 * Rounding in the product and in each J_k is bounded by a modest multiple of eps * B.
 */
inline Eigen::Matrix3d jacobian_abs_product(const Params& p, const Eigen::Vector3d& x, double u_V)
{
    Eigen::Matrix3d B = Eigen::Matrix3d::Identity();
    Eigen::Vector3d xs = x;
    for (int k = 0; k < p.substeps; ++k) {
        Eigen::Matrix3d Jk;
        Eigen::Vector3d xn;
        ad_split(substep<Ad>(p, ad_seed(xs), u_V), &xn, &Jk);
        B = (Jk.cwiseAbs() * B).eval();
        xs = xn;
    }
    return B;
}

/* ------------------------------------------------------------------------------------------ */
/* EKF                                                                                        */
/* ------------------------------------------------------------------------------------------ */

/** Measurement set-ups (ekf.h). */
enum class Setup { CurrentAngle, Paper3Meas };

/** Filter configuration (ekf.h ekf_config_t), variances throughout. */
struct Config {
    Setup setup = Setup::CurrentAngle;
    Eigen::Vector3d x0 = Eigen::Vector3d::Zero();
    Eigen::Matrix3d P0 = Eigen::Matrix3d::Identity();
    Eigen::Matrix3d Q = Eigen::Matrix3d::Zero();
    Eigen::Vector3d r = Eigen::Vector3d::Ones(); /**< measurement variances: current, velocity, angle */
    Eigen::Vector3d var_floor = Eigen::Vector3d::Zero();
    Eigen::Vector3d var_ceil = Eigen::Vector3d::Constant(1e300);
    /** Model-torque noise (ekf.h ekf_config_t::qT_rel_s) [s]: the plate's torque density grows
     *  by qT_rel_s T^2, T = |n Kt i| + Kv |w| of the state before the step. */
    double qT_rel_s = 0.0;
    /** Impact timing (ekf.h ekf_config_t::impact_timing) [-]: a prediction that enters a stop (the
     *  angle before it between the stops; a sub-step starting inside one, or the predicted angle
     *  inside one) adds impact_timing (h / J M)^2 to the velocity variance, M the larger of the
     *  sub-steps' largest |M_stop| and |M_stop| at the predicted state, h = Ts / substeps. */
    double impact_timing = 0.0;
    /** Stuck-plate noise (ekf.h ekf_config_t::stuck_q_min, stuck_hold_frac): Q's (w, phi) block
     *  (the model-torque noise included) times 1 - (1 - stuck_q_min) min(1, hold / stuck_hold_frac)
     *  where the step holds the plate stuck with hold fraction hold > 0 (hold_fraction()). */
    double stuck_q_min = 1.0;
    double stuck_hold_frac = 0.8;
    /** ... not where the predicted angle is within this of a stop (ekf.h contact_band_rad) [rad] */
    double stuck_band_rad = 0.005;
    /** Consistency-driven inflation (ekf.h ekf_config_t::nis_inflate_alpha ...): the mean over
     *  the used channels of each correction's NIS, each clipped at 9, low-pass with gain alpha
     *  from 1; Q of the next predictions times (average / threshold)^2 above the threshold, at
     *  most max. */
    double nis_inflate_alpha = 0.0;
    double nis_inflate_threshold = 1.2;
    double nis_inflate_max = 100.0;
    /** Whiteness-driven inflation (ekf.h ekf_config_t::white_threshold): the angle innovation,
     *  clipped at 3 sigma, its mean low-pass with the same gain from 0; Q's (w, phi) block of the next predictions times
     *  k = mean^2 (2 - alpha) / (alpha white_threshold S) where that exceeds the NIS factor (at
     *  most max); 0 = off. */
    double white_threshold = 0.0;
};

/**
 * Q from continuous densities (ekf.h ekf_q_from_spectral): Q_ii = qu Ts / L^2; the (w, phi)
 * block qT / J^2 [[Ts, Ts^2/2], [Ts^2/2, Ts^3/3]]; no coupling of the current with (w, phi).
 */
inline Eigen::Matrix3d q_from_spectral(const Params& p, double qu_V2_s, double qT_Nm2_s)
{
    const double T = p.Ts_s;
    const double s = qT_Nm2_s / (p.J_kg_m2 * p.J_kg_m2);
    Eigen::Matrix3d Q = Eigen::Matrix3d::Zero();
    Q(0, 0) = qu_V2_s * T / (p.L_H * p.L_H);
    Q(1, 1) = s * T;
    Q(1, 2) = Q(2, 1) = s * T * T / 2.0;
    Q(2, 2) = s * T * T * T / 3.0;
    return Q;
}

/** Default noise densities documented in ekf.h (EKF_DEFAULT_QU_V2_S, EKF_DEFAULT_QT_NM2_S,
 *  EKF_DEFAULT_QT_REL_S). */
const double kDefaultQu_V2_s = 5.0e-6;
const double kDefaultQT_Nm2_s = 5.0e-6;
const double kDefaultQTRel_s = 0.0;
/** EKF_DEFAULT_IMPACT_TIMING (ekf.h). */
const double kDefaultImpactTiming = 0.003;
/** EKF_DEFAULT_STUCK_Q_MIN / EKF_DEFAULT_STUCK_HOLD_FRAC (ekf.h). */
const double kDefaultStuckQMin = 1.0;
const double kDefaultStuckHoldFrac = 0.8;
/** EKF_DEFAULT_NIS_INFLATE_ALPHA / _THRESHOLD / _MAX and EKF_NIS_INFLATE_CLIP (ekf.h). */
const double kDefaultNisInflateAlpha = 0.02;
const double kDefaultNisInflateThreshold = 1.2;
const double kDefaultNisInflateMax = 100.0;
const double kNisInflateClip = 9.0;
/** EKF_DEFAULT_WHITE_THRESHOLD (ekf.h). */
const double kDefaultWhiteThreshold = 0.0;

/** ekf_config_default() as documented in ekf.h. */
inline Config config_default(const Params& p, Setup setup)
{
    Config c;
    c.setup = setup;
    c.x0.setZero();
    c.P0 = Eigen::Vector3d(1.0, 100.0, 0.01).asDiagonal();
    c.Q = q_from_spectral(p, kDefaultQu_V2_s, kDefaultQT_Nm2_s);
    c.qT_rel_s = kDefaultQTRel_s;
    c.impact_timing = kDefaultImpactTiming;
    c.stuck_q_min = kDefaultStuckQMin;
    c.stuck_hold_frac = kDefaultStuckHoldFrac;
    c.nis_inflate_alpha = kDefaultNisInflateAlpha;
    c.nis_inflate_threshold = kDefaultNisInflateThreshold;
    c.nis_inflate_max = kDefaultNisInflateMax;
    c.white_threshold = kDefaultWhiteThreshold;
    c.r = Eigen::Vector3d(1.054e-4, 1.0, 2.668e-8);
    c.var_floor = Eigen::Vector3d::Constant(1e-12);
    c.var_ceil = Eigen::Vector3d(1e4, 1e6, 10.0);
    return c;
}

/** ekf_config_paper() as documented in ekf.h (paper section 3.3). */
inline Config config_paper()
{
    Config c;
    c.setup = Setup::Paper3Meas;
    c.x0.setZero();
    c.P0 = 100.0 * Eigen::Matrix3d::Identity();
    c.Q = 0.01 * Eigen::Matrix3d::Identity();
    c.r = Eigen::Vector3d(1e-4, 1.0, 1e-8);
    c.var_floor = Eigen::Vector3d::Constant(1e-12);
    c.var_ceil = Eigen::Vector3d(1e4, 1e6, 10.0);
    return c;
}

/** What one correction saw (ekf.h ekf_innov_t). */
struct Innov {
    Eigen::Vector3d innov = Eigen::Vector3d::Zero();
    Eigen::Vector3d innov_var = Eigen::Vector3d::Zero();
    Eigen::Vector3d nis = Eigen::Vector3d::Zero();
    double nis_total = 0.0;
    bool used[3] = {false, false, false};
    int n_used = 0;
};

/** Reference EKF: predict with f and its AD Jacobian, sequential scalar Joseph updates. */
class Ekf {
public:
    Ekf(const Params& p, const Config& c) : p_(p), c_(c), x_(c.x0), P_(c.P0) {}

    const Eigen::Vector3d& x() const { return x_; }
    const Eigen::Matrix3d& P() const { return P_; }
    const Params& params() const { return p_; }
    const Config& config() const { return c_; }

    /** x = f(x, u); P = F P F^T + Q with F = df/dx by AD; symmetrise; variance bounds. */
    void predict(double u_V)
    {
        Eigen::Vector3d xn;
        const Eigen::Matrix3d F = jacobian_ad(p_, x_, u_V, &xn);
        const double T = std::fabs(p_.n_gear * p_.Kt_Nm_A * x_(0)) + p_.Kv_Nm_s_rad * std::fabs(x_(1));
        const double peak = peak_stop_torque(p_, x_, u_V);
        const bool between = x_(2) >= p_.phi_closed_rad && x_(2) <= p_.phi_open_rad;
        const bool enters = between && (peak > 0.0 || xn(2) < p_.phi_closed_rad || xn(2) > p_.phi_open_rad);
        double q_impact = 0.0;
        if (enters && c_.impact_timing > 0.0) {
            const double m = std::max(peak, std::fabs(stop_torque<double>(p_, xn(2), xn(1), nullptr)));
            const double dw = p_.Ts_s / p_.substeps / p_.J_kg_m2 * m;
            q_impact = c_.impact_timing * dw * dw;
        }
        double q_plate = 1.0;
        const bool in_band = xn(2) < p_.phi_closed_rad + c_.stuck_band_rad || xn(2) > p_.phi_open_rad - c_.stuck_band_rad;
        if (c_.stuck_q_min < 1.0 && !in_band) {
            const double hold = hold_fraction(p_, x_, u_V);
            if (hold > 0.0) {
                q_plate = 1.0 - (1.0 - c_.stuck_q_min) * std::min(1.0, hold / c_.stuck_hold_frac);
            }
        }
        predict_with(F, xn, c_.qT_rel_s * T * T, q_impact, q_plate);
    }

    /** The covariance part of predict with a given F and predicted state (no model evaluation). */
    void predict_with(const Eigen::Matrix3d& F, const Eigen::Vector3d& x_pred, double q_model_Nm2_s = 0.0,
                      double q_impact = 0.0, double q_plate = 1.0)
    {
        Eigen::Matrix3d Qc = c_.Q;
        Qc(0, 0) *= q_scale_;
        Qc.block<2, 2>(1, 1) *= q_scale_plate_;
        Eigen::Matrix3d Q = Qc + q_from_spectral(p_, 0.0, q_model_Nm2_s);
        Q.block<2, 2>(1, 1) *= q_plate;
        x_ = x_pred;
        P_ = F * P_ * F.transpose() + Q;
        P_(1, 1) += q_impact;
        symmetrise();
        apply_bounds();
    }

    /**
     * Sequential scalar updates in channel order current, velocity (paper set-up only), angle.
     * z: current [A], velocity [rad/s], angle [rad].
     */
    Innov correct(const Eigen::Vector3d& z)
    {
        Innov out;
        const bool use[3] = {true, c_.setup == Setup::Paper3Meas, true};
        for (int j = 0; j < 3; ++j) {
            if (!use[j]) {
                continue;
            }
            const Eigen::RowVector3d H = Eigen::RowVector3d::Unit(j);
            const double y = z(j) - (H * x_)(0);
            const double s = (H * P_ * H.transpose())(0) + c_.r(j);
            const Eigen::Vector3d K = P_ * H.transpose() / s;
            x_ += K * y;
            const Eigen::Matrix3d IKH = Eigen::Matrix3d::Identity() - K * H;
            P_ = IKH * P_ * IKH.transpose() + K * c_.r(j) * K.transpose();
            symmetrise();
            out.innov(j) = y;
            out.innov_var(j) = s;
            out.nis(j) = y * y / s;
            out.nis_total += out.nis(j);
            out.used[j] = true;
            ++out.n_used;
        }
        apply_bounds();
        if (out.n_used > 0 && c_.nis_inflate_alpha > 0.0) {
            double v = 0.0;
            for (int j = 0; j < 3; ++j) {
                v += out.used[j] ? std::min(out.nis(j), kNisInflateClip) : 0.0;
            }
            v /= out.n_used;
            nis_avg_ += c_.nis_inflate_alpha * (v - nis_avg_);
            const double r = nis_avg_ / c_.nis_inflate_threshold;
            q_scale_ = r > 1.0 ? std::min(r * r, c_.nis_inflate_max) : 1.0;
            q_scale_plate_ = q_scale_;
            if (c_.white_threshold > 0.0 && out.used[2]) {
                const double a = c_.nis_inflate_alpha;
                const double ymax = std::sqrt(kNisInflateClip * out.innov_var(2));
                phi_innov_avg_ += a * (std::max(-ymax, std::min(ymax, out.innov(2))) - phi_innov_avg_);
                const double k = phi_innov_avg_ * phi_innov_avg_ * (2.0 - a) / (a * c_.white_threshold * out.innov_var(2));
                q_scale_plate_ = std::max(q_scale_plate_, std::min(k, c_.nis_inflate_max));
            }
        }
        return out;
    }

    /** The factor on Q of the next prediction (consistency-driven inflation). */
    double q_scale() const { return q_scale_; }
    /** The factor on Q's (w, phi) block of the next prediction (also whiteness-driven). */
    double q_scale_plate() const { return q_scale_plate_; }

private:
    void symmetrise() { P_ = (0.5 * (P_ + P_.transpose())).eval(); }

    /** Floor: raise the diagonal entry. Ceiling: scale row and column by sqrt(ceil / P_ii). */
    void apply_bounds()
    {
        for (int i = 0; i < 3; ++i) {
            if (P_(i, i) < c_.var_floor(i)) {
                P_(i, i) = c_.var_floor(i);
            }
            if (P_(i, i) > c_.var_ceil(i)) {
                const double f = std::sqrt(c_.var_ceil(i) / P_(i, i));
                P_.row(i) *= f;
                P_.col(i) *= f;
            }
        }
    }

    Params p_;
    Config c_;
    Eigen::Vector3d x_;
    Eigen::Matrix3d P_;
    double nis_avg_ = 1.0;
    double q_scale_ = 1.0;
    double q_scale_plate_ = 1.0;
    double phi_innov_avg_ = 0.0;
};

} // namespace tvref

#endif /* TV_REF_HPP */
