/**
 * @file fuzz_can.c
 * @brief libFuzzer target of the CAN command path (firmware/protocols/can_proto.h): the command
 *        decoders and can_proto_node_receive() acting on a running application, float build as
 *        on the ECU.
 *
 * The input is a sequence of 12-byte records, one frame each: selector, DLC, 8 data bytes, time
 * step [us] (16 bit). Selector bits 0-1 choose the identifier (TV_CMD_CONTROL, TV_CMD_EXCITATION,
 * a telemetry id, or an arbitrary one from bits 2-6); bit 7 makes the CRC valid so the fuzzer gets
 * past it to the signal decoding and the node's state machine. After every frame the node and the
 * application must still hold a valid control (app_set_control() accepts it again) and a finite
 * state; every decoder must refuse or accept without undefined behaviour (ASan + UBSan).
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "can_proto.h"

static app_t s_app;
static can_proto_node_t s_node;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    app_config_t cfg;
    can_proto_config_t nc;
    uint64_t t_us = 0u;
    size_t off;
    app_config_default(&cfg);
    if (app_init(&s_app, &cfg) != 0) {
        abort();
    }
    can_proto_config_default(&nc);
    if (can_proto_node_init(&s_node, &nc, &s_app) != 0) {
        abort();
    }
    for (off = 0; off + 12u <= size; off += 12u) {
        const uint8_t *p = data + off;
        hal_can_frame_t f;
        can_proto_control_t ctl;
        can_proto_excitation_t exc;
        app_control_t now;
        const uint8_t sel = p[0];
        memset(&f, 0, sizeof f);
        switch (sel & 3u) {
        case 0: f.id = CAN_PROTO_ID_CMD_CONTROL; break;
        case 1: f.id = CAN_PROTO_ID_CMD_EXCITATION; break;
        case 2: f.id = CAN_PROTO_ID_EST_STATE; break;
        default: f.id = 0x0F0u + ((sel >> 2) & 0x1Fu); break;
        }
        f.dlc = (uint8_t)(p[1] % 10u); /* 8 and 9: a DLC the protocol must refuse */
        memcpy(f.data, p + 2, 8u);
        if ((sel & 0x80u) != 0u) {
            f.data[0] = can_proto_frame_crc(&f);
        }
        t_us += (uint64_t)p[10] | ((uint64_t)p[11] << 8);
        (void)can_proto_decode_control(&f, &ctl);
        (void)can_proto_decode_excitation(&f, &exc);
        (void)can_proto_check(&f);
        (void)can_proto_node_receive(&s_node, &s_app, &f, t_us);
        can_proto_node_update(&s_node, &s_app, NULL, t_us);
        /* whatever arrived, the control in force is one the application accepts */
        now = s_app.cfg.control;
        if (app_set_control(&s_app, &now) != 0) {
            abort();
        }
    }
    return 0;
}
