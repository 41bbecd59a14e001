/**
 * @file diag_detect.h
 * @brief The first fault detectors on the 1 kHz path, each reporting to its codes (diag.h):
 *
 *   TRACK VOTE (P0121, P0221, P2135), the estimator as third voter. While both position tracks
 *     are in range, a disagreement |phi1 - phi2| > tps_disagree_rad is resolved against the
 *     estimator's prediction phi_pred of this sample (the previous estimate moved on by one
 *     period, computed before this sample corrects the estimator): a track within
 *     tps_vote_frac * |phi1 - phi2| of the prediction, and closer than the other, is kept and
 *     the other is named (P0121 for track 1, P0221 for track 2: one failed check); when neither
 *     is, P2135 fails and no angle is used. Agreeing tracks pass all three. A named track stays
 *     out of the angle (the kept track alone) for as long as its code is pending or confirmed, so
 *     the estimator, and with it the next vote, is never pulled toward the faulty track. A track
 *     that drifts slowly is averaged into the estimate before it crosses the threshold: the vote
 *     can then not tell the tracks apart and reports P2135 (limitation, README).
 *   JAM (P2111 stuck open, P2112 stuck closed): the target (closed loop: the application's;
 *     open loop, app.c: the stop the voltage pushes toward, so a plate resting at that stop
 *     passes) is at least
 *     jam_error_rad from the estimated angle, the applied voltage pushes toward it with at least
 *     jam_u_min_V and at least jam_break_factor times the model's breakaway voltage u_break in the
 *     push's direction (the stall voltage whose torque equals the static friction, plus the
 *     preload and spring where they oppose the push: diag_jam_breakaway_Nm(); below it a healthy
 *     plate may rightly stay stuck), and the estimated angle moved less than jam_still_rad over the
 *     last DIAG_JAM_WINDOW samples, all of them driven toward the target (after a target step or a
 *     bridge-off pause the plate gets the whole window to move, and a plate still coasting against
 *     the drive, DIAG_JAM_COAST_RAD over DIAG_JAM_COAST_N samples, gets the window from its turn): a failed check (P2112 when the target is
 *     above, i.e. commanded to open; P2111 below). Pushing and moving, or the target within
 *     jam_error_rad, passes.
 *   OPEN WINDING (P2100): over the period that just ended the bridge was enabled and applied
 *     |u| >= open_u_min_V with |u - e| >= open_u_min_V as well, e = n Ke w moved open_emf_allow_V
 *     toward 0 (w the estimated velocity at
 *     the start of the period: the back-EMF leaves that much to drive a current; the first
 *     condition keeps a wrong velocity estimate, e.g. against a stop the model does not know yet,
 *     from making a small voltage look large), and the measured current (plausible) is below
 *     open_i_max_A: a failed check when it also changed by at most open_di_max_A since the
 *     period's start (an open winding carries none at all; a current sweeping through zero
 *     conducts: not judged); a current at or above open_i_max_A passes.
 *   WINDING RESISTANCE (P2101 above, P1A01 below its range), an adapted parameter against its
 *     healthy range: the estimator's R + dR (its winding-resistance error state), while the bridge
 *     drives a measured current of at least r_excite_A (the state is updated only under current,
 *     and it can be left wrong by an excursion while the bridge is off: measured, class b unit
 *     1013 in limp_home, dR jumping 0.58 ohm with the bridge off and no current, corrected within
 *     20 ms of drive) and its sigma is below r_sigma_max_frac * R: above r_high_frac * R fails
 *     P2101, below r_low_frac * R fails P1A01, in between passes both. R is the model's nominal
 *     resistance at the winding's temperature when the application knows it (the model's R is
 *     at 20 degC: app_set_winding_temp()), else the model's R as it is; with the temperature
 *     known, r_high_frac_known takes the place of r_high_frac (tighter on an identified unit), and
 *     below r_low_frac_known * R P1A01 fails too when the motor-constant signature's back-EMF slope
 *     says the back-EMF constant dropped with the resistance (shorted turns, not a sensor gain).
 *     With the temperature known, the voltage equation's fit (volt_fit.h) reading R above
 *     r_fit_high_frac * R in DIAG_R_FIT_HIGH_WINDOWS windows in a row fails P2101 as well, at every
 *     driven step until a window reads below (diag_fit_resistance_check()).
 *   ADAPTED MECHANICS (P2119 friction above, P1A02 spring preload below its range), the
 *     estimator's friction level 1 + f and preload 1 + m against their healthy ranges, checked
 *     every DIAG_PARAM_DECIM steps (the estimates move over seconds: a 1 kHz check would repeat
 *     itself) while the model is the one in service (not during stop learning), the estimator
 *     ran, and the estimated plate speed is at least param_excite_rad_s (the estimator updates f
 *     and m only while the plate slides; at rest they are frozen and the check waits). Friction:
 *     while sigma(f) <= friction_sigma_max, above friction_high_rel fails P2119, else passes.
 *     Preload: while sigma(m) <= preload_sigma_max, below preload_low_rel fails P1A02, else passes.
 *     The bounds lie outside the healthy population (friction +-30 %, preload +-20 % around the
 *     class nominal, plant_draw.h) with the estimation error measured on it (README). Since the
 *     levels move over seconds, a level beyond its bound fails only after param_slow_hold checks
 *     in a row.
 *   TORQUE SIGNATURE (behind the same two codes, fast): diag_torque_feed() regresses the torque
 *     the model did not explain in each sample (the estimator's velocity correction x J / Ts) on
 *     the model's spring torque and on its friction torque opposing the motion, with exponential
 *     forgetting (torque_tau_samples), fed only while the plate slides (see its conditions). At
 *     each check the 2x2 solve gives a spring deficit a and a friction excess e, i.e. a preload
 *     (1 + m)(1 - a) and a friction (1 + f)(1 + e): below preload_fast_low fails P1A02 (while the
 *     signature's friction is at most preload_fast_friction_max; or below DIAG_PRELOAD_BOTH_LOW
 *     with the friction below DIAG_FRICTION_BOTH_LOW), above friction_fast_high fails
 *     P2119 (while its preload is at least friction_fast_preload_min and 1 + f at least
 *     friction_fast_level_min). Judged only when fed within DIAG_TORQUE_FRESH steps, with enough
 *     weight, non-collinear regressors (torque_corr_max), small sigmas of f and m, and no
 *     motor-circuit or jam code (P2100, P2101, P1A01, P2111, P2112) pending or confirmed.
 *   AWAY READING (behind P1A02, fast): the signature's samples moving away from limp-home at
 *     most away_w_max_rad_s are also summed alone; there the spring and the friction both oppose
 *     the move (collinear: the signature does not judge them), and the friction they imply with
 *     the spring as modelled is (1 + f)(1 + sum(y_f) / sum(F)), y_f the unexplained torque along
 *     the friction, F the model's friction torque. With the preload at its nominal instead, the
 *     adapted share m M0 (diag_detect_set_preload()) goes back to the friction; the larger of the
 *     two readings below away_friction_min fails P1A02 (value: the reading): no healthy unit read
 *     below 0.5 (the soak), while a spring that no longer opposes the move leaves a reading of
 *     0 or less. Judged with the signature's conditions while its newest sample is such a one
 *     and for DIAG_AWAY_STALE_CHECKS checks after.
 *   SPRING PROBE (behind P1A02, a plate that holds): the signature's samples moving toward
 *     limp-home ("closing", w < 0 above it) and those moving away from it ("opening") are also
 *     regressed on the spring alone, each direction apart. A weaker spring leaves a torque away
 *     from limp-home in either direction (a > 0 in both readings); more friction one against the
 *     motion, along the spring's in closing samples (collinear: the signature does not judge
 *     them), against it in opening ones (less friction the reverse). When either reading
 *     a = sum(s y) / sum(s s) (the larger, if both) reaches probe_trigger (over probe_min_weight
 *     decayed samples; the closing reading also takes slower samples of a plate the drive pulls
 *     back toward limp-home: DIAG_PROBE_SLOW_W_RAD_S) and
 *     the plate then rests (the estimate moved less than 0.2 probe_move_rad away from limp-home
 *     over the jam window, w < DIAG_PROBE_REST_W_RAD_S that way) or creeps back toward
 *     limp-home (DIAG_PROBE_CREEP_RAD, DIAG_PROBE_CREEP_W_RAD_S) where the caller
 *     allows it, diag_spring_probe() asks the caller to apply the model's spring torque
 *     M0 (1 + m) sp(phi) + c phi plus probe_friction_frac of its sliding friction (1 + f) Mc,
 *     away from limp-home, for up to DIAG_PROBE_MAX_STEPS steps (1 + m and 1 + f as they were
 *     before the suspicion: the fault pulls them while it is seen). A healthy
 *     plate stays (its static friction is at least its sliding friction), more friction holds it
 *     harder; without its spring it moves: probe_move_rad away from limp-home (from where it
 *     turns, if it crept) is one failed check of P1A02 (value 1 - a) and ends the probe; the next
 *     starts when the plate rests again. Moving DIAG_PROBE_UNSURE_FRAC of that to less than it
 *     gives no verdict but keeps the suspicion. A probe that holds gives no verdict and ends the
 *     suspicion (one begun on a creeping plate keeps it), as do DIAG_PROBE_MAX_N moving probes.
 *     While probes have moved the plate, diag_param_check() does not pass P1A02.
 *   BRIDGE DIRECTION LOST (P1A03), in the open-winding check's samples (same gate): the terminal
 *     voltage the measured current implies, v = e + (i1 - a_T i0) / b_T (e = n Ke times the
 *     differentiated measured angle, the one the estimator gets: the estimate's velocity can be
 *     far off against a stop that the model places a little elsewhere, measured; the model's
 *     exact armature solution over one period inverted: i0 the current measured at the
 *     period's start, i1 at its end, a_T = a^N, b_T = b (1 + a + ... + a^(N-1)) with the
 *     model's nominal R and L, diag_detect_set_armature()), against the commanded u. A lost direction applies 0 V (both low
 *     sides on): the winding is shorted and a moving plate's back-EMF drives i = -n Ke w / R, so
 *     v is about 0 while a current flows; an open winding carries no current at all (v = the
 *     floating back-EMF); a healthy bridge gives v about u. With |current| >= open_i_max_A and
 *     |e| <= |u|: |v| < bridge_lost_frac |u| fails P1A03 (and passes P2100: the winding
 *     conducts) unless the plate brakes hard (e u < -DIAG_BRIDGE_BRAKE_FRAC u^2: a doubled
 *     winding reads as little there; not judged), else passes a pending or confirmed P1A03 (this
 *     direction works; an idle code is not reported: a pass would change nothing). No current while the plate moves
 *     (|v| >= bridge_lost_frac |u|: the floating back-EMF): P2100 fails (open). No current and no
 *     motion (|v| < bridge_lost_frac |u|): both faults look alike (nothing flows, nothing moves;
 *     the terminal voltage is not measured): P2100 fails as before (its 10 ms target), the
 *     direction is suspected, and the detector asks for a REVERSE PULSE: the application drives
 *     the next period the other way (diag_probe_direction(), one period at the limited duty). If
 *     current then flows while P2100 is pending, the winding conducts: P2100 passes and P1A03
 *     fails, and later motionless no-current samples fail P1A03 instead of P2100 (as long as
 *     P1A03 is pending or confirmed); a sample in the other, working direction neither passes nor
 *     fails P1A03. An open winding never conducts: its pulses fail P2100 too.
 *   SUPPLY LOW (P0562): every DIAG_SUPPLY_DECIM calls of diag_circuit_check(), the measured
 *     supply below supply_low_V fails, at or above supply_low_V + supply_hyst_V passes, in
 *     between nothing.
 *   TRACK CIRCUIT LOW (P0122 track 1, P0222 track 2), an event counter: every sample whose
 *     track reads below its range (the caller's tps_min_counts: a 0 V reading, a lost wiper) is a
 *     failed check; every fixed window of DIAG_TPS_CLEAN_WINDOW samples without one gives one
 *     passed check. A steady low track confirms at the code's count (ms); sporadic dropouts add
 *     up as long as most windows hold one (the 1 kHz leaky counter alone would leak a 10 %
 *     dropout rate away: 9 passes per failure).
 *   CURRENT SENSOR (P1A04), an offset of the current measurement, by three checks that report to
 *     the one code (each check is one window):
 *     FIT OFFSET (diag_isens_fit_check()): each window of the voltage equation's fit with an
 *       intercept (volt_fit.h: the offset b it reads, by instrumental variables) at or above
 *       isens_fit_max_A fails, below half of it passes; judged while its variance inflation is at
 *       most isens_fit_vif_max, on the model in service, not while P2100 or P1A03 is active.
 *     ZERO CHECK: while the bridge is off (since at least DIAG_ISENS_SETTLE periods: the winding
 *       current has decayed through the body diodes well within one), the measured current must
 *       read 0; the mean of DIAG_ISENS_ZERO_N such samples above isens_zero_max_A in magnitude
 *       fails, else passes (value: the mean [A]).
 *     IN-SERVICE BIAS: while the bridge drives (since at least DIAG_ISENS_SETTLE periods), the
 *       model is the one in service (not during stop learning) and the estimator corrected with
 *       the current, the samples whose predicted |current| i is at most isens_i_max_hold times
 *       the current that holds the model's spring preload (diag_detect_set_preload()) and whose
 *       |innovation| is at most isens_innov_max_A (a stop impact; samples beyond either are
 *       skipped, the window goes on) have their current innovation y (measured minus
 *       predicted) regressed on (1, i, w) over DIAG_ISENS_WIN such samples (i is the PREDICTED
 *       current, measured minus innovation: the measured one carries the noise that is also in
 *       y, which would bias the slope and, selected by the band, the mean of y; w the estimated
 *       velocity at the period's start). A sensor offset b adds b to y
 *       whatever the current's sign; a resistance error (and a current-gain error, which looks
 *       like one) adds a term proportional to i, a back-EMF constant error one proportional to w:
 *       the intercept separates the offset from the healthy units' spread in R and Kt/Ke. The
 *       window's intercept above isens_bias_max_A in magnitude fails, else passes (value: the
 *       intercept [A]); a window whose intercept is ill-determined (variance inflation
 *       1 + m' C^-1 m above isens_vif_max, m the regressors' means and C their covariance: one
 *       current sign, one speed) is not judged. A sample with no correction or implausible
 *       restarts the window; while the bridge is off or its current settles the window waits and
 *       goes on when it drives again (limp-home's 0.6 s drives seldom fill one between two offs).
 *     A current-gain error is a scaled R in the voltage equation and a scaled Kt in the mechanics,
 *     both inside the population's spread: it is judged on identified units only, by the
 *     MOTOR-CONSTANT SIGNATURE below.
 *   MOTOR-CONSTANT SIGNATURE (P1A04 or P1A01; identified units, diag_detect_config_identified()):
 *     a gain g of the current sensor makes the apparent resistance (R + dR) / R read 1 / g and the
 *     torque per measured ampere 1 / g too small, so the adapted friction 1 + f and preload 1 + m
 *     both read about g; shorted turns do the same to R and Kt but also lower the back-EMF
 *     constant, which leaves a current innovation proportional to the velocity (the in-service
 *     window's slope kw; measured on identified unit 1000 in closed-loop driving: healthy and gain
 *     errors |kw| < 0.001 A s/rad, 20 % of the turns shorted 0.019, 35 % 0.041). While
 *     (R + dR) / R < gain_r_max (diag_resistance_check()), a window judged since then supplies kw
 *     (when its velocity varied: gain_w_var_min). The DRIVEN window adds evidence of a deficit
 *     only: every driven, corrected sample meanwhile, whatever its current, regressed the same
 *     way over DIAG_KW_WIN samples (the band window fills at small currents only: limp-home's
 *     drives gave it 3 - 27 samples each); a window is judged where the velocity's variance
 *     reached DIAG_KW_W_VAR_MIN, the squared correlation of current and velocity is at most
 *     DIAG_KW_RHO2_MAX and the resistance ratio moved at most DIAG_KW_R_STEADY over it (its
 *     convergence after a step is in the innovations), and two judged windows in a row above
 *     gain_kw_max set kw_short (measured, windows of motion on identified units: shorted turns
 *     +0.012 ... +0.066 A s/rad, a gain of 5 - 20 % -0.007 ... +0.004, the first window after a
 *     gain's onset up to +0.010 with the adapted states still settling). It gives no gain
 *     verdict: a short developing over seconds reads a small kw while it is small.
 *     diag_param_check() then fails, at each of its checks with 1 + f and 1 + m both above
 *     gain_mech_min (their sigmas within the mechanics checks' bounds, no open winding or jam
 *     code), P1A01 with kw_short or the band window's kw above gain_kw_max, else P1A04 (value:
 *     (R + dR) / R). kw is signed: shorted turns' back-EMF deficit raises the current with the
 *     motion. With the winding's temperature known (diag_resistance_check()'s
 *     temp_known) a resistance below gain_r_known_max is no cold winding, so friction up alone
 *     suffices (a gain's excess torque may be taken up by the friction state alone, as in the
 *     12 V sine). Meanwhile the resistance check does not pass P1A01, and P2119 does not fail
 *     while the preload is up too, for gain_hold_checks checks (a gain error raises the friction
 *     before the preload), or at all while the temperature is known and R below
 *     gain_r_known_max; after that, friction up alone fails P2119 as
 *     before. A cold winding lowers R alone, ice raises friction alone: neither moves all three.
 *   OFFSET SIGNATURE (P1A04; identified units): an offset b of the current sensor takes about
 *     n Kt b out of (or adds it to) the torque per measured ampere whatever the motion, which the
 *     adapted preload takes up while the friction (whose torque changes sign with the motion)
 *     stays, and it makes R read i / (i + b) times its value on the side where the current holds
 *     the plate; a raised resistance leaves the mechanics alone (the estimator's torque comes from
 *     the measured current; measured: 1 + m 0.987-1.002 with R x1.25 and x1.5, 0.75-0.98 with an
 *     offset of -0.1 A). So diag_param_check() fails P1A04 once, for isens_sig_checks checks in a
 *     row, either the apparent resistance read above 1 / gain_r_max with the winding's temperature
 *     known (else it may be a warm winding, and a weak spring lowers 1 + m) and 1 + m below
 *     1 / gain_mech_min or 1 + f below isens_sig_friction_low with a deficit larger than R's
 *     excess, 1 + f within its healthy range (friction_high_rel: a jam's drag, far above, is not
 *     the sensor; a gain below 1 lowers both levels, and in the 12 V sine the friction alone) and
 *     R's excess at most DIAG_ISENS_SIG_EXCESS_PER_DEFICIT times the larger deficit (a raised
 *     winding moves R alone), or 1 + m above gain_mech_min and 1 + f within 1 / gain_mech_min ...
 *     gain_mech_min (a gain above 1 and shorted turns raise the friction with the preload: the
 *     motor-constant signature's case) with the apparent resistance below gain_r_max, or not above
 *     1 / gain_r_max while no P1A02 or P2119 is pending or confirmed (no fault raises a spring,
 *     and on class b's larger holding currents +50 mA moves R by only 1 - 3 %: README "The
 *     preload up without the resistance"; the low side keeps its resistance term, a preload a
 *     few per cent low with R as it was being also a fatigued spring);
 *     their sigmas within the mechanics checks' bounds, no open winding or jam code. On a unit
 *     that is not identified but has the fit's per-unit baseline, the first reading only, with
 *     the fit's R over the baseline's standing for the apparent resistance once r_fit_up_n
 *     reached DIAG_R_FIT_LOW_WINDOWS (diag_fit_resistance_check(): a step of the fit's R above
 *     1 / gain_fit_base_max, at most r_fit_base_high_frac, n Ke intact): a gain below 1 (the
 *     levels read g where the model's mechanics are the unit's; README "A current gain below 1
 *     from the fit"). While 1 + m
 *     or 1 + f reads that low with the temperature known, P2101 is not failed (no verdict).
 *
 * Pure C99, no heap, no globals; fixed cost per call.
 */
