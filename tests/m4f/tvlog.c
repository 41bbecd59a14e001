/**
 * @file tvlog.c
 * @brief Replay stream format and the shared replay step (see tvlog.h).
 */
#include "tvlog.h"

#include <stddef.h>
#include <string.h>

static void put32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)v;
    b[1] = (uint8_t)(v >> 8);
    b[2] = (uint8_t)(v >> 16);
    b[3] = (uint8_t)(v >> 24);
}

static uint32_t get32(const uint8_t *b)
{
    return (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) | ((uint32_t)b[3] << 24);
}

static uint32_t fbits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float bitsf(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

void tvlog_header_encode(uint8_t b[TVLOG_HEADER_BYTES], const char magic[8], uint32_t count, uint32_t rec_bytes)
{
    memcpy(b, magic, 8u);
    put32(b + 8, count);
    put32(b + 12, rec_bytes);
}

int tvlog_header_decode(const uint8_t b[TVLOG_HEADER_BYTES], const char magic[8], uint32_t rec_bytes,
                        uint32_t *count)
{
    if (memcmp(b, magic, 8u) != 0 || get32(b + 12) != rec_bytes) {
        return -1;
    }
    *count = get32(b + 8);
    return 0;
}

void tvlog_in_encode(uint8_t b[TVLOG_IN_BYTES], const tvlog_in_t *r)
{
    uint32_t k;
    put32(b, (uint32_t)r->t_us);
    put32(b + 4, (uint32_t)(r->t_us >> 32));
    for (k = 0u; k < 4u; ++k) {
        b[8u + 2u * k] = (uint8_t)r->adc[k];
        b[9u + 2u * k] = (uint8_t)(r->adc[k] >> 8);
    }
    b[16] = r->driver_fault;
    b[17] = r->cmd;
    b[18] = 0u;
    b[19] = 0u;
    put32(b + 20, fbits(r->cmd_arg));
}

void tvlog_in_decode(const uint8_t b[TVLOG_IN_BYTES], tvlog_in_t *r)
{
    uint32_t k;
    r->t_us = (uint64_t)get32(b) | ((uint64_t)get32(b + 4) << 32);
    for (k = 0u; k < 4u; ++k) {
        r->adc[k] = (uint16_t)(b[8u + 2u * k] | (b[9u + 2u * k] << 8));
    }
    r->driver_fault = b[16];
    r->cmd = b[17];
    r->cmd_arg = bitsf(get32(b + 20));
}

int tvlog_replay_init(app_t *app, int stops_known)
{
    app_config_t cfg;
    app_config_default(&cfg);
    if (stops_known) {
        cfg.stop_track.envelope = 0u;
    }
    return app_init(app, &cfg);
}

void tvlog_apply_cmd(app_t *app, const tvlog_in_t *in)
{
    if (in->cmd == TVLOG_CMD_CLEAR_FAULTS) {
        app_clear_faults(app);
    } else if (in->cmd >= TVLOG_CMD_MODE && in->cmd <= TVLOG_CMD_MODE + (uint8_t)APP_MODE_POSITION) {
        app_control_t ctl = app->cfg.control;
        ctl.mode = (app_mode_t)(in->cmd - TVLOG_CMD_MODE);
        if (ctl.mode == APP_MODE_POSITION) {
            ctl.target_rad = (tv_real_t)in->cmd_arg;
        }
        (void)app_set_control(app, &ctl);
    }
}

void tvlog_replay_step(app_t *app, const tvlog_in_t *in, uint32_t index, app_output_t *out,
                       uint8_t b[TVLOG_OUT_BYTES])
{
    app_input_t ai;
    uint32_t w[TVLOG_OUT_WORDS];
    uint32_t k;
    tvlog_apply_cmd(app, in);
    memcpy(ai.adc, in->adc, sizeof ai.adc);
    ai.t_us = in->t_us;
    ai.driver_fault = in->driver_fault;
    app_step(app, &ai, out);

    w[0] = index;
    w[1] = fbits(out->duty);
    w[2] = out->bridge_enable;
    w[3] = fbits((float)out->u_cmd_V);
    for (k = 0u; k < 3u; ++k) {
        w[4u + k] = fbits((float)out->z[k]);
        w[8u + k] = fbits((float)out->x[k]);
        w[11u + k] = fbits((float)out->sigma[k]);
        w[14u + k] = fbits((float)out->innov.innov[k]);
        w[17u + k] = fbits((float)out->innov.innov_var[k]);
        w[20u + k] = fbits((float)out->innov.nis[k]);
    }
    w[7] = fbits((float)out->supply_V);
    w[23] = fbits((float)out->innov.nis_total);
    w[24] = (uint32_t)out->innov.used[0] | ((uint32_t)out->innov.used[1] << 8) |
            ((uint32_t)out->innov.used[2] << 16) | ((uint32_t)out->innov.n_used << 24);
    w[25] = (uint32_t)out->ekf_status;
    w[26] = out->faults;
    w[27] = out->missing_samples;
    for (k = 0u; k < TVLOG_OUT_WORDS; ++k) {
        put32(b + (size_t)4u * k, w[k]);
    }
}

static const char *const s_names[TVLOG_OUT_WORDS] = {
    "index",       "duty",         "bridge_enable", "u_cmd_V",      "z[current]",   "z[velocity]", "z[angle]",
    "supply_V",    "x[i]",         "x[w]",          "x[phi]",       "sigma[i]",     "sigma[w]",    "sigma[phi]",
    "innov[0]",    "innov[1]",     "innov[2]",      "innov_var[0]", "innov_var[1]", "innov_var[2]", "nis[0]",
    "nis[1]",      "nis[2]",       "nis_total",     "used",         "ekf_status",   "faults",      "missing_samples"};

const char *tvlog_out_word_name(uint32_t k)
{
    return k < TVLOG_OUT_WORDS ? s_names[k] : "";
}

int tvlog_out_word_is_float(uint32_t k)
{
    return k == 1u || k == 3u || (k >= 4u && k <= 23u);
}

uint32_t tvlog_out_word(const uint8_t b[TVLOG_OUT_BYTES], uint32_t k)
{
    return k < TVLOG_OUT_WORDS ? get32(b + (size_t)4u * k) : 0u;
}
