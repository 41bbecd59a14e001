/**
 * @file plant.h
 * @brief High-fidelity plant of the electronic throttle valve for the host simulation: DC motor
 *        with gearbox, return springs with limp-home preload, stick-slip friction, Hunt-Crossley
 *        hard stops, an H-bridge (averaged or PWM-resolved, with a diode-freewheel disabled
 *        state) and the ECU's analog front end (current sense, two ratiometric position
 *        tracks, supply divider, ADC) with seeded noise.
 *
 * This model is deliberately SEPARATE from, and more faithful than, the estimator's discrete
 * model (firmware/estimator/tv_model.h): the estimator is tested against it. Double precision, C99, no
 * heap, no globals; all state lives in a caller-owned plant_t.
 *
 * STATES (plate side of the gearbox, SI): armature current i [A], plate velocity w [rad/s],
 * plate angle phi [rad] (0 at limp-home, positive = opening).
 *
 * CONTINUOUS DYNAMICS (firmware/estimator/MODEL.md, paper Table 1 defaults):
 *   L di/dt = u - R i - Ke n w
 *   J dw/dt = n Kt i - Mspring(phi) - Kv w - Mcoul(w) + Mstop(phi, w)
 *   dphi/dt = w
 *   Mspring = M0 sat(phi / d_lh) + c phi        (limp-home preload, see below)
 *   Mcoul   = set-valued Coulomb/Stribeck law: |Mcoul| <= g(w), Mcoul = g(w) sign(w) when w != 0,
 *             g(w) = Mc + (Ms - Mc) exp(-|w| / ws). At w = 0 it takes whatever value in
 *             [-Ms, Ms] holds the plate (true sticking).
 *   Mstop   = Hunt-Crossley contact at the two hard stops, never pulling:
 *             closed stop, p = phi_closed - phi > 0:  Mstop = +max(0, p^e (k - lambda w))
 *             open stop,   p = phi - phi_open   > 0:  Mstop = -max(0, p^e (k + lambda w))
 *
 * LIMP-HOME PRELOAD. The paper's -M0 sign(phi) is set-valued at phi = 0: the plate can rest at
 * limp-home against up to M0 of other torque. Physically the preload comes from two preloaded
 * springs handing over at a limp-home lever stop, which has a small but finite compliance; the
 * plant models exactly that: a stiff detent, linear over |phi| <= d_lh (default 1e-4 rad,
 * below the ADC's angle resolution of ~4.5e-4 rad/count), equal to M0 sign(phi) outside. This
 * keeps a potential energy (so the scheme does not create energy when crossing limp-home), and
 * its stiffness M0 / d_lh = 2500 N m/rad gives a local frequency sqrt(2500 / J) = 1250 rad/s,
 * i.e. h * omega = 0.025 at the default sub-step h = 20 us, far inside the stability limit 2
 * of the Verlet position update. plant_config_check() enforces h * omega <= 0.5.
 * Resting at limp-home is then an ordinary stick state of the friction law.
 *
 * INTEGRATION SCHEME (fixed sub-step h = 1 ms / substeps_per_ms, default 20 us = 50 kHz). One
 * sub-step from (i0, w0, phi0) is a Strang splitting of armature and mechanics:
 *   1. Armature half-slice h/2 with the velocity held at w0: exact solution of the linear RL
 *      equation (zero-order hold of u and of the back-EMF): i' = a i + b (u - Ke n w),
 *      a = exp(-R h / 2L), b = -expm1(-R h / 2L) / R (h / 2L when R = 0). Stable for every h
 *      (0 < a <= 1): the current never flips sign from numerics. With the bridge disabled the
 *      body diodes are an exact complementarity law (below), zero crossing located exactly.
 *   2. Mechanics by position Verlet: drift phi_m = phi0 + (h/2) w0; kick over h with the
 *      mid-step current i_m and angle phi_m, one implicit equation in w1 solved in closed form:
 *        J (w1 - w0) = h [ n Kt i_m - Mspring(phi_m) - Kv (w0 + w1)/2 - Mcoul + Mstop(phi_m, w1) ],
 *        Mcoul in g Sign(w1)   (Sign set-valued at 0);
 *      drift phi1 = phi_m + (h/2) w1. Viscous friction is implicit midpoint (A-stable), the
 *      contact damping is implicit (unconditionally stable, however deep the penetration), and
 *      the Coulomb term is a set-valued (Moreau) law: the friction impulse can stop the plate
 *      within a sub-step but never reverse it, and a plate at rest stays at exactly w = 0
 *      while |net non-friction torque| <= Ms (g is taken at w0, i.e. g(0) = Ms, for that
 *      decision; while the plate slides through the whole kick g is re-evaluated at the mean
 *      velocity of the first solution). The kick equation is strictly increasing and
 *      piecewise linear in w1, so its solution is unique and found without iteration.
 *   3. Armature half-slice h/2 with the velocity held at w1.
 *   Spring, detent and contact stiffness are explicit in phi (Verlet), stable for h omega < 2;
 *   the margins are wide: omega = 1250 rad/s (detent), ~7700 rad/s (contact stiffness at
 *   0.1 rad penetration, far beyond any impact reachable at 13.5 V), 380 rad/s (electro-
 *   mechanical oscillation n K / sqrt(L J)); plant_config_check() enforces h omega <= 0.5 for
 *   each. Smooth motion is integrated to second order; sticking, friction reversal and stop
 *   impacts are resolved to one sub-step, so trajectories converge to first order overall
 *   (at the defaults, under the paper's 12 V / 5 Hz drive, the h vs h/2 difference over 1 s is
 *   5e-5 rad max, 0.004 rad/s and 0.8 mA RMS). For R = Kv = friction = 0 the map is symmetric
 *   and volume preserving: energy does not drift; it oscillates within ~(h * 380 rad/s)^2 / 4.
 *
 * H-BRIDGE. Input: signed duty in [-1, 1] and an enable flag.
 *   - enabled, averaged mode (default): u = duty * Vs;
 *   - enabled, PWM-ripple mode: sign-magnitude, centre-aligned PWM at pwm_frequency_Hz with
 *     slow decay: during the on-time |duty| / f_pwm, centred in each PWM period (period starts at
 *     t = 0), the bridge applies sign(duty) * Vs, otherwise 0 V (both low sides on). Each
 *     armature half-slice (h/2 = 10 us by default) uses the exact fraction of its time spent
 *     at +Vs, -Vs and 0, so the switching is averaged exactly per slice;
 *   - disabled: all switches off. A current flows only through the body diodes into the supply:
 *     u = -sign(i) (Vs + 2 V_diode) until i reaches 0 (the zero crossing is clamped, the diodes
 *     do not conduct backwards), then the winding is open and i stays exactly 0 unless the
 *     back-EMF exceeds Vs + 2 V_diode (the diodes then conduct, generator mode).
 *   The "bridge voltage" reported is the mean terminal voltage of the winding (for an open
 *   winding that is the back-EMF Ke n w).
 *
 * SENSOR TRANSFER FUNCTIONS (noise terms are independent zero-mean Gaussians, drawn once per
 * plant_sample() call; LSB = adc_ref_V / 2^adc_bits):
 *   current pin  V_i  = current_offset_V + current_gain_V_A * (i + n_i),      n_i ~ N(0, current_noise_A^2)
 *   track input  x    = (phi + n_phi - phi_closed) / (phi_open - phi_closed), n_phi ~ N(0, angle_noise_rad^2)
 *                       (the SAME n_phi feeds both tracks: it is the plate/wiper position noise)
 *   track 1 out  V_t1 = clamp(tps_supply_V * (tps_offset_frac + tps_span_frac * x) + n_e1, 0, tps_supply_V)
 *   track 2 out  V_t2 = clamp(tps_supply_V * (1 - tps_offset_frac - tps_span_frac * x) + n_e2, 0, tps_supply_V)
 *                       n_e1, n_e2 ~ N(0, tps_noise_V^2) independent (electrical noise per track)
 *   track pins   V_p1 = tps_divider_gain * V_t1,  V_p2 = tps_divider_gain * V_t2
 *   supply pin   V_s  = supply_divider_gain * (supply_V + n_s),               n_s ~ N(0, supply_noise_V^2)
 *   ADC          counts = min(max(floor(V_pin / LSB + 0.5), 0), 2^adc_bits - 1)
 * So with the defaults (tps1 + tps2 = 5 V, divider 0.66, ADC reference 3.3 V): 4096 counts/5 V of
 * the track sum, 410 counts at the closed stop and 3686 at the open stop on track 1, 2048
 * counts at zero current with 124.12 counts/A, 2793 counts (2792.7) at 13.5 V supply. The inverse
 * (calibration) belongs to the firmware; its defaults must match these functions.
 */
