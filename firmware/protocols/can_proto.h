/**
 * @file can_proto.h
 * @brief The controller's CAN protocol: telemetry out, commands in. Platform-neutral C99: no
 *        heap, no OS or HAL calls (it only uses the frame type of hal.h), so the Linux
 *        controller (SocketCAN), the Cortex-M4F ECU (bxCAN) and the host simulation share it.
 *        tools/throttle.dbc describes the same frames for bench tools; tests/test_can_dbc.py
 *        proves the two agree signal by signal.
 *
 * FRAMES. Classic CAN, 11-bit identifiers, DLC 8 for every frame. Signals are little-endian
 * (Intel) unsigned or two's-complement integers: physical = raw * scale + offset (offset is 0
 * except for StopClosed, StopOpen and FreezeAngle, whose ranges do not start at 0). Bit positions count from bit 0 = LSB of data[0] (DBC "@1" numbering).
 *
 *   id     name                 dir      default period
 *   0x100  TV_CMD_CONTROL       bench->TV  every 10..50 ms (the heartbeat; see TIMEOUT)
 *   0x101  TV_CMD_EXCITATION    bench->TV  when the waveform changes (repeating it is fine)
 *   0x180  TV_EST_STATE         TV->bench  10 ms
 *   0x181  TV_EST_SIGMA         TV->bench  10 ms
 *   0x182  TV_EST_INNOV         TV->bench  10 ms
 *   0x183  TV_STATUS            TV->bench  10 ms
 *   0x184  TV_MEAS              TV->bench  10 ms
 *   0x185  TV_LOOP              TV->bench  100 ms
 *   0x186  TV_CMD_STATS         TV->bench  100 ms
 *   0x187  TV_EKF_STATS         TV->bench  100 ms
 *   0x188  TV_TIME              TV->bench  10 ms, always in the same tick as TV_EST_STATE
 *   0x189  TV_HEALTH_1          TV->bench  100 ms (condition monitoring: winding, friction)
 *   0x18A  TV_HEALTH_2          TV->bench  100 ms (condition monitoring: spring preload, stops)
 *   0x18B  TV_DIAG              TV->bench  100 ms (diagnostic codes: count, last confirmed, action)
 *   0x18C  TV_DIAG_FREEZE       TV->bench  100 ms (freeze frame of the last confirmed code)
 *   0x18D  TV_HEALTH_3          TV->bench  100 ms (condition monitoring: position-track agreement)
 *   0x18E  TV_HEALTH_4          TV->bench  100 ms (condition monitoring: the voltage equation's fit)
 *   0x18F  TV_HEALTH_5          TV->bench  1000 ms (condition monitoring: the fit's per-unit baseline)
 *
 * Every frame starts with the same protection header (AUTOSAR E2E profile 1 layout):
 *   bits 0..7   CRC      CRC-8 SAE J1850: polynomial 0x1D, initial value 0xFF, final XOR 0xFF,
 *                        no reflection (check value of "123456789" = 0x4B), computed over the
 *                        data ID (the 11-bit frame id as two bytes, low byte first, then high
 *                        byte) followed by data[1..7]. Including the id means a payload that
 *                        is valid for one frame is rejected under any other id.
 *   bits 8..11  Counter  4-bit rolling counter, +1 (mod 16) per frame sent with that id.
 *
 * Signal layout (start bit | length, s = signed, scale, unit, [valid or representable range]):
 *
 *   TV_CMD_CONTROL 0x100
 *     Mode          12|4        1                [0, 4]   app_mode_t: 0 off, 1 sine, 2 steps, 3 chirp, 4 position
 *                                                         (APP_MODE_EXTERNAL, replay only, cannot be commanded)
 *     TargetAngle   16|16 s     0.0001 rad       [-0.5, 2.0]
 *     DutyLimit     32|8        0.005            [0.005, 1.0]
 *     FaultClear    40|1        1                [0, 1]   clears latched faults on its 0 -> 1 edge
 *     WindingTempValid 41|1     1                [0, 1]   1: WindingTemp holds the winding's temperature
 *                                                         (a sensor, or the engine controller's estimate);
 *                                                         0 (as senders of reserved bits send): unknown
 *     WindingTemp   48|8        1 degC, offset -40  [-40, 180]  app_set_winding_temp(): the resistance
 *                                                         check and TV_HEALTH_3 ResistanceRef20 refer the
 *                                                         winding's resistance to 20 degC with it; held
 *                                                         until the next TV_CMD_CONTROL
 *     bits 42..47 and 56..63 reserved (send 0, ignored)
 *   TV_CMD_EXCITATION 0x101
 *     Amplitude     16|8        0.1 V            [0, 24]
 *     Frequency     24|16       0.01 Hz          [0, 200]  sine / steps frequency, chirp start
 *     ChirpEndFreq  40|16       0.01 Hz          [0, 200]
 *     ChirpPeriod   56|8        0.1 s            [0.1, 25.5]
 *     bits 12..15 reserved
 *   TV_EST_STATE 0x180 (estimate after this step's correction)
 *     EstCurrent    16|16 s     0.001 A          [-32.768, 32.767]
 *     EstVelocity   32|16 s     0.01 rad/s       [-327.68, 327.67]
 *     EstAngle      48|16 s     0.0001 rad       [-3.2768, 3.2767]
 *   TV_EST_SIGMA 0x181 (standard deviations sqrt(P_ii), not variances)
 *     SigmaCurrent  16|16       0.0001 A         [0, 6.5535]
 *     SigmaVelocity 32|16       0.001 rad/s      [0, 65.535]
 *     SigmaAngle    48|16       1e-06 rad        [0, 0.065535]
 *   TV_EST_INNOV 0x182 (innovations z - x_pred of this step; 0 for unused channels)
 *     InnovCurrent  16|16 s     0.0001 A         [-3.2768, 3.2767]
 *     InnovVelocity 32|16 s     0.001 rad/s      [-32.768, 32.767]
 *     InnovAngle    48|16 s     1e-06 rad        [-0.032768, 0.032767]
 *   TV_STATUS 0x183
 *     Mode          12|4        1                effective app_mode_t (OFF while the command link waits
 *                                                or has timed out)
 *     Faults        16|12       1                latched APP_FAULT_* mask of app.h (bits 0..11)
 *     BridgeEnable  28|1        1                bridge enable output of this step
 *     EkfOk         29|1        1                this step's correction succeeded
 *     CmdActive     30|1        1                a commander is in control (link ACTIVE)
 *     CmdTimeout    31|1        1                command timeout latched (outputs OFF until FaultClear)
 *     ChannelsUsed  32|2        1                measurement channels used by the correction (NIS dof)
 *     HalError      34|1        1                the platform's I/O failed this step
 *     Nis           36|12       0.01             [0, 40.95] NIS of this step (saturates: beyond 40.95 is
 *                                                an outlier for 1..3 dof; TV_EKF_STATS has the window mean)
 *     Duty          48|16 s     0.0001           [-1, 1] PWM duty of this step
 *   TV_MEAS 0x184 (measurements in units, after calibration)
 *     MeasCurrent   16|16 s     0.001 A          [-32.768, 32.767]
 *     MeasAngle     32|16 s     0.0001 rad       [-3.2768, 3.2767] mean of the two tracks
 *     SupplyVoltage 48|16       0.001 V          [0, 65.535]
 *   TV_LOOP 0x185 (platform loop statistics since start)
 *     Overruns      16|16       1                periods missed (saturates at 65535)
 *     LatencyMax    32|16       1 us             worst wake-up latency (saturates)
 *     ExecMax       48|16       1 us             worst execution time of one tick (saturates)
 *   TV_CMD_STATS 0x186 (command reception counters since start, all modulo 2^length)
 *     Timeouts      12|4, Accepted 16|8, CrcErrors 24|8, CounterErrors 32|8 (repeated + out of
 *     sequence), DlcErrors 40|8, RangeErrors 48|8, UnknownIds 56|8
 *   TV_EKF_STATS 0x187 (filter statistics over the window since this frame was last sent)
 *     NisMean       16|16       0.001            [0, 65.535] mean NIS of the window's corrections
 *     Corrections   32|16       1                successful corrections in the window
 *     Rejected      48|16       1                filter calls rejected since start, modulo 65536
 *   TV_TIME 0x188 (sent in the same tick as TV_EST_STATE, right after the other frames of that
 *   tick, so a receiver pairs it with the TV_EST_STATE before it)
 *     SampleTime    16|32       1 us             [0, 4294967295] when the inputs of this tick's step
 *                                                were read, platform clock since start (wraps after
 *                                                71.6 min); bits 12..15 and 48..63 reserved
 *   TV_HEALTH_1 0x189 (condition monitoring, the estimator's adapted parameters of this step;
 *   resolution = scale; bits 12..15 reserved; a value beyond its field saturates)
 *     ResistanceEst     16|14    0.001 ohm        [0, 16.383]  winding resistance R + dR (app_output_t::r_est_ohm)
 *     ResistanceSigma   30|10    0.001 ohm        [0, 1.023]   its standard deviation (saturates: the
 *                                                              resistance check needs sigma <= 0.05 R anyway)
 *     FrictionRel       40|12    0.0005           [0, 2.0475]  friction level relative to the model, 1 + f
 *                                                              (the filter holds |f| < 1)
 *     FrictionRelSigma  52|12    0.0002           [0, 0.819]   its standard deviation
 *   TV_HEALTH_2 0x18A (bits 12..15 and 63 reserved)
 *     PreloadRel        16|12    0.0005           [0, 2.0475]  spring preload relative to the model, 1 + m
 *     PreloadRelSigma   28|10    0.0002           [0, 0.2046]  its standard deviation
 *     StopClosed        38|12    0.0001 rad, offset -0.4  [-0.4, 0.0095]  closed-stop contact onset in use
 *                                                              (stop learning accepts -0.30..-0.02)
 *     StopOpen          50|13    0.0001 rad, offset 1.0   [1.0, 1.8191]   open-stop contact onset in use
 *                                                              (stop learning accepts 1.10..1.70)
 *   TV_HEALTH_3 0x18D (condition monitoring, the position tracks' agreement over the last second,
 *   app_output_t::tps_diff_rad, and the winding's resistance at 20 degC; bits 12..15 and 62..63
 *   reserved; a value beyond its field saturates)
 *     TrackDiff         16|16s   1e-5 rad         [-0.32768, 0.32767]  mean of phi1 - phi2 (calibrated
 *                                                              tracks; the plausibility limit is 0.035)
 *     TrackDiffSd       32|16    1e-6 rad         [0, 0.065535]  its standard deviation (a healthy pair:
 *                                                              about the two tracks' quantisation)
 *     ResistanceRef20   48|14    0.001 ohm        [0, 16.383]  R + dR referred to 20 degC with the
 *                                                              winding's temperature (app_output_t::r_20_ohm):
 *                                                              the trend of a winding's wear whatever
 *                                                              its temperature; 0 while it is unknown
 *   TV_HEALTH_4 0x18E (condition monitoring, the voltage equation's fit of the winding,
 *   firmware/estimator/volt_fit.h: its last window; bits 12..15 reserved; a value beyond its
 *   field saturates)
 *     FitResistance     16|14    0.001 ohm        [0, 16.383]  the fit's winding resistance R
 *                                                              (app_output_t::fit_r_ohm): within 1 - 2 %
 *                                                              where ResistanceEst (R + dR) can be 7 - 12 %
 *                                                              off; 0 until the fit's first window
 *     FitResistanceSigma 30|10   0.001 ohm        [0, 1.023]   its standard deviation
 *     FitBackEmf        40|12    0.0005 V s/rad   [0, 2.0475]  the fit's back-EMF constant at the plate,
 *                                                              n Ke (app_output_t::fit_nke_V_s); 0 until
 *                                                              the first window
 *     FitCurrentOffset  52|12s   0.0001 A         [-0.2048, 0.2047]  the current sensor's offset the fit
 *                                                              reads (app_output_t::fit_i_off_A, P1A04's
 *                                                              reading); 0 until a window gave one
 *   TV_HEALTH_5 0x18F (condition monitoring, every second: the voltage equation fit's per-unit
 *   baseline, README "A per-unit baseline of the fit"; bits 12..15 and 60..63 reserved; a value
 *   beyond its field saturates). A tester reads a learned baseline off a unit here, to store it
 *   or compare it with the one stored (stop_learn.h sl_nvm_t)
 *     FitBaseResistance20 16|14  0.001 ohm        [0, 16.383]  the baseline's R at 20 degC
 *                                                              (app_output_t::fit_base_r_ohm); 0 while
 *                                                              there is none
 *     FitBaseBackEmf    30|12    0.0005 V s/rad   [0, 2.0475]  its n Ke at the plate
 *                                                              (app_output_t::fit_base_nke_V_s); 0 while none
 *     FitBaseState      42|2     1                0 none and not learning (diag.fit_base_windows = 0),
 *                                                 1 learning (no baseline yet, fit_base_windows > 0),
 *                                                 2 in force (given or learned)
 *                                                 (app_output_t::fit_base_state)
 *     FitBaseWindows    44|16    1                [0, 65535]  the fit's windows summed toward the
 *                                                              learning under way (app_t::fit_base_n,
 *                                                              app_output_t::fit_base_windows; saturates);
 *                                                              0 when none is
 *   TV_DIAG 0x18B (diagnostic codes, firmware/diag/diag.h; code index = diag_dtc_t, 15 = none)
 *     DtcCount          12|4     1                [0, 15]  codes confirmed now
 *     LastDtc           16|4     1                [0, 15]  the code confirmed most recently since start (15: none)
 *     LastDtcStatus     20|2     1                0 none, 1 confirmed (active), 2 history (healed or cleared)
 *     Action            22|2     1                diag_action_t in force: 0 none, 1 limited authority, 2 safe state
 *     LastDtcConfirmations 24|8  1                [0, 255] times LastDtc was confirmed since start (saturates)
 *     ConfirmedMask     32|16    1                bit k: code k confirmed now
 *     LastDtcTime       48|16    0.1 s            [0, 6553.5] time of LastDtc's last confirmation since
 *                                                 the application's first step (saturates)
 *   TV_DIAG_FREEZE 0x18C (the freeze frame of LastDtc's last confirmation: the estimate before the
 *   confirming sample, the supply and the duty of the period that ended)
 *     FreezeDtc         12|4     1                [0, 15]  the code the frame belongs to (15: none, all 0)
 *     FreezeAngle       16|12    0.001 rad, offset -0.5  [-0.5, 3.595]
 *     FreezeVelocity    28|12 s  0.05 rad/s       [-102.4, 102.35]
 *     FreezeDuty        40|8 s   0.01             [-1.28, 1.27]
 *     FreezeSupply      48|8     0.1 V            [0, 25.5]
 *     FreezeCurrent     56|8 s   0.1 A            [-12.8, 12.7]  estimated winding current
 *
 * Telemetry values beyond their representable range saturate to the nearest end (a NaN is sent
 * as 0). Commands are never clamped: a value outside its valid range rejects the whole frame.
 *
 * RECEPTION (can_proto_node_receive), checked in this order, first failure wins:
 *   id not a command id (or an extended id)  -> ignored, counted "unknown"
 *   DLC != 8                                 -> rejected, "dlc"
 *   CRC mismatch                             -> rejected, "crc" (counter state unchanged)
 *   counter delta d = (rx - last) mod 16, per id:
 *     first frame of that id                 -> accepted (synchronises)
 *     d == 0                                 -> rejected, "repeated"
 *     d > max_counter_delta                  -> rejected, "sequence" (stale or lost frames);
 *                                               the reference resynchronises to this counter so
 *                                               the next in-sequence frame is accepted
 *   a signal outside its valid range         -> rejected, "range" (the counter is consumed)
 *   otherwise                                -> accepted, applied to the application
 *
 * TIMEOUT (silence is the fail-safe signal). With cmd_timeout_ms > 0 the node starts in link
 * state WAITING with the application forced to APP_MODE_OFF (PWM 0, bridge disabled) until the
 * first valid TV_CMD_CONTROL. Each accepted TV_CMD_CONTROL feeds the watchdog; when none has
 * been accepted for longer than cmd_timeout_ms the link latches TIMEOUT: the application is
 * forced to APP_MODE_OFF and stays there, whatever later commands say, until an accepted
 * TV_CMD_CONTROL carries a 0 -> 1 edge of FaultClear (which also clears the application's
 * latched faults). With cmd_timeout_ms == 0 (standalone bench use) there is no watchdog and the
 * configured mode runs from start; commands are still accepted.
 *
 * Typical use on a platform (firmware/linux_rt/main.c does exactly this), once per 1 ms tick:
 *   can_proto_node_init(&node, &cfg, &app);                    once, after app_init()
 *   rc = app_tick(&app, &out);                                  every tick
 *   while (n++ < CAN_PROTO_RX_MAX_PER_TICK && hal_can_receive(&f) == 1)
 *       (void)can_proto_node_receive(&node, &app, &f, t_us);
 *   can_proto_node_update(&node, &app, stepped ? &out : NULL, t_us);
 *   loop = {overruns, worst latency, worst tick, time the ADC was read};
 *   k = can_proto_node_transmit(&node, &app, &out, &loop, rc != TV_OK, t_us, frames);
 *   for (i = 0; i < k; ++i) (void)hal_can_send(&frames[i]);
 * t_us is the platform's monotonic clock [us] (hal_time_us()). Each telemetry frame describes
 * the step of the tick it is sent in; frames of different ids go out in different ticks
 * (staggered), except TV_TIME, which pairs with the TV_EST_STATE of its tick.
 */
