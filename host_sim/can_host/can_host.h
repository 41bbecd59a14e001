/**
 * @file can_host.h
 * @brief Host side of the CAN protocol (firmware/protocols/can_proto.h): the command encoders a
 *        bench commander sends with and the telemetry decoder it reads with. No firmware image
 *        runs them, so they live here (throttle_cmd, the tests, the VM test).
 */
#ifndef CAN_HOST_H
#define CAN_HOST_H

#include "can_proto.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Encode TV_CMD_CONTROL (for commanders and tests).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE / TV_ERR_NONFINITE when a value is outside its
 *         valid range or counter > 15.
 */
int can_host_encode_control(const can_proto_control_t *cmd, uint8_t counter, hal_can_frame_t *frame);

/** Encode TV_CMD_EXCITATION; returns as can_host_encode_control(). */
int can_host_encode_excitation(const can_proto_excitation_t *cmd, uint8_t counter, hal_can_frame_t *frame);

/**
 * Decode one telemetry frame into the fields of *tm that frame carries (others untouched).
 * Counters arrive modulo their field widths.
 * @return a can_proto_rx_result_t from the DLC and CRC checks (ACCEPTED when decoded), or
 *         CAN_PROTO_RX_UNKNOWN_ID for a non-telemetry id; TV_ERR_NULL.
 */
int can_host_decode_telemetry(const hal_can_frame_t *frame, can_proto_telemetry_t *tm);

#ifdef __cplusplus
}
#endif

#endif /* CAN_HOST_H */