#ifndef DIAG_DETECT_H
#define DIAG_DETECT_H

#include <stdint.h>

#include "diag.h"
#include "tv_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Samples over which the jam check measures the plate's motion (8 ms at 1 kHz). */
#define DIAG_JAM_WINDOW 8u

/** A plate whose estimated angle moved more than DIAG_JAM_COAST_RAD against the drive over the
 * last DIAG_JAM_COAST_N samples still coasts the old way: the jam check's count of driven samples
 * waits (1.5 mrad over 3 samples, 0.5 rad/s; a blocked plate's estimate jitters within some
 * 0.6 mrad: the 12-bit tracks' steps and noise) [rad], [samples]. */
#define DIAG_JAM_COAST_RAD TV_R(0.0015)
#define DIAG_JAM_COAST_N 3u

/** P1A03 does not fail on a conducting sample whose measured back-EMF e opposes the drive u by more
 * than this fraction of |u| (e u < -DIAG_BRIDGE_BRAKE_FRAC u^2: the plate braked hard). The implied
 * terminal voltage is reckoned with the model's R: a winding k times it reads
 * v / u = 1 / k + (1 - 1 / k) e / u, which for k = 2.4 (winding_resistance_high x2 on a unit whose
 * winding is 1.2 times its class's) is 0.27 at e / u = -0.25 and falls below bridge_lost_frac
 * (0.25) from e / u = -0.29 on: all_varied unit 1000 braking in closed-loop steps and in `drive`
 * read v / u = 0.15 and confirmed P1A03 (safe state) before P2101. A lost direction still fails
 * on every sample whose plate moves with the drive, is at rest or brakes less (its v is about 0
 * whatever e); the fault matrix's 300 lost directions all confirmed P1A03 as before, 0 - 18 ms
 * later (README "P1A03 and a braking doubled winding"). */