#ifndef CAN_PROTO_H
#define CAN_PROTO_H

#include <stddef.h>
#include <stdint.h>

#include "app.h"
#include "hal.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Frame identifiers (11 bit). */
#define CAN_PROTO_ID_CMD_CONTROL 0x100u
#define CAN_PROTO_ID_CMD_EXCITATION 0x101u
#define CAN_PROTO_ID_EST_STATE 0x180u
#define CAN_PROTO_ID_EST_SIGMA 0x181u
#define CAN_PROTO_ID_EST_INNOV 0x182u
#define CAN_PROTO_ID_STATUS 0x183u
#define CAN_PROTO_ID_MEAS 0x184u
#define CAN_PROTO_ID_LOOP 0x185u
#define CAN_PROTO_ID_CMD_STATS 0x186u
#define CAN_PROTO_ID_EKF_STATS 0x187u
#define CAN_PROTO_ID_TIME 0x188u
#define CAN_PROTO_ID_HEALTH_1 0x189u
#define CAN_PROTO_ID_HEALTH_2 0x18Au
#define CAN_PROTO_ID_DIAG 0x18Bu
#define CAN_PROTO_ID_DIAG_FREEZE 0x18Cu
#define CAN_PROTO_ID_HEALTH_3 0x18Du
#define CAN_PROTO_ID_HEALTH_4 0x18Eu
#define CAN_PROTO_ID_HEALTH_5 0x18Fu
/** Platform frame of the Cortex-M4F ECU: CPU load of the control step (DWT cycles). Listed in
 *  the frame table and the DBC, but not scheduled by the node: the ECU sends it itself every
 *  CAN_PROTO_ECU_CPU_PERIOD_MS with can_proto_encode_ecu_cpu(). */
