/**
 * @file tv_deriv.h
 * @brief Host/test-only: the continuous-time right-hand side of the estimator's model, for
 *        analysis and tests. The firmware's prediction map (tv_model.h) treats friction
 *        implicitly and never needs it, so it is not part of the firmware.
 */
#ifndef TV_DERIV_H
#define TV_DERIV_H

#include "tv_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * dx/dt at x, u with the friction sign smoothed as sgn(w) ~ w / sqrt(w^2 + e_w^2) and the
 * limp-home preload sign as phi / sqrt(phi^2 + e_phi^2); built on tvm_friction_level() and
 * tvm_stop_torque().
 */
void tvm_deriv(const tvm_t *m, const tv_real_t x[TVM_NX], tv_real_t u_V, tv_real_t dxdt[TVM_NX]);

#ifdef __cplusplus
}
#endif

#endif /* TV_DERIV_H */