#ifndef PLANT_H
#define PLANT_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Largest time span one plant_advance() call integrates [s] (bounds the loop). */
#define PLANT_ADVANCE_MAX_S 1.0
/** Smallest allowed number of integration sub-steps per millisecond (50 kHz). */
#define PLANT_SUBSTEPS_PER_MS_MIN 50
/** Largest allowed number of integration sub-steps per millisecond (5 MHz). */
#define PLANT_SUBSTEPS_PER_MS_MAX 5000
/** plant_set_state() accepts angles up to this far beyond either hard stop [rad]. */
#define PLANT_STATE_PENETRATION_MAX_RAD 0.1
/** plant_set_state() accepts |velocity| up to this [rad/s]. */
#define PLANT_STATE_VELOCITY_MAX_RAD_S 1000.0
/** plant_set_state() accepts |current| up to this [A]. */
#define PLANT_STATE_CURRENT_MAX_A 1000.0
/** Bound on h * omega for every explicit stiffness of the scheme (limit of stability is 2). */
#define PLANT_STABILITY_H_OMEGA_MAX 0.5

/** Every parameter of the plant. Units are in the field names; defaults from plant_config_default(). */
typedef struct {
    /* --- motor and mechanics, plate side (paper Table 1) --- */
    double R_ohm;           /**< armature resistance [ohm], default 4.3; >= 0 (0 only for lossless checks) */
    double L_H;             /**< armature inductance [H], default 0.002; > 0 */
    double Ke_V_s_rad;      /**< back-EMF constant, motor side [V s/rad], default 0.017; >= 0 */
    double Kt_Nm_A;         /**< torque constant, motor side [N m/A], default 0.017; >= 0 */
    double J_kg_m2;         /**< inertia at the plate shaft [kg m^2], default 0.0016; > 0 */
    double n_gear;          /**< gear ratio motor:plate [-], default 40; > 0 */
    double Mc_Nm;           /**< Coulomb (sliding) friction level [N m], default 0.2; >= 0 */
    double Ms_Nm;           /**< stiction (breakaway) torque [N m], default 0.3; >= Mc_Nm */
    double ws_rad_s;        /**< Stribeck velocity [rad/s], default 1; > 0 */
    double Kv_Nm_s_rad;     /**< viscous friction [N m s/rad], default 0.01; >= 0 */
    double M0_Nm;           /**< spring preload at limp-home [N m], default 0.25; >= 0 */
    double c_Nm_rad;        /**< return-spring stiffness [N m/rad], default 0.059; >= 0 */
    double limp_home_width_rad; /**< half-width d_lh of the limp-home detent over which the preload
                                     ramps linearly from -M0 to +M0 [rad], default 1e-4; > 0 and
                                     h sqrt((M0 / d_lh + c) / J) <= PLANT_STABILITY_H_OMEGA_MAX */
    /* --- hard stops (not in the paper) --- */
    double phi_closed_rad;  /**< closed hard stop [rad], default -0.10 (-5.7 deg); < 0 */
    double phi_open_rad;    /**< open hard stop [rad], default -0.10 + 84 deg = 1.3660766; > 0 */
    double stop_k_Nm_rad;   /**< Hunt-Crossley stiffness k [N m / rad^e], default 2.0e5 (secant
                                 stiffness k p^(e-1) = 1e4 N m/rad at p = 2.5 mrad, tangent 1.5e4);
                                 >= 0 (0 removes the stops, for tests) */
    double stop_exponent;   /**< Hunt-Crossley exponent e [-], default 1.5 (Hertzian); 1..3 */
    double stop_lambda_Nm_s_rad; /**< Hunt-Crossley damping lambda [N m s / rad^(e+1)], default
                                      2.865e4 = 0.14325 s/rad * k: coefficient of restitution
                                      0.50 at a 10 rad/s impact (0.91 at 1, 0.84 at 2, 0.67 at 5,
                                      0.39 at 15, 0.32 at 20 rad/s; it falls with speed as in real
                                      contacts; independent of k, e, J: alpha v_in = x solves
                                      x - ln(1+x) = -e x - ln(1 - e x)); >= 0 */
    /* --- integration --- */
    int substeps_per_ms;    /**< integration sub-steps per millisecond [-], default 50 (h = 20 us);
                                 PLANT_SUBSTEPS_PER_MS_MIN..PLANT_SUBSTEPS_PER_MS_MAX */
    /* --- H-bridge --- */
    double supply_V;        /**< bridge supply voltage Vs [V], default 13.5 (a 12 V amplitude fits);
                                 > 0, <= 100 */
    double diode_drop_V;    /**< forward drop of one body diode [V], default 0.7; 0..5 */
    int pwm_ripple;         /**< 0 (default): bridge voltage averaged (duty * Vs); 1: resolve the
                                 PWM switching per sub-step (exact on-time fractions) */
    double pwm_frequency_Hz; /**< PWM frequency, centre-aligned [Hz], default 20000; 100..1e6 */
    /* --- current-sense amplifier --- */
    double current_offset_V; /**< amplifier output at zero current [V], default 1.65; finite */
    double current_gain_V_A; /**< amplifier gain [V/A], default 0.1; != 0, |gain| <= 100 */
    double current_noise_A;  /**< standard deviation of the current noise, referred to the winding
                                  current [A], default 0.01; >= 0 */
    /* --- position sensor (two ratiometric tracks of opposite slope) --- */
    double tps_supply_V;     /**< sensor supply (ratiometric reference) [V], default 5.0; > 0 */
    double tps_offset_frac;  /**< track 1 output at the angle tps_ref_closed_rad, fraction of
                                  tps_supply_V [-], default 0.10; >= 0, offset + span <= 1 */
    double tps_span_frac;    /**< track 1 rise from tps_ref_closed_rad to tps_ref_open_rad, fraction
                                  of tps_supply_V [-], default 0.80; > 0 */
    double tps_ref_closed_rad; /**< plate angle at which track 1 reads tps_offset_frac [rad], default
                                    -0.10 (the default closed stop). The sensor's transfer is tied to
                                    the plate angle, not to where the stops are: a unit whose stop
                                    sits elsewhere is seen there by the tracks */
    double tps_ref_open_rad; /**< plate angle at which track 1 reads offset + span [rad], default the
                                  default open stop; > tps_ref_closed_rad */
    double angle_noise_rad;  /**< standard deviation of the plate-angle noise seen by both tracks
                                  (one realisation shared) [rad], default 1e-4; >= 0 */
    double tps_noise_V;      /**< standard deviation of the independent electrical noise added to
                                  each track's output [V], default 0; >= 0 */
    double tps_divider_gain; /**< divider from each track to its ADC pin [-], default 0.66; (0, 1] */
    /* --- supply measurement --- */
    double supply_divider_gain; /**< divider from the supply to its ADC pin [-], default 1/6; (0, 1] */
    double supply_noise_V;      /**< standard deviation of the supply-measurement noise, referred to
                                     the supply [V], default 0.01; >= 0 */
    /* --- ADC --- */
    double adc_ref_V;       /**< ADC reference voltage [V], default 3.3; > 0 */
    int adc_bits;           /**< ADC resolution [bits], default 12; 8..16 */
} plant_config_t;