#define DIAG_BRIDGE_BRAKE_FRAC TV_R(0.25)

/** OFFSET SIGNATURE, R read high: the resistance's excess (R + dR) / R - 1 at most this times the
 * larger of the preload's and the friction's deficits, 1 - (1 + m) and 1 - (1 + f). An offset b
 * moves both by about n Kt b / M0 on a plate held against its preload (R reads i / (i - b) times
 * its value) and R by less where the currents are larger; a gain below 1 moves the friction
 * several times as much as R; a raised winding moves R alone, the levels dipping by a few per
 * cent while the estimator catches up. Measured on the fault matrix's identified units (every
 * check of the reading, 350 runs: offsets -50 mA and +0.1 A, gain -5 %, R x1.25, x1.5, x2):
 * offsets and gains at most 3.9, raised windings at least 9.9 (R x2 on unit 1004 in closed-loop
 * steps had held the reading 30 checks and confirmed P1A04 before P2101). */
#define DIAG_ISENS_SIG_EXCESS_PER_DEFICIT TV_R(6.0)

/** The adapted-mechanics check runs every this many calls of diag_param_check() (10 ms at 1 kHz). */
#define DIAG_PARAM_DECIM 10u

/** The supply check runs every this many calls of diag_circuit_check() (10 ms at 1 kHz). */
#define DIAG_SUPPLY_DECIM 10u

/** The track low-circuit check's window (500 ms, a multiple of DIAG_SUPPLY_DECIM): a window without
 *  a low sample gives the track's code one passed check. */
#define DIAG_TPS_CLEAN_WINDOW 500u
/** Current-sensor check: periods the bridge must have been off (or driving) before a sample counts. */
#define DIAG_ISENS_SETTLE 2u
/** Current-sensor zero check: samples at rest per check (32 ms at 1 kHz). */
#define DIAG_ISENS_ZERO_N 32u
#ifndef DIAG_KW_WIN
/** Samples of the driven back-EMF window (MOTOR-CONSTANT SIGNATURE): every driven, corrected
 * sample while the resistance reads low on an identified unit, whatever its current. */
#define DIAG_KW_WIN 200u
#endif
/** The driven window's kw is taken only where the velocity's variance over it reached this
 * [(rad/s)^2]: motion, not creep. */
#define DIAG_KW_W_VAR_MIN TV_R(1.0)
/** ... where the squared correlation of current and velocity over it is at most this [-] ... */
#define DIAG_KW_RHO2_MAX TV_R(0.81)
/** ... and where the resistance ratio moved at most this over it [-]. */
#define DIAG_KW_R_STEADY TV_R(0.1)
/** Resistance checks in a row at or above gain_r_max after which the driven back-EMF window's
 * last judged reading (kw_prev) is dropped. A shorter excursion keeps it, so that the next judged
 * window makes the pair that sets kw_short: with shorted turns the resistance state swings with
 * the sign of i w, the back-EMF constant being low (measured: class b, 20 % shorted, 5 V slow
 * sine, R + dR 0.60 - 0.80 R while the motor drives the plate, 1.17 R for 0.22 s as it leaves the
 * open stop, every period, which dropped the reading each time before the pair was complete).
 * r_low itself, kw_short and the rest of the signature's state clear at once, as before. */
#define DIAG_R_LOW_EXIT 500u
/** Current-sensor in-service check: driven samples in the band per window. */
#ifndef DIAG_ISENS_WIN
#define DIAG_ISENS_WIN 500u
#endif
/** The torque signature is judged only when it was fed within this many steps (a stale
 *  signature, e.g. of the instant a plate was blocked, judges nothing). */
#define DIAG_TORQUE_FRESH 60u
/** The away reading is judged at the checks that find its newest sample moving away from
 * limp-home and at this many checks after the last such (its sums as they were, the levels as
 * adapted since): a burst of away samples too short for the confirmation's 3 failing checks
 * still confirms (a broken spring's plate left the reading's speed range after 2 failing checks
 * in the 5 V sine, all_varied 1004, and waited 1.07 s for the next opening). Unbounded, a
 * healthy reading judged long after its samples, with the friction adapted since, went down to
 * 0.45 (soak scenarios, 2,430 runs of 20 s). */
#define DIAG_AWAY_STALE_CHECKS 2u
/** Steps without a torque-signature sample after which the next sample first rescales the sums
 * from before (the signature's and the away reading's) to at most torque_min_weight samples, and
 * the spring probe's two readings to at most probe_min_weight:
 * evidence from before a pause (a hold, a bridge-off phase, the slow sine's reversal) no longer
 * outweighs what the plate does now. */
#define DIAG_TORQUE_PAUSE 250u

