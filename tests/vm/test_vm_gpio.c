/**
 * @file test_vm_gpio.c
 * @brief The libgpiod module (hal/linux/lx_gpio) against a real kernel GPIO chip: inside the
 *        test VM, gpio-amdpt (drivers/gpio/gpio-amdpt.c, the kernel's generic MMIO GPIO
 *        library underneath) drives a reserved RAM page that an ACPI table declares as its
 *        registers. The test reads and writes those registers through /dev/mem as the pins:
 *        the output register shows what the driver drives, the input register is what the
 *        driver reads.
 *
 *   test_vm_gpio <physical address of the registers>
 */
#define _GNU_SOURCE

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "lx_config.h"
#include "lx_gpio.h"
#include "tv_status.h"
#include "tv_test.h"

#define PT_DIRECTION 0u
#define PT_INPUTDATA 1u
#define PT_OUTPUTDATA 2u

static volatile uint32_t *s_regs;

static unsigned pin_out(unsigned line)
{
    return (s_regs[PT_OUTPUTDATA] >> line) & 1u;
}

static unsigned pin_is_output(unsigned line)
{
    return (s_regs[PT_DIRECTION] >> line) & 1u;
}

static void pin_in(unsigned line, unsigned level)
{
    if (level) {
        s_regs[PT_INPUTDATA] |= 1u << line;
    } else {
        s_regs[PT_INPUTDATA] &= ~(1u << line);
    }
}

/* The chip is found by label, name, number and path (gpiod_chip_open_lookup). */
static void test_chip_lookup(void)
{
    static const char *const names[] = {"AMDIF030:00", "gpiochip0", "0", "/dev/gpiochip0"};
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; ++i) {
        lx_gpio_t g;
        char err[LX_ERR_LEN];
        const int rc = lx_gpio_open(&g, names[i], "throttle-test", 0u, 0, 1u, 1, err, sizeof err);
        TV_CHECK_EQ_INT(rc, TV_OK);
        if (rc != TV_OK) {
            printf("  %s: %s\n", names[i], err);
        }
        lx_gpio_close(&g);
    }
}

/* The enable output: requested low (bridge disabled), follows the logical value, honours
 * active-low, refuses values other than 0/1 by disabling, and is driven inactive on close. */
static void test_enable_output_drives_the_pin(void)
{
    lx_gpio_t g;
    char err[LX_ERR_LEN];
    pin_in(1u, 1u);
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "AMDIF030:00", "throttle-test", 0u, 0, 1u, 1, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(pin_is_output(0u), 1);
    TV_CHECK_EQ_INT(pin_out(0u), 0);
    TV_CHECK_EQ_INT(pin_is_output(1u), 0);
    TV_CHECK_EQ_INT(lx_gpio_set_enable(&g, 1), TV_OK);
    TV_CHECK_EQ_INT(pin_out(0u), 1);
    TV_CHECK_EQ_INT(lx_gpio_set_enable(&g, 0), TV_OK);
    TV_CHECK_EQ_INT(pin_out(0u), 0);
    TV_CHECK_EQ_INT(lx_gpio_set_enable(&g, 1), TV_OK);
    TV_CHECK_EQ_INT(lx_gpio_set_enable(&g, 2), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(pin_out(0u), 0);
    TV_CHECK_EQ_INT(lx_gpio_set_enable(&g, 1), TV_OK);
    lx_gpio_close(&g);
    TV_CHECK_EQ_INT(pin_out(0u), 0);
    /* active low on line 2: inactive = high */
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "gpiochip0", "throttle-test", 2u, 1, 1u, 1, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(pin_out(2u), 1);
    TV_CHECK_EQ_INT(lx_gpio_set_enable(&g, 1), TV_OK);
    TV_CHECK_EQ_INT(pin_out(2u), 0);
    lx_gpio_close(&g);
    TV_CHECK_EQ_INT(pin_out(2u), 1);
}

/* The fault input follows the pin, with its polarity. */
static void test_fault_input_reads_the_pin(void)
{
    lx_gpio_t g;
    char err[LX_ERR_LEN];
    int fault = -1;
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "gpiochip0", "throttle-test", 0u, 0, 1u, 1, err, sizeof err), TV_OK);
    pin_in(1u, 1u); /* nFAULT high: no fault */
    TV_CHECK_EQ_INT(lx_gpio_get_fault(&g, &fault), TV_OK);
    TV_CHECK_EQ_INT(fault, 0);
    pin_in(1u, 0u);
    TV_CHECK_EQ_INT(lx_gpio_get_fault(&g, &fault), TV_OK);
    TV_CHECK_EQ_INT(fault, 1);
    pin_in(1u, 1u);
    lx_gpio_close(&g);
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "gpiochip0", "throttle-test", 0u, 0, 3u, 0, err, sizeof err), TV_OK);
    pin_in(3u, 1u); /* active high */
    TV_CHECK_EQ_INT(lx_gpio_get_fault(&g, &fault), TV_OK);
    TV_CHECK_EQ_INT(fault, 1);
    pin_in(3u, 0u);
    TV_CHECK_EQ_INT(lx_gpio_get_fault(&g, &fault), TV_OK);
    TV_CHECK_EQ_INT(fault, 0);
    lx_gpio_close(&g);
}

