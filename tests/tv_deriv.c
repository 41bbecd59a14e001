/**
 * @file tv_deriv.c
 * @brief Continuous-time right-hand side of the estimator's model (see tv_deriv.h).
 */
#include "tv_deriv.h"

void tvm_deriv(const tvm_t *m, const tv_real_t x[TVM_NX], tv_real_t u_V, tv_real_t dxdt[TVM_NX])
{
    const tv_real_t i = x[TVM_I];
    const tv_real_t w = x[TVM_W];
    const tv_real_t phi = x[TVM_PHI];
    const tv_real_t sw = w / TV_SQRT(w * w + m->p.e_w_rad_s * m->p.e_w_rad_s);
    const tv_real_t sp = phi / TV_SQRT(phi * phi + m->p.e_phi_rad * m->p.e_phi_rad);
    const tv_real_t mf = tvm_friction_level(m, w) * sw + m->p.Kv_Nm_s_rad * w;
    const tv_real_t torque = m->nKt_Nm_A * i - m->p.M0_Nm * sp - m->p.c_Nm_rad * phi - mf + tvm_stop_torque(m, phi, w);
    dxdt[TVM_I] = (u_V - m->p.R_ohm * i - m->nKe_V_s * w) / m->p.L_H;
    dxdt[TVM_W] = torque / m->p.J_kg_m2;
    dxdt[TVM_PHI] = w;
}
