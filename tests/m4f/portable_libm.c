/**
 * @file portable_libm.c
 * @brief expf() and sinf() written with nothing but IEEE-754 single-precision +, -, *, and
 *        integer/bit operations, linked in place of the C library's versions (-Wl,--wrap=expf,
 *        --wrap=sinf) into BOTH the host replay and the QEMU replay image of the "portable"
 *        comparison. Basic float operations are correctly rounded on x86-64 SSE and on the
 *        Cortex-M4F FPU alike, so with contraction off (-ffp-contract=off) these return the same
 *        bits on both: any remaining difference between the two replays would then come from
 *        the compilers, not from glibc vs newlib. Test code only (about 1-2 ulp accurate); the
 *        firmware uses the C library.
 */
#include <stdint.h>
#include <string.h>

float __wrap_expf(float x);
float __wrap_sinf(float x);

static float from_bits(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* 2^n for -126 <= n <= 127. */
static float pow2i(int32_t n)
{
    return from_bits((uint32_t)(n + 127) << 23);
}

float __wrap_expf(float x)
{
    const float ln2_hi = 6.93145752e-01f; /* 0x3f317200: low bits zero, n * ln2_hi exact */
    const float ln2_lo = 1.42860677e-06f; /* ln 2 - ln2_hi */
    float kf;
    float r;
    float p;
    int32_t n;
    if (x != x) {
        return x;
    }
    if (x > 88.7228317f) {
        return from_bits(0x7f800000u);
    }
    if (x < -103.972076f) {
        return 0.0f;
    }
    kf = x * 1.44269502f;
    n = (int32_t)(kf + (kf >= 0.0f ? 0.5f : -0.5f));
    r = (x - (float)n * ln2_hi) - (float)n * ln2_lo; /* |r| <= ~0.35 */
    p = 1.0f + r * (1.0f + r * (0.5f + r * (1.66666672e-01f + r * (4.16666679e-02f +
                    r * (8.33333377e-03f + r * (1.38888892e-03f + r * 1.98412701e-04f))))));
    if (n < -126) {
        return p * pow2i(n + 64) * pow2i(-64);
    }
    if (n > 127) {
        return p * pow2i(n - 1) * 2.0f;
    }
    return p * pow2i(n);
}

float __wrap_sinf(float x)
{
    /* Cody-Waite reduction by pi/2 in three parts; the first two have trailing zero bits so
     * k * part is exact for |k| < 2^7 (|x| < ~200 rad, which covers the replay's phases). */
    const float pio2_1 = 1.57078552e+00f;  /* 0x3fc90f80 */
    const float pio2_2 = 1.08042732e-05f;  /* 0x37354400 */
    const float pio2_3 = 6.07709438e-11f;  /* 0x2e85a308 */
    float kf;
    float r;
    float r2;
    float s;
    float c;
    int32_t k;
    if (x != x) {
        return x;
    }
    kf = x * 6.36619747e-01f;
    k = (int32_t)(kf + (kf >= 0.0f ? 0.5f : -0.5f));
    r = ((x - (float)k * pio2_1) - (float)k * pio2_2) - (float)k * pio2_3;
    r2 = r * r;
    s = r + r * r2 * (-1.66666672e-01f + r2 * (8.33333377e-03f + r2 * (-1.98412701e-04f + r2 * 2.75573188e-06f)));
    c = 1.0f + r2 * (-0.5f + r2 * (4.16666679e-02f + r2 * (-1.38888892e-03f + r2 * 2.48015876e-05f)));
    switch ((uint32_t)k & 3u) {
    case 0u:
        return s;
    case 1u:
        return c;
    case 2u:
        return -s;
    default:
        return -c;
    }
}
