/**
 * @file can_proto.c
 * @brief The controller's CAN protocol (see can_proto.h for every frame, signal and rule).
 */
#include "can_proto.h"

#include <string.h>

#include "tv_status.h"

/* ---- signal tables (must match tools/throttle.dbc; tests/test_can_dbc.py proves it) ------- */

#define SIG_CRC {"CRC", 0u, 8u, 0u, 1.0f, 0.0f, 0.0f, 255.0f, ""}
#define SIG_COUNTER {"Counter", 8u, 4u, 0u, 1.0f, 0.0f, 0.0f, 15.0f, ""}

static const can_proto_signal_t s_sig_control[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"Mode", 12u, 4u, 0u, 1.0f, 0.0f, 0.0f, 7.0f, ""},
    {"TargetAngle", 16u, 16u, 1u, 0.0001f, 0.0f, -0.5f, 2.0f, "rad"},
    {"DutyLimit", 32u, 8u, 0u, 0.005f, 0.0f, 0.005f, 1.0f, ""},
    {"FaultClear", 40u, 1u, 0u, 1.0f, 0.0f, 0.0f, 1.0f, ""},
    {"WindingTempValid", 41u, 1u, 0u, 1.0f, 0.0f, 0.0f, 1.0f, ""},
    {"WindingTemp", 48u, 8u, 0u, 1.0f, -40.0f, -40.0f, 180.0f, "degC"},
};
static const can_proto_signal_t s_sig_excitation[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"Amplitude", 16u, 8u, 0u, 0.1f, 0.0f, 0.0f, 24.0f, "V"},
    {"Frequency", 24u, 16u, 0u, 0.01f, 0.0f, 0.0f, 200.0f, "Hz"},
    {"ChirpEndFreq", 40u, 16u, 0u, 0.01f, 0.0f, 0.0f, 200.0f, "Hz"},
    {"ChirpPeriod", 56u, 8u, 0u, 0.1f, 0.0f, 0.1f, 25.5f, "s"},
};
static const can_proto_signal_t s_sig_state[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"EstCurrent", 16u, 16u, 1u, 0.001f, 0.0f, -32.768f, 32.767f, "A"},
    {"EstVelocity", 32u, 16u, 1u, 0.01f, 0.0f, -327.68f, 327.67f, "rad/s"},
    {"EstAngle", 48u, 16u, 1u, 0.0001f, 0.0f, -3.2768f, 3.2767f, "rad"},
};
static const can_proto_signal_t s_sig_sigma[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"SigmaCurrent", 16u, 16u, 0u, 0.0001f, 0.0f, 0.0f, 6.5535f, "A"},
    {"SigmaVelocity", 32u, 16u, 0u, 0.001f, 0.0f, 0.0f, 65.535f, "rad/s"},
    {"SigmaAngle", 48u, 16u, 0u, 1e-06f, 0.0f, 0.0f, 0.065535f, "rad"},
};
static const can_proto_signal_t s_sig_innov[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"InnovCurrent", 16u, 16u, 1u, 0.0001f, 0.0f, -3.2768f, 3.2767f, "A"},
    {"InnovVelocity", 32u, 16u, 1u, 0.001f, 0.0f, -32.768f, 32.767f, "rad/s"},
    {"InnovAngle", 48u, 16u, 1u, 1e-06f, 0.0f, -0.032768f, 0.032767f, "rad"},
};
static const can_proto_signal_t s_sig_status[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"Mode", 12u, 4u, 0u, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Faults", 16u, 12u, 0u, 1.0f, 0.0f, 0.0f, 4095.0f, ""},
    {"BridgeEnable", 28u, 1u, 0u, 1.0f, 0.0f, 0.0f, 1.0f, ""},
    {"EkfOk", 29u, 1u, 0u, 1.0f, 0.0f, 0.0f, 1.0f, ""},
    {"CmdActive", 30u, 1u, 0u, 1.0f, 0.0f, 0.0f, 1.0f, ""},
    {"CmdTimeout", 31u, 1u, 0u, 1.0f, 0.0f, 0.0f, 1.0f, ""},
    {"ChannelsUsed", 32u, 2u, 0u, 1.0f, 0.0f, 0.0f, 3.0f, ""},
    {"HalError", 34u, 1u, 0u, 1.0f, 0.0f, 0.0f, 1.0f, ""},
    {"Nis", 36u, 12u, 0u, 0.01f, 0.0f, 0.0f, 40.95f, ""},
    {"Duty", 48u, 16u, 1u, 0.0001f, 0.0f, -1.0f, 1.0f, ""},
};
static const can_proto_signal_t s_sig_meas[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"MeasCurrent", 16u, 16u, 1u, 0.001f, 0.0f, -32.768f, 32.767f, "A"},
    {"MeasAngle", 32u, 16u, 1u, 0.0001f, 0.0f, -3.2768f, 3.2767f, "rad"},
    {"SupplyVoltage", 48u, 16u, 0u, 0.001f, 0.0f, 0.0f, 65.535f, "V"},
};
static const can_proto_signal_t s_sig_loop[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"Overruns", 16u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, ""},
    {"LatencyMax", 32u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, "us"},
    {"ExecMax", 48u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, "us"},
};
static const can_proto_signal_t s_sig_cmd_stats[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"Timeouts", 12u, 4u, 0u, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Accepted", 16u, 8u, 0u, 1.0f, 0.0f, 0.0f, 255.0f, ""},
    {"CrcErrors", 24u, 8u, 0u, 1.0f, 0.0f, 0.0f, 255.0f, ""},
    {"CounterErrors", 32u, 8u, 0u, 1.0f, 0.0f, 0.0f, 255.0f, ""},
    {"DlcErrors", 40u, 8u, 0u, 1.0f, 0.0f, 0.0f, 255.0f, ""},
    {"RangeErrors", 48u, 8u, 0u, 1.0f, 0.0f, 0.0f, 255.0f, ""},
    {"UnknownIds", 56u, 8u, 0u, 1.0f, 0.0f, 0.0f, 255.0f, ""},
};
static const can_proto_signal_t s_sig_ekf_stats[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"NisMean", 16u, 16u, 0u, 0.001f, 0.0f, 0.0f, 65.535f, ""},
    {"Corrections", 32u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, ""},
    {"Rejected", 48u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, ""},
};
/* SampleTime is 32 bits: the typed encoder and decoder move it as an integer (a float holds
 * only 24 bits exactly); the generic pack/unpack (float) are exact up to 2^24 us. */
