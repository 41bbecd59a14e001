/**
 * @file semihost.c
 * @brief Arm semihosting calls over BKPT 0xAB (M-profile), see semihost.h.
 */
#include "semihost.h"

#include <stddef.h>

enum {
    SYS_OPEN = 0x01,
    SYS_CLOSE = 0x02,
    SYS_WRITE0 = 0x04,
    SYS_WRITE = 0x05,
    SYS_READ = 0x06,
    SYS_FLEN = 0x0C,
    SYS_GET_CMDLINE = 0x15,
    SYS_EXIT = 0x18,
    SYS_EXIT_EXTENDED = 0x20
};
/** ADP_Stopped_ApplicationExit: the reason code of a normal exit. */
#define SH_ADP_APPLICATION_EXIT 0x20026u

static int32_t sh_call(uint32_t op, const void *arg)
{
    register uint32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return (int32_t)r0;
}

static uint32_t str_len(const char *s)
{
    uint32_t n = 0u;
    while (s[n] != '\0') {
        ++n;
    }
    return n;
}

void sh_puts(const char *s)
{
    (void)sh_call(SYS_WRITE0, s);
}

void sh_put_u32(uint32_t v)
{
    char buf[11];
    int k = 10;
    buf[k] = '\0';
    do {
        buf[--k] = (char)('0' + (v % 10u));
        v /= 10u;
    } while (v != 0u && k > 0);
    sh_puts(&buf[k]);
}

void sh_put_i32(int32_t v)
{
    if (v < 0) {
        sh_puts("-");
        sh_put_u32(0u - (uint32_t)v);
    } else {
        sh_put_u32((uint32_t)v);
    }
}

void sh_put_hex32(uint32_t v)
{
    static const char digits[] = "0123456789abcdef";
    char buf[11];
    int k;
    buf[0] = '0';
    buf[1] = 'x';
    for (k = 0; k < 8; ++k) {
        buf[2 + k] = digits[(v >> (28u - 4u * (uint32_t)k)) & 0xFu];
    }
    buf[10] = '\0';
    sh_puts(buf);
}

int32_t sh_open(const char *path, int32_t mode)
{
    const uint32_t args[3] = {(uint32_t)(uintptr_t)path, (uint32_t)mode, str_len(path)};
    return sh_call(SYS_OPEN, args);
}

int32_t sh_close(int32_t fd)
{
    const uint32_t args[1] = {(uint32_t)fd};
    return sh_call(SYS_CLOSE, args);
}

int32_t sh_read(int32_t fd, void *buf, uint32_t len)
{
    const uint32_t args[3] = {(uint32_t)fd, (uint32_t)(uintptr_t)buf, len};
    /* SYS_READ returns the number of bytes NOT read. */
    const int32_t left = sh_call(SYS_READ, args);
    if (left < 0 || (uint32_t)left > len) {
        return -1;
    }
    return (int32_t)(len - (uint32_t)left);
}

int32_t sh_write(int32_t fd, const void *buf, uint32_t len)
{
    const uint32_t args[3] = {(uint32_t)fd, (uint32_t)(uintptr_t)buf, len};
    /* SYS_WRITE returns the number of bytes NOT written. */
    return sh_call(SYS_WRITE, args) == 0 ? 0 : -1;
}

int32_t sh_get_cmdline(char *buf, uint32_t len)
{
    uint32_t args[2] = {(uint32_t)(uintptr_t)buf, len};
    if (buf == NULL || len == 0u) {
        return -1;
    }
    buf[0] = '\0';
    return sh_call(SYS_GET_CMDLINE, args) == 0 ? 0 : -1;
}

uint32_t sh_split_words(char *s, char **words, uint32_t max)
{
    uint32_t n = 0u;
    if (s == NULL || words == NULL) {
        return 0u;
    }
    while (*s != '\0' && n < max) {
        while (*s == ' ') {
            *s++ = '\0';
        }
        if (*s == '\0') {
            break;
        }
        words[n++] = s;
        while (*s != '\0' && *s != ' ') {
            ++s;
        }
    }
    return n;
}

void sh_exit(int32_t status)
{
    if (status == 0) {
        (void)sh_call(SYS_EXIT, (const void *)(uintptr_t)SH_ADP_APPLICATION_EXIT);
    } else {
        const uint32_t args[2] = {SH_ADP_APPLICATION_EXIT, (uint32_t)status};
        (void)sh_call(SYS_EXIT_EXTENDED, args);
        /* Without the extension, any other reason code ends the session with status 1. */
        (void)sh_call(SYS_EXIT, (const void *)(uintptr_t)0x20023u); /* ADP_Stopped_RunTimeErrorUnknown */
    }
    for (;;) {
    }
}
