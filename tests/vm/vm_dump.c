/**
 * @file vm_dump.c
 * @brief Copy standard input to the x86 I/O port 0xE9, which QEMU's isa-debugcon device
 *        (-debugcon file:...) appends to a host file: the test VM's way out for its logs.
 *        No interrupts and no driver are involved (a second 16550 UART stalled under the
 *        PREEMPT_RT kernel: "irq 3: nobody cared").
 */
#define _GNU_SOURCE

#include <stdio.h>
#include <sys/io.h>

int main(void)
{
    unsigned char buf[4096];
    size_t n;
    if (ioperm(0xE9, 1, 1) != 0) {
        perror("vm_dump: ioperm(0xE9)");
        return 1;
    }
    while ((n = fread(buf, 1u, sizeof buf, stdin)) > 0u) {
        size_t i;
        for (i = 0; i < n; ++i) {
            outb(buf[i], 0xE9);
        }
    }
    return 0;
}
