/**
 * @file throttle_cmd.c
 * @brief throttle_cmd: the bench-side commander of the CAN protocol (firmware/protocols/can_proto.h). Sends
 *        TV_CMD_CONTROL (the heartbeat) every --rate-ms and TV_CMD_EXCITATION with every 5th
 *        of them, each with its rolling counter and CRC, over SocketCAN. cansend cannot do this
 *        (it would need the CRC by hand), so this tool is what a bench script uses.
 *
 *   throttle_cmd -i IFACE [--mode M] [--target RAD] [--duty-limit X] [--amplitude V]
 *                [--freq HZ] [--f1 HZ] [--period S] [--clear] [--rate-ms N] [--duration-s S]
 *   throttle_cmd -i IFACE --script FILE
 *
 * Steady mode sends one command until SIGINT/SIGTERM or --duration-s; --clear sends FaultClear = 1
 * in the first 3 control frames (a clear edge: it also ends a latched command timeout).
 *
 * Script mode: one directive per line, "<time_s> <directive> [key=value ...]", times ascending
 * from the start of the program ('#' comments):
 *   set mode=M target=RAD duty_limit=X winding_temp=DEGC|none amplitude=V freq=HZ f1=HZ
 *       period=S   (any subset)
 *   clear                 FaultClear = 1 in the next 3 control frames
 *   silence / resume      stop / restart sending (silence longer than can.cmd_timeout_ms is a fault)
 *   bad KIND              inject one bad frame: crc (a flipped data bit), dlc (DLC 7), repeat (the
 *                         last control frame again), stale (counter one behind), range (mode 15 with a
 *                         valid CRC), unknown (id 0x1FF)
 *   end                   stop
 * Modes: off, sine, steps, chirp, position, stop_learn (the start-up stop learning), ident (the
 * identification excitation). Exit status 0, 1 on a CAN error, 2 on bad arguments.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "can_host.h"
#include "can_proto.h"
#include "lx_can.h"
#include "lx_config.h"
#include "tv_status.h"

#define MAX_SCRIPT_LINES 256
#define EXCITATION_EVERY 5u
#define CLEAR_FRAMES 3u

typedef struct {
    double t_s;
    char text[160];
} line_t;

typedef struct {
    can_proto_control_t ctl;
    can_proto_excitation_t exc;
    uint8_t ctr_ctl;
    uint8_t ctr_exc;
    unsigned clear_left;
    int silent;
    hal_can_frame_t last_ctl;
    int have_last;
    unsigned long sent;
    unsigned long errors;
} cmd_state_t;

static volatile sig_atomic_t s_stop;
static line_t s_script[MAX_SCRIPT_LINES];

static void on_signal(int sig)
{
    (void)sig;
    s_stop = 1;
}

static int parse_mode(const char *s, app_mode_t *m)
{
    /* app_mode_t by value; "external" (5) is replay only and not a command */
    static const char *const names[] = {"off", "sine", "steps", "chirp", "position", "", "stop_learn", "ident"};
    int i;
    for (i = 0; i < (int)(sizeof names / sizeof names[0]); ++i) {
        if (names[i][0] != '\0' && strcmp(s, names[i]) == 0) {
            *m = (app_mode_t)i;
            return 0;
        }
    }
    return -1;
}

static int parse_float(const char *s, float *v)
{
    char *end = NULL;
    const double d = strtod(s, &end);
    if (end == s || *end != '\0') {
        return -1;
    }
    *v = (float)d;
    return 0;
}

/* A winding temperature [degC] in -40 .. 180, or "none" (unknown: WindingTempValid 0). */
static int parse_temp(const char *s, can_proto_control_t *c)
{
    float t;
    if (strcmp(s, "none") == 0) {
        c->temp_valid = 0u;
        c->winding_temp_C = 0.0f;
        return 0;
    }
    if (parse_float(s, &t) != 0 || !(t >= (float)APP_WINDING_TEMP_MIN_C && t <= (float)APP_WINDING_TEMP_MAX_C)) {
        return -1;
    }
    c->temp_valid = 1u;
    c->winding_temp_C = t;
    return 0;
}