static const can_proto_signal_t s_sig_time[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"SampleTime", 16u, 32u, 0u, 1.0f, 0.0f, 0.0f, 4294967295.0f, "us"},
};

static const can_proto_signal_t s_sig_health_1[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"ResistanceEst", 16u, 14u, 0u, 0.001f, 0.0f, 0.0f, 16.383f, "ohm"},
    {"ResistanceSigma", 30u, 10u, 0u, 0.001f, 0.0f, 0.0f, 1.023f, "ohm"},
    {"FrictionRel", 40u, 12u, 0u, 0.0005f, 0.0f, 0.0f, 2.0475f, ""},
    {"FrictionRelSigma", 52u, 12u, 0u, 0.0002f, 0.0f, 0.0f, 0.819f, ""},
};
static const can_proto_signal_t s_sig_health_2[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"PreloadRel", 16u, 12u, 0u, 0.0005f, 0.0f, 0.0f, 2.0475f, ""},
    {"PreloadRelSigma", 28u, 10u, 0u, 0.0002f, 0.0f, 0.0f, 0.2046f, ""},
    {"StopClosed", 38u, 12u, 0u, 0.0001f, -0.4f, -0.4f, 0.0095f, "rad"},
    {"StopOpen", 50u, 13u, 0u, 0.0001f, 1.0f, 1.0f, 1.8191f, "rad"},
};
static const can_proto_signal_t s_sig_health_3[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"TrackDiff", 16u, 16u, 1u, 1e-5f, 0.0f, -0.32768f, 0.32767f, "rad"},
    {"TrackDiffSd", 32u, 16u, 0u, 1e-6f, 0.0f, 0.0f, 0.065535f, "rad"},
    {"ResistanceRef20", 48u, 14u, 0u, 0.001f, 0.0f, 0.0f, 16.383f, "ohm"},
};
static const can_proto_signal_t s_sig_health_4[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"FitResistance", 16u, 14u, 0u, 0.001f, 0.0f, 0.0f, 16.383f, "ohm"},
    {"FitResistanceSigma", 30u, 10u, 0u, 0.001f, 0.0f, 0.0f, 1.023f, "ohm"},
    {"FitBackEmf", 40u, 12u, 0u, 0.0005f, 0.0f, 0.0f, 2.0475f, "Vs/rad"},
    {"FitCurrentOffset", 52u, 12u, 1u, 0.0001f, 0.0f, -0.2048f, 0.2047f, "A"},
};
static const can_proto_signal_t s_sig_health_5[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"FitBaseResistance20", 16u, 14u, 0u, 0.001f, 0.0f, 0.0f, 16.383f, "ohm"},
    {"FitBaseBackEmf", 30u, 12u, 0u, 0.0005f, 0.0f, 0.0f, 2.0475f, "Vs/rad"},
    {"FitBaseState", 42u, 2u, 0u, 1.0f, 0.0f, 0.0f, 3.0f, ""},
    {"FitBaseWindows", 44u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, ""},
};
static const can_proto_signal_t s_sig_diag[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"DtcCount", 12u, 4u, 0u, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"LastDtc", 16u, 4u, 0u, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"LastDtcStatus", 20u, 2u, 0u, 1.0f, 0.0f, 0.0f, 3.0f, ""},
    {"Action", 22u, 2u, 0u, 1.0f, 0.0f, 0.0f, 3.0f, ""},
    {"LastDtcConfirmations", 24u, 8u, 0u, 1.0f, 0.0f, 0.0f, 255.0f, ""},
    {"ConfirmedMask", 32u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, ""},
    {"LastDtcTime", 48u, 16u, 0u, 0.1f, 0.0f, 0.0f, 6553.5f, "s"},
};
static const can_proto_signal_t s_sig_diag_freeze[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"FreezeDtc", 12u, 4u, 0u, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"FreezeAngle", 16u, 12u, 0u, 0.001f, -0.5f, -0.5f, 3.595f, "rad"},
    {"FreezeVelocity", 28u, 12u, 1u, 0.05f, 0.0f, -102.4f, 102.35f, "rad/s"},
    {"FreezeDuty", 40u, 8u, 1u, 0.01f, 0.0f, -1.28f, 1.27f, ""},
    {"FreezeSupply", 48u, 8u, 0u, 0.1f, 0.0f, 0.0f, 25.5f, "V"},
    {"FreezeCurrent", 56u, 8u, 1u, 0.1f, 0.0f, -12.8f, 12.7f, "A"},
};

static const can_proto_signal_t s_sig_ecu_cpu[] = {
    SIG_CRC,
    SIG_COUNTER,
    {"CyclesMax", 16u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, "cycles"},
    {"CyclesMean", 32u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, "cycles"},
    {"OverBudget", 48u, 16u, 0u, 1.0f, 0.0f, 0.0f, 65535.0f, ""},
};

#define MSG(id, name, cmd, sigs) {(name), (sigs), (id), (cmd), (uint8_t)(sizeof(sigs) / sizeof((sigs)[0]))}

