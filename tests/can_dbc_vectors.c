/**
 * @file can_dbc_vectors.c
 * @brief Test vectors for tests/test_can_dbc.py, which decodes them with tools/throttle.dbc:
 *        frames encoded by the C protocol (firmware/protocols/can_proto.h), printed as candump lines, each
 *        followed by the physical value every signal must decode to.
 *
 * Output lines:
 *   SIGNAL <msg> <sig> <start> <length> <signed> <scale> <offset> <min> <max> "<unit>"
 *                              the C signal table, for a field-by-field comparison with the DBC
 *   FRAME <candump line>       one encoded frame, alternately in log (-L) and default format
 *   EXPECT <msg> <sig> <value> <tol>
 *                              the value the DBC must decode for that signal of the last FRAME
 *   DTC <index> <code>         the firmware's code table (firmware/diag/diag.h), which the DBC's
 *                              value tables of LastDtc and FreezeDtc must name alike
 *
 * Two kinds of vectors:
 *   typed  - the public encoders (can_host_encode_control/excitation/telemetry) fed known
 *            values; EXPECT holds the value put into the C struct field, so a signal wired to
 *            the wrong field, a wrong scale, start bit, length or sign fails. Tolerance: half
 *            a count of the signal's scale (the encoding's rounding), plus float rounding.
 *   sweep  - can_proto_pack() with raw values from one end of every field to the other
 *            (extremes, zero, alternating bit patterns); EXPECT holds what can_proto_unpack()
 *            decodes, tolerance 1e-6 relative (float vs double arithmetic).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "can_host.h"
#include "can_proto.h"
#include "tv_status.h"

static unsigned s_frame_no;

static void print_frame(const hal_can_frame_t *f)
{
    unsigned k;
    if (s_frame_no % 2u == 0u) {
        printf("FRAME (%u.%06u) vcan0 %03X#", 1700000000u + s_frame_no, s_frame_no % 1000000u, (unsigned)f->id);
        for (k = 0; k < f->dlc; ++k) {
            printf("%02X", f->data[k]);
        }
    } else {
        printf("FRAME   vcan0  %03X   [%u] ", (unsigned)f->id, (unsigned)f->dlc);
        for (k = 0; k < f->dlc; ++k) {
            printf(" %02X", f->data[k]);
        }
    }
    printf("\n");
    ++s_frame_no;
}

/* Typed expectation: tolerance half a count of the signal's scale plus float rounding. */
static void expect(const char *msg_name, const char *sig_name, double value)
{
    size_t i;
    for (i = 0; can_proto_msg_at(i) != NULL; ++i) {
        const can_proto_msg_t *m = can_proto_msg_at(i);
        uint8_t k;
        if (strcmp(m->name, msg_name) != 0) {
            continue;
        }
        for (k = 0; k < m->n_signals; ++k) {
            if (strcmp(m->signals[k].name, sig_name) == 0) {
                /* wide fields (the 32-bit SampleTime) are carried as integers: exact */
                const double tol = m->signals[k].length > 24u ? 0.0
                                                               : 0.5 * (double)m->signals[k].scale * 1.0001 + 1e-6 * fabs(value);
                printf("EXPECT %s %s %.17g %.3g\n", msg_name, sig_name, value, tol);
                return;
            }
        }
    }
    printf("EXPECT %s %s %.9g 0 # no such signal in the C table\n", msg_name, sig_name, value);
}

static void print_tables(void)
{
    size_t i;
    for (i = 0; can_proto_msg_at(i) != NULL; ++i) {
        const can_proto_msg_t *m = can_proto_msg_at(i);
        uint8_t k;
        printf("MESSAGE %s %u %u\n", m->name, (unsigned)m->id, (unsigned)CAN_PROTO_DLC);
        for (k = 0; k < m->n_signals; ++k) {
            const can_proto_signal_t *s = &m->signals[k];
            printf("SIGNAL %s %s %u %u %u %.9g %.9g %.9g %.9g \"%s\"\n", m->name, s->name, (unsigned)s->start_bit,
                   (unsigned)s->length, (unsigned)s->is_signed, (double)s->scale, (double)s->offset, (double)s->min,
                   (double)s->max, s->unit);
        }
    }
}