/** Detector thresholds (diag_detect_config_default()). */
typedef struct {
    tv_real_t tps_disagree_rad; /**< track disagreement that calls the vote [rad], > 0; default 0.005
                                     (11 counts; healthy tracks share the plate's noise and differ by
                                     their quantisation, <= 1 count = 4.5e-4 rad) */
    tv_real_t tps_vote_frac;    /**< a kept track lies within this fraction of the disagreement from
                                     the prediction [-], (0, 0.5]; default 0.25 */
    tv_real_t jam_error_rad;    /**< target error from which a plate must move [rad], > 0; default 0.035 */
    tv_real_t jam_u_min_V;      /**< voltage toward the target from which the plate must move [V], > 0; default 3 */
    tv_real_t jam_break_factor; /**< ... and at least this times the model's breakaway voltage [-], > 0; default 2
                                     (the population's friction, springs, R and Kt spread up to about 1.5x) */
    tv_real_t jam_still_rad;    /**< motion over DIAG_JAM_WINDOW samples below which the plate is still [rad], > 0; default 0.002 */
    tv_real_t jam_limp_margin_rad; /**< diag_jam_breakaway_Nm(): within this of limp-home the springs count as
                                     opposing any push [rad], > 0; default 0.05 (the preload's sign turns there) */
    tv_real_t open_u_min_V;     /**< |u| and |u - n Ke w| from which a current must flow [V], > 0; default 3 */
    tv_real_t open_emf_allow_V; /**< the back-EMF n Ke w in that second test is first taken this much closer
                                     to 0 (and 0 within it) [V], >= 0; default 0.35: n Ke times the 0.5
                                     rad/s bias of a held plate's estimated velocity (class a; 0.8 rad/s on
                                     class b), DIAG_PROBE_REST_W_RAD_S. Without it an open winding under a
                                     slowly rising 3 V waited up to 8 ms for the estimate (fault matrix,
                                     slow_sine); a lower 2.5 V gate instead let shorted turns' back-EMF
                                     error at speed (20 % of the turns: 2.7 V at 20 rad/s) look like an
                                     open winding (5 more of 150 runs) */
    tv_real_t open_i_max_A;     /**< |current| below which none flows [A], > 0; default 0.15 */
    tv_real_t open_di_max_A;    /**< ... and changing by at most this over the period [A], > 0; default 0.05
                                     (3 sigma of a healthy sensor's period-to-period noise). A current
                                     sweeping through zero conducts: shorted turns lower the back-EMF
                                     constant, so where the model's back-EMF is 3 V off the voltage
                                     the unit's may match it, and its current crossed the band in 5
                                     samples, confirming P2100 in 12 runs of the fault matrix
                                     (`winding_short`, 12 V sine) */
    tv_real_t r_high_frac;      /**< R + dR above this times R fails P2101 [-], > 1; default 1.35 (units
                                     spread +-20 %, and a winding warms up by some 10 %) */
    tv_real_t r_high_frac_known; /**< the same while the winding's temperature is known [-], > 1; default
                                      1.35 as r_high_frac (the units' spread); 1.15 on an identified unit
                                      (diag_detect_config_identified(): its own R, within 2 % at the end
                                      of every healthy population run, at a known temperature, so +25 %
                                      is a fault; without the temperature a warm winding reads +27 % at
                                      90 degC and the wide bound stays) */
    tv_real_t r_low_frac;       /**< R + dR below this times R fails P1A01 [-], (0, 1); default 0.65 */
    tv_real_t r_low_frac_known; /**< with the winding's temperature known, R + dR below this times R fails
                                     P1A01 too once a window judged since R read below gain_r_max gives a
                                     back-EMF slope |kw| above gain_kw_max (the back-EMF constant down
                                     with the resistance: shorted turns; a current-sensor gain reads R
                                     low with the back-EMF intact) [-], (0, 1); default 0.65 as
                                     r_low_frac; 0.85 on an identified unit (the mirror of
                                     r_high_frac_known's 1.15: 20 % of the turns shorted read 0.70-0.80
                                     in closed-loop driving, where the motor-constant signature's 200
                                     checks of motion did not come within 6 s) */
    tv_real_t r_sigma_max_frac; /**< the check runs while sigma(dR) <= this times R [-], > 0; default 0.05 */
    tv_real_t r_excite_A;       /**< ... and the measured |current| is at least this [A], > 0; default 0.4 */
    tv_real_t friction_high_rel;  /**< friction level 1 + f above this fails P2119 [-], > 1; default 1.7 (the
                                       population's friction spreads +-30 %) */
    tv_real_t friction_sigma_max; /**< the friction check runs while sigma(f) <= this [-], > 0; default 0.05 */
    tv_real_t preload_low_rel;    /**< preload 1 + m below this fails P1A02 [-], (0, 1); default 0.4 (the
                                       population's preload spreads +-20 %) */
    tv_real_t preload_sigma_max;  /**< the preload check runs while sigma(m) <= this [-], > 0; default 0.03 */
    tv_real_t param_excite_rad_s; /**< ... and both only while the estimated |velocity| is at least this
                                       [rad/s], > 0; default 0.5 (the estimator's own f / m update threshold) */
    tv_real_t bridge_lost_frac;   /**< implied terminal voltage below this fraction of |u| fails P1A03 [-], (0, 1);
                                       default 0.25 (healthy: 0.5 and more with R +-20 %, warm, |n Ke w| <= |u|) */
    tv_real_t supply_low_V;       /**< measured supply below this fails P0562 [V], > 0; default 11.5 (healthy
                                       units measure 12.4 V and more: 13.5 +- 1 V, divider +-1 %) */
    tv_real_t supply_hyst_V;      /**< ... and passes from supply_low_V + this [V], > 0; default 0.5 */
    tv_real_t isens_zero_max_A;   /**< |mean current| with the bridge off above which P1A04 fails [A], > 0;
                                       default 0.02 (the mean of 32 samples of a healthy sensor: noise
                                       10 mA and 8-11 mA counts, sigma about 2 mA) */
    tv_real_t isens_bias_max_A;   /**< |intercept| of the in-service window above which P1A04 fails [A], > 0;
                                       default 0.035 (README: healthy population); 0.025 in
                                       diag_detect_config_identified() (a 50 mA offset reads 0.030 -
                                       0.034 there, healthy identified units within 0.013 but for
                                       single windows in closed-loop driving) */
    tv_real_t isens_fit_max_A;    /**< |offset| the voltage equation's fit reads (volt_fit.h, vfit_t::i_off_A)
                                       at or above which P1A04 fails [A], > 0; below half of it the window
                                       passes, in between nothing (diag_isens_fit_check()); default 0.035
                                       (the fault matrix's healthy evaluation runs read at most 0.025, +50 mA
                                       0.045 - 0.064 once the window lies after the onset) */
    tv_real_t isens_fit_vif_max;  /**< ... judged while that offset's variance inflation (vfit_t::i_off_vif) is at
                                       most this [-], >= 1; default 50 (a closed-loop ramp's slow, steady motion
                                       leaves current and velocity near their means: its windows' inflation is
                                       48 - 8e12, median 13,600, and they read offsets of amps on healthy units;
                                       closed-loop driving's windows 1 - 177, median 10, the offset right) */
    tv_real_t isens_vif_max;      /**< the window is judged while its intercept's variance inflation is
                                       at most this [-], >= 1; default 6 (with 20, a healthy unit whose
                                       small currents came at one high speed had its back-EMF error
                                       extrapolated into the intercept: README; healthy windows at
                                       4 - 6 read within 0.022 A, all_varied +-50 mA in `drive` 0.035
                                       - 0.046 A there) */
    tv_real_t isens_i_max_hold;   /**< the window takes the driven samples whose predicted |current| is at
                                       most this fraction of the current that holds the model's spring
                                       preload, M0 / (n Kt) (diag_detect_set_preload()) [-], > 0;
                                       default 0.8: 0.29 A on the paper's throttle (where a resistance
                                       error, however adapted, can add little: README), 0.58 A on class b,
                                       whose currents stay above 0.3 A in 98 % of closed-loop driving */
    tv_real_t isens_innov_max_A;  /**< ... and whose |current innovation| is at most this [A], > 0; default
                                       0.15 (3x the 50 mA offset the check is for, 15 sigma of a healthy
                                       sensor's noise): a stop impact's back-EMF step the model placed a
                                       period late (-1.45 A on class-b unit 1001 in the 12 V sine) is no
                                       sensor offset, and one such sample moved a 500-sample window's
                                       intercept by 3 mA (README "P1A04 and stop impacts") */
    tv_real_t torque_tau_samples; /**< TORQUE SIGNATURE: forgetting time of the regression [fed samples], >= 10;
                                       default 100 */
    tv_real_t torque_min_weight;  /**< the signature is judged once its weight (decayed sample count) is at
                                       least this [samples], > 0; default 60 */
    tv_real_t torque_corr_max;    /**< ... and the two regressors' correlation |rho| at most this [-], (0, 1);
                                       default 0.9 (collinear data cannot tell spring from friction) */
    tv_real_t torque_clip_Nm;     /**< a sample whose unexplained torque exceeds +- this is not fed [N m], > 0;
                                       default 0.6 (a spring's whole torque is about 0.35 N m; a jam's or a
                                       lost drive's is larger) */
    tv_real_t torque_w_min_rad_s; /**< a sample is fed only while the estimated |velocity| is at least this
                                       [rad/s], > 0; default 1 (the Stribeck branch, which the units' spread
                                       changes most, stays out) */
    tv_real_t torque_move_min_rad; /**< ... and the estimated angle moved at least this over the last
                                       DIAG_JAM_WINDOW samples [rad], > 0; default 0.004 (a blocked plate
                                       whose one-step velocity estimate is kicked by the drive is no sliding
                                       plate) */
    tv_real_t torque_accel_max_Nm; /**< ... and the model's predicted net torque J dw/dt is at most this in
                                       magnitude [N m], > 0; default 0.3 (an inertia, torque-constant or
                                       resistance error of the unit shows in the fast transients) */
    tv_real_t preload_fast_low;   /**< the signature's preload (1 + m)(1 - a) below this fails P1A02 [-], (0, 1);
                                       default 0.5 */
    tv_real_t preload_fast_friction_max; /**< ... while the same signature's friction is at most this [-], > 0;
                                       default 2.0 (1.3 in diag_detect_config_identified(): friction x2 seen in
                                       closing motion alone looks like a weak spring) */
    tv_real_t away_friction_min;  /**< AWAY READING: the friction that the signature's samples moving away from
                                       limp-home alone imply, the larger of the readings with the preload as
                                       adapted and as nominal (file comment), below this fails P1A02 [-], > 0; default 0.35 (the healthy soak's
                                       lowest reading 0.52; a spring that no longer opposes the move reads 0 or
                                       less, and a higher bound is crossed sooner while the readings from
                                       before the break decay: 0.2 confirmed 3 broken springs 9 ms late) */
    tv_real_t away_w_max_rad_s;   /**< ... from the samples whose estimated |velocity| is at most this [rad/s], > 0;
                                       default 5 (the viscous friction, which the reading does not model, is
                                       spread +-50 %: on class b unit 1019 in the chirp, Kv at half the
                                       model's read as a friction of 0.06) */
    tv_real_t friction_fast_high; /**< the signature's friction (1 + f)(1 + e) above this fails P2119 [-], > 1;
                                       default 1.7 (1.5 and 1.6 confirmed it on healthy all_varied units in
                                       the 70 s false-alarm soak: 1002 in chirp, 1010 in chirp and open_steps,
                                       whose viscous and Stribeck friction differ from the model's) */
    tv_real_t friction_fast_preload_min; /**< ... while the same signature's preload is at least this [-], > 0;
                                       default 0.8 (a broken spring seen in closing motion alone looks like
                                       friction; unit 1010 reads 0.73-0.76 with a friction of 1.7) */
    tv_real_t friction_fast_level_min; /**< ... and the estimator's own level 1 + f at least this [-], > 0;
                                       default 1.3 (it follows a real change within about a second; a
                                       healthy unit whose viscous or Stribeck friction differs from the
                                       model's reads a high signature at speed while 1 + f stays near 1.2:
                                       measured, class b unit 1010 of all_varied in chirp and the 12 V sine) */
    tv_real_t probe_trigger;      /**< SPRING PROBE: the closing or the opening reading a = sum(s y) / sum(s s)
                                       (s the model's spring torque, y the unexplained torque, the signature's
                                       samples of that direction) from which a held plate is probed [-], > 0;
                                       default 0.1 */
    tv_real_t probe_min_weight;   /**< ... once that direction's weight (decayed count) is at least this
                                       [samples], > 0; default 5 (a full-range step feeds some 30 at
                                       class a's slew; class b's faster slew some 10, which 15 missed:
                                       all_varied unit 1001, closed_steps, 9.96 after 1.2 -> 0.2 rad; the
                                       opening move of limp_home's return fed class b units 4.8 - 5.7,
                                       which 8 missed: all_varied 1001 and 1004, a broken spring
                                       confirmed 346 and 1,249 ms after the bridge drove again, 129 and
                                       125 ms with 5) */
    tv_real_t probe_friction_frac; /**< the probe's torque above the model's spring, as a fraction of the
                                       adapted sliding friction (1 + f) Mc [-], (0, 1); default 0.65 */
    tv_real_t probe_move_rad;     /**< the plate's motion away from limp-home within a probe that fails
                                       P1A02 [rad], > 0; default 0.0015 */
    uint16_t param_slow_hold;     /**< the adapted levels (1 + f, 1 + m) fail only once beyond their bounds for
                                       this many checks in a row [checks], > 0; default 95 (with the codes'
                                       confirmation counts about the former 100 checks = 1 s of motion) */
    tv_real_t gain_r_max;         /**< MOTOR-CONSTANT SIGNATURE (identified units only): the apparent
                                       resistance (R + dR) / R below this opens it [-], (0, 1); default 0.975
                                       (healthy identified units read 0.99-1.01; a current gain g reads 1 / g) */
    tv_real_t gain_mech_min;      /**< ... and it fails once the adapted friction 1 + f and preload 1 + m
                                       are both above this [-], > 1; default 1.025 (healthy identified units
                                       read at most 1.005; a torque per measured ampere too small by 1 / g
                                       raises both by g) */
    tv_real_t gain_kw_max;        /**< ... as a current-sensor gain (P1A04) while the in-service window's
                                       back-EMF slope |kw| is at most this, as shorted turns (P1A01) above
                                       it [A s/rad], > 0; default 0.006 (healthy and a gain error: below
                                       0.001; 20 % of the turns shorted: about 0.02, README) */
    tv_real_t gain_w_var_min;     /**< a window's kw counts when its velocity variance is at least this
                                       [(rad/s)^2], > 0; default 0.09 (a 0.3 rad/s spread) */
    uint16_t gain_hold_checks;    /**< while the apparent resistance is below gain_r_max, P2119 does not
                                       fail while the preload is above gain_mech_min, nor for this many
                                       mechanics checks [checks], > 0; default 300 (3 s of motion: a gain
                                       error raises the friction before the preload; friction alone on a
                                       cold winding, whose R reads low, is then judged as before) */
    tv_real_t ke_short_max;       /**< BACK-EMF CHECK (the voltage equation's fit, volt_fit.h): shorted turns
                                       (P1A01) when two windows in a row read n Ke below this fraction of the
                                       model's with R below the model's [-], (0, 1); default 0.86 (the class's
                                       healthy units spread +-10 %: the lowest read 0.91; 20 % of the turns
                                       shorted reads 0.66 - 0.89 on them, 0.80 - 0.84 on a unit of the
                                       class's own constants); diag_detect_config_identified(): 0.95
                                       (healthy identified units read 0.994 - 1.002), where the
                                       fit's R must read below the same fraction too */
    tv_real_t ke_sigma_max;       /**< ... a window counts when the fit's standard deviation of n Ke is at
                                       most this fraction of the model's [-], > 0; default 0.03 (a slow
                                       sine's creep leaves n Ke undetermined, read 0.4 - 1.6 with sigma
                                       0.1 - 0.9) */
    tv_real_t r_fit_high_frac;    /**< FIT RESISTANCE (P2101): the voltage equation's fit reading R above
                                       this times the model's (at the winding's known temperature) in
                                       DIAG_R_FIT_HIGH_WINDOWS windows in a row fails P2101 [-], > 1;
                                       default 1.25 (measured, the model in service: the healthy
                                       population's windows read at most 1.223 of the class's R, 1,620
                                       runs of 30 s; stops_varied units, whose R is the class's, at most
                                       1.036). The bound leaves about 2 % for the temperature's error on
                                       a unit at the top of the class's spread (R +20 %): a reading 5 K
                                       low is 2 % of R */
    tv_real_t gain_r_known_max;   /**< with the winding's temperature known, the apparent resistance below this
                                       lets the motor-constant signature take friction up alone and holds
                                       P2119 [-], (0, 1); default 0.96 (a gain of 5 % reads 0.945-0.964, 10 %
                                       0.91; a temperature reading up to 10 K too high leaves a friction
                                       fault to P2119) */
    tv_real_t isens_sig_friction_low; /**< OFFSET SIGNATURE (below): the adapted friction 1 + f below this
                                       counts as low for its high side as 1 + m below 1 / gain_mech_min does,
                                       when its deficit 1 - (1 + f) also exceeds the resistance's excess
                                       (R + dR) / R - 1 (a gain g moves the friction several times 1 - g,
                                       a resistance step the friction a fraction of its own step: class
                                       b, R x2, 1 + f 0.943 for a second) [-], (0, 1); default 0.95 (a
                                       gain of -5 % in the 12 V sine: 0.80-0.91; class b's healthy
                                       friction 0.98, 0.97 for a second after a resistance step, which
                                       with 0.976 held P2101 1-2 s) */
    uint16_t isens_sig_checks;    /**< OFFSET SIGNATURE (identified units, or the fit's R up against its
                                       per-unit baseline): P1A04 fails once the apparent
                                       resistance and the preload have read off together, the friction as
                                       it was, for this many mechanics checks in a row [checks], > 0;
                                       default 30 (300 ms of motion: a resistance x2 dips the preload for
                                       about 60 ms while the estimator catches up) */
    uint8_t identified;           /**< 1: the bounds of diag_detect_config_identified() are in force (the
                                       filter's model is the unit's own); 0: the class's (default) */
    /* THE FIT'S PER-UNIT BASELINE (README "A per-unit baseline of the fit"): the voltage equation's
     * fit read on this unit while it was healthy, stored like the learned stops. With it, the
     * fit's checks judge R and n Ke relative to the unit's own values rather than the class's,
     * whose +-20 % and +-10 % spread the class bounds must cover. */
    tv_real_t fit_base_r_ohm;     /**< the unit's winding resistance at APP_R_REF_TEMP_C as the fit read it
                                       healthy [ohm], >= 0; 0: no baseline (the default; learned when
                                       fit_base_windows > 0) */
    tv_real_t fit_base_nke_V_s;   /**< the unit's n Ke at the plate as the fit read it healthy [V s/rad], >= 0;
                                       0: no baseline (both or neither) */
    uint16_t fit_base_windows;    /**< learn the baseline as the mean of this many of the fit's windows of the
                                       model in service with the winding's temperature known, no code
                                       pending or confirmed and n Ke determined (ke_sigma_max) [windows];
                                       0: do not learn (the default: a baseline learned on a faulty unit
                                       would hide its fault; an end-of-line test or the first healthy
                                       minutes of service set it) */
    tv_real_t r_fit_base_high_frac; /**< with a baseline: P2101 when the fit's R reads above this times the
                                       baseline's (at the known temperature) in DIAG_R_FIT_HIGH_WINDOWS
                                       windows in a row [-], > 1; default 1.10 */
    tv_real_t gain_fit_base_max;  /**< with a baseline: P1A04 (a current-sensor gain above 1, which divides
                                       the fit's R and leaves its n Ke) when the fit's R reads below this
                                       times the baseline's, with n Ke above ke_short_max of the baseline's,
                                       in DIAG_R_FIT_LOW_WINDOWS windows in a row [-], (0, 1); default 0.97 */
} diag_detect_config_t;