/* key=value of a "set" directive. */
static int set_kv(cmd_state_t *st, const char *kv)
{
    char key[32];
    const char *eq = strchr(kv, '=');
    size_t kl;
    if (eq == NULL || (kl = (size_t)(eq - kv)) == 0u || kl >= sizeof key) {
        return -1;
    }
    memcpy(key, kv, kl);
    key[kl] = '\0';
    ++eq;
    if (strcmp(key, "mode") == 0) {
        return parse_mode(eq, &st->ctl.mode);
    }
    if (strcmp(key, "target") == 0) {
        return parse_float(eq, &st->ctl.target_rad);
    }
    if (strcmp(key, "duty_limit") == 0) {
        return parse_float(eq, &st->ctl.duty_limit);
    }
    if (strcmp(key, "winding_temp") == 0) {
        return parse_temp(eq, &st->ctl);
    }
    if (strcmp(key, "amplitude") == 0) {
        return parse_float(eq, &st->exc.amplitude_V);
    }
    if (strcmp(key, "freq") == 0) {
        return parse_float(eq, &st->exc.freq_Hz);
    }
    if (strcmp(key, "f1") == 0) {
        return parse_float(eq, &st->exc.chirp_f1_Hz);
    }
    if (strcmp(key, "period") == 0) {
        return parse_float(eq, &st->exc.chirp_period_s);
    }
    return -1;
}

static void send(lx_can_t *can, cmd_state_t *st, const hal_can_frame_t *f)
{
    if (lx_can_send(can, f) == TV_OK) {
        ++st->sent;
    } else {
        ++st->errors;
    }
}

static int send_control(lx_can_t *can, cmd_state_t *st)
{
    hal_can_frame_t f;
    can_proto_control_t c = st->ctl;
    c.fault_clear = st->clear_left > 0u ? 1u : 0u;
    if (can_host_encode_control(&c, st->ctr_ctl, &f) != TV_OK) {
        return -1;
    }
    if (st->clear_left > 0u) {
        --st->clear_left;
    }
    st->ctr_ctl = (uint8_t)((st->ctr_ctl + 1u) & 15u);
    st->last_ctl = f;
    st->have_last = 1;
    send(can, st, &f);
    return 0;
}

static int send_excitation(lx_can_t *can, cmd_state_t *st)
{
    hal_can_frame_t f;
    if (can_host_encode_excitation(&st->exc, st->ctr_exc, &f) != TV_OK) {
        return -1;
    }
    st->ctr_exc = (uint8_t)((st->ctr_exc + 1u) & 15u);
    send(can, st, &f);
    return 0;
}

static int inject(lx_can_t *can, cmd_state_t *st, const char *kind)
{
    hal_can_frame_t f;
    can_proto_control_t c = st->ctl;
    c.fault_clear = 0u;
    if (can_host_encode_control(&c, st->ctr_ctl, &f) != TV_OK) {
        return -1;
    }
    if (strcmp(kind, "crc") == 0) {
        f.data[4] ^= 0x01u;
    } else if (strcmp(kind, "dlc") == 0) {
        f.dlc = 7u;
    } else if (strcmp(kind, "repeat") == 0) {
        if (!st->have_last) {
            return -1;
        }
        f = st->last_ctl;
    } else if (strcmp(kind, "stale") == 0) {
        (void)can_host_encode_control(&c, (uint8_t)((st->ctr_ctl + 14u) & 15u), &f);
    } else if (strcmp(kind, "range") == 0) {
        f.data[1] = (uint8_t)((f.data[1] & 0x0Fu) | 0xF0u);
        f.data[0] = can_proto_frame_crc(&f);
        st->ctr_ctl = (uint8_t)((st->ctr_ctl + 1u) & 15u); /* a range failure consumes the counter */
    } else if (strcmp(kind, "unknown") == 0) {
        f.id = 0x1FFu;
    } else {
        return -1;
    }
    send(can, st, &f);
    return 0;
}