/** True mechanical and electrical state. */
typedef struct {
    double current_A;      /**< armature current i [A] */
    double velocity_rad_s; /**< plate angular velocity w [rad/s], positive = opening */
    double angle_rad;      /**< plate angle phi [rad], 0 at limp-home, positive = opening */
} plant_state_t;

/** One set of ADC conversions, all channels taken at the same instant. */
typedef struct {
    double t_s;              /**< plant time of the conversion [s] (exact: sub-step count * h + remainder) */
    uint16_t current_counts; /**< current-sense channel [counts] */
    uint16_t tps1_counts;    /**< position track 1 (rising with angle) [counts] */
    uint16_t tps2_counts;    /**< position track 2 (falling with angle) [counts] */
    uint16_t supply_counts;  /**< supply-divider channel [counts] */
    /* Host diagnostics only (the firmware sees nothing but counts): analog pin voltages of
       this conversion, noise included, before quantisation. */
    double current_pin_V;    /**< voltage at the current ADC pin [V] */
    double tps1_pin_V;       /**< voltage at the track-1 ADC pin [V] */
    double tps2_pin_V;       /**< voltage at the track-2 ADC pin [V] */
    double supply_pin_V;     /**< voltage at the supply ADC pin [V] */
} plant_adc_t;

/**
 * Faults acting on the plant and its analogue front end (plant_set_faults(); the spec parser
 * and time schedule of host_sim are in plant_fault.h). plant_faults_none() is the healthy
 * plant; every field's healthy value is given. The physical faults change the parameters the
 * integration uses (plant_t::cfg, derived from the nominal plant_t::cfg_nominal); the sensor
 * faults change the pin voltages of plant_sample() before quantisation.
 */