/** A spring probe reading: the signature's samples of one direction regressed on the model's
 * spring torque s alone, a = sy / ss (decayed as the signature). */
typedef struct {
    tv_real_t w;  /**< decayed count of samples */
    tv_real_t ss; /**< spring regressor squared */
    tv_real_t sy; /**< spring regressor x unexplained torque */
} diag_spring_reading_t;

/** Detector state. Allocate statically; diag_detect_init() before use. */
typedef struct {
    diag_detect_config_t cfg;
    tv_real_t phi_hist[DIAG_JAM_WINDOW]; /**< last estimated angles (ring) [rad] */
    uint8_t hist_n;        /**< valid entries of phi_hist */
    uint8_t hist_i;        /**< next slot of phi_hist */
    uint8_t jam_push_n;    /**< consecutive diag_jam_check() calls driving toward a target at least jam_error_rad
                                away, the same way, at most DIAG_JAM_WINDOW */
    int8_t jam_dir;        /**< that drive's direction: +1 opening, -1 closing, 0 none */
    uint8_t tps_named;     /**< 0: no track named; 1 or 2: the track the vote named (kept out) */
    uint8_t param_tick;    /**< calls of diag_param_check() since its last check, 0..DIAG_PARAM_DECIM - 1 */
    uint8_t supply_tick;   /**< calls of diag_circuit_check() since its last check, 0..DIAG_SUPPLY_DECIM - 1 */
    uint8_t tps_win_tick;  /**< supply checks since the track window began, 0..DIAG_TPS_CLEAN_WINDOW / DIAG_SUPPLY_DECIM - 1 */
    uint8_t tps_dirty[2];  /**< per track, 1: a low sample in the current window */
    uint16_t tps_low_n[2]; /**< per track, low samples since the last clean window (freeze value) */
    tv_real_t arm_a;       /**< a_T of the armature over one period (diag_detect_set_armature()) */
    tv_real_t arm_inv_b;   /**< 1 / b_T [ohm]; 0: not set, no bridge check */
    tv_real_t m0_Nm;        /**< the model's spring preload [N m] (diag_detect_set_preload()) */
    tv_real_t aw_fs;        /**< away reading: decayed sum of the model's friction torque (1 + f) g [N m] */
    tv_real_t isens_band_A; /**< the in-service window's band on the predicted |current| [A]: isens_i_max_hold
                                 times the preload-holding current (diag_detect_set_preload(); the
                                 paper's throttle's until set) */
    tv_real_t i_prev_A;    /**< the current measured at the last call of diag_open_check() (0 when not active) */
    int8_t dead_dir;       /**< the drive direction suspected lost (+1, -1; 0: none) */
    uint8_t probe_req;     /**< 1: a reverse pulse against dead_dir is asked for (diag_probe_direction()) */
    uint8_t isens_off;     /**< consecutive bridge-off periods, saturating at DIAG_ISENS_SETTLE */
    uint8_t isens_on;      /**< consecutive driven periods, saturating at DIAG_ISENS_SETTLE */
    uint8_t isens_win_low; /**< 1 when the in-service window began while the resistance read low (r_low) */
    uint16_t isens_zn;     /**< samples in the zero check's sum */
    uint16_t isens_n;      /**< samples in the in-service window */
    tv_real_t isens_zsum;  /**< sum of the measured current at rest [A] */
    tv_real_t isens_s[8];  /**< the window's sums: i, w, i i, i w, w w, y, i y, w y */
    tv_real_t tq_lam;      /**< forgetting factor per fed sample, 1 - 1 / torque_tau_samples */
    tv_real_t tq_w;        /**< weight: decayed count of fed samples */
    tv_real_t tq_ss;       /**< decayed sums: spring regressor squared, */
    tv_real_t tq_sf;       /**<   spring x friction regressor, */
    tv_real_t tq_ff;       /**<   friction regressor squared, */
    tv_real_t tq_sy;       /**<   spring regressor x unexplained torque, */
    tv_real_t tq_fy;       /**<   friction regressor x unexplained torque */
    tv_real_t preload_fast;  /**< the last judged signature's preload (1 + m)(1 - a) [-] (0: none yet) */
    tv_real_t friction_fast; /**< the last judged signature's friction (1 + f)(1 + e) [-] (0: none yet) */
    uint16_t tq_age;       /**< diag_param_check() calls since the signature was last fed (saturating) */
    uint16_t slow_f_run;   /**< consecutive checks with 1 + f above friction_high_rel */
    uint16_t slow_m_run;   /**< consecutive checks with 1 + m below preload_low_rel */
    uint8_t fast_m_amb;    /**< consecutive checks whose signature reads a preload below preload_fast_low with its
                                friction above DIAG_PRELOAD_FAST_CLEAR (saturating) */
    tv_real_t aw_w;        /**< away reading: decayed count of the signature's samples moving away from limp-home, */
    tv_real_t aw_fy;       /**<   their unexplained torque along the friction (opposing the motion) [N m] */
    uint8_t aw_last;       /**< 1 when the signature's newest sample was one of them */
    uint8_t aw_stale;      /**< checks (every DIAG_PARAM_DECIM steps) since one found aw_last set (saturating) */
    diag_spring_reading_t pc; /**< spring probe: the signature's samples toward limp-home */
    diag_spring_reading_t po; /**< spring probe: its samples away from limp-home */
    tv_real_t probe_phi0;  /**< the angle at the probe's start [rad] */
    tv_real_t probe_T;     /**< the probe's torque [N m] */
    tv_real_t probe_pre_ref;  /**< the estimator's 1 + m while nothing was suspected, as latched one
                                   DIAG_PROBE_REF_LAG before the latest latch [-] */
    tv_real_t probe_fric_ref; /**< the estimator's 1 + f likewise [-] */
    tv_real_t probe_pre_lag;  /**< the estimator's 1 + m at the latest latch: the next probe_pre_ref [-] */
    tv_real_t probe_fric_lag; /**< the estimator's 1 + f at the latest latch: the next probe_fric_ref [-] */
    tv_real_t r_ratio;     /**< the last (R + dR) / R of diag_resistance_check() [-] (0: none yet) */
    tv_real_t isens_kw;    /**< the back-EMF slope kw of the last in-service window judged while the
                                apparent resistance was below gain_r_max [A s/rad] */
    uint8_t r_low;         /**< 1 while (R + dR) / R < gain_r_max (identified units) */
    uint16_t r_out_n;      /**< resistance checks in a row at or above gain_r_max (saturating) */
    uint8_t r_high;        /**< 1 while (R + dR) / R > 1 / gain_r_max with the temperature known (identified) */
    uint8_t r_low_known;   /**< 1 while (R + dR) / R < gain_r_known_max with the temperature known (identified) */
    uint8_t mech_low;      /**< 1 while the adapted preload 1 + m < 1 / gain_mech_min or friction 1 + f <
                                isens_sig_friction_low, their
                                sigmas within preload_sigma_max and friction_sigma_max (identified units;
                                set by diag_param_check()) */
    uint8_t kw_ok;         /**< 1 once a window's kw was taken since r_low was set */
    uint16_t kw_n;         /**< samples in the driven back-EMF window (diag_current_sensor_check()) */
    tv_real_t kw_s[8];     /**< its sums, as isens_s: i, w, i i, i w, w w, y, i y, w y */
    tv_real_t kw_r0;       /**< the resistance ratio r_ratio when it began [-] */
    tv_real_t kw_prev;     /**< the driven window's last judged kw [A s/rad] */
    uint8_t kw_prev_ok;    /**< 1 when kw_prev is from a window judged since r_low was set, or before an
                                excursion above gain_r_max shorter than DIAG_R_LOW_EXIT checks */
    uint8_t kw_short;      /**< 1 once two judged driven windows in a row read kw above gain_kw_max
                                since r_low was set: a back-EMF deficit (shorted turns) */
    uint8_t ke_low_n;      /**< the voltage equation's fit: windows in a row that read n Ke below
                                ke_short_max (saturating at DIAG_KE_SHORT_WINDOWS;
                                diag_backemf_check()); at DIAG_KE_SHORT_WINDOWS: shorted turns */
    uint8_t r_fit_high_n;  /**< the voltage equation's fit: windows in a row that read R above
                                r_fit_high_frac with the temperature known (saturating at
                                DIAG_R_FIT_HIGH_WINDOWS; diag_fit_resistance_check()) */
    tv_real_t r_fit_ratio; /**< the fit's R over the model's in the last window judged [-] (P2101's
                                freeze value while the fit fails it) */
    uint8_t r_fit_low_n;   /**< with a baseline: windows in a row whose R read below gain_fit_base_max of it
                                with n Ke as it was (saturating at DIAG_R_FIT_LOW_WINDOWS) */
    uint8_t r_fit_up_n;    /**< with a baseline: windows in a row whose R read above 1 / gain_fit_base_max of it
                                and at most r_fit_base_high_frac with n Ke as it was (saturating at
                                DIAG_R_FIT_LOW_WINDOWS): on a unit that is not identified, the offset
                                signature's apparent resistance up (diag_param_check()) */
    uint8_t r_fit_calm_age; /**< with a baseline: windows since one read R at most halfway to 1 /
                                gain_fit_base_max of it (saturating at 254; 255 before the first window
                                judged, which counts as 1 after a calm one when it reads above) */
    uint16_t gain_wait;    /**< mechanics checks since r_low was set (saturating) */
    uint16_t offset_sig_n; /**< mechanics checks in a row that read the offset signature (saturating) */
    uint8_t probe_t;       /**< steps into the running probe (0: none running) */
    uint8_t probe_lag_t;   /**< calls of diag_spring_probe() with nothing suspected since the latest latch */
    uint8_t probe_n;       /**< probes that moved the plate since the suspicion was raised */
    uint8_t probe_creep;   /**< 1: the running probe began on a plate creeping toward limp-home */
    uint8_t probe_creep_n; /**< probes begun on a creeping plate that held, since the suspicion was raised */
} diag_detect_t;

