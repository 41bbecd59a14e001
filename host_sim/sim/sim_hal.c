/**
 * @file sim_hal.c
 * @brief hal/hal.h on one static plant, plus the simulation controls (see sim_hal.h).
 */
#include "sim_hal.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "tv_status.h"

/** Largest standard (11-bit) and extended (29-bit) CAN identifiers. */
#define SIM_HAL_CAN_STD_ID_MAX 0x7FFu
#define SIM_HAL_CAN_EXT_ID_MAX 0x1FFFFFFFu

static plant_t s_plant;
static int s_configured;
static float s_duty;
static int s_enable;
static int s_driver_fault;
static int s_forced[HAL_ADC_CHANNELS];
static uint16_t s_forced_counts[HAL_ADC_CHANNELS];
static uint32_t s_adc_fail_reads;
static plant_adc_t s_last_adc;
static int s_have_last_adc;
static hal_can_frame_t s_can_queue[SIM_HAL_CAN_QUEUE_LEN];
static uint32_t s_can_head; /* index of the oldest frame */
static uint32_t s_can_count;
static uint32_t s_can_overflows;

/* ------------------------------------------------------------------------------------------ */
/* Simulation controls                                                                         */
/* ------------------------------------------------------------------------------------------ */

int sim_hal_configure(const plant_config_t *cfg, uint64_t seed)
{
    plant_t fresh;
    int rc;
    if (cfg == NULL) {
        return TV_ERR_NULL;
    }
    rc = plant_init(&fresh, cfg, seed);
    if (rc != TV_OK) {
        return rc;
    }
    s_plant = fresh;
    s_configured = 1;
    s_duty = 0.0f;
    s_enable = 0;
    s_driver_fault = 0;
    memset(s_forced, 0, sizeof s_forced);
    memset(s_forced_counts, 0, sizeof s_forced_counts);
    s_adc_fail_reads = 0u;
    memset(&s_last_adc, 0, sizeof s_last_adc);
    s_have_last_adc = 0;
    memset(s_can_queue, 0, sizeof s_can_queue);
    s_can_head = 0u;
    s_can_count = 0u;
    s_can_overflows = 0u;
    return TV_OK;
}

int sim_hal_advance(double dt_s)
{
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    return plant_advance(&s_plant, dt_s);
}

