/**
 * @file vm_plant.c
 * @brief The throttle valve for throttle_linux inside the test VM: the high-fidelity plant
 *        (host_sim/plant/plant.h) behind the same interfaces a real controller has.
 *
 *   vm_plant --root DIR --gpio-phys ADDR --enable-line N --fault-line N --duration-s S
 *            --truth FILE [--seed N] [--fault-at S --fault-len S] [--cpu N]
 *
 * It creates, under DIR, what the sysfs PWM class and IIO show user space (plain files):
 *   DIR/pwmchip0/{export,npwm}, DIR/pwmchip0/pwm{0,1}/{period,duty_cycle,enable,polarity}
 *   DIR/iio:device0/{name,in_voltage0_raw..in_voltage3_raw}
 * and plays the pins of the real kernel GPIO chip the VM has (gpio-amdpt on a reserved RAM
 * page, see hal/linux/README.md, "Against a real kernel"): it maps the chip's registers through /dev/mem (the kernel
 * is booted with iomem=relaxed), reads the bridge-enable output the driver drives
 * (DIRECTION and OUTPUTDATA registers) and drives the nFAULT input (INPUTDATA, active low:
 * 1 = no fault). Then, every millisecond of CLOCK_MONOTONIC:
 *   1. integrate the plant over the elapsed real time with the bridge command in force;
 *   2. read the new command: duty = (duty_cycle(pwm0) - duty_cycle(pwm1)) / period for the
 *      enabled channels, bridge enabled when the enable line is an output driven high;
 *   3. convert the ADC channels and write them (fixed width, one pwrite each: a reader never
 *      sees a partial number);
 *   4. record the true state with CLOCK_REALTIME (candump stamps frames with that clock).
 * At the end it writes the truth as CSV (t_mono_s: CLOCK_MONOTONIC just before the sample's
 * files were written, t_real_s: CLOCK_REALTIME, current_A, velocity_rad_s, angle_rad, duty,
 * enable, fault_pin) and prints "vm_plant: FINAL ..." with the outputs it sees last, and its
 * own loop statistics. SIGTERM ends it early (truth still written).
 */
#define _GNU_SOURCE

#include <errno.h>
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "plant.h"
#include "tv_status.h"

/* gpio-amdpt register offsets (drivers/gpio/gpio-amdpt.c) */
#define PT_DIRECTION_REG 0x00u
#define PT_INPUTDATA_REG 0x04u
#define PT_OUTPUTDATA_REG 0x08u

#define MAX_TRUTH 60000u

typedef struct {
    double t_mono_s;
    double t_real_s;
    float current_A, velocity_rad_s, angle_rad, duty;
    uint8_t enable, fault_pin;
} truth_t;

static truth_t s_truth[MAX_TRUTH];
static volatile sig_atomic_t s_stop;

static void on_signal(int sig)
{
    (void)sig;
    s_stop = 1;
}

static int write_text(const char *dir, const char *name, const char *text)
{
    char path[512];
    FILE *f;
    (void)snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "vm_plant: %s: %s\n", path, strerror(errno));
        return -1;
    }
    (void)fputs(text, f);
    return fclose(f);
}