/** Defaults (see diag_detect_config_t). Does nothing when cfg is NULL. */
void diag_detect_config_default(diag_detect_config_t *cfg);

/**
 * The bounds for a filter whose model is the unit's own (identified: `identify` parameter file,
 * or an end-of-line identification), on top of diag_detect_config_default(): the unit's healthy
 * friction and preload are then the model's (1 +- the estimation error, not +-30 %), so the
 * torque signature may judge a change relative to them: friction_fast_high 1.15 with
 * friction_fast_level_min 1.1 (friction +25 % is seen), preload_fast_low 0.7 (a spring at 50 %
 * is seen) with preload_fast_friction_max 1.3; and so may the adapted level: friction_high_rel
 * 1.15 (on an identified unit the healthy 1 + f reads 0.98-1.00 in every scenario, sigma
 * 0.01-0.02; README "Identified units"); and the in-service window's intercept,
 * isens_bias_max_A 0.025 (the filter absorbs a third of an offset: 50 mA reads 0.030 - 0.034 in
 * the 12 V sine of class b, under the default 0.035). Sets identified = 1. The parameter file key
 * diag.identified = 1 (written by identify) selects it. Does nothing when cfg is NULL.
 */
void diag_detect_config_identified(diag_detect_config_t *cfg);

/**
 * Validate and start (no history, no track named).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE; TV_ERR_CONFIG (a threshold out of its range).
 */
int diag_detect_init(diag_detect_t *dd, const diag_detect_config_t *cfg);

/** What diag_tps_vote() decided for this sample's angle. */
typedef enum {
    DIAG_TPS_BOTH = 0,  /**< both tracks (the caller's own rule) */
    DIAG_TPS_ONLY1 = 1, /**< track 1 alone (track 2 named) */
    DIAG_TPS_ONLY2 = 2, /**< track 2 alone (track 1 named) */
    DIAG_TPS_NONE = 3   /**< no angle (P2135: the tracks disagree and neither agrees with the estimator) */
} diag_tps_use_t;

/**
 * The track vote (see the file comment); reports P0121, P0221, P2135.
 * @param both_in_range  1 when both tracks are in range (and neither range fault latched): the
 *                       vote runs; 0: the three codes are not run and DIAG_TPS_BOTH is returned
 * @param phi1_rad, phi2_rad  the two tracks' angles [rad]
 * @param phi_pred_rad   the estimator's prediction of this sample's angle [rad]
 * @param snap           the step's snapshot (value in the freeze frame: |phi1 - phi2| [rad])
 * @return the angle to use (diag_tps_use_t); DIAG_TPS_BOTH when an argument is NULL or not finite.
 */
diag_tps_use_t diag_tps_vote(diag_detect_t *dd, diag_t *d, int both_in_range, tv_real_t phi1_rad, tv_real_t phi2_rad,
                             tv_real_t phi_pred_rad, const diag_snapshot_t *snap);

/**
 * The jam check (see the file comment); reports P2111, P2112. Every call adds phi_est_rad to
 * the motion history; the check runs from the DIAG_JAM_WINDOW-th call on, and judges the motion
 * only once the drive toward the target (the same direction, the target jam_error_rad or more
 * away) lasted the last DIAG_JAM_WINDOW calls (a plate gets that long to move after a target step
 * or when the bridge resumes: a healthy one needs about 2 ms).
 * @param active       1 in closed loop with the bridge driving; 0: not run
 * @param target_rad   the target in force [rad]
 * @param phi_est_rad  the estimated angle [rad]
 * @param u_V          the voltage applied toward the target [V]
 * @param u_break_V    the model's breakaway voltage at this angle in the push's direction [V]
 *                     (R / (n Kt) times diag_jam_breakaway_Nm())
 * @param snap         the step's snapshot (value in the freeze frame: |target - phi| [rad])
 */
void diag_jam_check(diag_detect_t *dd, diag_t *d, int active, tv_real_t target_rad, tv_real_t phi_est_rad, tv_real_t u_V,
                    tv_real_t u_break_V, const diag_snapshot_t *snap);

/**
 * The model's breakaway torque for the jam check's gate (u_break_V = R / (n Kt) times it): the
 * static friction Ms, plus the springs' preload and rate M0 + c |phi| when they oppose the push
 * (a push away from limp-home, u phi > 0, or any push within jam_limp_margin_rad of it). A push
 * toward limp-home from beyond the margin has the springs on its side: their help is not counted
 * (Ms alone), so a plate stuck short of a target nearer limp-home is judged from
 * jam_break_factor R Ms / (n Kt) on (3.8 V at the nominal model, where the controller's bounded
 * integral leaves it about 6 V at 0.04-0.05 rad of error) instead of from twice the
 * spring-opposed breakaway (7-8 V, which it never applied there: README, jam).
 * @param dd      the detector (its jam_limp_margin_rad); NULL: the spring-opposed value
 * @param u_V     the voltage applied (its sign is the push's direction) [V]
 * @param phi_rad the estimated angle [rad] (0 = limp-home)
 * @param Ms_Nm, M0_Nm, c_Nm_rad  the model's static friction, preload and spring rate
 * @return the breakaway torque [N m]
 */
tv_real_t diag_jam_breakaway_Nm(const diag_detect_t *dd, tv_real_t u_V, tv_real_t phi_rad, tv_real_t Ms_Nm, tv_real_t M0_Nm,
                               tv_real_t c_Nm_rad);