#define CAN_PROTO_ID_ECU_CPU 0x1A0u
/** Period of TV_ECU_CPU [ms]. */
#define CAN_PROTO_ECU_CPU_PERIOD_MS 100u

/** Data length of every frame [bytes]. */
#define CAN_PROTO_DLC 8u
/** CRC-8 SAE J1850 parameters. */
#define CAN_PROTO_CRC8_POLY 0x1Du
#define CAN_PROTO_CRC8_INIT 0xFFu
#define CAN_PROTO_CRC8_XOROUT 0xFFu

/** Number of command frames and of telemetry frames. */
#define CAN_PROTO_N_CMD 2u
#define CAN_PROTO_N_TX 16u
/** Platform frames in the table after the telemetry (TV_ECU_CPU). */
#define CAN_PROTO_N_PLATFORM 1u
/** Most signals in one frame, CRC and counter included. */
#define CAN_PROTO_MAX_SIGNALS 12u
/** Code index sent in LastDtc / FreezeDtc when there is none (diag_dtc_t values are below it). */
#define CAN_PROTO_DTC_NONE 15u
/** Frames a platform should take from its receive queue per tick (bounds the tick's work). */
#define CAN_PROTO_RX_MAX_PER_TICK 16u
/** Largest command timeout accepted [ms]. */
#define CAN_PROTO_TIMEOUT_MAX_MS 60000u

