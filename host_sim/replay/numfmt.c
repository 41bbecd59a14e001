/**
 * @file numfmt.c
 * @brief Fast %.9g and integer formatting (see numfmt.h).
 */
#include "numfmt.h"

#include <stdio.h>
#include <string.h>

/* Exact powers of ten (every 10^k with k <= 22 is a double). */
static const double s_pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                   1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* "00" .. "99" */
static const char s_pairs[201] = "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
                                 "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
                                 "8081828384858687888990919293949596979899";

/* Significant digits of %.9g. */
#define NUMFMT_DIGITS 9
/* The scaled value is within 1.2e-7 of the exact one; closer than this to a tie: fall back. */
#define NUMFMT_TIE_MARGIN 1e-6

static size_t slow(char *out, const char *fmt, double v)
{
    const int n = snprintf(out, NUMFMT_MAX, fmt, v);
    return n > 0 ? (size_t)n : 0u;
}

/* a * 10^k, correctly rounded, for -22 <= k <= 22. */
static double scale10(double a, int k)
{
    return k >= 0 ? a * s_pow10[k] : a / s_pow10[-k];
}

size_t numfmt_g9(char *out, double v)
{
    char dig[NUMFMT_DIGITS];
    double a;
    double p;
    double fl;
    uint32_t n;
    int e2 = 0;
    int e;
    int k;
    size_t len = 0;
    if (!(v == v) || v - v != 0.0) {
        return slow(out, "%.9g", v);
    }
    if (v == 0.0) {
        return slow(out, "%.9g", v); /* "0" or "-0" */
    }
    a = v < 0.0 ? -v : v;
    {
        /* binary exponent from the bits: a in [2^(e2-1), 2^e2) for normal numbers */
        uint64_t bits;
        memcpy(&bits, &a, sizeof bits);
        e2 = (int)((bits >> 52) & 0x7FFu) - 1022;
        if (e2 == -1022) {
            return slow(out, "%.9g", v); /* subnormal */
        }
    }
    /* (e2 - 1) log10(2) <= log10(a), and it is never within 1e-4 of an integer for the exponents
     * of a double (other than 0), so e is floor(log10 a) or one below. Integer floor of
     * (e2 - 1) * 78913 / 2^18 (78913 / 2^18 = log10(2) to 2e-7, exact enough for |e2| < 1100). */
    {
        const int32_t t = (int32_t)(e2 - 1) * 78913;
        e = t >= 0 ? (int)(t / 262144) : -(int)((-t + 262143) / 262144);
    }
    if (e < -14 || e > 29) { /* 10^(8 - e) must be exact: |8 - e| <= 22 (one step up below) */
        return slow(out, "%.9g", v);
    }
    p = scale10(a, 8 - e);
    if (p >= 1e9) {
        ++e;
        p = scale10(a, 8 - e);
    }
    if (p < 1e8 - 1.0) {
        return slow(out, "%.9g", v);
    }
    fl = (double)(uint32_t)p; /* floor: 0 < p < 1e9 */
    if (p - fl - 0.5 < NUMFMT_TIE_MARGIN && fl + 0.5 - p < NUMFMT_TIE_MARGIN) {
        return slow(out, "%.9g", v);
    }
    n = (uint32_t)(p + 0.5); /* exact: p < 1e9, its ulp <= 2^-23 */
    if (n >= 1000000000u) {  /* rounded up to the next decade */
        n = 100000000u;
        ++e;
    }
    /* 9 digits: one, then four pairs from the table */
    for (k = NUMFMT_DIGITS - 2; k > 0; k -= 2) {
        const uint32_t q = n / 100u;
        const uint32_t pair = n - q * 100u;
        dig[k] = s_pairs[(size_t)pair * 2u];
        dig[k + 1] = s_pairs[(size_t)pair * 2u + 1u];
        n = q;
    }
    dig[0] = (char)('0' + (int)n);
    if (v < 0.0) {
        out[len++] = '-';
    }
    {
        int last = NUMFMT_DIGITS - 1; /* index of the last significant (non-stripped) digit */
        while (last > 0 && dig[last] == '0') {
            --last;
        }
        if (e < -4 || e >= NUMFMT_DIGITS) {
            /* d.ddde+XX */
            int ae = e < 0 ? -e : e;
            out[len++] = dig[0];
            if (last > 0) {
                out[len++] = '.';
                for (k = 1; k <= last; ++k) {
                    out[len++] = dig[k];
                }
            }
            out[len++] = 'e';
            out[len++] = e < 0 ? '-' : '+';
            if (ae >= 100) {
                out[len++] = (char)('0' + ae / 100);
                ae %= 100;
            }
            out[len++] = (char)('0' + ae / 10);
            out[len++] = (char)('0' + ae % 10);
        } else if (e >= 0) {
            /* e + 1 integer digits, then the fraction */
            for (k = 0; k <= e; ++k) {
                out[len++] = dig[k];
            }
            if (last > e) {
                out[len++] = '.';
                for (k = e + 1; k <= last; ++k) {
                    out[len++] = dig[k];
                }
            }
        } else {
            /* 0.000ddd */
            out[len++] = '0';
            out[len++] = '.';
            for (k = 0; k < -e - 1; ++k) {
                out[len++] = '0';
            }
            for (k = 0; k <= last; ++k) {
                out[len++] = dig[k];
            }
        }
    }
    out[len] = '\0';
    return len;
}

size_t numfmt_g17(char *out, double v)
{
    return slow(out, "%.17g", v);
}

size_t numfmt_u64(char *out, uint64_t v)
{
    char tmp[24];
    size_t n = sizeof tmp;
    size_t len;
    while (v >= 100u) {
        const uint64_t q = v / 100u;
        const size_t pair = (size_t)(v - q * 100u);
        tmp[--n] = s_pairs[2u * pair + 1u];
        tmp[--n] = s_pairs[2u * pair];
        v = q;
    }
    if (v >= 10u) {
        tmp[--n] = s_pairs[2u * (size_t)v + 1u];
        tmp[--n] = s_pairs[2u * (size_t)v];
    } else {
        tmp[--n] = (char)('0' + (int)v);
    }
    len = sizeof tmp - n;
    memcpy(out, tmp + n, len);
    out[len] = '\0';
    return len;
}

size_t numfmt_i64(char *out, int64_t v)
{
    if (v < 0) {
        out[0] = '-';
        /* -(v + 1) + 1 avoids overflowing on INT64_MIN */
        return 1u + numfmt_u64(out + 1, (uint64_t)(-(v + 1)) + 1u);
    }
    return numfmt_u64(out, (uint64_t)v);
}