/**
 * The open-winding and bridge-direction check (see the file comment); reports P2100 and P1A03
 * (P1A03 only after diag_detect_set_armature()). Call once per step: it keeps the current for
 * the next call.
 * @param active     1 when the bridge drove the period that just ended and the current sample is plausible
 * @param u_V        the voltage applied over that period [V]
 * @param emf_V      the back-EMF n Ke w at its start [V] (the estimate's w: P2100's gate)
 * @param meas_ok    1 when emf_meas_V is known (an angle now and one before); 0: P1A03 not judged
 * @param emf_meas_V the back-EMF of the measured motion, n Ke times the differentiated angle [V]
 * @param current_A  the measured current [A]
 * @param snap       the step's snapshot (value in the freeze frame: P2100 |current| [A]; P1A03 the
 *                   implied terminal voltage over the commanded one, v / u [-])
 */
void diag_open_check(diag_detect_t *dd, diag_t *d, int active, tv_real_t u_V, tv_real_t emf_V, int meas_ok,
                     tv_real_t emf_meas_V, tv_real_t current_A, const diag_snapshot_t *snap);

/**
 * The armature's exact solution over one period, for the bridge check: i1 = a_T i0 + b_T (u - e).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (a_T not in [0, 1), b_T not > 0).
 */
int diag_detect_set_armature(diag_detect_t *dd, tv_real_t a_T, tv_real_t b_T);

/**
 * The model's spring preload M0 and motor torque constant at the plate n Kt. The current that
 * holds the preload, M0 / (n Kt), scales the current sensor's in-service band (isens_i_max_hold):
 * a motor with a lower resistance and torque constant runs at higher currents, and a band fixed
 * in amperes would see almost none of them. M0 turns the adapted preload 1 + m into a torque for
 * the away reading (away_friction_min). Until set, the paper's throttle's (TV_PAPER_M0_NM,
 * TV_PAPER_N_GEAR TV_PAPER_KT_NM_A: a holding current of 0.37 A).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (not finite or not > 0: both kept).
 */
int diag_detect_set_preload(diag_detect_t *dd, tv_real_t M0_Nm, tv_real_t nKt_Nm_A);

/**
 * The reverse pulse the bridge check asks for (see the file comment).
 * @return +1 or -1: drive the next period in this direction (then diag_probe_done()); 0: none
 */
int diag_probe_direction(const diag_detect_t *dd);

/** The pulse was applied (or is no longer wanted). */
void diag_probe_done(diag_detect_t *dd);

/**
 * The supply and track low-circuit checks (see the file comment); report P0562, P0122, P0222.
 * Call once per step: the supply is checked at every DIAG_SUPPLY_DECIM-th call (the first at the
 * DIAG_SUPPLY_DECIM-th), the tracks at every call.
 * @param low1, low2  1 when the track's sample is below its range
 * @param supply_V    the measured supply [V] (P0562's freeze value)
 * @param snap        the step's snapshot (P0122 / P0222 freeze value: low samples counted since
 *                    the last clean window [-])
 */
void diag_circuit_check(diag_detect_t *dd, diag_t *d, int low1, int low2, tv_real_t supply_V, const diag_snapshot_t *snap);

/**
 * The winding-resistance check (see the file comment); reports P2101, P1A01.
 * @param active       1 when the bridge drove the period that ended and the one starting (the
 *                     model is the one in service: not while the stops are being learned)
 * @param current_A    the measured current [A]
 * @param r_est_ohm    the estimator's R + dR [ohm]
 * @param r_sigma_ohm  its standard deviation [ohm] (0: the estimator has no such state: not run)
 * @param r_nom_ohm    the model's R [ohm], > 0, at the winding's temperature when it is known
 * @param temp_known   1 when r_nom_ohm was referred to the winding's known temperature: the bound
 *                     r_high_frac_known applies
 * @param snap         the step's snapshot (value in the freeze frame: (R + dR) / R [-])
 */
void diag_resistance_check(diag_detect_t *dd, diag_t *d, int active, tv_real_t current_A, tv_real_t r_est_ohm,
                           tv_real_t r_sigma_ohm, tv_real_t r_nom_ohm, int temp_known, const diag_snapshot_t *snap);

/** Windows in a row of the fit's resistance that read R above r_fit_high_frac (about 0.75 s of
 * drive: a single window's R is off by up to a few per cent on healthy units). */
#define DIAG_R_FIT_HIGH_WINDOWS 3u

/** Windows in a row of the fit's resistance that read a current gain against the unit's baseline:
 * one more than the fit's blocks per window (volt_fit.c's default 4), so that the run always holds a
 * window wholly after an onset. The windows across the onset of shorted turns read R down before
 * their n Ke follows (20 % of the turns: P1A04 first, about 0.6 s after the onset, in 23 of the
 * fault matrix's 150 runs with 3). */
#define DIAG_R_FIT_LOW_WINDOWS 5u

/** Windows of the fit after the latest one that read R at most halfway to 1 / gain_fit_base_max of
 * the baseline within which a run of windows reading R above it may begin (the offset signature's
 * R up on a unit that is not identified, diag_param_check()): a step of the apparent resistance
 * (a current gain below 1) enters the fit's sliding window of 4 blocks over 4 windows; a winding
 * drifting up by +50 % over 200 s takes about 25 windows to cross the half. */
#define DIAG_R_FIT_UP_ONSET 4u

/**
 * The fit's resistance check (P2101): one window of the voltage equation's fit (volt_fit.h), called
 * when the fit takes one. DIAG_R_FIT_HIGH_WINDOWS windows in a row whose R reads above
 * r_fit_high_frac of the model's make diag_resistance_check() fail P2101 at each driven step (whatever
 * the current; the estimator's R + dR does not pass it meanwhile) until a window reads at or below
 * the bound. The fit's R is the winding's own, free of the estimator's other parameters, so on a
 * unit of the class's model it sees a raised winding that R + dR (bound r_high_frac_known, 1.35 R)
 * lets through. The count clears when the window is not judged: the model not in service or the
 * winding's temperature unknown (a warm winding reads +27 % at 90 degC), and while the open-winding,
 * bridge or current-sensor code (P2100, P1A03, P1A04) is pending or confirmed (an offset of the
 * current sensor moves the fit's R: the fit's offset check names it first).
 * With a per-unit baseline (base 1: r_ratio and ke_ratio are relative to it) the bound is
 * r_fit_base_high_frac, and DIAG_R_FIT_LOW_WINDOWS windows in a row whose R reads below
 * gain_fit_base_max with n Ke above ke_short_max read a current-sensor gain: the resistance check
 * then fails P1A04 at each driven step until a window reads otherwise. Windows in a row whose R
 * reads above 1 / gain_fit_base_max and at most r_fit_base_high_frac with n Ke above ke_short_max,
 * the run begun within DIAG_R_FIT_UP_ONSET windows of one reading R at most halfway to 1 /
 * gain_fit_base_max (or of the first window judged), count in r_fit_up_n: on a unit that is not
 * identified, the offset signature's R up (diag_param_check()).
 * @param active   1 when the window was the model in service with the winding's temperature known
 * @param r_ratio  the fit's R over the model's (or the baseline's) at the winding's temperature [-]
 * @param ke_ratio the fit's n Ke over the model's (or the baseline's) [-]
 * @param base     1 when the ratios are relative to the unit's baseline (fit_base_r_ohm)
 */
void diag_fit_resistance_check(diag_detect_t *dd, const diag_t *d, int active, tv_real_t r_ratio, tv_real_t ke_ratio,
                               int base);

/** Windows in a row of the back-EMF check that read shorted turns (diag_backemf_check()). */
#define DIAG_KE_SHORT_WINDOWS 2u

/**
 * The back-EMF check: one window of the voltage equation's fit (volt_fit.h), called when the fit
 * takes one. Two windows in a row whose n Ke reads below ke_short_max of the model's, with R below
 * the model's (DIAG_KE_SHORT_WINDOWS) read shorted turns: the resistance check (diag_resistance_check()) then fails P1A01 at
 * its rate, and the motor-constant signature names shorted turns rather than a current gain (a
 * gain divides the fit's R, never its n Ke). A window whose n Ke has a standard deviation above
 * ke_sigma_max of the model's is not counted; while the open-winding or bridge code (P2100,
 * P1A03) is pending or confirmed, the voltage equation has no current to fit and the state clears.
 * @param r_ratio      the fit's R over the model's (at the winding's temperature when known) [-]
 * @param ke_ratio     the fit's n Ke over the model's [-]
 * @param ke_sigma_rel its standard deviation over the model's n Ke [-]
 */
void diag_backemf_check(diag_detect_t *dd, const diag_t *d, tv_real_t r_ratio, tv_real_t ke_ratio, tv_real_t ke_sigma_rel);

/**
 * The offset check of the voltage equation's fit (P1A04): one window of its instrumental-variable
 * fit with an intercept (volt_fit.h), called when the fit gives one. The offset b it reads at or
 * above isens_fit_max_A in magnitude fails P1A04, below half of it passes, in between nothing (a
 * 20 mA offset, or a healthy unit's model errors at their largest, neither adds to the code's
 * leaky counter nor takes from it). Not judged while the open-winding or bridge code (P2100,
 * P1A03) is pending or confirmed: the voltage the bridge applies is then not the winding's; nor
 * while the offset's variance inflation is above isens_fit_vif_max (the regressors' means
 * confound it). The caller judges only the model in service (not during stop learning or the
 * identification sequence: their drives against the stops read offsets of 35 mA and more on
 * healthy units with an inflation of 10 - 50).
 * @param offset_A the fit's offset b [A] (the freeze frame's value)
 * @param vif      its variance inflation [-]
 * @param snap     the step's snapshot
 */
void diag_isens_fit_check(diag_t *d, const diag_detect_t *dd, tv_real_t offset_A, tv_real_t vif, const diag_snapshot_t *snap);

/**
 * The adapted-mechanics check (see the file comment); reports P2119, P1A02. Call once per step:
 * the check runs at every DIAG_PARAM_DECIM-th call (the first check at the DIAG_PARAM_DECIM-th).
 * @param active           1 when the estimator ran this step and the model is the one in service
 *                         (not during stop learning)
 * @param w_rad_s          the estimated velocity [rad/s]
 * @param friction_rel     the estimator's friction level 1 + f [-]
 * @param friction_sigma   its standard deviation [-] (0: no such state: not run)
 * @param preload_rel      the estimator's preload 1 + m [-]
 * @param preload_sigma    its standard deviation [-] (0: no such state: not run)
 * @param snap             the step's snapshot (value in the freeze frame: 1 + f, or 1 + m)
 */