static int directive(lx_can_t *can, cmd_state_t *st, char *text, double *end_s)
{
    char *save = NULL;
    char *word = strtok_r(text, " \t", &save);
    if (word == NULL) {
        return 0;
    }
    if (strcmp(word, "set") == 0) {
        char *kv;
        while ((kv = strtok_r(NULL, " \t", &save)) != NULL) {
            if (set_kv(st, kv) != 0) {
                fprintf(stderr, "throttle_cmd: bad setting '%s'\n", kv);
                return -1;
            }
        }
        return 0;
    }
    if (strcmp(word, "clear") == 0) {
        st->clear_left = CLEAR_FRAMES;
        return 0;
    }
    if (strcmp(word, "silence") == 0) {
        st->silent = 1;
        return 0;
    }
    if (strcmp(word, "resume") == 0) {
        st->silent = 0;
        return 0;
    }
    if (strcmp(word, "bad") == 0) {
        const char *kind = strtok_r(NULL, " \t", &save);
        if (kind == NULL || inject(can, st, kind) != 0) {
            fprintf(stderr, "throttle_cmd: bad injection '%s'\n", kind != NULL ? kind : "");
            return -1;
        }
        return 0;
    }
    if (strcmp(word, "end") == 0) {
        *end_s = 0.0;
        return 1;
    }
    fprintf(stderr, "throttle_cmd: unknown directive '%s'\n", word);
    return -1;
}

static int load_script(const char *path, int *n)
{
    FILE *f = fopen(path, "r");
    char buf[200];
    int line_no = 0;
    *n = 0;
    if (f == NULL) {
        fprintf(stderr, "throttle_cmd: %s: %s\n", path, strerror(errno));
        return -1;
    }
    while (fgets(buf, sizeof buf, f) != NULL) {
        char *hash = strchr(buf, '#');
        char *p;
        char *end = NULL;
        double t;
        ++line_no;
        if (hash != NULL) {
            *hash = '\0';
        }
        p = buf;
        while (*p == ' ' || *p == '\t') {
            ++p;
        }
        if (*p == '\0' || *p == '\n') {
            continue;
        }
        t = strtod(p, &end);
        if (end == p || *n >= MAX_SCRIPT_LINES || (*n > 0 && t < s_script[*n - 1].t_s)) {
            fprintf(stderr, "throttle_cmd: %s:%d: expected '<time_s> <directive>' with ascending times\n", path,
                    line_no);
            (void)fclose(f);
            return -1;
        }
        s_script[*n].t_s = t;
        (void)snprintf(s_script[*n].text, sizeof s_script[*n].text, "%s", end);
        p = s_script[*n].text + strlen(s_script[*n].text);
        while (p > s_script[*n].text && (p[-1] == '\n' || p[-1] == '\r' || p[-1] == ' ')) {
            *--p = '\0';
        }
        ++*n;
    }
    (void)fclose(f);
    return 0;
}

static void usage(void)
{
    fprintf(stderr, "usage: throttle_cmd -i IFACE [--mode off|sine|steps|chirp|position|stop_learn|ident] [--target RAD]\n"
                    "         [--duty-limit X] [--amplitude V] [--freq HZ] [--f1 HZ] [--period S] [--clear]\n"
                    "         [--winding-temp DEGC|none] [--rate-ms N] [--duration-s S]\n"
                    "       throttle_cmd -i IFACE --script FILE [--rate-ms N]\n");
}