/** Telemetry frame indices (order of can_proto_config_t::period_ms and of transmission). */
enum {
    CAN_PROTO_TX_EST_STATE = 0,
    CAN_PROTO_TX_EST_SIGMA = 1,
    CAN_PROTO_TX_EST_INNOV = 2,
    CAN_PROTO_TX_STATUS = 3,
    CAN_PROTO_TX_MEAS = 4,
    CAN_PROTO_TX_LOOP = 5,
    CAN_PROTO_TX_CMD_STATS = 6,
    CAN_PROTO_TX_EKF_STATS = 7,
    CAN_PROTO_TX_TIME = 8,
    CAN_PROTO_TX_HEALTH_1 = 9,
    CAN_PROTO_TX_HEALTH_2 = 10,
    CAN_PROTO_TX_DIAG = 11,
    CAN_PROTO_TX_DIAG_FREEZE = 12,
    CAN_PROTO_TX_HEALTH_3 = 13,
    CAN_PROTO_TX_HEALTH_4 = 14,
    CAN_PROTO_TX_HEALTH_5 = 15
};

/** One signal of a frame, as in the DBC: physical = raw * scale + offset. */
typedef struct {
    const char *name;  /**< DBC signal name */
    uint8_t start_bit; /**< LSB position, 0 = bit 0 of data[0] */
    uint8_t length;    /**< bits, 1..32 */
    uint8_t is_signed; /**< 1: two's complement */
    float scale;       /**< physical units per count */
    float offset;      /**< physical value at raw 0 */
    float min;         /**< commands: smallest valid value; telemetry: smallest representable */
    float max;         /**< commands: largest valid value; telemetry: largest representable */
    const char *unit;  /**< DBC unit string ("" when none) */
} can_proto_signal_t;

