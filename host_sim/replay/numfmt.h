/**
 * @file numfmt.h
 * @brief Fast text formatting of numbers for the streaming CSV writers (raw logs, replay
 *        output): the exact text of printf("%.9g") at a tenth of its cost, and integers.
 *
 * numfmt_g9() computes the 9 significant digits with one correctly rounded multiplication or
 * division by an exact power of ten (10^0 .. 10^22) and falls back to snprintf() whenever that
 * could differ from the exactly rounded decimal: within 1e-6 of a rounding tie (the scaled value's
 * error is below 1.2e-7), outside 1e-14 <= |v| < 1e31, and for NaN and infinities. The result
 * is therefore always byte-identical to snprintf("%.9g") (tests/test_replay_reader.c checks it
 * on millions of values); %.9g round-trips every float exactly.
 */
#ifndef NUMFMT_H
#define NUMFMT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Buffer size that holds any numfmt_*() result with its terminator [bytes]. */
#define NUMFMT_MAX 32

/**
 * Format v as printf("%.9g", v) does.
 * @param out at least NUMFMT_MAX bytes; NUL-terminated on return
 * @return the length written (without the terminator)
 */
size_t numfmt_g9(char *out, double v);

/**
 * Format v as printf("%.17g", v) (shortest form that round-trips every double), via snprintf.
 * @return the length written (without the terminator)
 */
size_t numfmt_g17(char *out, double v);

/** Format an unsigned integer in decimal. @return the length written (without the terminator). */
size_t numfmt_u64(char *out, uint64_t v);

/** Format a signed integer in decimal. @return the length written (without the terminator). */
size_t numfmt_i64(char *out, int64_t v);

#ifdef __cplusplus
}
#endif

#endif /* NUMFMT_H */