/* Commands first (index = id - CAN_PROTO_ID_CMD_CONTROL), then telemetry in CAN_PROTO_TX_* order. */
static const can_proto_msg_t s_msgs[CAN_PROTO_N_CMD + CAN_PROTO_N_TX + CAN_PROTO_N_PLATFORM] = {
    MSG(CAN_PROTO_ID_CMD_CONTROL, "TV_CMD_CONTROL", 1u, s_sig_control),
    MSG(CAN_PROTO_ID_CMD_EXCITATION, "TV_CMD_EXCITATION", 1u, s_sig_excitation),
    MSG(CAN_PROTO_ID_EST_STATE, "TV_EST_STATE", 0u, s_sig_state),
    MSG(CAN_PROTO_ID_EST_SIGMA, "TV_EST_SIGMA", 0u, s_sig_sigma),
    MSG(CAN_PROTO_ID_EST_INNOV, "TV_EST_INNOV", 0u, s_sig_innov),
    MSG(CAN_PROTO_ID_STATUS, "TV_STATUS", 0u, s_sig_status),
    MSG(CAN_PROTO_ID_MEAS, "TV_MEAS", 0u, s_sig_meas),
    MSG(CAN_PROTO_ID_LOOP, "TV_LOOP", 0u, s_sig_loop),
    MSG(CAN_PROTO_ID_CMD_STATS, "TV_CMD_STATS", 0u, s_sig_cmd_stats),
    MSG(CAN_PROTO_ID_EKF_STATS, "TV_EKF_STATS", 0u, s_sig_ekf_stats),
    MSG(CAN_PROTO_ID_TIME, "TV_TIME", 0u, s_sig_time),
    MSG(CAN_PROTO_ID_HEALTH_1, "TV_HEALTH_1", 0u, s_sig_health_1),
    MSG(CAN_PROTO_ID_HEALTH_2, "TV_HEALTH_2", 0u, s_sig_health_2),
    MSG(CAN_PROTO_ID_DIAG, "TV_DIAG", 0u, s_sig_diag),
    MSG(CAN_PROTO_ID_DIAG_FREEZE, "TV_DIAG_FREEZE", 0u, s_sig_diag_freeze),
    MSG(CAN_PROTO_ID_HEALTH_3, "TV_HEALTH_3", 0u, s_sig_health_3),
    MSG(CAN_PROTO_ID_HEALTH_4, "TV_HEALTH_4", 0u, s_sig_health_4),
    MSG(CAN_PROTO_ID_HEALTH_5, "TV_HEALTH_5", 0u, s_sig_health_5),
    MSG(CAN_PROTO_ID_ECU_CPU, "TV_ECU_CPU", 0u, s_sig_ecu_cpu),
};

/* First transmission of each telemetry frame after the time base [ms]: staggered, except
 * TV_TIME, which goes out in the same tick as TV_EST_STATE. With the default periods (10 ms for
 * 0..4 and TV_TIME, 1000 ms for TV_HEALTH_5, 100 ms for the others) no two ids share a tick: the
 * 10 ms frames occupy 0..4 mod 10, the 100 ms ones 5..9, 18, 19, 28 and 29 mod 100, TV_HEALTH_5
 * 38 mod 1000 (38 mod 100 and 8 mod 10: free of both). */
static const uint8_t s_tx_offset_ms[CAN_PROTO_N_TX] = {0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 0u, 8u, 9u, 18u, 19u, 28u, 29u, 38u};
/* Transmission order within a tick: CAN_PROTO_TX_* order, TV_TIME last (it pairs with the
 * TV_EST_STATE before it). */
static const uint8_t s_tx_order[CAN_PROTO_N_TX] = {0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 9u, 10u, 11u, 12u, 13u, 14u, 15u, 8u};

/* The code index fields are 4 bits (CAN_PROTO_DTC_NONE = 15 means none) and the mask 16 bits. */
typedef char can_proto_dtc_fits_t[(unsigned)DIAG_DTC_COUNT <= CAN_PROTO_DTC_NONE ? 1 : -1];

/* Tolerance of the receive range check, in counts: accepts min/max themselves despite the
 * float rounding of raw * scale, and nothing one count beyond. */
#define RANGE_TOL_COUNTS 1e-3f

/* ---- CRC, bits ---------------------------------------------------------------------------- */

uint8_t can_proto_crc8(const uint8_t *data, size_t len)
{
    uint8_t crc = CAN_PROTO_CRC8_INIT;
    size_t i;
    for (i = 0; i < len; ++i) {
        int b;
        crc = (uint8_t)(crc ^ data[i]);
        for (b = 0; b < 8; ++b) {
            const unsigned shifted = ((unsigned)crc << 1) & 0xFFu;
            crc = (uint8_t)((crc & 0x80u) != 0u ? (shifted ^ CAN_PROTO_CRC8_POLY) : shifted);
        }
    }
    return (uint8_t)(crc ^ CAN_PROTO_CRC8_XOROUT);
}

uint8_t can_proto_frame_crc(const hal_can_frame_t *frame)
{
    uint8_t buf[2u + 7u];
    if (frame == NULL) {
        return 0u;
    }
    buf[0] = (uint8_t)(frame->id & 0xFFu);
    buf[1] = (uint8_t)((frame->id >> 8) & 0xFFu);
    memcpy(&buf[2], &frame->data[1], 7u);
    return can_proto_crc8(buf, sizeof buf);
}

uint8_t can_proto_frame_counter(const hal_can_frame_t *frame)
{
    return frame == NULL ? 0u : (uint8_t)(frame->data[1] & 0x0Fu);
}

static void put_bits(uint8_t data[8], unsigned start, unsigned len, uint32_t raw)
{
    unsigned k;
    for (k = 0; k < len; ++k) {
        const unsigned bit = start + k;
        const uint8_t mask = (uint8_t)(1u << (bit % 8u));
        if (((raw >> k) & 1u) != 0u) {
            data[bit / 8u] = (uint8_t)(data[bit / 8u] | mask);
        } else {
            data[bit / 8u] = (uint8_t)(data[bit / 8u] & (uint8_t)~mask);
        }
    }
}

static uint32_t get_bits(const uint8_t data[8], unsigned start, unsigned len)
{
    uint32_t raw = 0u;
    unsigned k;
    for (k = 0; k < len; ++k) {
        const unsigned bit = start + k;
        if (((data[bit / 8u] >> (bit % 8u)) & 1u) != 0u) {
            raw |= (uint32_t)1u << k;
        }
    }
    return raw;
}