int sim_hal_truth(plant_state_t *out)
{
    if (out == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    return plant_truth(&s_plant, out);
}

int sim_hal_config_in_force(plant_config_t *out)
{
    if (out == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    *out = s_plant.cfg;
    return TV_OK;
}

int sim_hal_set_state(const plant_state_t *state)
{
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    return plant_set_state(&s_plant, state);
}

int sim_hal_bridge_voltage(double *mean_V)
{
    if (mean_V == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    return plant_bridge_voltage(&s_plant, mean_V);
}

double sim_hal_time_s(void)
{
    return s_configured ? plant_time_s(&s_plant) : 0.0;
}

void sim_hal_outputs(float *duty, int *enable)
{
    if (duty != NULL) {
        *duty = s_duty;
    }
    if (enable != NULL) {
        *enable = s_enable;
    }
}

int sim_hal_set_faults(const plant_faults_t *faults)
{
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    return plant_set_faults(&s_plant, faults);
}

void sim_hal_set_driver_fault(int active)
{
    s_driver_fault = active ? 1 : 0;
}

int sim_hal_force_adc(int channel, uint16_t counts)
{
    if (channel < 0 || channel >= HAL_ADC_CHANNELS) {
        return TV_ERR_RANGE;
    }
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    if ((uint32_t)counts > ((uint32_t)1u << s_plant.cfg.adc_bits) - 1u) {
        return TV_ERR_RANGE;
    }
    s_forced[channel] = 1;
    s_forced_counts[channel] = counts;
    return TV_OK;
}

int sim_hal_release_adc(int channel)
{
    if (channel < 0 || channel >= HAL_ADC_CHANNELS) {
        return TV_ERR_RANGE;
    }
    s_forced[channel] = 0;
    return TV_OK;
}

void sim_hal_fail_adc_reads(uint32_t n_reads)
{
    s_adc_fail_reads = n_reads;
}

int sim_hal_last_adc(plant_adc_t *out)
{
    if (out == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_configured || !s_have_last_adc) {
        return TV_ERR_CONFIG;
    }
    *out = s_last_adc;
    return TV_OK;
}

uint32_t sim_hal_can_overflows(void)
{
    return s_can_overflows;
}

uint32_t sim_hal_can_pending(void)
{
    return s_can_count;
}

/* ------------------------------------------------------------------------------------------ */
/* hal.h                                                                                       */
/* ------------------------------------------------------------------------------------------ */

int hal_init(void)
{
    if (!s_configured) {
        plant_config_t cfg;
        plant_config_default(&cfg);
        return sim_hal_configure(&cfg, 1u);
    }
    return TV_OK;
}

/* Push the HAL outputs in force to the plant's bridge (duty is always valid here). */
static int sim_hal_apply_bridge(void)
{
    return plant_set_bridge(&s_plant, (double)s_duty, s_enable);
}

int hal_pwm_set_duty(float duty)
{
    int rc = TV_OK;
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    if (duty != duty || duty - duty != 0.0f) {
        rc = TV_ERR_NONFINITE;
    } else if (duty < -1.0f || duty > 1.0f) {
        rc = TV_ERR_RANGE;
    }
    s_duty = rc == TV_OK ? duty : 0.0f; /* hal.h: a rejected duty sets the output to 0 */
    {
        const int prc = sim_hal_apply_bridge();
        return rc != TV_OK ? rc : prc;
    }
}

int hal_bridge_enable(int enable)
{
    int rc = TV_OK;
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    if (enable != 0 && enable != 1) {
        rc = TV_ERR_RANGE;
        enable = 0; /* a bad argument must not switch the bridge on */
    }
    s_enable = enable;
    {
        const int prc = sim_hal_apply_bridge();
        return rc != TV_OK ? rc : prc;
    }
}

int hal_driver_fault(int *fault_active)
{
    if (fault_active == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    *fault_active = s_driver_fault;
    return TV_OK;
}

/* Plant time [s] -> microseconds, rounded to nearest (plant time is >= 0). */
static uint64_t sim_hal_us(double t_s)
{
    return (uint64_t)floor(t_s * 1e6 + 0.5);
}

int hal_adc_read(hal_adc_sample_t *sample)
{
    plant_adc_t a;
    int rc;
    int k;
    if (sample == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_configured) {
        return TV_ERR_CONFIG;
    }
    if (s_adc_fail_reads > 0u) {
        --s_adc_fail_reads;
        return TV_ERR_IO;
    }
    rc = plant_sample(&s_plant, &a);
    if (rc != TV_OK) {
        return rc;
    }
    sample->counts[HAL_ADC_CURRENT] = a.current_counts;
    sample->counts[HAL_ADC_TPS1] = a.tps1_counts;
    sample->counts[HAL_ADC_TPS2] = a.tps2_counts;
    sample->counts[HAL_ADC_SUPPLY] = a.supply_counts;
    for (k = 0; k < HAL_ADC_CHANNELS; ++k) {
        if (s_forced[k]) {
            sample->counts[k] = s_forced_counts[k];
        }
    }
    a.current_counts = sample->counts[HAL_ADC_CURRENT];
    a.tps1_counts = sample->counts[HAL_ADC_TPS1];
    a.tps2_counts = sample->counts[HAL_ADC_TPS2];
    a.supply_counts = sample->counts[HAL_ADC_SUPPLY];
    sample->t_us = sim_hal_us(a.t_s);
    s_last_adc = a;
    s_have_last_adc = 1;
    return TV_OK;
}

int sim_hal_last_adc_time_us(uint64_t *t_us)
{
    if (t_us == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_have_last_adc) {
        return TV_ERR_CONFIG;
    }
    *t_us = sim_hal_us(s_last_adc.t_s);
    return TV_OK;
}

uint64_t hal_time_us(void)
{
    return s_configured ? sim_hal_us(plant_time_s(&s_plant)) : 0u;
}

int hal_can_send(const hal_can_frame_t *frame)
{
    hal_can_frame_t f;
    uint32_t tail;
    if (frame == NULL) {
        return TV_ERR_NULL;
    }
    if (frame->dlc > 8u || frame->extended > 1u ||
        frame->id > (frame->extended ? SIM_HAL_CAN_EXT_ID_MAX : SIM_HAL_CAN_STD_ID_MAX)) {
        return TV_ERR_RANGE;
    }
    if (s_can_count >= SIM_HAL_CAN_QUEUE_LEN) {
        ++s_can_overflows;
        return TV_ERR_IO;
    }
    f = *frame;
    memset(f.data + f.dlc, 0, sizeof f.data - f.dlc); /* hal.h: bytes beyond dlc are 0 */
    tail = (s_can_head + s_can_count) % SIM_HAL_CAN_QUEUE_LEN;
    s_can_queue[tail] = f;
    ++s_can_count;
    return TV_OK;
}

int hal_can_receive(hal_can_frame_t *frame)
{
    if (frame == NULL) {
        return TV_ERR_NULL;
    }
    if (s_can_count == 0u) {
        return 0;
    }
    *frame = s_can_queue[s_can_head];
    s_can_head = (s_can_head + 1u) % SIM_HAL_CAN_QUEUE_LEN;
    --s_can_count;
    return 1;
}