typedef struct {
    double friction_factor;   /**< Mc and Ms x this [-]; healthy 1; 0.1..100 */
    double jam_Nm;            /**< jam: a holding torque added to the friction level [N m], the
                                   plate stopped where it is when it starts (velocity set to 0);
                                   healthy 0; 0..1e3 */
    double spring_factor;     /**< M0 and c x this [-]; healthy 1; 0..10 */
    double resistance_factor; /**< R x this [-]; healthy 1; 0.1..100 */
    double short_fraction;    /**< part of the turns shorted [-]: R, Kt and Ke x (1 - s), L x (1 - s)^2
                                   (the circulating current in the shorted turns is not modelled);
                                   healthy 0; 0..0.95 */
    int winding_open;         /**< 1: the winding is open: i = 0 whatever the bridge does, the
                                   terminals float at the back-EMF; healthy 0 */
    int bridge_lost;          /**< +1: the bridge cannot drive positive duty (it applies 0 V, both
                                   low sides on, when positive duty is commanded); -1: negative;
                                   healthy 0 */
    double supply_drop_V;     /**< supply sag: the bridge supply (and what the supply pin measures)
                                   is supply_V - this [V]; healthy 0; 0 <= drop < supply_V */
    double current_offset_A;  /**< current-sense offset referred to the winding current [A]; healthy 0; |.| <= 100 */
    double current_gain_err;  /**< current-sense gain error [-] (gain x (1 + this)); healthy 0; > -1, <= 10 */
    double tps_offset_V[2];   /**< offset added to track 1 / track 2's output [V]; healthy 0; |.| <= tps_supply_V */
    double tps_gain_err[2];   /**< track output x (1 + this) [-]; healthy 0; > -1, <= 10 */
    int tps_stuck[2];         /**< 1: the track's output stays at its value of the first
                                   plant_sample() after the fault started; healthy 0 */
    double tps_dropout_prob[2]; /**< intermittent track: probability per plant_sample() that the
                                     wiper loses contact and the output reads 0 V [-]; healthy 0;
                                     0..1 (drawn from a generator of its own: the noise stream of
                                     the plant is the same as in a healthy run) */
} plant_faults_t;

