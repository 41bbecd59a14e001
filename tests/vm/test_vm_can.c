/**
 * @file test_vm_can.c
 * @brief The SocketCAN module (hal/linux/lx_can) and the protocol over it, against a real
 *        kernel: run inside the test VM with vcan0 up and vcan1 created but down. A second raw
 *        socket (plain SocketCAN calls, not lx_can) is the peer on the bus.
 */
#define _GNU_SOURCE

#include <errno.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "can_host.h"
#include "can_proto.h"
#include "lx_can.h"
#include "lx_config.h"
#include "tv_status.h"
#include "tv_test.h"

static int s_peer = -1;

static int peer_open(const char *ifname)
{
    struct sockaddr_can addr;
    const int fd = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    struct timeval tv = {1, 0};
    if (fd < 0) {
        return -1;
    }
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = (int)if_nametoindex(ifname);
    if (bind(fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        (void)close(fd);
        return -1;
    }
    (void)setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    return fd;
}

static int peer_send(uint32_t id_flags, uint8_t dlc, const uint8_t *data)
{
    struct can_frame cf;
    memset(&cf, 0, sizeof cf);
    cf.can_id = id_flags;
    cf.can_dlc = dlc;
    if (data != NULL) {
        memcpy(cf.data, data, dlc);
    }
    return write(s_peer, &cf, sizeof cf) == (ssize_t)sizeof cf ? 0 : -1;
}

/* Poll lx_can_receive for up to 1 s (delivery on vcan is immediate; this is slack for TCG). */
static int receive_wait(lx_can_t *c, hal_can_frame_t *f)
{
    int k;
    for (k = 0; k < 1000; ++k) {
        const int r = lx_can_receive(c, f);
        const struct timespec ms = {0, 1000000L};
        if (r != 0) {
            return r;
        }
        (void)nanosleep(&ms, NULL);
    }
    return 0;
}

static void test_open_errors_from_a_real_kernel(void)
{
    lx_can_t c;
    char err[LX_ERR_LEN];
    TV_CHECK_EQ_INT(lx_can_open(&c, "tvnosuch0", err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "can.interface = 'tvnosuch0': no such network interface") != NULL);
    TV_CHECK_EQ_INT(lx_can_open(&c, "lo", err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "can.interface = 'lo': not a CAN interface") != NULL);
    TV_CHECK_EQ_INT(lx_can_open(&c, "vcan1", err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "can.interface = 'vcan1': interface is down") != NULL);
    printf("  %s\n", err);
}

static void test_frames_both_ways(void)
{
    lx_can_t c;
    hal_can_frame_t f;
    hal_can_frame_t g;
    struct can_frame cf;
    char err[LX_ERR_LEN];
    static const uint8_t d8[8] = {0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88};
    TV_CHECK_EQ_INT(lx_can_open(&c, "vcan0", err, sizeof err), TV_OK);
    /* lx_can -> peer, standard id */
    memset(&f, 0, sizeof f);
    f.id = 0x123u;
    f.dlc = 8u;
    memcpy(f.data, d8, 8u);
    TV_CHECK_EQ_INT(lx_can_send(&c, &f), TV_OK);
    TV_CHECK(read(s_peer, &cf, sizeof cf) == (ssize_t)sizeof cf);
    TV_CHECK_EQ_INT(cf.can_id, 0x123);
    TV_CHECK_EQ_INT(cf.can_dlc, 8);
    TV_CHECK(memcmp(cf.data, d8, 8u) == 0);
    /* extended id */
    f.id = 0x1ABCDEF0u;
    f.extended = 1u;
    f.dlc = 3u;
    TV_CHECK_EQ_INT(lx_can_send(&c, &f), TV_OK);
    TV_CHECK(read(s_peer, &cf, sizeof cf) == (ssize_t)sizeof cf);
    TV_CHECK_EQ_INT(cf.can_id, 0x1ABCDEF0u | CAN_EFF_FLAG);
    TV_CHECK_EQ_INT(cf.can_dlc, 3);
    /* our own frames do not come back to our socket */
    TV_CHECK_EQ_INT(lx_can_receive(&c, &g), 0);
    /* refused before reaching the kernel */
    f.dlc = 9u;
    TV_CHECK_EQ_INT(lx_can_send(&c, &f), TV_ERR_RANGE);
    f.dlc = 8u;
    f.extended = 0u;
    f.id = 0x800u;
    TV_CHECK_EQ_INT(lx_can_send(&c, &f), TV_ERR_RANGE);
    /* peer -> lx_can: standard 8 bytes, extended 0 bytes, 3 bytes (the rest must read 0), then
     * a remote request, which is skipped */
    TV_CHECK_EQ_INT(peer_send(0x7FFu, 8u, d8), 0);
    TV_CHECK_EQ_INT(peer_send(0x00000001u | CAN_EFF_FLAG, 0u, NULL), 0);
    TV_CHECK_EQ_INT(peer_send(0x100u, 3u, d8), 0);
    TV_CHECK_EQ_INT(peer_send(0x101u | CAN_RTR_FLAG, 8u, NULL), 0);
    TV_CHECK_EQ_INT(receive_wait(&c, &g), 1);
    TV_CHECK(g.id == 0x7FFu && g.extended == 0u && g.dlc == 8u && memcmp(g.data, d8, 8u) == 0);
    TV_CHECK_EQ_INT(receive_wait(&c, &g), 1);
    TV_CHECK(g.id == 1u && g.extended == 1u && g.dlc == 0u);
    TV_CHECK_EQ_INT(receive_wait(&c, &g), 1);
    TV_CHECK(g.id == 0x100u && g.dlc == 3u && g.data[2] == 0x33u && g.data[3] == 0u && g.data[7] == 0u);
    TV_CHECK_EQ_INT(receive_wait(&c, &g), 0);
    TV_CHECK_EQ_INT(c.skipped, 1);
    lx_can_close(&c);
}

/* 2000 frames each way in a burst arrive complete and in order. */
static void test_burst_in_order(void)
{
    lx_can_t c;
    hal_can_frame_t f;
    char err[LX_ERR_LEN];
    unsigned k;
    unsigned in_order = 0u;
    unsigned sent_ok = 0u;
    TV_CHECK_EQ_INT(lx_can_open(&c, "vcan0", err, sizeof err), TV_OK);
    memset(&f, 0, sizeof f);
    f.id = 0x181u;
    f.dlc = 8u;
    for (k = 0; k < 2000u; ++k) {
        struct can_frame cf;
        f.data[0] = (uint8_t)(k & 0xFFu);
        f.data[1] = (uint8_t)(k >> 8);
        sent_ok += lx_can_send(&c, &f) == TV_OK;
        if (read(s_peer, &cf, sizeof cf) == (ssize_t)sizeof cf && cf.data[0] == (k & 0xFFu) && cf.data[1] == (k >> 8)) {
            ++in_order;
        }
    }
    TV_CHECK_EQ_INT(sent_ok, 2000);
    TV_CHECK_EQ_INT(in_order, 2000);
    in_order = 0u;
    for (k = 0; k < 200u; ++k) { /* within the socket's receive buffer */
        uint8_t d[2];
        d[0] = (uint8_t)k;
        d[1] = 0xA5u;
        (void)peer_send(0x102u, 2u, d);
    }
    for (k = 0; k < 200u; ++k) {
        hal_can_frame_t g;
        if (receive_wait(&c, &g) == 1 && g.data[0] == (uint8_t)k && g.data[1] == 0xA5u) {
            ++in_order;
        }
    }
    TV_CHECK_EQ_INT(in_order, 200);
    lx_can_close(&c);
}

/* The protocol node over the real socket: commands from the peer are accepted, a corrupted
 * one rejected; telemetry reaches the peer with a valid CRC. */
static void test_protocol_over_socketcan(void)
{
    static app_t app;
    app_config_t acfg;
    can_proto_config_t pcfg;
    can_proto_node_t node;
    can_proto_control_t cmd = {APP_MODE_POSITION, 0.3f, 0.9f, 0u, 0u, 0.0f};
    hal_can_frame_t f;
    hal_can_frame_t frames[CAN_PROTO_N_TX];
    app_output_t out;
    lx_can_t c;
    char err[LX_ERR_LEN];
    size_t n;
    size_t k;
    int got = 0;
    app_config_default(&acfg);
    TV_CHECK_EQ_INT(app_init(&app, &acfg), TV_OK);
    can_proto_config_default(&pcfg);
    TV_CHECK_EQ_INT(can_proto_node_init(&node, &pcfg, &app), TV_OK);
    TV_CHECK_EQ_INT(lx_can_open(&c, "vcan0", err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(can_host_encode_control(&cmd, 0u, &f), TV_OK);
    TV_CHECK_EQ_INT(peer_send(f.id, f.dlc, f.data), 0);
    f.data[3] ^= 0x10u;
    TV_CHECK_EQ_INT(peer_send(f.id, f.dlc, f.data), 0);
    TV_CHECK_EQ_INT(receive_wait(&c, &f), 1);
    TV_CHECK_EQ_INT(can_proto_node_receive(&node, &app, &f, 1000u), CAN_PROTO_RX_ACCEPTED);
    TV_CHECK_EQ_INT(receive_wait(&c, &f), 1);
    TV_CHECK_EQ_INT(can_proto_node_receive(&node, &app, &f, 1000u), CAN_PROTO_RX_BAD_CRC);
    TV_CHECK_EQ_INT(app.cfg.control.mode, APP_MODE_POSITION);
    memset(&out, 0, sizeof out);
    n = can_proto_node_transmit(&node, &app, &out, NULL, 0, 0u, frames);
    TV_CHECK_EQ_INT(n, 2); /* EST_STATE and TIME are due at the time base */
    for (k = 0; k < n; ++k) {
        struct can_frame cf;
        hal_can_frame_t r;
        TV_CHECK_EQ_INT(lx_can_send(&c, &frames[k]), TV_OK);
        if (read(s_peer, &cf, sizeof cf) == (ssize_t)sizeof cf) {
            memset(&r, 0, sizeof r);
            r.id = cf.can_id;
            r.dlc = cf.can_dlc;
            memcpy(r.data, cf.data, 8u);
            got += can_proto_check(&r) == CAN_PROTO_RX_ACCEPTED;
        }
    }
    TV_CHECK_EQ_INT(got, (int)n);
    lx_can_close(&c);
}

int main(void)
{
    s_peer = peer_open("vcan0");
    if (s_peer < 0) {
        printf("FAIL peer socket on vcan0: %s\n", strerror(errno));
        return 1;
    }
    TV_TEST_RUN(test_open_errors_from_a_real_kernel);
    TV_TEST_RUN(test_frames_both_ways);
    TV_TEST_RUN(test_burst_in_order);
    TV_TEST_RUN(test_protocol_over_socketcan);
    (void)close(s_peer);
    return tv_test_summary();
}
