/**
 * @file lx_err.h
 * @brief Error messages of the Linux controller's modules: every lx_ function that can fail
 *        writes one line naming the configuration key and value into a caller buffer.
 */
#ifndef LX_ERR_H
#define LX_ERR_H

/** Longest error message written by the lx_ modules [bytes]. */
#define LX_ERR_LEN 512u

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** printf() into err (capacity err_len, always NUL-terminated); nothing when err is NULL or err_len 0. */
void lx_err_set(char *err, size_t err_len, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#ifdef __cplusplus
}
#endif

#endif /* LX_ERR_H */