/**
 * The plant instance. Complete here so it can be allocated statically; treat every field as
 * private and use the functions below.
 */
typedef struct {
    plant_config_t cfg;     /**< parameters in force: cfg_nominal with the faults applied */
    plant_config_t cfg_nominal; /**< validated copy of the configuration (the healthy unit) */
    plant_faults_t faults;  /**< faults in force (plant_set_faults()) */
    double tps_stuck_V[2];  /**< output of a stuck track [V] (valid when tps_stuck_held) */
    int tps_stuck_held[2];  /**< 1: tps_stuck_V holds the stuck output */
    uint64_t fault_rng_s[4]; /**< xoshiro256** state of the intermittent-track draws */
    double h_s;             /**< integration sub-step [s] */
    double a_half;          /**< exp(-R h / (2 L)): armature decay over half a sub-step [-] */
    double b_half_A_V;      /**< armature ZOH gain over half a sub-step [A/V] */
    double current_A;       /**< state: armature current [A] */
    double velocity_rad_s;  /**< state: plate velocity [rad/s] */
    double angle_rad;       /**< state: plate angle [rad] */
    double duty;            /**< commanded duty [-], -1..1 */
    int enable;             /**< bridge enabled (1) or all switches off (0) */
    uint64_t substeps_done; /**< completed full sub-steps on the time grid [-] */
    double frac_s;          /**< time past the last grid point, 0 <= frac_s < h [s] */
    double mean_bridge_V;   /**< mean terminal voltage over the last plant_advance() [V] */
    uint64_t rng_s[4];      /**< xoshiro256** state */
    double gauss_spare;     /**< second Box-Muller normal, valid when gauss_has_spare */
    int gauss_has_spare;    /**< 1 when gauss_spare holds an unused normal */
} plant_t;