/** One frame: its id, name and signals (CRC first, Counter second in every frame). */
typedef struct {
    const char *name;                  /**< DBC message name */
    const can_proto_signal_t *signals; /**< the signals, CRC and Counter first */
    uint32_t id;                       /**< 11-bit identifier */
    uint8_t is_command;                /**< 1: bench -> controller (range-checked on receive) */
    uint8_t n_signals;                 /**< entries of signals[] */
} can_proto_msg_t;

/** Decoded TV_CMD_CONTROL. */
typedef struct {
    app_mode_t mode;     /**< requested mode */
    float target_rad;    /**< closed-loop target angle [rad] */
    float duty_limit;    /**< |duty| limit, (0, 1] */
    uint8_t fault_clear; /**< FaultClear bit (acted on at its 0 -> 1 edge) */
    uint8_t temp_valid;  /**< WindingTempValid: 1 when winding_temp_C holds the winding's temperature */
    float winding_temp_C; /**< WindingTemp [degC], -40 .. 180 (read only with temp_valid) */
} can_proto_control_t;

/** Decoded TV_CMD_EXCITATION. */
typedef struct {
    float amplitude_V;    /**< excitation amplitude [V] */
    float freq_Hz;        /**< sine / step frequency, chirp start [Hz] */
    float chirp_f1_Hz;    /**< chirp end frequency [Hz] */
    float chirp_period_s; /**< chirp sweep duration [s] */
} can_proto_excitation_t;

/** Platform loop statistics reported in TV_LOOP. */
typedef struct {
    uint32_t overruns;       /**< periods missed since start */
    uint32_t latency_max_us; /**< worst wake-up latency [us] */
    uint32_t exec_max_us;    /**< worst execution time of one tick [us] */
    uint32_t sample_time_us; /**< when this tick's inputs were read, platform clock since start [us] */
} can_proto_loop_stats_t;

/** Command reception counters (the node's, since start). */
typedef struct {
    uint32_t accepted;  /**< frames accepted and applied */
    uint32_t unknown;   /**< frames with an id that is not a command */
    uint32_t dlc;       /**< wrong data length */
    uint32_t crc;       /**< CRC mismatch */
    uint32_t repeated;  /**< counter equal to the last one of that id */
    uint32_t sequence;  /**< counter jumped by more than max_counter_delta (stale or lost) */
    uint32_t range;     /**< a signal outside its valid range */
    uint32_t timeouts;  /**< command timeouts latched */
} can_proto_rx_stats_t;

