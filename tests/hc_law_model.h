/**
 * @file hc_law_model.h
 * @brief Test helper shared by the stop tests: the default model with a learned Hunt-Crossley
 *        contact law (stiffness k [N m/rad^e], exponent e, damping 0.16 k as the start-up routine
 *        sets it).
 */
#ifndef HC_LAW_MODEL_H
#define HC_LAW_MODEL_H

#include "tv_model.h"

static tvm_params_t hc_law_model(double k, double e)
{
    tvm_params_t p;
    tvm_params_default(&p);
    p.k_stop_Nm_rad = (tv_real_t)k;
    p.stop_exponent = (tv_real_t)e;
    p.d_stop_Nm_s_rad = (tv_real_t)(0.16 * k);
    return p;
}

#endif /* HC_LAW_MODEL_H */