/**
 * Fill *cfg with the defaults documented at each field of plant_config_t (paper Table 1,
 * 13.5 V supply, 50 sub-steps per ms, averaged bridge). Does nothing when cfg is NULL.
 */
void plant_config_default(plant_config_t *cfg);

/**
 * Check every field of *cfg, in declaration order, then the stability conditions of the
 * integration scheme (h omega <= PLANT_STABILITY_H_OMEGA_MAX for the limp-home detent, the
 * stop contact at PLANT_STATE_PENETRATION_MAX_RAD and the electromechanical mode, reported as
 * "limp_home_width_rad", "stop_k_Nm_rad" and "substeps_per_ms").
 * @param cfg     configuration to check
 * @param status  optional (may be NULL): receives TV_OK, TV_ERR_NULL (cfg NULL),
 *                TV_ERR_NONFINITE (a field is NaN/Inf) or TV_ERR_CONFIG (out of range)
 * @return NULL when the configuration is valid, else the name of the first bad field as a
 *         static string (for example "L_H"; "cfg" when cfg is NULL).
 */
const char *plant_config_check(const plant_config_t *cfg, int *status);

/**
 * Initialise a plant: copy and validate the configuration, seed the noise generator, state
 * i = 0, w = 0, phi = 0 (at rest at limp-home), bridge disabled with duty 0, time 0.
 * @param plant  instance to initialise
 * @param cfg    configuration (copied)
 * @param seed   noise seed: the same seed reproduces a run exactly, different seeds differ
 * @return TV_OK; TV_ERR_NULL if plant or cfg is NULL; TV_ERR_NONFINITE or TV_ERR_CONFIG if a
 *         field is invalid (plant_config_check() names it). On error *plant is not written.
 */
