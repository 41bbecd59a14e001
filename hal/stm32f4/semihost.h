/**
 * @file semihost.h
 * @brief Arm semihosting (the debugger or QEMU performs I/O for the target): console output,
 *        host files, command line, exit. Used by the QEMU test images and by the ECU's trace
 *        build only: on a board without a debugger attached, the BKPT it executes faults.
 *
 * Operation numbers and argument blocks: "Semihosting for AArch32 and AArch64", Arm, 2.0.
 */
#ifndef SEMIHOST_H
#define SEMIHOST_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** File modes of sh_open() (ISO C fopen() modes, as the specification numbers them). */
enum { SH_MODE_RB = 1, SH_MODE_WB = 5 };

/** Write a NUL-terminated string to the debug console. */
void sh_puts(const char *s);

/** Write an unsigned decimal number to the console. */
void sh_put_u32(uint32_t v);

/** Write a signed decimal number to the console. */
void sh_put_i32(int32_t v);

/** Write a number as 0x-prefixed, 8-digit hexadecimal. */
void sh_put_hex32(uint32_t v);

/** Open a host file. @return a handle >= 0, or -1. */
int32_t sh_open(const char *path, int32_t mode);

/** Close a handle. @return 0 or -1. */
int32_t sh_close(int32_t fd);

/** Read up to len bytes. @return the number of bytes read (0 at end of file), or -1. */
int32_t sh_read(int32_t fd, void *buf, uint32_t len);

/** Write len bytes. @return 0 when all were written, -1 otherwise. */
int32_t sh_write(int32_t fd, const void *buf, uint32_t len);

/**
 * The command line the host passed (QEMU: -semihosting-config arg=...), NUL-terminated.
 * @return 0, or -1 when it is unavailable or does not fit in len bytes.
 */
int32_t sh_get_cmdline(char *buf, uint32_t len);

/**
 * Split a command line in place at spaces (they become NULs) into at most max words.
 * @return the number of words written to words[].
 */
uint32_t sh_split_words(char *s, char **words, uint32_t max);

/** End the session with an exit status (0 = success). Does not return. */
void sh_exit(int32_t status) __attribute__((noreturn));

#ifdef __cplusplus
}
#endif

#endif /* SEMIHOST_H */