static int make_dir(const char *path)
{
    if (mkdir(path, 0755) != 0 && errno != EEXIST) {
        fprintf(stderr, "vm_plant: mkdir %s: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

static long read_long(int fd)
{
    char buf[32];
    const ssize_t n = pread(fd, buf, sizeof buf - 1u, 0);
    if (n <= 0) {
        return 0;
    }
    buf[n] = '\0';
    return strtol(buf, NULL, 10); /* stops at the newline (pwrite may leave an old tail after it) */
}

static double now_s(clockid_t clk)
{
    struct timespec ts;
    (void)clock_gettime(clk, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    static plant_t plant;
    plant_config_t pc;
    const char *root = NULL;
    const char *truth_path = NULL;
    unsigned long gpio_phys = 0;
    unsigned enable_line = 0u;
    unsigned fault_line = 1u;
    double duration_s = 10.0;
    double fault_at = -1.0;
    double fault_len = 0.0;
    unsigned long long seed = 7u;
    int cpu = -1;
    char chip[300], ch[2][320], iio[300], path[700];
    int fd_duty[2], fd_en[2], fd_period[2], fd_adc[4];
    volatile uint32_t *regs;
    int memfd;
    struct timespec next;
    double t0, last;
    unsigned n_truth = 0u;
    unsigned long ticks = 0u, late = 0u;
    double lat_max = 0.0;
    int i;
    struct sigaction sa;

    for (i = 1; i + 1 < argc; i += 2) {
        const char *a = argv[i];
        const char *v = argv[i + 1];
        if (strcmp(a, "--root") == 0) {
            root = v;
        } else if (strcmp(a, "--truth") == 0) {
            truth_path = v;
        } else if (strcmp(a, "--gpio-phys") == 0) {
            gpio_phys = strtoul(v, NULL, 0);
        } else if (strcmp(a, "--enable-line") == 0) {
            enable_line = (unsigned)strtoul(v, NULL, 0);
        } else if (strcmp(a, "--fault-line") == 0) {
            fault_line = (unsigned)strtoul(v, NULL, 0);
        } else if (strcmp(a, "--duration-s") == 0) {
            duration_s = strtod(v, NULL);
        } else if (strcmp(a, "--fault-at") == 0) {
            fault_at = strtod(v, NULL);
        } else if (strcmp(a, "--fault-len") == 0) {
            fault_len = strtod(v, NULL);
        } else if (strcmp(a, "--seed") == 0) {
            seed = strtoull(v, NULL, 0);
        } else if (strcmp(a, "--cpu") == 0) {
            cpu = (int)strtol(v, NULL, 0);
        } else {
            break;
        }
    }
    if (root == NULL || truth_path == NULL || gpio_phys == 0u || i < argc) {
        fprintf(stderr, "usage: vm_plant --root DIR --gpio-phys ADDR --enable-line N --fault-line N "
                        "--duration-s S --truth FILE [--seed N] [--fault-at S --fault-len S] [--cpu N]\n");
        return 2;
    }

    /* the file trees */
    (void)snprintf(chip, sizeof chip, "%s/pwmchip0", root);
    (void)snprintf(iio, sizeof iio, "%s/iio:device0", root);
    if (make_dir(root) || make_dir(chip) || make_dir(iio) || write_text(chip, "export", "") ||
        write_text(chip, "npwm", "2\n") || write_text(iio, "name", "vm-plant-adc\n")) {
        return 1;
    }
    for (i = 0; i < 2; ++i) {
        (void)snprintf(ch[i], sizeof ch[i], "%s/pwm%d", chip, i);
        if (make_dir(ch[i]) || write_text(ch[i], "period", "0\n") || write_text(ch[i], "duty_cycle", "0\n") ||
            write_text(ch[i], "enable", "0\n") || write_text(ch[i], "polarity", "normal\n")) {
            return 1;
        }
        (void)snprintf(path, sizeof path, "%s/duty_cycle", ch[i]);
        fd_duty[i] = open(path, O_RDONLY);
        (void)snprintf(path, sizeof path, "%s/enable", ch[i]);
        fd_en[i] = open(path, O_RDONLY);
        (void)snprintf(path, sizeof path, "%s/period", ch[i]);
        fd_period[i] = open(path, O_RDONLY);
        if (fd_duty[i] < 0 || fd_en[i] < 0 || fd_period[i] < 0) {
            fprintf(stderr, "vm_plant: opening %s: %s\n", ch[i], strerror(errno));
            return 1;
        }
    }
    for (i = 0; i < 4; ++i) {
        (void)snprintf(path, sizeof path, "%s/in_voltage%d_raw", iio, i);
        fd_adc[i] = open(path, O_RDWR | O_CREAT | O_TRUNC, 0644);
        if (fd_adc[i] < 0) {
            fprintf(stderr, "vm_plant: %s: %s\n", path, strerror(errno));
            return 1;
        }
    }

    /* the GPIO chip's registers */
    memfd = open("/dev/mem", O_RDWR | O_SYNC);
    if (memfd < 0) {
        fprintf(stderr, "vm_plant: /dev/mem: %s\n", strerror(errno));
        return 1;
    }
    regs = (volatile uint32_t *)mmap(NULL, 4096u, PROT_READ | PROT_WRITE, MAP_SHARED, memfd, (off_t)gpio_phys);
    if ((void *)regs == MAP_FAILED) {
        fprintf(stderr, "vm_plant: mmap /dev/mem at 0x%lx: %s (boot with iomem=relaxed)\n", gpio_phys, strerror(errno));
        return 1;
    }
    regs[PT_INPUTDATA_REG / 4u] |= 1u << fault_line; /* nFAULT high: no fault */

    plant_config_default(&pc);
    if (plant_init(&plant, &pc, seed) != TV_OK) {
        fprintf(stderr, "vm_plant: plant_init failed\n");
        return 1;
    }
    {
        plant_adc_t a;
        (void)plant_sample(&plant, &a);
        {
            const uint16_t c[4] = {a.current_counts, a.tps1_counts, a.tps2_counts, a.supply_counts};
            for (i = 0; i < 4; ++i) {
                char buf[16];
                (void)snprintf(buf, sizeof buf, "%5u\n", (unsigned)c[i]);
                if (pwrite(fd_adc[i], buf, 6u, 0) != 6) {
                    return 1;
                }
            }
        }
    }
    if (cpu >= 0) {
        cpu_set_t set;
        CPU_ZERO(&set);
        CPU_SET((size_t)cpu, &set);
        (void)sched_setaffinity(0, sizeof set, &set);
    }
    {
        struct sched_param sp;
        memset(&sp, 0, sizeof sp);
        sp.sched_priority = 70; /* below the controller's 80 */
        if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0) {
            fprintf(stderr, "vm_plant: SCHED_FIFO refused (%s), running SCHED_OTHER\n", strerror(errno));
        }
    }
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    (void)sigaction(SIGTERM, &sa, NULL);
    (void)sigaction(SIGINT, &sa, NULL);
    (void)write_text(root, "ready", "1\n");
    printf("vm_plant: ready (root %s, gpio registers at 0x%lx, enable line %u, nFAULT line %u)\n", root, gpio_phys,
           enable_line, fault_line);
    fflush(stdout);

    (void)clock_gettime(CLOCK_MONOTONIC, &next);
    t0 = last = (double)next.tv_sec + (double)next.tv_nsec * 1e-9;
    while (!s_stop) {
        double t;
        double dt;
        long period;
        long d[2];
        long en[2];
        uint32_t dir;
        uint32_t out;
        int enable;
        double duty;
        int fault_pin;
        double t_sample;
        plant_adc_t a;
        plant_state_t x;
        next.tv_nsec += 1000000L;
        if (next.tv_nsec >= 1000000000L) {
            next.tv_nsec -= 1000000000L;
            ++next.tv_sec;
        }
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL) == EINTR && !s_stop) {
        }
        t = now_s(CLOCK_MONOTONIC);
        {
            const double lat = t - ((double)next.tv_sec + (double)next.tv_nsec * 1e-9);
            if (lat > lat_max) {
                lat_max = lat;
            }
            if (lat > 1e-3) {
                ++late;
                next.tv_sec = (time_t)t; /* do not try to catch up */
                next.tv_nsec = (long)((t - (double)(time_t)t) * 1e9);
            }
        }
        if (t - t0 >= duration_s) {
            break;
        }
        /* 1. integrate over the elapsed time with the command in force */
        dt = t - last;
        last = t;
        while (dt > 0.0) {
            const double step = dt > 0.5 ? 0.5 : dt;
            if (plant_advance(&plant, step) != TV_OK) {
                fprintf(stderr, "vm_plant: plant_advance failed\n");
                return 1;
            }
            dt -= step;
        }
        /* 2. the new command */
        period = read_long(fd_period[0]);
        for (i = 0; i < 2; ++i) {
            d[i] = read_long(fd_duty[i]);
            en[i] = read_long(fd_en[i]);
        }
        dir = regs[PT_DIRECTION_REG / 4u];
        out = regs[PT_OUTPUTDATA_REG / 4u];
        enable = ((dir >> enable_line) & 1u) != 0u && ((out >> enable_line) & 1u) != 0u;
        duty = period > 0 ? ((en[0] ? (double)d[0] : 0.0) - (en[1] ? (double)d[1] : 0.0)) / (double)period : 0.0;
        duty = duty > 1.0 ? 1.0 : (duty < -1.0 ? -1.0 : duty);
        (void)plant_set_bridge(&plant, duty, enable);
        fault_pin = !(fault_at >= 0.0 && t - t0 >= fault_at && t - t0 < fault_at + fault_len);
        if (fault_pin) {
            regs[PT_INPUTDATA_REG / 4u] |= 1u << fault_line;
        } else {
            regs[PT_INPUTDATA_REG / 4u] &= ~(1u << fault_line);
        }
        /* 3. the ADC; the sample's time is taken before its files are written */
        (void)plant_sample(&plant, &a);
        t_sample = now_s(CLOCK_MONOTONIC);
        {
            const uint16_t c[4] = {a.current_counts, a.tps1_counts, a.tps2_counts, a.supply_counts};
            for (i = 0; i < 4; ++i) {
                char buf[16];
                (void)snprintf(buf, sizeof buf, "%5u\n", (unsigned)c[i]);
                (void)pwrite(fd_adc[i], buf, 6u, 0);
            }
        }
        /* 4. the truth, on candump's clock */
        (void)plant_truth(&plant, &x);
        if (n_truth < MAX_TRUTH) {
            truth_t *r = &s_truth[n_truth++];
            r->t_mono_s = t_sample;
            r->t_real_s = now_s(CLOCK_REALTIME);
            r->current_A = (float)x.current_A;
            r->velocity_rad_s = (float)x.velocity_rad_s;
            r->angle_rad = (float)x.angle_rad;
            r->duty = (float)duty;
            r->enable = (uint8_t)enable;
            r->fault_pin = (uint8_t)fault_pin;
        }
        ++ticks;
    }
    {
        FILE *f = fopen(truth_path, "w");
        unsigned k;
        if (f == NULL) {
            fprintf(stderr, "vm_plant: %s: %s\n", truth_path, strerror(errno));
            return 1;
        }
        fprintf(f, "t_mono_s,t_real_s,current_A,velocity_rad_s,angle_rad,duty,enable,fault_pin\n");
        for (k = 0; k < n_truth; ++k) {
            const truth_t *r = &s_truth[k];
            fprintf(f, "%.6f,%.6f,%.5f,%.4f,%.6f,%.4f,%u,%u\n", r->t_mono_s, r->t_real_s, (double)r->current_A,
                    (double)r->velocity_rad_s, (double)r->angle_rad, (double)r->duty, (unsigned)r->enable,
                    (unsigned)r->fault_pin);
        }
        (void)fclose(f);
    }
    printf("vm_plant: FINAL pwm0 duty %ld enable %ld, pwm1 duty %ld enable %ld, gpio enable %u (direction %u), "
           "%lu ticks, %lu late, worst wake-up latency %.0f us\n",
           read_long(fd_duty[0]), read_long(fd_en[0]), read_long(fd_duty[1]), read_long(fd_en[1]),
           (unsigned)((regs[PT_OUTPUTDATA_REG / 4u] >> enable_line) & 1u),
           (unsigned)((regs[PT_DIRECTION_REG / 4u] >> enable_line) & 1u), ticks, late, lat_max * 1e6);
    return 0;
}
