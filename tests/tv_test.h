/**
 * @file tv_test.h
 * @brief Minimal test harness shared by the C test executables.
 *
 * Every check compares a number with a bound and prints both on failure. A test executable
 * calls TV_TEST_RUN(fn) for each test function and returns tv_test_summary(), which prints
 * "N passed, N failed" and is non-zero when anything failed.
 */
#ifndef TV_TEST_H
#define TV_TEST_H

#include <math.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

static int tv_test_checks_failed_ = 0;
static int tv_test_checks_run_ = 0;
static int tv_tests_passed_ = 0;
static int tv_tests_failed_ = 0;

/** Fail the current test (and continue) when cond is false. */
#define TV_CHECK(cond)                                                                        \
    do {                                                                                      \
        ++tv_test_checks_run_;                                                                \
        if (!(cond)) {                                                                        \
            ++tv_test_checks_failed_;                                                         \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);          \
        }                                                                                     \
    } while (0)

/** |actual - expected| <= tol, printing both numbers on failure. */
#define TV_CHECK_NEAR(actual, expected, tol)                                                  \
    do {                                                                                      \
        double tv_a_ = (double)(actual), tv_e_ = (double)(expected), tv_t_ = (double)(tol);   \
        ++tv_test_checks_run_;                                                                \
        if (!(fabs(tv_a_ - tv_e_) <= tv_t_)) {                                                \
            ++tv_test_checks_failed_;                                                         \
            fprintf(stderr, "%s:%d: %s = %.17g, expected %s = %.17g within %.3g (off by %.3g)\n", \
                    __FILE__, __LINE__, #actual, tv_a_, #expected, tv_e_, tv_t_,              \
                    fabs(tv_a_ - tv_e_));                                                     \
        }                                                                                     \
    } while (0)

/** actual <= bound, printing both on failure. */
#define TV_CHECK_LE(actual, bound)                                                            \
    do {                                                                                      \
        double tv_a_ = (double)(actual), tv_b_ = (double)(bound);                             \
        ++tv_test_checks_run_;                                                                \
        if (!(tv_a_ <= tv_b_)) {                                                              \
            ++tv_test_checks_failed_;                                                         \
            fprintf(stderr, "%s:%d: %s = %.17g, expected <= %s = %.17g\n", __FILE__, __LINE__, \
                    #actual, tv_a_, #bound, tv_b_);                                           \
        }                                                                                     \
    } while (0)

/** Integer equality. */
#define TV_CHECK_EQ_INT(actual, expected)                                                     \
    do {                                                                                      \
        long tv_a_ = (long)(actual), tv_e_ = (long)(expected);                                \
        ++tv_test_checks_run_;                                                                \
        if (tv_a_ != tv_e_) {                                                                 \
            ++tv_test_checks_failed_;                                                         \
            fprintf(stderr, "%s:%d: %s = %ld, expected %ld\n", __FILE__, __LINE__, #actual,   \
                    tv_a_, tv_e_);                                                            \
        }                                                                                     \
    } while (0)

/** Run one test function; it passes when none of its checks failed and it made at least one. */
#define TV_TEST_RUN(fn)                                                                       \
    do {                                                                                      \
        int tv_f0_ = tv_test_checks_failed_, tv_r0_ = tv_test_checks_run_;                    \
        fn();                                                                                 \
        if (tv_test_checks_failed_ == tv_f0_ && tv_test_checks_run_ > tv_r0_) {               \
            ++tv_tests_passed_;                                                               \
            printf("PASS %s (%d checks)\n", #fn, tv_test_checks_run_ - tv_r0_);               \
        } else {                                                                              \
            ++tv_tests_failed_;                                                               \
            printf("FAIL %s (%d of %d checks failed)\n", #fn, tv_test_checks_failed_ - tv_f0_, \
                   tv_test_checks_run_ - tv_r0_);                                             \
        }                                                                                     \
        fflush(stdout);                                                                       \
    } while (0)

/** Print the closing line and return the process exit code. */
static inline int tv_test_summary(void)
{
    printf("%d passed, %d failed\n", tv_tests_passed_, tv_tests_failed_);
    return tv_tests_failed_ == 0 && tv_tests_passed_ > 0 ? 0 : 1;
}

#ifdef __cplusplus
}
#endif

#endif /* TV_TEST_H */
