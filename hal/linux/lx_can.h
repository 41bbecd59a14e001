/**
 * @file lx_can.h
 * @brief One raw SocketCAN socket (PF_CAN, SOCK_RAW, CAN_RAW) bound to one interface,
 *        non-blocking, classic frames only (Documentation/networking/can.rst).
 */
#ifndef LX_CAN_H
#define LX_CAN_H

#include <stddef.h>
#include <stdint.h>

#include "hal.h"

#ifdef __cplusplus
extern "C" {
#endif

/** An opened socket. Zero-initialise, then lx_can_open(). */
typedef struct {
    int fd;           /**< socket, -1 when closed */
    int is_open;      /**< 1 between a successful open and close */
    uint32_t skipped; /**< received frames dropped (remote requests, wrong size) */
} lx_can_t;

/**
 * Open a raw CAN socket on an interface.
 * @param ifname  interface (config key can.interface), e.g. can0 or vcan0
 * @param err     receives a message naming the config key and value on error
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (the kernel has no SocketCAN, no such interface,
 *         not a CAN interface, interface down, bind refused). On error nothing stays open.
 */
int lx_can_open(lx_can_t *can, const char *ifname, char *err, size_t err_len);

/**
 * Queue one frame.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE (dlc > 8, id beyond 11/29 bits); TV_ERR_CONFIG when
 *         not open; TV_ERR_IO when the queue is full (EAGAIN/ENOBUFS) or the write failed.
 */
int lx_can_send(lx_can_t *can, const hal_can_frame_t *frame);

/**
 * Take one received data frame without waiting (remote-request frames are skipped).
 * @return 1 when *frame was written, 0 when none is pending, TV_ERR_NULL, TV_ERR_CONFIG when
 *         not open, TV_ERR_IO on a read error.
 */
int lx_can_receive(lx_can_t *can, hal_can_frame_t *frame);

/** Close the socket. Safe to call twice. */
void lx_can_close(lx_can_t *can);

#ifdef __cplusplus
}
#endif

#endif /* LX_CAN_H */
