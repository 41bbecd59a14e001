/**
 * @file can_host.c
 * @brief Command encoders and telemetry decoder of the CAN protocol, host side (see can_host.h).
 */
#include "can_host.h"

#include <string.h>

#include "tv_status.h"

int can_host_encode_control(const can_proto_control_t *cmd, uint8_t counter, hal_can_frame_t *frame)
{
    float phys[8];
    if (cmd == NULL || frame == NULL) {
        return TV_ERR_NULL;
    }
    phys[0] = 0.0f;
    phys[1] = 0.0f;
    phys[2] = (float)(unsigned)cmd->mode;
    phys[3] = cmd->target_rad;
    phys[4] = cmd->duty_limit;
    phys[5] = cmd->fault_clear != 0u ? 1.0f : 0.0f;
    phys[6] = cmd->temp_valid != 0u ? 1.0f : 0.0f;
    phys[7] = cmd->temp_valid != 0u ? cmd->winding_temp_C : -40.0f; /* raw 0 when unknown */
    if ((unsigned)cmd->mode > (unsigned)APP_MODE_IDENT || cmd->mode == APP_MODE_EXTERNAL) {
        return TV_ERR_RANGE;
    }
    return can_proto_pack(can_proto_find_msg(CAN_PROTO_ID_CMD_CONTROL), phys, counter, 0, frame);
}

int can_host_encode_excitation(const can_proto_excitation_t *cmd, uint8_t counter, hal_can_frame_t *frame)
{
    float phys[6];
    if (cmd == NULL || frame == NULL) {
        return TV_ERR_NULL;
    }
    phys[0] = 0.0f;
    phys[1] = 0.0f;
    phys[2] = cmd->amplitude_V;
    phys[3] = cmd->freq_Hz;
    phys[4] = cmd->chirp_f1_Hz;
    phys[5] = cmd->chirp_period_s;
    return can_proto_pack(can_proto_find_msg(CAN_PROTO_ID_CMD_EXCITATION), phys, counter, 0, frame);
}

static uint32_t u32_of(float v)
{
    return v <= 0.0f ? 0u : (uint32_t)(v + 0.5f);
}