static void typed_commands(void)
{
    static const struct {
        app_mode_t mode;
        float target, limit;
        uint8_t clear;
        uint8_t temp_valid;
        float temp;
    } c[] = {{APP_MODE_OFF, 0.0f, 0.005f, 0u, 0u, 0.0f},        {APP_MODE_SINE, -0.5f, 1.0f, 1u, 1u, -40.0f},
             {APP_MODE_STEPS, 2.0f, 0.5f, 0u, 1u, 180.0f},      {APP_MODE_CHIRP, 0.12345f, 0.955f, 1u, 1u, 87.0f},
             {APP_MODE_POSITION, -0.0321f, 0.2f, 0u, 1u, 20.0f}};
    static const struct {
        float amp, f0, f1, period;
    } e[] = {{0.0f, 0.0f, 0.0f, 0.1f}, {24.0f, 200.0f, 200.0f, 25.5f}, {12.3f, 5.55f, 123.45f, 2.0f},
             {0.1f, 0.01f, 199.99f, 7.7f}};
    size_t i;
    for (i = 0; i < sizeof c / sizeof c[0]; ++i) {
        can_proto_control_t cmd;
        hal_can_frame_t f;
        cmd.mode = c[i].mode;
        cmd.target_rad = c[i].target;
        cmd.duty_limit = c[i].limit;
        cmd.fault_clear = c[i].clear;
        cmd.temp_valid = c[i].temp_valid;
        cmd.winding_temp_C = c[i].temp;
        if (can_host_encode_control(&cmd, (uint8_t)(i * 3u % 16u), &f) != TV_OK) {
            printf("ERROR encode_control %u\n", (unsigned)i);
            continue;
        }
        print_frame(&f);
        expect("TV_CMD_CONTROL", "Counter", (double)(i * 3u % 16u));
        expect("TV_CMD_CONTROL", "Mode", (double)c[i].mode);
        expect("TV_CMD_CONTROL", "TargetAngle", (double)c[i].target);
        expect("TV_CMD_CONTROL", "DutyLimit", (double)c[i].limit);
        expect("TV_CMD_CONTROL", "FaultClear", (double)c[i].clear);
        expect("TV_CMD_CONTROL", "WindingTempValid", (double)c[i].temp_valid);
        expect("TV_CMD_CONTROL", "WindingTemp", c[i].temp_valid ? (double)c[i].temp : -40.0);
    }
    for (i = 0; i < sizeof e / sizeof e[0]; ++i) {
        can_proto_excitation_t cmd;
        hal_can_frame_t f;
        cmd.amplitude_V = e[i].amp;
        cmd.freq_Hz = e[i].f0;
        cmd.chirp_f1_Hz = e[i].f1;
        cmd.chirp_period_s = e[i].period;
        if (can_host_encode_excitation(&cmd, (uint8_t)(15u - i), &f) != TV_OK) {
            printf("ERROR encode_excitation %u\n", (unsigned)i);
            continue;
        }
        print_frame(&f);
        expect("TV_CMD_EXCITATION", "Counter", (double)(15u - i));
        expect("TV_CMD_EXCITATION", "Amplitude", (double)e[i].amp);
        expect("TV_CMD_EXCITATION", "Frequency", (double)e[i].f0);
        expect("TV_CMD_EXCITATION", "ChirpEndFreq", (double)e[i].f1);
        expect("TV_CMD_EXCITATION", "ChirpPeriod", (double)e[i].period);
    }
}

/* The ECU's platform frame: values inside the field, and one saturating. */
static void typed_ecu_cpu(void)
{
    static const uint32_t vals[][3] = {{0u, 0u, 0u}, {4057u, 3859u, 0u}, {16800u, 12000u, 7u}, {70000u, 65535u, 65536u}};
    size_t i;
    for (i = 0; i < sizeof vals / sizeof vals[0]; ++i) {
        hal_can_frame_t f;
        if (can_proto_encode_ecu_cpu(vals[i][0], vals[i][1], vals[i][2], (uint8_t)i, &f) != TV_OK) {
            printf("ERROR encode_ecu_cpu %u\n", (unsigned)i);
            continue;
        }
        print_frame(&f);
        expect("TV_ECU_CPU", "Counter", (double)i);
        expect("TV_ECU_CPU", "CyclesMax", (double)(vals[i][0] < 65535u ? vals[i][0] : 65535u));
        expect("TV_ECU_CPU", "CyclesMean", (double)(vals[i][1] < 65535u ? vals[i][1] : 65535u));
        expect("TV_ECU_CPU", "OverBudget", (double)(vals[i][2] < 65535u ? vals[i][2] : 65535u));
    }
}