int plant_init(plant_t *plant, const plant_config_t *cfg, uint64_t seed);

/**
 * Command the H-bridge; takes effect for all following integration.
 * @param plant   the plant
 * @param duty    signed duty [-], -1..1 (bridge voltage duty * supply_V when enabled)
 * @param enable  nonzero: bridge drives; 0: all switches off (diode freewheel, then open)
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE if duty is NaN/Inf; TV_ERR_RANGE if |duty| > 1.
 *         On error nothing is changed.
 */
int plant_set_bridge(plant_t *plant, double duty, int enable);

/**
 * Integrate the plant forward by dt_s. Time is kept on a fixed grid of sub-steps h: a call
 * first completes a partially done sub-step, then takes whole sub-steps, then one partial
 * sub-step for any remainder (exact ZOH over the shorter length). Remainders below 1e-9 h are
 * treated as rounding and dropped, so dt_s = 1e-3 is exactly 1 ms worth of whole sub-steps.
 * @param plant  the plant
 * @param dt_s   time to advance [s], 0..PLANT_ADVANCE_MAX_S
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE if dt_s is NaN/Inf; TV_ERR_RANGE if dt_s is
 *         negative or above PLANT_ADVANCE_MAX_S (nothing changed); TV_ERR_NUMERIC if the state
 *         became non-finite (state and time restored to the values before the call).
 */
int plant_advance(plant_t *plant, double dt_s);

/**
 * Convert all ADC channels at the current plant time (one set of noise draws per call; the
 * generator advances by the same amount whatever the sigmas, so runs stay aligned).
 * @param plant  the plant (its noise generator advances)
 * @param out    conversion results and sample time
 * @return TV_OK; TV_ERR_NULL.
 */
int plant_sample(plant_t *plant, plant_adc_t *out);

/** Fill *f with the healthy values of plant_faults_t (no fault). Does nothing when f is NULL. */
void plant_faults_none(plant_faults_t *f);

/**
 * Put faults into force from now on (the next plant_advance() and plant_sample()). The
 * parameters in force are recomputed from the nominal configuration each call, so a call with
 * plant_faults_none() restores the healthy unit. A jam that starts (jam_Nm goes from 0 to
 * > 0) stops the plate where it is; a stuck track starts holding at the next conversion.
 * @param plant   the plant
 * @param faults  faults (copied)
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE if a field is NaN/Inf; TV_ERR_RANGE if a field
 *         is outside its documented range; TV_ERR_CONFIG if the faulty parameters fail
 *         plant_config_check() (a stability bound). On error nothing is changed.
 */
int plant_set_faults(plant_t *plant, const plant_faults_t *faults);

/**
 * True state at the current plant time.
 * @return TV_OK; TV_ERR_NULL.
 */
int plant_truth(const plant_t *plant, plant_state_t *out);

/**
 * True bridge (winding terminal) voltage: its mean over the last plant_advance() call with
 * dt_s > 0 (0 before the first). This is the exact input u the continuous model received.
 * @return TV_OK; TV_ERR_NULL.
 */
int plant_bridge_voltage(const plant_t *plant, double *mean_V);

/**
 * Current plant time [s]: completed sub-steps * h + remainder. 0 when plant is NULL.
 */
double plant_time_s(const plant_t *plant);

/**
 * Overwrite the true state (scenarios, tests). Time, bridge command and noise stream are kept.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE if a component is NaN/Inf; TV_ERR_RANGE if
 *         |current| > PLANT_STATE_CURRENT_MAX_A, |velocity| > PLANT_STATE_VELOCITY_MAX_RAD_S or
 *         the angle is more than PLANT_STATE_PENETRATION_MAX_RAD beyond a stop. On error
 *         nothing is changed.
 */
int plant_set_state(plant_t *plant, const plant_state_t *state);

#ifdef __cplusplus
}
#endif

#endif /* PLANT_H */
