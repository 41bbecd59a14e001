/**
 * @file lx_can.c
 * @brief Raw SocketCAN socket (see lx_can.h).
 */
#define _GNU_SOURCE /* struct ifreq, SIOCGIFHWADDR, SOCK_NONBLOCK */

#include "lx_can.h"

#include <errno.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <net/if_arp.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "lx_err.h"
#include "tv_status.h"

static int fail(lx_can_t *can, int rc)
{
    if (can->fd >= 0) {
        (void)close(can->fd);
    }
    can->fd = -1;
    can->is_open = 0;
    return rc;
}

int lx_can_open(lx_can_t *can, const char *ifname, char *err, size_t err_len)
{
    struct ifreq ifr;
    struct sockaddr_can addr;
    unsigned idx;
    if (can == NULL || ifname == NULL) {
        lx_err_set(err, err_len, "lx_can_open: NULL argument");
        return TV_ERR_NULL;
    }
    memset(can, 0, sizeof *can);
    can->fd = -1;
    if (ifname[0] == '\0' || strlen(ifname) >= IFNAMSIZ) {
        lx_err_set(err, err_len, "can.interface = '%s': not a valid interface name (1..%d characters)", ifname,
                IFNAMSIZ - 1);
        return TV_ERR_CONFIG;
    }
    can->fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (can->fd < 0) {
        lx_err_set(err, err_len,
                "can.interface = '%s': this kernel offers no raw CAN sockets (socket(PF_CAN): %s); "
                "load the can and can-raw modules",
                ifname, strerror(errno));
        return fail(can, TV_ERR_CONFIG);
    }
    idx = if_nametoindex(ifname);
    if (idx == 0u) {
        lx_err_set(err, err_len, "can.interface = '%s': no such network interface", ifname);
        return fail(can, TV_ERR_CONFIG);
    }
    memset(&ifr, 0, sizeof ifr);
    memcpy(ifr.ifr_name, ifname, strlen(ifname) + 1u);
    if (ioctl(can->fd, SIOCGIFHWADDR, &ifr) != 0 || ifr.ifr_hwaddr.sa_family != ARPHRD_CAN) {
        lx_err_set(err, err_len, "can.interface = '%s': not a CAN interface", ifname);
        return fail(can, TV_ERR_CONFIG);
    }
    if (ioctl(can->fd, SIOCGIFFLAGS, &ifr) != 0 || (ifr.ifr_flags & IFF_UP) == 0) {
        lx_err_set(err, err_len,
                "can.interface = '%s': interface is down (ip link set %s up type can bitrate 500000; vcan: ip link set "
                "%s up)",
                ifname, ifname, ifname);
        return fail(can, TV_ERR_CONFIG);
    }
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = (int)idx;
    if (bind(can->fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        lx_err_set(err, err_len, "can.interface = '%s': bind: %s", ifname, strerror(errno));
        return fail(can, TV_ERR_CONFIG);
    }
    can->is_open = 1;
    return TV_OK;
}

int lx_can_send(lx_can_t *can, const hal_can_frame_t *frame)
{
    struct can_frame cf;
    ssize_t n;
    if (can == NULL || frame == NULL) {
        return TV_ERR_NULL;
    }
    if (!can->is_open) {
        return TV_ERR_CONFIG;
    }
    if (frame->dlc > 8u || frame->id > (frame->extended ? CAN_EFF_MASK : CAN_SFF_MASK)) {
        return TV_ERR_RANGE;
    }
    memset(&cf, 0, sizeof cf);
    cf.can_id = frame->id | (frame->extended ? CAN_EFF_FLAG : 0u);
    cf.can_dlc = frame->dlc;
    memcpy(cf.data, frame->data, frame->dlc);
    n = write(can->fd, &cf, sizeof cf);
    if (n != (ssize_t)sizeof cf) {
        return TV_ERR_IO;
    }
    return TV_OK;
}

int lx_can_receive(lx_can_t *can, hal_can_frame_t *frame)
{
    if (can == NULL || frame == NULL) {
        return TV_ERR_NULL;
    }
    if (!can->is_open) {
        return TV_ERR_CONFIG;
    }
    for (;;) {
        struct can_frame cf;
        const ssize_t n = read(can->fd, &cf, sizeof cf);
        if (n < 0) {
            return errno == EAGAIN || errno == EWOULDBLOCK ? 0 : TV_ERR_IO;
        }
        if (n != (ssize_t)sizeof cf || (cf.can_id & (CAN_RTR_FLAG | CAN_ERR_FLAG)) != 0u || cf.can_dlc > 8u) {
            ++can->skipped;
            continue;
        }
        memset(frame, 0, sizeof *frame);
        frame->extended = (uint8_t)((cf.can_id & CAN_EFF_FLAG) != 0u ? 1u : 0u);
        frame->id = cf.can_id & (frame->extended ? CAN_EFF_MASK : CAN_SFF_MASK);
        frame->dlc = cf.can_dlc;
        memcpy(frame->data, cf.data, cf.can_dlc);
        return 1;
    }
}

void lx_can_close(lx_can_t *can)
{
    if (can == NULL || !can->is_open) {
        return;
    }
    (void)close(can->fd);
    can->fd = -1;
    can->is_open = 0;
}