static int64_t raw_min(const can_proto_signal_t *s)
{
    return s->is_signed ? -((int64_t)1 << (s->length - 1u)) : 0;
}

static int64_t raw_max(const can_proto_signal_t *s)
{
    return s->is_signed ? ((int64_t)1 << (s->length - 1u)) - 1 : ((int64_t)1 << s->length) - 1;
}

static uint32_t field_mask(const can_proto_signal_t *s)
{
    return s->length >= 32u ? 0xFFFFFFFFu : (((uint32_t)1u << s->length) - 1u);
}

static float raw_to_phys(const can_proto_signal_t *s, uint32_t bits)
{
    int64_t raw = (int64_t)bits;
    if (s->length == 0u || s->length > 32u) { /* not in the tables; keeps the shifts defined */
        return s->offset;
    }
    if (s->is_signed && (bits & ((uint32_t)1u << (s->length - 1u))) != 0u) {
        raw -= (int64_t)1 << s->length;
    }
    return (float)raw * s->scale + s->offset;
}

/* Physical value to raw bits. saturate: clamp to the field (NaN -> 0); else TV_ERR_RANGE when
 * outside [min, max] or the field. */
static int phys_to_bits(const can_proto_signal_t *s, float phys, int saturate, uint32_t *bits)
{
    const float lo = (float)raw_min(s);
    const float hi = (float)raw_max(s);
    float x;
    int64_t raw;
    if (!(phys == phys)) { /* NaN */
        if (!saturate) {
            return TV_ERR_NONFINITE;
        }
        phys = s->offset; /* raw 0 */
    } else if (phys - phys != 0.0f && !saturate) { /* +-Inf: saturates below when allowed */
        return TV_ERR_NONFINITE;
    }
    x = (phys - s->offset) / s->scale;
    /* Clamp one count beyond the field first, so the conversion to an integer is defined,
     * then round half away from zero (no libm needed). */
    x = x < lo - 1.0f ? lo - 1.0f : (x > hi + 1.0f ? hi + 1.0f : x);
    x = x >= 0.0f ? (float)(int64_t)(x + 0.5f) : -(float)(int64_t)(0.5f - x);
    if (!saturate) {
        const float rlo = (s->min - s->offset) / s->scale - RANGE_TOL_COUNTS;
        const float rhi = (s->max - s->offset) / s->scale + RANGE_TOL_COUNTS;
        if (x < rlo || x > rhi || x < lo || x > hi) {
            return TV_ERR_RANGE;
        }
    }
    raw = (int64_t)x;
    raw = raw < raw_min(s) ? raw_min(s) : (raw > raw_max(s) ? raw_max(s) : raw);
    *bits = (uint32_t)((uint64_t)raw & field_mask(s));
    return TV_OK;
}

/* ---- generic frames ----------------------------------------------------------------------- */

const can_proto_msg_t *can_proto_find_msg(uint32_t id)
{
    size_t i;
    for (i = 0; i < sizeof s_msgs / sizeof s_msgs[0]; ++i) {
        if (s_msgs[i].id == id) {
            return &s_msgs[i];
        }
    }
    return NULL;
}

const can_proto_msg_t *can_proto_msg_at(size_t i)
{
    return i < sizeof s_msgs / sizeof s_msgs[0] ? &s_msgs[i] : NULL;
}

int can_proto_pack(const can_proto_msg_t *msg, const float *phys, uint8_t counter, int saturate,
                   hal_can_frame_t *frame)
{
    hal_can_frame_t f;
    uint8_t k;
    if (msg == NULL || phys == NULL || frame == NULL) {
        return TV_ERR_NULL;
    }
    if (counter > 15u) {
        return TV_ERR_RANGE;
    }
    memset(&f, 0, sizeof f);
    f.id = msg->id;
    f.extended = 0u;
    f.dlc = CAN_PROTO_DLC;
    for (k = 2u; k < msg->n_signals; ++k) {
        uint32_t bits = 0u;
        const int rc = phys_to_bits(&msg->signals[k], phys[k], saturate, &bits);
        if (rc != TV_OK) {
            return rc;
        }
        put_bits(f.data, msg->signals[k].start_bit, msg->signals[k].length, bits);
    }
    put_bits(f.data, 8u, 4u, counter);
    f.data[0] = can_proto_frame_crc(&f);
    *frame = f;
    return TV_OK;
}

int can_proto_unpack(const can_proto_msg_t *msg, const hal_can_frame_t *frame, float *phys)
{
    uint8_t k;
    if (msg == NULL || frame == NULL || phys == NULL) {
        return TV_ERR_NULL;
    }
    for (k = 0u; k < msg->n_signals; ++k) {
        const can_proto_signal_t *s = &msg->signals[k];
        phys[k] = raw_to_phys(s, get_bits(frame->data, s->start_bit, s->length));
    }
    return TV_OK;
}

/* Range check of a command's signals (index >= 2), in counts. */
static int in_range(const can_proto_msg_t *msg, const float *phys)
{
    uint8_t k;
    for (k = 2u; k < msg->n_signals; ++k) {
        const can_proto_signal_t *s = &msg->signals[k];
        const float x = (phys[k] - s->offset) / s->scale;
        if (x < (s->min - s->offset) / s->scale - RANGE_TOL_COUNTS ||
            x > (s->max - s->offset) / s->scale + RANGE_TOL_COUNTS) {
            return 0;
        }
    }
    return 1;
}