int main(int argc, char **argv)
{
    static cmd_state_t st;
    lx_can_t can;
    char err[LX_ERR_LEN];
    const char *iface = NULL;
    const char *script = NULL;
    double duration_s = 0.0;
    long rate_ms = 20;
    int n_lines = 0;
    int next_line = 0;
    struct timespec t0;
    struct timespec next;
    unsigned long next_ctl_ms = 0;
    unsigned long n_ctl = 0;
    struct sigaction sa;
    int i;

    st.ctl.mode = APP_MODE_OFF;
    st.ctl.target_rad = 0.3f;
    st.ctl.duty_limit = 0.95f;
    st.exc.amplitude_V = 12.0f;
    st.exc.freq_Hz = 5.0f;
    st.exc.chirp_f1_Hz = 20.0f;
    st.exc.chirp_period_s = 2.0f;
    for (i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int bad = 0;
        if (strcmp(a, "--clear") == 0) {
            st.clear_left = CLEAR_FRAMES;
            continue;
        }
        if (v == NULL) {
            usage();
            return 2;
        }
        ++i;
        if (strcmp(a, "-i") == 0) {
            iface = v;
        } else if (strcmp(a, "--script") == 0) {
            script = v;
        } else if (strcmp(a, "--mode") == 0) {
            bad = parse_mode(v, &st.ctl.mode);
        } else if (strcmp(a, "--target") == 0) {
            bad = parse_float(v, &st.ctl.target_rad);
        } else if (strcmp(a, "--duty-limit") == 0) {
            bad = parse_float(v, &st.ctl.duty_limit);
        } else if (strcmp(a, "--winding-temp") == 0) {
            bad = parse_temp(v, &st.ctl);
        } else if (strcmp(a, "--amplitude") == 0) {
            bad = parse_float(v, &st.exc.amplitude_V);
        } else if (strcmp(a, "--freq") == 0) {
            bad = parse_float(v, &st.exc.freq_Hz);
        } else if (strcmp(a, "--f1") == 0) {
            bad = parse_float(v, &st.exc.chirp_f1_Hz);
        } else if (strcmp(a, "--period") == 0) {
            bad = parse_float(v, &st.exc.chirp_period_s);
        } else if (strcmp(a, "--rate-ms") == 0) {
            rate_ms = strtol(v, NULL, 10);
            bad = rate_ms < 1 || rate_ms > 10000;
        } else if (strcmp(a, "--duration-s") == 0) {
            duration_s = strtod(v, NULL);
            bad = !(duration_s > 0.0);
        } else {
            bad = 1;
        }
        if (bad) {
            fprintf(stderr, "throttle_cmd: bad option %s %s\n", a, v);
            usage();
            return 2;
        }
    }
    if (iface == NULL) {
        usage();
        return 2;
    }
    {
        hal_can_frame_t probe;
        if (can_host_encode_control(&st.ctl, 0u, &probe) != TV_OK ||
            can_host_encode_excitation(&st.exc, 0u, &probe) != TV_OK) {
            fprintf(stderr, "throttle_cmd: a value is outside its range (see firmware/protocols/can_proto.h)\n");
            return 2;
        }
    }
    if (script != NULL && load_script(script, &n_lines) != 0) {
        return 2;
    }
    if (lx_can_open(&can, iface, err, sizeof err) != TV_OK) {
        fprintf(stderr, "throttle_cmd: %s\n", err);
        return 1;
    }
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    (void)clock_gettime(CLOCK_MONOTONIC, &t0);
    next = t0;
    while (!s_stop) {
        /* times follow the clock, not the number of wake-ups (a late wake-up loses nothing) */
        struct timespec now;
        double t_s;
        int stop = 0;
        (void)clock_gettime(CLOCK_MONOTONIC, &now);
        t_s = (double)(now.tv_sec - t0.tv_sec) + (double)(now.tv_nsec - t0.tv_nsec) * 1e-9;
        while (next_line < n_lines && s_script[next_line].t_s <= t_s) {
            const int r = directive(&can, &st, s_script[next_line].text, &duration_s);
            ++next_line;
            if (r < 0) {
                lx_can_close(&can);
                return 2;
            }
            if (r > 0) {
                stop = 1;
                break;
            }
        }
        if (stop || (script == NULL && duration_s > 0.0 && t_s >= duration_s)) {
            break;
        }
        if (t_s * 1000.0 >= (double)next_ctl_ms) {
            if (!st.silent) {
                (void)send_control(&can, &st);
                if (n_ctl % EXCITATION_EVERY == 0u) {
                    (void)send_excitation(&can, &st);
                }
                ++n_ctl;
            }
            next_ctl_ms += (unsigned long)rate_ms;
            if ((double)next_ctl_ms <= t_s * 1000.0) {
                next_ctl_ms = (unsigned long)(t_s * 1000.0) + (unsigned long)rate_ms;
            }
        }
        next.tv_nsec += 1000000L;
        if (next.tv_nsec >= 1000000000L) {
            next.tv_nsec -= 1000000000L;
            ++next.tv_sec;
        }
        if (next.tv_sec < now.tv_sec || (next.tv_sec == now.tv_sec && next.tv_nsec < now.tv_nsec)) {
            next = now; /* behind: do not try to catch up wake-ups */
        }
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL) == EINTR && !s_stop) {
        }
    }
    lx_can_close(&can);
    printf("throttle_cmd: sent %lu frames, %lu send errors\n", st.sent, st.errors);
    return st.errors > 0u ? 1 : 0;
}
