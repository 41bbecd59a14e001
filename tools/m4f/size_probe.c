/**
 * @file size_probe.c
 * @brief Links the float estimator for Cortex-M4F so its flash and RAM footprint can be read
 *        off with arm-none-eabi-size. Built twice: with TV_PROBE_ESTIMATOR (calls every entry
 *        point the application uses) and without (the same start-up, no estimator); the
 *        difference of the two is what the estimator costs.
 */
#include "ekf.h"

#ifdef TV_PROBE_ESTIMATOR
/* Statically allocated, as on the ECU: the filter state counts in .bss. */
static ekf_t s_filter;
static ekf_meas_t s_meas;
static ekf_innov_t s_innov;
#endif

/* volatile so the work is kept */
volatile float g_sink;

int main(void)
{
#ifdef TV_PROBE_ESTIMATOR
    tvm_params_t p;
    ekf_config_t cfg;
    tv_real_t sigma[TVM_NX];
    tvm_params_default(&p);
    ekf_config_default(&cfg, EKF_SETUP_CURRENT_ANGLE);
    if (ekf_init(&s_filter, &p, &cfg) == 0) {
        (void)ekf_predict(&s_filter, 1.0f);
        (void)ekf_correct(&s_filter, &s_meas, &s_innov);
        ekf_sigma(&s_filter, sigma);
        g_sink = sigma[0] + s_innov.nis_total;
    }
#else
    g_sink = 0.0f;
#endif
    return 0;
}