int can_proto_check(const hal_can_frame_t *frame)
{
    const can_proto_msg_t *msg;
    if (frame == NULL) {
        return TV_ERR_NULL;
    }
    msg = frame->extended ? NULL : can_proto_find_msg(frame->id);
    if (msg == NULL) {
        return CAN_PROTO_RX_UNKNOWN_ID;
    }
    if (frame->dlc != CAN_PROTO_DLC) {
        return CAN_PROTO_RX_BAD_DLC;
    }
    if (can_proto_frame_crc(frame) != frame->data[0]) {
        return CAN_PROTO_RX_BAD_CRC;
    }
    if (msg->is_command) {
        float phys[CAN_PROTO_MAX_SIGNALS] = {0.0f};
        (void)can_proto_unpack(msg, frame, phys);
        if (!in_range(msg, phys)) {
            return CAN_PROTO_RX_RANGE;
        }
    }
    return CAN_PROTO_RX_ACCEPTED;
}

/* ---- typed commands ----------------------------------------------------------------------- */

/* Validate a command frame of table entry k (id, CRC, counter field) and unpack its signals. */
static int unpack_command(const hal_can_frame_t *frame, size_t k, float *phys)
{
    int rc;
    if (frame == NULL) {
        return TV_ERR_NULL;
    }
    if (frame->extended || frame->id != s_msgs[k].id) {
        return CAN_PROTO_RX_UNKNOWN_ID;
    }
    rc = can_proto_check(frame);
    if (rc == CAN_PROTO_RX_ACCEPTED) {
        (void)can_proto_unpack(&s_msgs[k], frame, phys);
    }
    return rc;
}

int can_proto_decode_control(const hal_can_frame_t *frame, can_proto_control_t *cmd)
{
    float phys[CAN_PROTO_MAX_SIGNALS] = {0.0f};
    const int rc = cmd == NULL ? TV_ERR_NULL : unpack_command(frame, 0, phys);
    if (rc != CAN_PROTO_RX_ACCEPTED) {
        return rc;
    }
    cmd->mode = (app_mode_t)(int)phys[2];
    if (cmd->mode == APP_MODE_EXTERNAL) {
        /* replay only: another controller's duty comes from a log, never over CAN */
        return CAN_PROTO_RX_RANGE;
    }
    cmd->target_rad = phys[3];
    cmd->duty_limit = phys[4];
    cmd->fault_clear = phys[5] != 0.0f ? 1u : 0u;
    cmd->temp_valid = phys[6] != 0.0f ? 1u : 0u;
    cmd->winding_temp_C = phys[7];
    return CAN_PROTO_RX_ACCEPTED;
}

int can_proto_decode_excitation(const hal_can_frame_t *frame, can_proto_excitation_t *cmd)
{
    float phys[CAN_PROTO_MAX_SIGNALS] = {0.0f};
    const int rc = cmd == NULL ? TV_ERR_NULL : unpack_command(frame, 1, phys);
    if (rc != CAN_PROTO_RX_ACCEPTED) {
        return rc;
    }
    cmd->amplitude_V = phys[2];
    cmd->freq_Hz = phys[3];
    cmd->chirp_f1_Hz = phys[4];
    cmd->chirp_period_s = phys[5];
    return CAN_PROTO_RX_ACCEPTED;
}

/* ---- telemetry ---------------------------------------------------------------------------- */

void can_proto_telemetry_from_app(const app_t *app, const app_output_t *out, can_proto_telemetry_t *tm)
{
    int k;
    if (tm == NULL) {
        return;
    }
    if (app != NULL) {
        tm->mode = (uint8_t)app->cfg.control.mode;
        tm->ekf_rejected = app->ekf.n_rejected;
    }
    tm->last_dtc = CAN_PROTO_DTC_NONE;
    tm->freeze_dtc = CAN_PROTO_DTC_NONE;
    if (app != NULL && app->diag.last_confirmed < (uint8_t)DIAG_DTC_COUNT) {
        const diag_code_state_t *c = &app->diag.code[app->diag.last_confirmed];
        const diag_freeze_t *fz = &c->freeze;
        tm->last_dtc = app->diag.last_confirmed;
        tm->last_dtc_status = c->confirmed ? 1u : 2u;
        tm->last_dtc_confirmations = (uint8_t)(c->confirmations < 255u ? c->confirmations : 255u);
        tm->last_dtc_time_s = fz->t_us >= app->t0_us ? (float)(fz->t_us - app->t0_us) * 1e-6f : 0.0f;
        tm->freeze_dtc = app->diag.last_confirmed;
        tm->freeze_angle_rad = (float)fz->x[TVM_PHI];
        tm->freeze_velocity_rad_s = (float)fz->x[TVM_W];
        tm->freeze_duty = (float)fz->duty;
        tm->freeze_supply_V = (float)fz->supply_V;
        tm->freeze_current_A = (float)fz->x[TVM_I];
    }
    if (out == NULL) {
        return;
    }
    for (k = 0; k < 3; ++k) {
        tm->est[k] = (float)out->x[k];
        tm->sigma[k] = (float)out->sigma[k];
        tm->innov[k] = (float)out->innov.innov[k];
    }
    tm->nis = (float)out->innov.nis_total;
    tm->duty = out->duty;
    tm->meas_current_A = (float)out->z[EKF_CH_CURRENT];
    tm->meas_angle_rad = (float)out->z[EKF_CH_ANGLE];
    tm->supply_V = (float)out->supply_V;
    tm->faults = (uint16_t)(out->faults & 0xFFFu);
    tm->bridge_enable = out->bridge_enable != 0u ? 1u : 0u;
    tm->ekf_ok = out->ekf_status == TV_OK && out->innov.n_used > 0u ? 1u : 0u;
    tm->channels_used = out->innov.n_used > 3u ? 3u : out->innov.n_used;
    tm->r_est_ohm = (float)out->r_est_ohm;
    tm->r_sigma_ohm = (float)out->r_sigma_ohm;
    tm->friction_rel = (float)out->friction_rel;
    tm->friction_rel_sigma = (float)out->friction_rel_sigma;
    tm->preload_rel = (float)out->preload_rel;
    tm->preload_rel_sigma = (float)out->preload_rel_sigma;
    tm->stop_closed_rad = (float)out->stop_closed_rad;
    tm->stop_open_rad = (float)out->stop_open_rad;
    tm->tps_diff_rad = (float)out->tps_diff_rad;
    tm->tps_diff_sd_rad = (float)out->tps_diff_sd_rad;
    tm->r_20_ohm = (float)out->r_20_ohm;
    tm->fit_r_ohm = (float)out->fit_r_ohm;
    tm->fit_r_sigma_ohm = (float)out->fit_r_sigma_ohm;
    tm->fit_nke_V_s = (float)out->fit_nke_V_s;
    tm->fit_i_off_A = (float)out->fit_i_off_A;
    tm->fit_base_r_ohm = (float)out->fit_base_r_ohm;
    tm->fit_base_nke_V_s = (float)out->fit_base_nke_V_s;
    tm->fit_base_state = out->fit_base_state;
    tm->fit_base_windows = out->fit_base_windows;
    {
        uint32_t mask = out->dtc_confirmed & 0xFFFFu;
        uint8_t n = 0u;
        tm->dtc_mask = (uint16_t)mask;
        while (mask != 0u) { /* at most 16 iterations */
            mask &= mask - 1u;
            ++n;
        }
        tm->dtc_count = n;
        tm->dtc_action = out->dtc_action;
    }
}

