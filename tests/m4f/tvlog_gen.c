/**
 * @file tvlog_gen.c
 * @brief Replay input stream generator (see tvlog_gen.h).
 */
#include "tvlog_gen.h"

#include <stddef.h>

#include "tv_status.h"

/* Step of an event at per-mille p of the run. */
static uint32_t at(const tvlog_gen_t *g, uint32_t permille)
{
    return (uint32_t)(((uint64_t)g->steps * permille) / 1000u);
}

/* The scenario: command, fault injection and lost samples of step k. */
static void scenario(const tvlog_gen_t *g, uint32_t k, tvlog_in_t *r, int *drop)
{
    r->cmd = TVLOG_CMD_NONE;
    r->cmd_arg = 0.0f;
    r->driver_fault = 0u;
    *drop = 0;
    if (k == at(g, 250u)) {
        r->cmd = TVLOG_CMD_MODE + (uint8_t)APP_MODE_STEPS;
    } else if (k == at(g, 383u)) {
        r->cmd = TVLOG_CMD_MODE + (uint8_t)APP_MODE_CHIRP;
    } else if (k == at(g, 517u)) {
        r->cmd = TVLOG_CMD_MODE + (uint8_t)APP_MODE_POSITION;
        r->cmd_arg = 0.3f;
    } else if (k == at(g, 600u)) {
        r->cmd = TVLOG_CMD_MODE + (uint8_t)APP_MODE_POSITION;
        r->cmd_arg = 0.9f;
    } else if (k == at(g, 683u)) {
        r->driver_fault = 1u; /* latches APP_FAULT_DRIVER: safe state */
    } else if (k == at(g, 717u) || k == at(g, 800u)) {
        r->cmd = TVLOG_CMD_CLEAR_FAULTS;
    } else if (k == at(g, 833u)) {
        r->cmd = TVLOG_CMD_MODE + (uint8_t)APP_MODE_OFF;
    } else if (k == at(g, 883u)) {
        r->cmd = TVLOG_CMD_MODE + (uint8_t)APP_MODE_SINE;
    }
    if (k == at(g, 633u)) {
        *drop = 1; /* one sample lost: the most the ECU predicts across (ecu_main.c) */
    }
    if (k >= at(g, 767u) && k < at(g, 767u) + 10u) {
        r->adc[1] = 0u; /* track 1 open: range and disagreement faults */
    }
}

int tvlog_gen_init(tvlog_gen_t *g, uint32_t steps, uint64_t seed)
{
    plant_config_t pc;
    int rc;
    if (g == NULL) {
        return TV_ERR_NULL;
    }
    if (steps < 100u) {
        return TV_ERR_RANGE;
    }
    plant_config_default(&pc);
    rc = plant_init(&g->plant, &pc, seed);
    if (rc == TV_OK) {
        rc = tvlog_replay_init(&g->app, 1);
    }
    g->k = 0u;
    g->steps = steps;
    return rc;
}

int tvlog_gen_next(tvlog_gen_t *g, tvlog_in_t *rec)
{
    plant_adc_t s;
    int drop;
    if (g->k >= g->steps) {
        return -1;
    }
    (void)plant_sample(&g->plant, &s);
    /* Start at t = 5 s: the application's time origin is its first sample, not 0. */
    rec->t_us = 5000000u + 1000u * (uint64_t)g->k;
    rec->adc[0] = s.current_counts;
    rec->adc[1] = s.tps1_counts;
    rec->adc[2] = s.tps2_counts;
    rec->adc[3] = s.supply_counts;
    scenario(g, g->k, rec, &drop);
    if (!drop) {
        app_output_t out;
        uint8_t obuf[TVLOG_OUT_BYTES];
        tvlog_replay_step(&g->app, rec, g->k, &out, obuf);
        (void)plant_set_bridge(&g->plant, (double)out.duty, out.bridge_enable);
    }
    ++g->k;
    if (plant_advance(&g->plant, 1e-3) != TV_OK) {
        return -2;
    }
    return drop ? 0 : 1;
}