/** Everything the telemetry frames carry, in physical units. */
typedef struct {
    float est[3];          /**< estimate: current [A], velocity [rad/s], angle [rad] */
    float sigma[3];        /**< standard deviations, same units */
    float innov[3];        /**< innovations: current [A], velocity [rad/s], angle [rad] */
    float nis;             /**< NIS of this step [-] */
    float duty;            /**< PWM duty [-1, 1] */
    float meas_current_A;  /**< measured current [A] */
    float meas_angle_rad;  /**< measured angle [rad] */
    float supply_V;        /**< measured supply [V] */
    uint8_t mode;          /**< effective app_mode_t */
    uint16_t faults;       /**< APP_FAULT_* mask (low 12 bits) */
    uint8_t bridge_enable; /**< 0 / 1 */
    uint8_t ekf_ok;        /**< 0 / 1 */
    uint8_t cmd_active;    /**< 0 / 1 */
    uint8_t cmd_timeout;   /**< 0 / 1 */
    uint8_t channels_used; /**< 0..3 */
    uint8_t hal_error;     /**< 0 / 1 */
    can_proto_loop_stats_t loop; /**< TV_LOOP, and TV_TIME (sample_time_us) */
    can_proto_rx_stats_t rx;     /**< TV_CMD_STATS (sent modulo the field widths) */
    float nis_mean;        /**< mean NIS over the TV_EKF_STATS window [-] */
    uint32_t corrections;  /**< corrections in that window */
    uint32_t ekf_rejected; /**< filter calls rejected since start */
    /* condition monitoring (TV_HEALTH_1, TV_HEALTH_2): app_output_t's adapted parameters */
    float r_est_ohm;          /**< winding resistance R + dR [ohm] */
    float r_sigma_ohm;        /**< its standard deviation [ohm] */
    float friction_rel;       /**< friction level relative to the model, 1 + f [-] */
    float friction_rel_sigma; /**< its standard deviation [-] */
    float preload_rel;        /**< spring preload relative to the model, 1 + m [-] */
    float preload_rel_sigma;  /**< its standard deviation [-] */
    float stop_closed_rad;    /**< closed-stop contact onset in use [rad] */
    float stop_open_rad;      /**< open-stop contact onset in use [rad] */
    float tps_diff_rad;       /**< TV_HEALTH_3: mean of phi1 - phi2 over the last second [rad] */
    float tps_diff_sd_rad;    /**< its standard deviation [rad] */
    float r_20_ohm;           /**< TV_HEALTH_3: winding resistance R + dR referred to 20 degC [ohm];
                                   0 while the winding's temperature is unknown */
    float fit_r_ohm;          /**< TV_HEALTH_4: the voltage equation fit's winding resistance R [ohm];
                                   0 until its first window */
    float fit_r_sigma_ohm;    /**< its standard deviation [ohm] */
    float fit_nke_V_s;        /**< the fit's back-EMF constant at the plate, n Ke [V s/rad]; 0 until
                                   its first window */
    float fit_i_off_A;        /**< the current sensor's offset the fit reads [A]; 0 until it read one */
    float fit_base_r_ohm;     /**< TV_HEALTH_5: the fit's per-unit baseline, R at 20 degC [ohm]; 0: none */
    float fit_base_nke_V_s;   /**< its n Ke at the plate [V s/rad]; 0: none */
    uint8_t fit_base_state;   /**< 0 none and not learning, 1 learning, 2 in force (app_output_t::fit_base_state) */
    uint16_t fit_base_windows; /**< windows summed toward the learning under way (app_output_t::fit_base_windows) */
    /* diagnostic codes (TV_DIAG, TV_DIAG_FREEZE) */
    uint8_t dtc_count;        /**< codes confirmed now, 0..15 */
    uint16_t dtc_mask;        /**< bit k: code k confirmed now */
    uint8_t dtc_action;       /**< diag_action_t in force, 0..2 */
    uint8_t last_dtc;         /**< code confirmed most recently (diag_dtc_t), CAN_PROTO_DTC_NONE when none */
    uint8_t last_dtc_status;  /**< 0 none, 1 confirmed now, 2 history (healed or cleared) */
    uint8_t last_dtc_confirmations; /**< times last_dtc was confirmed since start (saturates at 255) */
    float last_dtc_time_s;    /**< its last confirmation, since the application's first step [s] */
    uint8_t freeze_dtc;       /**< the code of the freeze frame below (= last_dtc) */
    float freeze_angle_rad;   /**< freeze frame: estimated angle [rad] */
    float freeze_velocity_rad_s; /**< freeze frame: estimated velocity [rad/s] */
    float freeze_duty;        /**< freeze frame: duty of the period that ended [-] */
    float freeze_supply_V;    /**< freeze frame: measured supply [V] */
    float freeze_current_A;   /**< freeze frame: estimated current [A] */
} can_proto_telemetry_t;

/** Command link state. */
typedef enum {
    CAN_PROTO_LINK_WAITING = 0, /**< no valid command yet (outputs OFF when the watchdog is on) */
    CAN_PROTO_LINK_ACTIVE = 1,  /**< commands arriving */
    CAN_PROTO_LINK_TIMEOUT = 2  /**< command timeout latched: outputs OFF until FaultClear */
} can_proto_link_t;