/* Physical values of one telemetry frame, in signal order. */
static int telemetry_phys(uint32_t id, const can_proto_telemetry_t *tm, float *p)
{
    switch (id) {
    case CAN_PROTO_ID_EST_STATE:
        p[2] = tm->est[0];
        p[3] = tm->est[1];
        p[4] = tm->est[2];
        return TV_OK;
    case CAN_PROTO_ID_EST_SIGMA:
        p[2] = tm->sigma[0];
        p[3] = tm->sigma[1];
        p[4] = tm->sigma[2];
        return TV_OK;
    case CAN_PROTO_ID_EST_INNOV:
        p[2] = tm->innov[0];
        p[3] = tm->innov[1];
        p[4] = tm->innov[2];
        return TV_OK;
    case CAN_PROTO_ID_STATUS:
        p[2] = (float)tm->mode;
        p[3] = (float)tm->faults;
        p[4] = (float)(tm->bridge_enable != 0u);
        p[5] = (float)(tm->ekf_ok != 0u);
        p[6] = (float)(tm->cmd_active != 0u);
        p[7] = (float)(tm->cmd_timeout != 0u);
        p[8] = (float)tm->channels_used;
        p[9] = (float)(tm->hal_error != 0u);
        p[10] = tm->nis;
        p[11] = tm->duty;
        return TV_OK;
    case CAN_PROTO_ID_MEAS:
        p[2] = tm->meas_current_A;
        p[3] = tm->meas_angle_rad;
        p[4] = tm->supply_V;
        return TV_OK;
    case CAN_PROTO_ID_LOOP:
        p[2] = (float)tm->loop.overruns;
        p[3] = (float)tm->loop.latency_max_us;
        p[4] = (float)tm->loop.exec_max_us;
        return TV_OK;
    case CAN_PROTO_ID_CMD_STATS:
        p[2] = (float)(tm->rx.timeouts % 16u);
        p[3] = (float)(tm->rx.accepted % 256u);
        p[4] = (float)(tm->rx.crc % 256u);
        p[5] = (float)((tm->rx.repeated + tm->rx.sequence) % 256u);
        p[6] = (float)(tm->rx.dlc % 256u);
        p[7] = (float)(tm->rx.range % 256u);
        p[8] = (float)(tm->rx.unknown % 256u);
        return TV_OK;
    case CAN_PROTO_ID_EKF_STATS:
        p[2] = tm->nis_mean;
        p[3] = (float)tm->corrections;
        p[4] = (float)(tm->ekf_rejected % 65536u);
        return TV_OK;
    case CAN_PROTO_ID_TIME:
        p[2] = 0.0f; /* written as an integer by can_proto_encode_telemetry() */
        return TV_OK;
    case CAN_PROTO_ID_HEALTH_1:
        p[2] = tm->r_est_ohm;
        p[3] = tm->r_sigma_ohm;
        p[4] = tm->friction_rel;
        p[5] = tm->friction_rel_sigma;
        return TV_OK;
    case CAN_PROTO_ID_HEALTH_2:
        p[2] = tm->preload_rel;
        p[3] = tm->preload_rel_sigma;
        p[4] = tm->stop_closed_rad;
        p[5] = tm->stop_open_rad;
        return TV_OK;
    case CAN_PROTO_ID_HEALTH_3:
        p[2] = tm->tps_diff_rad;
        p[3] = tm->tps_diff_sd_rad;
        p[4] = tm->r_20_ohm;
        return TV_OK;
    case CAN_PROTO_ID_HEALTH_4:
        p[2] = tm->fit_r_ohm;
        p[3] = tm->fit_r_sigma_ohm;
        p[4] = tm->fit_nke_V_s;
        p[5] = tm->fit_i_off_A;
        return TV_OK;
    case CAN_PROTO_ID_HEALTH_5:
        p[2] = tm->fit_base_r_ohm;
        p[3] = tm->fit_base_nke_V_s;
        p[4] = (float)tm->fit_base_state;
        p[5] = (float)tm->fit_base_windows;
        return TV_OK;
    case CAN_PROTO_ID_DIAG:
        p[2] = (float)tm->dtc_count;
        p[3] = (float)tm->last_dtc;
        p[4] = (float)tm->last_dtc_status;
        p[5] = (float)tm->dtc_action;
        p[6] = (float)tm->last_dtc_confirmations;
        p[7] = (float)tm->dtc_mask;
        p[8] = tm->last_dtc_time_s;
        return TV_OK;
    case CAN_PROTO_ID_DIAG_FREEZE:
        p[2] = (float)tm->freeze_dtc;
        if (tm->freeze_dtc >= CAN_PROTO_DTC_NONE) {
            p[3] = -0.5f; /* raw 0: no frame */
            return TV_OK;
        }
        p[3] = tm->freeze_angle_rad;
        p[4] = tm->freeze_velocity_rad_s;
        p[5] = tm->freeze_duty;
        p[6] = tm->freeze_supply_V;
        p[7] = tm->freeze_current_A;
        return TV_OK;
    default:
        return TV_ERR_RANGE;
    }
}

