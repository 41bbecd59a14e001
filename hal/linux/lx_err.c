/**
 * @file lx_err.c
 * @brief Error messages of the Linux controller's modules (see lx_err.h).
 */
#include "lx_err.h"

#include <stdarg.h>
#include <stdio.h>

void lx_err_set(char *err, size_t err_len, const char *fmt, ...)
{
    if (err != NULL && err_len > 0u) {
        va_list ap;
        va_start(ap, fmt);
        /* clang-tidy 14 reports this va_list as uninitialised whenever this file is not the
         * first of a multi-file run (any file with this pattern, e.g. host_sim/replay/params.c too):
         * a false positive of clang-analyzer-valist.Uninitialized; va_start is right above. */
        (void)vsnprintf(err, err_len, fmt, ap); // NOLINT(clang-analyzer-valist.Uninitialized)
        va_end(ap);
    }
}
