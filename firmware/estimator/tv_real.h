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
#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(TV_REAL_DOUBLE)
/** Scalar type of model and filter (double build). */
typedef double tv_real_t;
#define TV_R(x) (x)
#define TV_SQRT(x) sqrt(x)
#define TV_EXP(x) exp(x)
#define TV_EXP_NEG(x) exp(-(x))
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
#define TV_EXP_NEG(x) tv_expf_neg(x)
#define TV_LOG(x) logf(x)
#define TV_LOG1P(x) log1pf(x)
#define TV_FABS(x) fabsf(x)
#define TV_REAL_IS_DOUBLE 0

/**
 * exp(-x) for x >= 0 in single precision: the Stribeck friction's exponential, several times per
 * period (firmware/estimator/tv_model.c). newlib's expf (fdlibm's, with its errno wrapper) took
 * 658 of the application step's 8,320 Cortex-M4F instructions; this one, about 45 a call inline,
 * brought the step's mean to 8,080 (firmware_report). Cephes' expf (S. L. Moshier): x = k ln 2 + r with k = round(x / ln 2) and ln 2 in two parts
 * (Cody and Waite), |r| <= ln 2 / 2, exp(-r) by Cephes' degree-7 polynomial, times 2^-k built in
 * the exponent field. Relative error within 1.5e-7 of the double exp (measured 8.3e-8: tests/test_model.c,
 * test_exp_neg); 0 from x >= 87 (exp(-87) is about the smallest normal float); NaN stays NaN;
 * a negative x (never passed) goes to expf.
 */
static inline float tv_expf_neg(float x)
{
    float r;
    float p;
    float s;
    int32_t k;
    uint32_t b;
    if (!(x < 87.0f)) {
        return x == x ? 0.0f : x;
    }
    if (x < 0.0f) {
        return expf(-x);
    }
    k = (int32_t)(x * 1.44269504088896341f + 0.5f);
    r = (float)k * 2.12194440e-4f + (x - (float)k * 0.693359375f); /* x - k ln 2 */
    r = -r;
    p = ((((1.9875691500e-4f * r + 1.3981999507e-3f) * r + 8.3334519073e-3f) * r + 4.1665795894e-2f) * r +
         1.6666665459e-1f) * r + 5.0000001201e-1f;
    p = p * r * r + r + 1.0f;
    b = (uint32_t)(127 - k) << 23;
    memcpy(&s, &b, sizeof s);
    return p * s;
}
#endif

/** x^y for x > 0 as exp(y log x): the one power the firmware uses (contact law, its fit). */
#define TV_POWP(x, y) TV_EXP((y) * TV_LOG(x))
/** True when v is neither NaN nor infinite (works without relying on isfinite's type-generic macro). */
#define TV_IS_FINITE(v) (((v) == (v)) && ((v) - (v) == TV_R(0.0)))

#ifdef __cplusplus
}
#endif

#endif /* TV_REAL_H */
