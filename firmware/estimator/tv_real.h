/**
 * @file tv_real.h
 * @brief Project-wide scalar type of the estimator, chosen at build time.
 *
 * The Cortex-M4F build uses `float` (its FPU is single precision); host analysis builds define
 * TV_REAL_DOUBLE and use `double`. Both are built and tested (estimator_f32, estimator_f64).
 * Literals go through TV_R() so that the float build never promotes to double.
 */
#ifndef TV_REAL_H
#define TV_REAL_H

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(TV_REAL_DOUBLE)
/** Scalar type of model and filter (double build). */
typedef double tv_real_t;
#define TV_R(x) (x)
#define TV_SQRT(x) sqrt(x)
#define TV_EXP(x) exp(x)
#define TV_LOG(x) log(x)
#define TV_LOG1P(x) log1p(x)
#define TV_FABS(x) fabs(x)
#define TV_REAL_IS_DOUBLE 1
#else
/** Scalar type of model and filter (float build, the Cortex-M4F default). */
typedef float tv_real_t;
#define TV_R(x) (x##f)
#define TV_SQRT(x) sqrtf(x)
#define TV_EXP(x) expf(x)
#define TV_LOG(x) logf(x)
#define TV_LOG1P(x) log1pf(x)
#define TV_FABS(x) fabsf(x)
#define TV_REAL_IS_DOUBLE 0
#endif

/** True when v is neither NaN nor infinite (works without relying on isfinite's type-generic macro). */
/** x^y for x > 0 as exp(y log x): the one power the firmware uses (contact law, its fit). */
#define TV_POWP(x, y) TV_EXP((y) * TV_LOG(x))
#define TV_IS_FINITE(v) (((v) == (v)) && ((v) - (v) == TV_R(0.0)))

#ifdef __cplusplus
}
#endif

#endif /* TV_REAL_H */