/* Every telemetry frame from one set of field values, each value inside its representable range. */
static void typed_telemetry(const can_proto_telemetry_t *tm, uint8_t counter)
{
    size_t k;
    for (k = 0; k < CAN_PROTO_N_TX; ++k) {
        const can_proto_msg_t *m = can_proto_msg_at(CAN_PROTO_N_CMD + k);
        hal_can_frame_t f;
        if (can_proto_encode_telemetry(m->id, tm, counter, &f) != TV_OK) {
            printf("ERROR encode_telemetry %s\n", m->name);
            continue;
        }
        print_frame(&f);
        expect(m->name, "Counter", (double)counter);
        switch (m->id) {
        case CAN_PROTO_ID_EST_STATE:
            expect(m->name, "EstCurrent", (double)tm->est[0]);
            expect(m->name, "EstVelocity", (double)tm->est[1]);
            expect(m->name, "EstAngle", (double)tm->est[2]);
            break;
        case CAN_PROTO_ID_EST_SIGMA:
            expect(m->name, "SigmaCurrent", (double)tm->sigma[0]);
            expect(m->name, "SigmaVelocity", (double)tm->sigma[1]);
            expect(m->name, "SigmaAngle", (double)tm->sigma[2]);
            break;
        case CAN_PROTO_ID_EST_INNOV:
            expect(m->name, "InnovCurrent", (double)tm->innov[0]);
            expect(m->name, "InnovVelocity", (double)tm->innov[1]);
            expect(m->name, "InnovAngle", (double)tm->innov[2]);
            break;
        case CAN_PROTO_ID_STATUS:
            expect(m->name, "Mode", (double)tm->mode);
            expect(m->name, "Faults", (double)tm->faults);
            expect(m->name, "BridgeEnable", (double)tm->bridge_enable);
            expect(m->name, "EkfOk", (double)tm->ekf_ok);
            expect(m->name, "CmdActive", (double)tm->cmd_active);
            expect(m->name, "CmdTimeout", (double)tm->cmd_timeout);
            expect(m->name, "ChannelsUsed", (double)tm->channels_used);
            expect(m->name, "HalError", (double)tm->hal_error);
            expect(m->name, "Nis", (double)tm->nis);
            expect(m->name, "Duty", (double)tm->duty);
            break;
        case CAN_PROTO_ID_MEAS:
            expect(m->name, "MeasCurrent", (double)tm->meas_current_A);
            expect(m->name, "MeasAngle", (double)tm->meas_angle_rad);
            expect(m->name, "SupplyVoltage", (double)tm->supply_V);
            break;
        case CAN_PROTO_ID_LOOP:
            expect(m->name, "Overruns", (double)tm->loop.overruns);
            expect(m->name, "LatencyMax", (double)tm->loop.latency_max_us);
            expect(m->name, "ExecMax", (double)tm->loop.exec_max_us);
            break;
        case CAN_PROTO_ID_CMD_STATS:
            expect(m->name, "Timeouts", (double)(tm->rx.timeouts % 16u));
            expect(m->name, "Accepted", (double)(tm->rx.accepted % 256u));
            expect(m->name, "CrcErrors", (double)(tm->rx.crc % 256u));
            expect(m->name, "CounterErrors", (double)((tm->rx.repeated + tm->rx.sequence) % 256u));
            expect(m->name, "DlcErrors", (double)(tm->rx.dlc % 256u));
            expect(m->name, "RangeErrors", (double)(tm->rx.range % 256u));
            expect(m->name, "UnknownIds", (double)(tm->rx.unknown % 256u));
            break;
        case CAN_PROTO_ID_TIME:
            expect(m->name, "SampleTime", (double)tm->loop.sample_time_us);
            break;
        case CAN_PROTO_ID_HEALTH_1:
            expect(m->name, "ResistanceEst", (double)tm->r_est_ohm);
            expect(m->name, "ResistanceSigma", (double)tm->r_sigma_ohm);
            expect(m->name, "FrictionRel", (double)tm->friction_rel);
            expect(m->name, "FrictionRelSigma", (double)tm->friction_rel_sigma);
            break;
        case CAN_PROTO_ID_HEALTH_2:
            expect(m->name, "PreloadRel", (double)tm->preload_rel);
            expect(m->name, "PreloadRelSigma", (double)tm->preload_rel_sigma);
            expect(m->name, "StopClosed", (double)tm->stop_closed_rad);
            expect(m->name, "StopOpen", (double)tm->stop_open_rad);
            break;
        case CAN_PROTO_ID_HEALTH_3:
            expect(m->name, "TrackDiff", (double)tm->tps_diff_rad);
            expect(m->name, "TrackDiffSd", (double)tm->tps_diff_sd_rad);
            expect(m->name, "ResistanceRef20", (double)tm->r_20_ohm);
            break;
        case CAN_PROTO_ID_HEALTH_4:
            expect(m->name, "FitResistance", (double)tm->fit_r_ohm);
            expect(m->name, "FitResistanceSigma", (double)tm->fit_r_sigma_ohm);
            expect(m->name, "FitBackEmf", (double)tm->fit_nke_V_s);
            expect(m->name, "FitCurrentOffset", (double)tm->fit_i_off_A);
            break;
        case CAN_PROTO_ID_HEALTH_5:
            expect(m->name, "FitBaseResistance20", (double)tm->fit_base_r_ohm);
            expect(m->name, "FitBaseBackEmf", (double)tm->fit_base_nke_V_s);
            expect(m->name, "FitBaseState", (double)tm->fit_base_state);
            expect(m->name, "FitBaseWindows", (double)tm->fit_base_windows);
            break;
        case CAN_PROTO_ID_DIAG:
            expect(m->name, "DtcCount", (double)tm->dtc_count);
            expect(m->name, "LastDtc", (double)tm->last_dtc);
            expect(m->name, "LastDtcStatus", (double)tm->last_dtc_status);
            expect(m->name, "Action", (double)tm->dtc_action);
            expect(m->name, "LastDtcConfirmations", (double)tm->last_dtc_confirmations);
            expect(m->name, "ConfirmedMask", (double)tm->dtc_mask);
            expect(m->name, "LastDtcTime", (double)tm->last_dtc_time_s);
            break;
        case CAN_PROTO_ID_DIAG_FREEZE:
            expect(m->name, "FreezeDtc", (double)tm->freeze_dtc);
            expect(m->name, "FreezeAngle", (double)tm->freeze_angle_rad);
            expect(m->name, "FreezeVelocity", (double)tm->freeze_velocity_rad_s);
            expect(m->name, "FreezeDuty", (double)tm->freeze_duty);
            expect(m->name, "FreezeSupply", (double)tm->freeze_supply_V);
            expect(m->name, "FreezeCurrent", (double)tm->freeze_current_A);
            break;
        default:
            expect(m->name, "NisMean", (double)tm->nis_mean);
            expect(m->name, "Corrections", (double)tm->corrections);
            expect(m->name, "Rejected", (double)(tm->ekf_rejected % 65536u));
            break;
        }
    }
}