/** Outcome of can_proto_node_receive() (non-negative), in checking order. */
typedef enum {
    CAN_PROTO_RX_ACCEPTED = 0,
    CAN_PROTO_RX_UNKNOWN_ID = 1,
    CAN_PROTO_RX_BAD_DLC = 2,
    CAN_PROTO_RX_BAD_CRC = 3,
    CAN_PROTO_RX_REPEATED = 4,
    CAN_PROTO_RX_SEQUENCE = 5,
    CAN_PROTO_RX_RANGE = 6
} can_proto_rx_result_t;

/** Node configuration. */
typedef struct {
    uint32_t cmd_timeout_ms;   /**< 0: no watchdog; else 1..CAN_PROTO_TIMEOUT_MAX_MS */
    uint8_t max_counter_delta; /**< largest accepted counter step, 1..14 (1: no frame may be lost) */
    uint16_t period_ms[CAN_PROTO_N_TX]; /**< period per telemetry frame [ms], 0 = not sent */
} can_proto_config_t;

/** Protocol node of one controller: command reception, watchdog, telemetry schedule. */
typedef struct {
    can_proto_config_t cfg;
    app_control_t commanded;     /**< control last commanded (config defaults until commands) */
    can_proto_rx_stats_t stats;  /**< reception counters */
    uint64_t last_control_us;    /**< time of the last accepted TV_CMD_CONTROL */
    uint64_t tx_due_us[CAN_PROTO_N_TX]; /**< next transmission time per telemetry frame */
    uint8_t rx_have[CAN_PROTO_N_CMD];    /**< 1 once a counter reference exists per command id */
    uint8_t rx_counter[CAN_PROTO_N_CMD]; /**< counter reference per command id */
    uint8_t tx_counter[CAN_PROTO_N_TX];  /**< next counter per telemetry frame */
    uint8_t link;                /**< can_proto_link_t */
    uint8_t last_clear;          /**< FaultClear of the last accepted TV_CMD_CONTROL */
    uint8_t tx_started;          /**< 1 once the schedule has its time base */
    float nis_sum;               /**< NIS sum over the TV_EKF_STATS window */
    uint32_t nis_n;              /**< corrections in that window */
} can_proto_node_t;

/* ---- low level: CRC, signal tables, generic pack/unpack ---------------------------------- */

/**
 * CRC-8 SAE J1850 (poly 0x1D, init 0xFF, xorout 0xFF) of len bytes.
 * @return the CRC; 0xFF ^ 0xFF = 0x00 for len 0. data may be NULL only when len is 0.
 */
uint8_t can_proto_crc8(const uint8_t *data, size_t len);

/** The frame's CRC: over the id (low byte, high byte) and data[1..7]. */
uint8_t can_proto_frame_crc(const hal_can_frame_t *frame);

/** Description of the frame with this id, or NULL when the id is not part of the protocol. */
const can_proto_msg_t *can_proto_find_msg(uint32_t id);

/** Description of the i-th frame, i < CAN_PROTO_N_CMD + CAN_PROTO_N_TX (commands first); NULL beyond. */
const can_proto_msg_t *can_proto_msg_at(size_t i);

/**
 * Pack physical values into a frame: id, DLC 8, reserved bits 0, the signals, then counter and
 * CRC (phys[0] and phys[1], the CRC and Counter entries, are ignored).
 * @param phys       one value per signal of msg, in msg->signals order
 * @param counter    rolling counter 0..15
 * @param saturate   1: values beyond the representable range saturate (telemetry);
 *                   0: a value outside [min, max] is an error (commands)
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE (counter > 15, or a value out of range when not
 *         saturating); TV_ERR_NONFINITE (NaN/Inf when not saturating; saturating sends 0).
 *         On error *frame is not written.
 */
int can_proto_pack(const can_proto_msg_t *msg, const float *phys, uint8_t counter, int saturate,
                   hal_can_frame_t *frame);

/**
 * Unpack all signals of msg from a frame (no CRC, DLC or range check; see can_proto_check()).
 * @param phys receives one value per signal (CRC and Counter included, as raw numbers)
 * @return TV_OK; TV_ERR_NULL.
 */
int can_proto_unpack(const can_proto_msg_t *msg, const hal_can_frame_t *frame, float *phys);

/**
 * Frame-level checks of a received frame of a known id: DLC, CRC, then (commands) ranges.
 * @return CAN_PROTO_RX_ACCEPTED, CAN_PROTO_RX_UNKNOWN_ID, CAN_PROTO_RX_BAD_DLC,
 *         CAN_PROTO_RX_BAD_CRC or CAN_PROTO_RX_RANGE; TV_ERR_NULL.
 */
int can_proto_check(const hal_can_frame_t *frame);

/* ---- typed commands ----------------------------------------------------------------------- */

/**
 * Decode and check a TV_CMD_CONTROL frame (DLC, CRC, ranges; not the counter).
 * @return a can_proto_rx_result_t (ACCEPTED when *cmd was written); TV_ERR_NULL.
 */
int can_proto_decode_control(const hal_can_frame_t *frame, can_proto_control_t *cmd);