int can_proto_encode_telemetry(uint32_t id, const can_proto_telemetry_t *tm, uint8_t counter, hal_can_frame_t *frame)
{
    float phys[CAN_PROTO_MAX_SIGNALS];
    const can_proto_msg_t *msg;
    int rc;
    if (tm == NULL || frame == NULL) {
        return TV_ERR_NULL;
    }
    msg = can_proto_find_msg(id);
    if (msg == NULL || msg->is_command) {
        return TV_ERR_RANGE;
    }
    memset(phys, 0, sizeof phys);
    rc = telemetry_phys(id, tm, phys);
    if (rc != TV_OK) {
        return rc;
    }
    rc = can_proto_pack(msg, phys, counter, 1, frame);
    if (rc == TV_OK && id == CAN_PROTO_ID_TIME) {
        put_bits(frame->data, 16u, 32u, tm->loop.sample_time_us);
        frame->data[0] = can_proto_frame_crc(frame);
    }
    return rc;
}

int can_proto_encode_ecu_cpu(uint32_t cycles_max, uint32_t cycles_mean, uint32_t over_budget, uint8_t counter,
                             hal_can_frame_t *frame)
{
    const uint32_t cap = 65535u;
    const float phys[5] = {0.0f, 0.0f, (float)(cycles_max < cap ? cycles_max : cap),
                           (float)(cycles_mean < cap ? cycles_mean : cap), (float)(over_budget < cap ? over_budget : cap)};
    if (frame == NULL) {
        return TV_ERR_NULL;
    }
    return can_proto_pack(&s_msgs[CAN_PROTO_N_CMD + CAN_PROTO_N_TX], phys, counter, 1, frame);
}

/* ---- the node ----------------------------------------------------------------------------- */