static void telemetry_sets(void)
{
    can_proto_telemetry_t a;
    memset(&a, 0, sizeof a);
    a.est[0] = 1.234f;
    a.est[1] = -45.67f;
    a.est[2] = 0.7071f;
    a.sigma[0] = 0.0123f;
    a.sigma[1] = 0.456f;
    a.sigma[2] = 0.000123f;
    a.innov[0] = -0.0042f;
    a.innov[1] = 1.5f;
    a.innov[2] = -0.000321f;
    a.nis = 3.21f;
    a.duty = -0.4321f;
    a.meas_current_A = -1.5f;
    a.meas_angle_rad = 1.3f;
    a.supply_V = 13.456f;
    a.mode = 4u;
    a.faults = 0x1A5u;
    a.bridge_enable = 1u;
    a.ekf_ok = 0u;
    a.cmd_active = 1u;
    a.cmd_timeout = 0u;
    a.channels_used = 2u;
    a.hal_error = 1u;
    a.loop.overruns = 12345u;
    a.loop.latency_max_us = 678u;
    a.loop.exec_max_us = 90u;
    a.rx.accepted = 300u;
    a.rx.crc = 3u;
    a.rx.repeated = 4u;
    a.rx.sequence = 5u;
    a.rx.dlc = 6u;
    a.rx.range = 7u;
    a.rx.unknown = 258u;
    a.rx.timeouts = 17u;
    a.nis_mean = 2.345f;
    a.corrections = 100u;
    a.ekf_rejected = 65537u;
    a.loop.sample_time_us = 123456789u;
    a.r_est_ohm = 4.321f;
    a.r_sigma_ohm = 0.0234f;
    a.friction_rel = 1.2345f;
    a.friction_rel_sigma = 0.01234f; /* 61.7 counts, not on a half count */
    a.preload_rel = 0.7005f;
    a.preload_rel_sigma = 0.0082f;
    a.stop_closed_rad = -0.1234f;
    a.stop_open_rad = 1.4321f;
    a.tps_diff_rad = -0.00321f;
    a.tps_diff_sd_rad = 0.000456f;
    a.r_20_ohm = 4.123f;
    a.fit_r_ohm = 3.987f;
    a.fit_r_sigma_ohm = 0.0123f;
    a.fit_nke_V_s = 0.1234f;
    a.fit_i_off_A = -0.0351f;
    a.fit_base_r_ohm = 4.0567f;
    a.fit_base_nke_V_s = 0.6512f;
    a.fit_base_state = 1u;
    a.fit_base_windows = 3u;
    a.dtc_count = 2u;
    a.last_dtc = 6u;
    a.last_dtc_status = 1u;
    a.dtc_action = 1u;
    a.last_dtc_confirmations = 3u;
    a.dtc_mask = 0x00C0u;
    a.last_dtc_time_s = 12.3f;
    a.freeze_dtc = 6u;
    a.freeze_angle_rad = 0.456f;
    a.freeze_velocity_rad_s = -12.35f;
    a.freeze_duty = -0.37f;
    a.freeze_supply_V = 13.5f;
    a.freeze_current_A = 1.7f;
    typed_telemetry(&a, 5u);
    /* the other signs, the other flag values, near the ends of the ranges */
    a.est[0] = -32.0f;
    a.est[1] = 327.0f;
    a.est[2] = -3.2f;
    a.sigma[0] = 6.5f;
    a.sigma[1] = 65.0f;
    a.sigma[2] = 0.065f;
    a.innov[0] = 3.2f;
    a.innov[1] = -32.0f;
    a.innov[2] = 0.032f;
    a.nis = 40.9f;
    a.duty = 1.0f;
    a.meas_current_A = 32.0f;
    a.meas_angle_rad = -3.2f;
    a.supply_V = 65.0f;
    a.mode = 1u;
    a.faults = 0xE5Au;
    a.bridge_enable = 0u;
    a.ekf_ok = 1u;
    a.cmd_active = 0u;
    a.cmd_timeout = 1u;
    a.channels_used = 3u;
    a.hal_error = 0u;
    a.loop.overruns = 65535u;
    a.loop.latency_max_us = 1u;
    a.loop.exec_max_us = 65000u;
    a.rx.accepted = 255u;
    a.rx.crc = 200u;
    a.rx.repeated = 0u;
    a.rx.sequence = 99u;
    a.rx.dlc = 1u;
    a.rx.range = 128u;
    a.rx.unknown = 0u;
    a.rx.timeouts = 15u;
    a.nis_mean = 65.0f;
    a.corrections = 65535u;
    a.ekf_rejected = 42u;
    a.loop.sample_time_us = 4294967295u;
    a.r_est_ohm = 16.0f;
    a.r_sigma_ohm = 1.0f;
    a.friction_rel = 2.0f;
    a.friction_rel_sigma = 0.8f;
    a.preload_rel = 0.0f;
    a.preload_rel_sigma = 0.2f;
    a.stop_closed_rad = -0.4f;
    a.stop_open_rad = 1.8f;
    a.tps_diff_rad = 0.3f;
    a.tps_diff_sd_rad = 0.065f;
    a.r_20_ohm = 16.38f;
    a.fit_r_ohm = 16.38f;
    a.fit_r_sigma_ohm = 1.02f;
    a.fit_nke_V_s = 2.047f;
    a.fit_i_off_A = 0.2047f;
    a.fit_base_r_ohm = 16.383f;
    a.fit_base_nke_V_s = 2.0475f;
    a.fit_base_state = 2u;
    a.fit_base_windows = 65535u;
    a.dtc_count = 15u;
    a.last_dtc = CAN_PROTO_DTC_NONE;
    a.last_dtc_status = 2u;
    a.dtc_action = 2u;
    a.last_dtc_confirmations = 255u;
    a.dtc_mask = 0xFFFFu;
    a.last_dtc_time_s = 6553.0f;
    a.freeze_dtc = 0u;
    a.freeze_angle_rad = 1.7f;
    a.freeze_velocity_rad_s = 100.0f;
    a.freeze_duty = 1.0f;
    a.freeze_supply_V = 25.0f;
    a.freeze_current_A = -12.0f;
    typed_telemetry(&a, 15u);
}