int can_host_decode_telemetry(const hal_can_frame_t *frame, can_proto_telemetry_t *tm)
{
    float p[CAN_PROTO_MAX_SIGNALS] = {0.0f};
    const can_proto_msg_t *msg;
    int rc;
    if (frame == NULL || tm == NULL) {
        return TV_ERR_NULL;
    }
    msg = frame->extended ? NULL : can_proto_find_msg(frame->id);
    if (msg == NULL || msg->is_command) {
        return CAN_PROTO_RX_UNKNOWN_ID;
    }
    rc = can_proto_check(frame);
    if (rc != CAN_PROTO_RX_ACCEPTED) {
        return rc;
    }
    (void)can_proto_unpack(msg, frame, p);
    switch (frame->id) {
    case CAN_PROTO_ID_EST_STATE:
        memcpy(tm->est, &p[2], sizeof tm->est);
        break;
    case CAN_PROTO_ID_EST_SIGMA:
        memcpy(tm->sigma, &p[2], sizeof tm->sigma);
        break;
    case CAN_PROTO_ID_EST_INNOV:
        memcpy(tm->innov, &p[2], sizeof tm->innov);
        break;
    case CAN_PROTO_ID_STATUS:
        tm->mode = (uint8_t)u32_of(p[2]);
        tm->faults = (uint16_t)u32_of(p[3]);
        tm->bridge_enable = (uint8_t)u32_of(p[4]);
        tm->ekf_ok = (uint8_t)u32_of(p[5]);
        tm->cmd_active = (uint8_t)u32_of(p[6]);
        tm->cmd_timeout = (uint8_t)u32_of(p[7]);
        tm->channels_used = (uint8_t)u32_of(p[8]);
        tm->hal_error = (uint8_t)u32_of(p[9]);
        tm->nis = p[10];
        tm->duty = p[11];
        break;
    case CAN_PROTO_ID_MEAS:
        tm->meas_current_A = p[2];
        tm->meas_angle_rad = p[3];
        tm->supply_V = p[4];
        break;
    case CAN_PROTO_ID_LOOP:
        tm->loop.overruns = u32_of(p[2]);
        tm->loop.latency_max_us = u32_of(p[3]);
        tm->loop.exec_max_us = u32_of(p[4]);
        break;
    case CAN_PROTO_ID_CMD_STATS:
        tm->rx.timeouts = u32_of(p[2]);
        tm->rx.accepted = u32_of(p[3]);
        tm->rx.crc = u32_of(p[4]);
        tm->rx.repeated = u32_of(p[5]); /* repeated + sequence, as sent */
        tm->rx.sequence = 0u;
        tm->rx.dlc = u32_of(p[6]);
        tm->rx.range = u32_of(p[7]);
        tm->rx.unknown = u32_of(p[8]);
        break;
    case CAN_PROTO_ID_TIME:
        tm->loop.sample_time_us = (uint32_t)frame->data[2] | (uint32_t)frame->data[3] << 8 | (uint32_t)frame->data[4] << 16 |
                                  (uint32_t)frame->data[5] << 24 /* bits 16..47, Intel order */;
        break;
    case CAN_PROTO_ID_HEALTH_1:
        tm->r_est_ohm = p[2];
        tm->r_sigma_ohm = p[3];
        tm->friction_rel = p[4];
        tm->friction_rel_sigma = p[5];
        break;
    case CAN_PROTO_ID_HEALTH_2:
        tm->preload_rel = p[2];
        tm->preload_rel_sigma = p[3];
        tm->stop_closed_rad = p[4];
        tm->stop_open_rad = p[5];
        break;
    case CAN_PROTO_ID_HEALTH_3:
        tm->tps_diff_rad = p[2];
        tm->tps_diff_sd_rad = p[3];
        tm->r_20_ohm = p[4];
        break;
    case CAN_PROTO_ID_HEALTH_4:
        tm->fit_r_ohm = p[2];
        tm->fit_r_sigma_ohm = p[3];
        tm->fit_nke_V_s = p[4];
        tm->fit_i_off_A = p[5];
        break;
    case CAN_PROTO_ID_HEALTH_5:
        tm->fit_base_r_ohm = p[2];
        tm->fit_base_nke_V_s = p[3];
        tm->fit_base_state = (uint8_t)u32_of(p[4]);
        tm->fit_base_windows = (uint16_t)u32_of(p[5]);
        break;
    case CAN_PROTO_ID_DIAG:
        tm->dtc_count = (uint8_t)u32_of(p[2]);
        tm->last_dtc = (uint8_t)u32_of(p[3]);
        tm->last_dtc_status = (uint8_t)u32_of(p[4]);
        tm->dtc_action = (uint8_t)u32_of(p[5]);
        tm->last_dtc_confirmations = (uint8_t)u32_of(p[6]);
        tm->dtc_mask = (uint16_t)u32_of(p[7]);
        tm->last_dtc_time_s = p[8];
        break;
    case CAN_PROTO_ID_DIAG_FREEZE:
        tm->freeze_dtc = (uint8_t)u32_of(p[2]);
        tm->freeze_angle_rad = p[3];
        tm->freeze_velocity_rad_s = p[4];
        tm->freeze_duty = p[5];
        tm->freeze_supply_V = p[6];
        tm->freeze_current_A = p[7];
        break;
    default: /* CAN_PROTO_ID_EKF_STATS, the only telemetry id left */
        tm->nis_mean = p[2];
        tm->corrections = u32_of(p[3]);
        tm->ekf_rejected = u32_of(p[4]);
        break;
    }
    return CAN_PROTO_RX_ACCEPTED;
}