void diag_param_check(diag_detect_t *dd, diag_t *d, int active, tv_real_t w_rad_s, tv_real_t friction_rel,
                      tv_real_t friction_sigma, tv_real_t preload_rel, tv_real_t preload_sigma, const diag_snapshot_t *snap);

/**
 * The current-sensor checks (see the file comment); report P1A04. Call once per step.
 * @param bridge_on   1 when the bridge drove the period that just ended, 0 when it was off
 * @param current_ok  1 when the current sample is plausible; 0: neither check uses this sample
 *                    (the in-service window restarts)
 * @param innov_ok    1 when the estimator ran and corrected with this current sample (innov_A is
 *                    its innovation); 0: the in-service window restarts
 * @param current_A   the measured current [A]
 * @param innov_A     the estimator's current innovation of this sample [A] (in-service check)
 * @param w_rad_s     the estimated velocity at the start of the period [rad/s]
 * @param snap        the step's snapshot (value in the freeze frame: the offending mean or intercept [A])
 */
void diag_current_sensor_check(diag_detect_t *dd, diag_t *d, int bridge_on, int current_ok, int innov_ok,
                               tv_real_t current_A, tv_real_t innov_A, tv_real_t w_rad_s, const diag_snapshot_t *snap);

/**
 * Feed one sample to the torque signature (see the file comment), once per step before
 * diag_param_check(). Nothing happens (no decay either) when active is 0, an argument is not
 * finite, |w_rad_s| < torque_w_min_rad_s or |accel_Nm| > torque_accel_max_Nm; except that a slower
 * sample moving toward limp-home while the drive pulls that way too feeds the spring probe's
 * closing reading (DIAG_PROBE_SLOW_W_RAD_S).
 * @param active       1 when torque_Nm is of this sample: the estimator predicted one period and
 *                     corrected with the angle, the model is the one in service, the plate is away
 *                     from both stops and from limp-home (the caller's margins)
 * @param w_rad_s      the estimated velocity [rad/s]
 * @param torque_Nm    the torque the model did not explain: J (w corrected - w predicted) / Ts [N m]
 * @param accel_Nm     the model's net torque over the period: J (w predicted - w previous) / Ts [N m]
 * @param spring_Nm    the model's spring torque at the angle, M0 (1 + m) sp(phi) + c phi [N m]
 * @param friction_Nm  the model's sliding friction level at the velocity, (1 + f) g(w) > 0 [N m]
 * @param u_V          the voltage the bridge applied over the period [V] (the slow samples' drive
 *                     direction; 0 feeds no slow sample)
 */
void diag_torque_feed(diag_detect_t *dd, int active, tv_real_t w_rad_s, tv_real_t torque_Nm, tv_real_t accel_Nm,
                      tv_real_t spring_Nm, tv_real_t friction_Nm, tv_real_t u_V);

/** The signature's friction up to which its low preload fails P1A02 at once [-]. Above it (up to
 * preload_fast_friction_max) the reading is ambiguous: more friction on some units leaks into the
 * spring column (measured: friction x2 on all_varied unit 1000 in `drive` reads a preload 0.47 with
 * a friction 1.44, a spring at 30 % on the same unit 0.48 with 1.44), so such checks fail only from
 * the DIAG_PRELOAD_FAST_AMBIG_HOLD-th in a row on. An identified unit's preload_fast_friction_max
 * (1.3) leaves no such band. */
#define DIAG_PRELOAD_FAST_CLEAR TV_R(1.3)
/** Ambiguous signature checks in a row (DIAG_PRELOAD_FAST_CLEAR) before they fail P1A02. */
#define DIAG_PRELOAD_FAST_AMBIG_HOLD 3u

/** The signature's preload below DIAG_PRELOAD_BOTH_LOW [-] with its friction below
 * DIAG_FRICTION_BOTH_LOW [-] fails P1A02 too (whatever preload_fast_low). A broken spring in fast
 * motion leaves a torque along the motion that the 2x2 solve splits between the spring column
 * and a friction deficit: in the 12 V sine on class b units (all_varied 1001, 1004; a few fed
 * samples per half-period, so the preload falls over four of them) the friction read 0.50 and
 * -0.08 with preloads of 0.55 and 0.54, 100 - 110 ms before the preload crossed 0.5. No fault
 * lowers the friction, and a healthy unit low on both is one at the corner of the spread (less
 * preload and less friction than its class): the lowest healthy readings of 2,430 soak runs of
 * 20 s with a preload below 0.65 had a friction of 0.648 or more (0.6485 with 0.6482; 0.559 with
 * 0.860). */
#define DIAG_PRELOAD_BOTH_LOW TV_R(0.6)
#define DIAG_FRICTION_BOTH_LOW TV_R(0.5)

/** A sample too slow for the signature (diag_torque_feed()) still feeds the spring probe's closing
 * reading while it moves toward limp-home with |w| >= DIAG_PROBE_SLOW_W_RAD_S [rad/s], the angle
 * moved >= DIAG_PROBE_SLOW_MOVE_RAD [rad] over the jam window, and the drive pulls toward
 * limp-home too (a plate the controller pulls back after an overshoot). */
#define DIAG_PROBE_SLOW_W_RAD_S TV_R(0.15)
#define DIAG_PROBE_SLOW_MOVE_RAD TV_R(0.0008)

/** The probe's torque takes the adapted levels 1 + m and 1 + f (probe_pre_ref, probe_fric_ref) as
 * they were DIAG_PROBE_REF_LAG to 2 DIAG_PROBE_REF_LAG calls of diag_spring_probe() before the
 * suspicion (latched every DIAG_PROBE_REF_LAG calls with nothing suspected, the older latch used):
 * a broken spring pulls the estimator's preload down within the move that raises the suspicion
 * (measured: all_varied unit 1002, closed-loop drive, 1 + m 0.79 -> 0.56 in the 20 ms before it),
 * and a probe with that torque held the plate without its spring for DIAG_PROBE_MAX_STEPS, which
 * ended the suspicion: P1A02 waited 1.05 s for the next move, 133 ms with the older latch. */
#define DIAG_PROBE_REF_LAG 32u

/** Steps a spring probe lasts at most (the plate held: no evidence). */
#define DIAG_PROBE_MAX_STEPS 15u
/** Probes that moved the plate after which the suspicion is dropped (P1A02 confirmed or not). */
#define DIAG_PROBE_MAX_N 8u
/** A probe that moved the plate away from limp-home by at least this fraction of probe_move_rad,
 * but less than probe_move_rad, gives no verdict and keeps the suspicion (it counts toward
 * DIAG_PROBE_MAX_N); one that moved less is a plate that holds (the suspicion ends). Without its
 * spring a plate the controller has not yet pulled back can move 1.4-1.5 mrad in a probe (fault
 * matrix, spring at 30 %: the 5th probe ended the suspicion at 1.47 mrad). */
#define DIAG_PROBE_UNSURE_FRAC TV_R(0.3)
/** The estimated speed away from limp-home below which a plate whose angle is still over the jam
 * window counts as at rest for a probe [rad/s] (toward limp-home: DIAG_PROBE_CREEP_W_RAD_S). A plate held by static friction without the spring the model pulls
 * with keeps an estimated speed of 0.1-0.3 rad/s toward limp-home (class b, measured), which a
 * bound of 0.05 rad/s let wait 35-100 ms before each probe. */
#define DIAG_PROBE_REST_W_RAD_S TV_R(0.5)
/** A plate CREEPING toward limp-home may be probed too: its window's motion toward limp-home below
 * DIAG_PROBE_CREEP_RAD [rad] and its estimated speed that way below DIAG_PROBE_CREEP_W_RAD_S
 * [rad/s]. A plate without its spring that the controller pulls back after an overshoot creeps
 * back at 0.1-0.4 rad/s (estimated 0.3-0.8) for 300 ms or more (class b, limp_home's opening step
 * to 0.8 rad), where the rest gate alone let it wait. The probe's motion away from limp-home then
 * counts from where the plate turns (a healthy plate stops and stays: friction opposes the
 * creep), and a creeping probe that holds (moved less than DIAG_PROBE_UNSURE_FRAC) gives no
 * verdict and keeps the suspicion, at most DIAG_PROBE_MAX_N times. */
#define DIAG_PROBE_CREEP_RAD TV_R(0.008)
#define DIAG_PROBE_CREEP_W_RAD_S TV_R(1.0)

/**
 * The spring probe (see the file comment); reports P1A02. Call once per step after the control
 * law, before diag_param_check().
 * @param allowed      1 in closed loop with the bridge driving, no code in force, the model in
 *                     service, the plate away from the stops and from limp-home (the caller's
 *                     margins): a probe may run; 0 ends a running probe (no verdict)
 * @param phi_rad      the estimated angle [rad]
 * @param w_rad_s      the estimated velocity [rad/s]
 * @param preload_Nm   the model's preload torque M0 (unadapted, > 0) [N m]
 * @param rate_Nm      the model's spring-rate torque at the angle, c phi [N m]
 * @param friction_Nm  the model's sliding friction Mc (unadapted) [N m] (a unit's static friction is at
 *                     least its sliding one, whatever its Stribeck drop)
 * @param preload_rel  the estimator's preload level 1 + m, and
 * @param friction_rel its friction level 1 + f [-]: kept while nothing is suspected, the probe uses
 *                     the levels from before the suspicion (the fault pulls them while it is seen)
 * @param torque_Nm    receives the motor torque to apply over the next period while a probe runs
 * @param snap         the step's snapshot (value in the freeze frame: the closing reading's preload
 *                     1 - a [-])
 * @return 1 when the caller applies *torque_Nm instead of its control law for the next period; 0 not
 */
int diag_spring_probe(diag_detect_t *dd, diag_t *d, int allowed, tv_real_t phi_rad, tv_real_t w_rad_s,
                      tv_real_t preload_Nm, tv_real_t rate_Nm, tv_real_t friction_Nm, tv_real_t preload_rel,
                      tv_real_t friction_rel, tv_real_t *torque_Nm, const diag_snapshot_t *snap);

#ifdef __cplusplus
}
#endif

#endif /* DIAG_DETECT_H */