/* Errors a real kernel produces, each naming the key and value. */
static void test_errors_named(void)
{
    lx_gpio_t g;
    lx_gpio_t h;
    char err[LX_ERR_LEN];
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "gpiochip5", "throttle-test", 0u, 0, 1u, 1, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "gpio.chip = 'gpiochip5'") != NULL);
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "gpiochip0", "throttle-test", 8u, 0, 1u, 1, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "gpio.bridge_enable.line = 8: chip 'gpiochip0' (AMDIF030:00) has 8 lines") != NULL);
    printf("  %s\n", err);
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "gpiochip0", "throttle-test", 0u, 0, 9u, 1, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "gpio.driver_fault.line = 9") != NULL);
    /* after a failed open the enable line was released again: it can be requested */
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "gpiochip0", "throttle-test", 0u, 0, 1u, 1, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(lx_gpio_open(&h, "gpiochip0", "second", 0u, 0, 4u, 1, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "gpio.bridge_enable.line = 0: line busy on chip 'gpiochip0', used by 'throttle-test'") != NULL);
    printf("  %s\n", err);
    TV_CHECK_EQ_INT(lx_gpio_open(&h, "gpiochip0", "second", 5u, 0, 1u, 1, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "gpio.driver_fault.line = 1: line busy") != NULL);
    /* and the failed second open did not disturb the first */
    TV_CHECK_EQ_INT(lx_gpio_set_enable(&g, 1), TV_OK);
    TV_CHECK_EQ_INT(pin_out(0u), 1);
    TV_CHECK_EQ_INT(pin_out(5u), 0);
    lx_gpio_close(&g);
}

int main(int argc, char **argv)
{
    unsigned long phys;
    int fd;
    if (argc != 2) {
        fprintf(stderr, "usage: test_vm_gpio <register address>\n");
        return 2;
    }
    phys = strtoul(argv[1], NULL, 0);
    fd = open("/dev/mem", O_RDWR | O_SYNC);
    if (fd < 0) {
        printf("FAIL /dev/mem: %s\n", strerror(errno));
        return 1;
    }
    s_regs = (volatile uint32_t *)mmap(NULL, 4096u, PROT_READ | PROT_WRITE, MAP_SHARED, fd, (off_t)phys);
    if ((void *)s_regs == MAP_FAILED) {
        printf("FAIL mmap of the GPIO registers at 0x%lx: %s\n", phys, strerror(errno));
        return 1;
    }
    TV_TEST_RUN(test_chip_lookup);
    TV_TEST_RUN(test_enable_output_drives_the_pin);
    TV_TEST_RUN(test_fault_input_reads_the_pin);
    TV_TEST_RUN(test_errors_named);
    return tv_test_summary();
}