/** Decode and check a TV_CMD_EXCITATION frame; returns as can_proto_decode_control(). */
int can_proto_decode_excitation(const hal_can_frame_t *frame, can_proto_excitation_t *cmd);

/** Rolling counter of a frame (bits 8..11). */
uint8_t can_proto_frame_counter(const hal_can_frame_t *frame);

/* ---- telemetry ---------------------------------------------------------------------------- */

/**
 * Fill the step-related fields of *tm from the application and its last output: estimate,
 * sigma, innovations, NIS, duty, measurements, mode, faults, flags, ekf_rejected, the health
 * indicators (adapted parameters, stops, track agreement, the voltage equation's fit and its
 * per-unit baseline) and the
 * diagnostic codes (confirmed codes and action of the output; the last confirmed code and its
 * freeze frame from app->diag). Loop, rx and window statistics and the link flags are left as
 * they are (the node fills them).
 */
void can_proto_telemetry_from_app(const app_t *app, const app_output_t *out, can_proto_telemetry_t *tm);

/**
 * Encode one telemetry frame (saturating).
 * @param id  one of the telemetry ids
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE (not a telemetry id, or counter > 15).
 */
int can_proto_encode_telemetry(uint32_t id, const can_proto_telemetry_t *tm, uint8_t counter, hal_can_frame_t *frame);

/**
 * Encode TV_ECU_CPU: worst and mean cycles of the control step and the count of steps over the
 * budget (16,800 cycles = 10 % of 168 MHz at 1 kHz). Each value saturates at 65535.
 * @return TV_OK or TV_ERR_NULL.
 */
int can_proto_encode_ecu_cpu(uint32_t cycles_max, uint32_t cycles_mean, uint32_t over_budget, uint8_t counter,
                             hal_can_frame_t *frame);

/* ---- the node ----------------------------------------------------------------------------- */

/** Defaults: timeout 100 ms, max counter delta 2, periods 10 ms (0x180..0x184, 0x188), 100 ms (0x185..0x187,
 *  0x189..0x18E), 1000 ms (0x18F: the fit's baseline changes once in a unit's life). */
void can_proto_config_default(can_proto_config_t *cfg);

/**
 * Validate the configuration and initialise the node for an initialised application. The
 * commanded control starts as app->cfg.control; with a watchdog (cmd_timeout_ms > 0) the
 * application is switched to APP_MODE_OFF until the first valid TV_CMD_CONTROL.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (timeout > CAN_PROTO_TIMEOUT_MAX_MS, counter delta
 *         outside 1..14). On error nothing is written.
 */
int can_proto_node_init(can_proto_node_t *node, const can_proto_config_t *cfg, app_t *app);

/**
 * Check one received frame and, when accepted, apply it: TV_CMD_CONTROL sets mode, target and
 * duty limit (and clears faults and a latched timeout on a FaultClear edge) and feeds the
 * watchdog; TV_CMD_EXCITATION sets amplitude and frequencies. app_set_control() is called only
 * when the control actually changes (it resets the position integrator).
 * @param t_us  monotonic time of reception [us] (the platform's tick time is fine)
 * @return a can_proto_rx_result_t; TV_ERR_NULL.
 */
int can_proto_node_receive(can_proto_node_t *node, app_t *app, const hal_can_frame_t *frame, uint64_t t_us);

/**
 * Once per tick after app_step(): the watchdog (may latch TIMEOUT and force APP_MODE_OFF) and
 * the NIS window of TV_EKF_STATS. out may be NULL (no step this tick).
 */
void can_proto_node_update(can_proto_node_t *node, app_t *app, const app_output_t *out, uint64_t t_us);

/**
 * The telemetry frames due at t_us, encoded into frames[0..n-1], in CAN_PROTO_TX_* order except
 * TV_TIME, which comes last (after the other frames of its tick). The
 * first call sets the time base; frame k (k <= CAN_PROTO_TX_EKF_STATS) is first sent k ms later
 * (staggered), TV_HEALTH_1, TV_HEALTH_2, TV_DIAG, TV_DIAG_FREEZE, TV_HEALTH_3, TV_HEALTH_4, TV_HEALTH_5 at
 * 8, 9, 18, 19, 28, 29, 38 ms (so with the default periods no two ids share a tick), except TV_TIME,
 * which is scheduled like TV_EST_STATE (offset 0, and its own period_ms: keep them equal to
 * pair them); then every period_ms. A late call sends each due frame once (no catching up).
 * @param loop       platform loop statistics (may be NULL: zeros)
 * @param hal_error  1 when the platform's I/O failed this tick
 * @return number of frames written (0..CAN_PROTO_N_TX); 0 on NULL arguments.
 */
size_t can_proto_node_transmit(can_proto_node_t *node, const app_t *app, const app_output_t *out,
                               const can_proto_loop_stats_t *loop, int hal_error, uint64_t t_us,
                               hal_can_frame_t frames[CAN_PROTO_N_TX]);

/** Command link state (can_proto_link_t). */
can_proto_link_t can_proto_node_link(const can_proto_node_t *node);

#ifdef __cplusplus
}
#endif

#endif /* CAN_PROTO_H */