/* Raw patterns per field: 0, all ones, the sign bit alone, alternating bits, 1. */
static uint32_t raw_pattern(unsigned n, unsigned length)
{
    const uint32_t mask = length >= 32u ? 0xFFFFFFFFu : ((1u << length) - 1u);
    switch (n % 6u) {
    case 0:
        return 0u;
    case 1:
        return mask;
    case 2:
        return (1u << (length - 1u)) & mask;
    case 3:
        return 0x55555555u & mask;
    case 4:
        return 0xAAAAAAAAu & mask;
    default:
        return 1u;
    }
}

static void sweep(void)
{
    size_t i;
    for (i = 0; can_proto_msg_at(i) != NULL; ++i) {
        const can_proto_msg_t *m = can_proto_msg_at(i);
        unsigned n;
        for (n = 0; n < 6u; ++n) {
            hal_can_frame_t f;
            float phys[CAN_PROTO_MAX_SIGNALS];
            uint8_t k;
            /* build the raw payload directly (commands may be out of their valid range here:
             * this checks bit layout and scale only), then seal it like the encoder does */
            memset(&f, 0, sizeof f);
            f.id = m->id;
            f.dlc = CAN_PROTO_DLC;
            for (k = 2u; k < m->n_signals; ++k) {
                const can_proto_signal_t *s = &m->signals[k];
                const uint32_t raw = raw_pattern(n + k, s->length);
                unsigned b;
                for (b = 0; b < s->length; ++b) {
                    const unsigned bit = (unsigned)s->start_bit + b;
                    if ((raw >> b) & 1u) {
                        f.data[bit / 8u] = (uint8_t)(f.data[bit / 8u] | (1u << (bit % 8u)));
                    }
                }
            }
            f.data[1] = (uint8_t)((f.data[1] & 0xF0u) | (n & 0x0Fu));
            f.data[0] = can_proto_frame_crc(&f);
            (void)can_proto_unpack(m, &f, phys);
            print_frame(&f);
            for (k = 0; k < m->n_signals; ++k) {
                printf("EXPECT %s %s %.17g %.3g\n", m->name, m->signals[k].name, (double)phys[k],
                       1e-6 * fabs((double)phys[k]) + 1e-9);
            }
        }
    }
}

static void print_dtc_table(void)
{
    int k;
    for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
        printf("DTC %d %s\n", k, diag_dtc_info((diag_dtc_t)k)->code);
    }
}

int main(void)
{
    print_tables();
    print_dtc_table();
    typed_commands();
    telemetry_sets();
    typed_ecu_cpu();
    printf("SWEEP\n");
    sweep();
    return 0;
}