void can_proto_config_default(can_proto_config_t *cfg)
{
    size_t k;
    if (cfg == NULL) {
        return;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->cmd_timeout_ms = 100u;
    cfg->max_counter_delta = 2u;
    for (k = 0; k < CAN_PROTO_N_TX; ++k) {
        cfg->period_ms[k] = k <= (size_t)CAN_PROTO_TX_MEAS || k == (size_t)CAN_PROTO_TX_TIME ? 10u : 100u;
    }
    cfg->period_ms[CAN_PROTO_TX_HEALTH_5] = 1000u; /* the fit's baseline: it changes once in a unit's life */
}

/* The control the application should run: the commanded one, OFF while a watchdog-protected
 * link is not ACTIVE. Calls app_set_control() only on a change, app_set_target() when only the
 * target changed. */
static int apply_control(can_proto_node_t *node, app_t *app)
{
    app_control_t eff = node->commanded;
    const app_control_t *cur = &app->cfg.control;
    if (node->cfg.cmd_timeout_ms > 0u && node->link != (uint8_t)CAN_PROTO_LINK_ACTIVE) {
        eff.mode = APP_MODE_OFF;
    }
    if (eff.mode == cur->mode && eff.amplitude_V == cur->amplitude_V && eff.freq_Hz == cur->freq_Hz &&
        eff.chirp_f1_Hz == cur->chirp_f1_Hz && eff.chirp_period_s == cur->chirp_period_s &&
        eff.duty_limit == cur->duty_limit) {
        /* Only the target moved (or nothing): a new set-point for the running position loop,
         * which keeps its integrator (app_set_control() would reset it: a bump on every step of
         * the target). */
        return eff.target_rad == cur->target_rad ? TV_OK : app_set_target(app, eff.target_rad);
    }
    return app_set_control(app, &eff);
}

int can_proto_node_init(can_proto_node_t *node, const can_proto_config_t *cfg, app_t *app)
{
    can_proto_node_t n;
    if (node == NULL || cfg == NULL || app == NULL) {
        return TV_ERR_NULL;
    }
    if (cfg->cmd_timeout_ms > CAN_PROTO_TIMEOUT_MAX_MS || cfg->max_counter_delta < 1u ||
        cfg->max_counter_delta > 14u) {
        return TV_ERR_CONFIG;
    }
    memset(&n, 0, sizeof n);
    n.cfg = *cfg;
    n.commanded = app->cfg.control;
    n.link = (uint8_t)CAN_PROTO_LINK_WAITING;
    if (apply_control(&n, app) != TV_OK) {
        return TV_ERR_CONFIG;
    }
    *node = n;
    return TV_OK;
}

can_proto_link_t can_proto_node_link(const can_proto_node_t *node)
{
    return node == NULL ? CAN_PROTO_LINK_WAITING : (can_proto_link_t)node->link;
}

int can_proto_node_receive(can_proto_node_t *node, app_t *app, const hal_can_frame_t *frame, uint64_t t_us)
{
    unsigned idx;
    uint8_t ctr;
    int rc;
    app_control_t before;
    if (node == NULL || app == NULL || frame == NULL) {
        return TV_ERR_NULL;
    }
    if (frame->extended || (frame->id != CAN_PROTO_ID_CMD_CONTROL && frame->id != CAN_PROTO_ID_CMD_EXCITATION)) {
        ++node->stats.unknown;
        return CAN_PROTO_RX_UNKNOWN_ID;
    }
    idx = (unsigned)(frame->id - CAN_PROTO_ID_CMD_CONTROL);
    if (frame->dlc != CAN_PROTO_DLC) {
        ++node->stats.dlc;
        return CAN_PROTO_RX_BAD_DLC;
    }
    if (can_proto_frame_crc(frame) != frame->data[0]) {
        ++node->stats.crc;
        return CAN_PROTO_RX_BAD_CRC;
    }
    ctr = can_proto_frame_counter(frame);
    if (node->rx_have[idx]) {
        const unsigned d = ((unsigned)ctr - (unsigned)node->rx_counter[idx]) & 0x0Fu;
        if (d == 0u) {
            ++node->stats.repeated;
            return CAN_PROTO_RX_REPEATED;
        }
        if (d > node->cfg.max_counter_delta) {
            node->rx_counter[idx] = ctr;
            ++node->stats.sequence;
            return CAN_PROTO_RX_SEQUENCE;
        }
    }
    node->rx_have[idx] = 1u;
    node->rx_counter[idx] = ctr;

    before = node->commanded;
    if (idx == 0u) {
        can_proto_control_t c;
        rc = can_proto_decode_control(frame, &c);
        if (rc != CAN_PROTO_RX_ACCEPTED) {
            ++node->stats.range;
            return CAN_PROTO_RX_RANGE;
        }
        if (app_set_winding_temp(app, c.temp_valid, (tv_real_t)c.winding_temp_C) != TV_OK) {
            ++node->stats.range; /* not reached: the signal's range is the application's */
            return CAN_PROTO_RX_RANGE;
        }
        node->commanded.mode = c.mode;
        node->commanded.target_rad = (tv_real_t)c.target_rad;
        node->commanded.duty_limit = (tv_real_t)c.duty_limit;
        node->last_control_us = t_us;
        if (c.fault_clear && !node->last_clear) {
            app_clear_faults(app);
            node->link = (uint8_t)CAN_PROTO_LINK_ACTIVE;
        } else if (node->link == (uint8_t)CAN_PROTO_LINK_WAITING) {
            node->link = (uint8_t)CAN_PROTO_LINK_ACTIVE;
        }
        node->last_clear = c.fault_clear;
    } else {
        can_proto_excitation_t e;
        rc = can_proto_decode_excitation(frame, &e);
        if (rc != CAN_PROTO_RX_ACCEPTED) {
            ++node->stats.range;
            return CAN_PROTO_RX_RANGE;
        }
        node->commanded.amplitude_V = (tv_real_t)e.amplitude_V;
        node->commanded.freq_Hz = (tv_real_t)e.freq_Hz;
        node->commanded.chirp_f1_Hz = (tv_real_t)e.chirp_f1_Hz;
        node->commanded.chirp_period_s = (tv_real_t)e.chirp_period_s;
    }
    if (apply_control(node, app) != TV_OK) {
        /* The application refused the combination: keep what runs, count it as out of range. */
        node->commanded = before;
        ++node->stats.range;
        return CAN_PROTO_RX_RANGE;
    }
    ++node->stats.accepted;
    return CAN_PROTO_RX_ACCEPTED;
}

void can_proto_node_update(can_proto_node_t *node, app_t *app, const app_output_t *out, uint64_t t_us)
{
    if (node == NULL || app == NULL) {
        return;
    }
    if (node->cfg.cmd_timeout_ms > 0u && node->link == (uint8_t)CAN_PROTO_LINK_ACTIVE && t_us > node->last_control_us &&
        t_us - node->last_control_us > (uint64_t)node->cfg.cmd_timeout_ms * 1000u) {
        node->link = (uint8_t)CAN_PROTO_LINK_TIMEOUT;
        ++node->stats.timeouts;
        (void)apply_control(node, app); /* to OFF: always valid */
    }
    if (out != NULL && out->ekf_status == TV_OK && out->innov.n_used > 0u) {
        node->nis_sum += (float)out->innov.nis_total;
        ++node->nis_n;
    }
}

size_t can_proto_node_transmit(can_proto_node_t *node, const app_t *app, const app_output_t *out,
                               const can_proto_loop_stats_t *loop, int hal_error, uint64_t t_us,
                               hal_can_frame_t frames[CAN_PROTO_N_TX])
{
    can_proto_telemetry_t tm;
    size_t n = 0;
    size_t i;
    size_t k;
    if (node == NULL || app == NULL || frames == NULL) {
        return 0;
    }
    if (!node->tx_started) {
        for (k = 0; k < CAN_PROTO_N_TX; ++k) {
            node->tx_due_us[k] = t_us + (uint64_t)s_tx_offset_ms[k] * 1000u;
        }
        node->tx_started = 1u;
    }
    memset(&tm, 0, sizeof tm);
    can_proto_telemetry_from_app(app, out, &tm);
    tm.cmd_active = node->link == (uint8_t)CAN_PROTO_LINK_ACTIVE ? 1u : 0u;
    tm.cmd_timeout = node->link == (uint8_t)CAN_PROTO_LINK_TIMEOUT ? 1u : 0u;
    tm.hal_error = hal_error ? 1u : 0u;
    if (loop != NULL) {
        tm.loop = *loop;
    }
    tm.rx = node->stats;
    tm.nis_mean = node->nis_n > 0u ? node->nis_sum / (float)node->nis_n : 0.0f;
    tm.corrections = node->nis_n;
    for (i = 0; i < CAN_PROTO_N_TX; ++i) {
        const uint64_t period_us = (uint64_t)node->cfg.period_ms[s_tx_order[i]] * 1000u;
        k = s_tx_order[i];
        if (period_us == 0u || t_us < node->tx_due_us[k]) {
            continue;
        }
        if (can_proto_encode_telemetry(s_msgs[CAN_PROTO_N_CMD + k].id, &tm, node->tx_counter[k], &frames[n]) == TV_OK) {
            ++n;
            node->tx_counter[k] = (uint8_t)((node->tx_counter[k] + 1u) & 0x0Fu);
        }
        node->tx_due_us[k] += period_us;
        if (node->tx_due_us[k] <= t_us) {
            node->tx_due_us[k] = t_us + period_us;
        }
        if (k == (size_t)CAN_PROTO_TX_EKF_STATS) {
            node->nis_sum = 0.0f;
            node->nis_n = 0u;
        }
    }
    return n;
}
