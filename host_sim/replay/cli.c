/**
 * @file cli.c
 * @brief Command-line helpers shared by the host executables (see cli.h).
 */
#define _POSIX_C_SOURCE 200809L

#include "cli.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int cli_parse_double(const char *s, double *out)
{
    char *end = NULL;
    double v;
    if (s == NULL || *s == '\0' || out == NULL) {
        return -1;
    }
    errno = 0;
    v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !(v == v) || v - v != 0.0) {
        return -1;
    }
    *out = v;
    return 0;
}

int cli_parse_u64(const char *s, unsigned long long *out)
{
    char *end = NULL;
    unsigned long long v;
    const char *p;
    if (s == NULL || *s == '\0' || out == NULL) {
        return -1;
    }
    for (p = s; *p != '\0'; ++p) {
        if (*p < '0' || *p > '9') {
            return -1;
        }
    }
    errno = 0;
    v = strtoull(s, &end, 10);
    if (errno == ERANGE) {
        return -2;
    }
    if (end == s || *end != '\0') {
        return -1;
    }
    *out = v;
    return 0;
}

int cli_usage_error(const char *prog, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "%s: ", prog);
    va_start(ap, fmt);
    /* va_start is right above: a false positive of clang-analyzer-valist.Uninitialized */
    (void)vfprintf(stderr, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized) */
    va_end(ap);
    fprintf(stderr, "\ntry '%s --help'\n", prog);
    return CLI_EXIT_USAGE;
}

int cli_is_one_of(const char *a, const char *const *names)
{
    size_t k;
    for (k = 0; names[k] != NULL; ++k) {
        if (strcmp(a, names[k]) == 0) {
            return 1;
        }
    }
    return 0;
}

int cli_option_value(const char *prog, const char *a, const char *v, const char *const *takes_value)
{
    if (!cli_is_one_of(a, takes_value)) {
        return cli_usage_error(prog, "unknown option '%s'", a);
    }
    if (v == NULL) {
        return cli_usage_error(prog, "option %s needs a value", a);
    }
    return 0;
}

int cli_set_input(const char *prog, const char **in_path, const char *a)
{
    if (*in_path != NULL) {
        return cli_usage_error(prog, "more than one input (%s and %s)", *in_path, a);
    }
    *in_path = a;
    return 0;
}

static const char *const s_noise_opts[CLI_NOISE_N] = {"--qu", "--qT", "--r-current", "--r-angle", "--r-velocity"};
static const char *const s_noise_keys[CLI_NOISE_N] = {"ekf.qu_V2_s", "ekf.qT_Nm2_s", "ekf.r_current_A2",
                                                      "ekf.r_angle_rad2", "ekf.r_velocity_rad2_s2"};

int cli_noise_index(const char *a)
{
    int k;
    for (k = 0; k < (int)CLI_NOISE_N; ++k) {
        if (strcmp(a, s_noise_opts[k]) == 0) {
            return k;
        }
    }
    return -1;
}

const char *cli_noise_param_key(cli_noise_t idx)
{
    return (unsigned)idx < (unsigned)CLI_NOISE_N ? s_noise_keys[idx] : "?";
}

int cli_noise_set(const char *prog, cli_noise_overrides_t *ov, const char *a, const char *v)
{
    const int k = cli_noise_index(a);
    double d = 0.0;
    if (k < 0) {
        return cli_usage_error(prog, "unknown option '%s'", a);
    }
    if (cli_parse_double(v, &d) != 0) {
        return cli_usage_error(prog, "option %s: '%s' is not a finite number", a, v);
    }
    if (k <= (int)CLI_NOISE_QT && d < 0.0) {
        return cli_usage_error(prog, "option %s: %s is negative (a noise density is >= 0)", a, v);
    }
    if (k > (int)CLI_NOISE_QT && !(d > 0.0)) {
        return cli_usage_error(prog, "option %s: %s is not > 0 (a variance)", a, v);
    }
    if (ov->given[k]) {
        return cli_usage_error(prog, "option %s given twice", a);
    }
    ov->given[k] = 1;
    ov->value[k] = d;
    return 0;
}

int cli_parse_temp(const char *s, double *out)
{
    double d = 0.0;
    if (cli_parse_double(s, &d) != 0 || !(d >= CLI_TEMP_MIN_C && d <= CLI_TEMP_MAX_C)) {
        return -1;
    }
    *out = d;
    return 0;
}

void cli_temps_default(cli_temps_t *t)
{
    memset(t, 0, sizeof *t);
    t->winding_C = 20.0;
    t->reading = CLI_TEMP_NONE;
}

int cli_is_temp_option(const char *a)
{
    return strcmp(a, "--winding-temp") == 0 || strcmp(a, "--temp-reading") == 0;
}

int cli_temp_set(const char *prog, cli_temps_t *t, const char *a, const char *v)
{
    const int k = strcmp(a, "--winding-temp") == 0 ? 0 : strcmp(a, "--temp-reading") == 0 ? 1 : -1;
    double d = 0.0;
    if (k < 0) {
        return cli_usage_error(prog, "unknown option '%s'", a);
    }
    if (t->given[k]) {
        return cli_usage_error(prog, "option %s given twice", a);
    }
    if (k == 1 && (strcmp(v, "plant") == 0 || strcmp(v, "none") == 0)) {
        t->reading = v[0] == 'p' ? CLI_TEMP_PLANT : CLI_TEMP_NONE;
        t->given[k] = 1;
        return 0;
    }
    if (cli_parse_temp(v, &d) != 0) {
        return cli_usage_error(prog, "option %s: '%s' is not a temperature in -40 .. 180 degC%s", a, v,
                               k == 1 ? " (nor plant or none)" : "");
    }
    if (k == 0) {
        t->winding_C = d;
    } else {
        t->reading = CLI_TEMP_VALUE;
        t->reading_C = d;
    }
    t->given[k] = 1;
    return 0;
}

int cli_temp_told(const cli_temps_t *t, double *c)
{
    if (t->reading == CLI_TEMP_NONE) {
        return 0;
    }
    *c = t->reading == CLI_TEMP_PLANT ? t->winding_C : t->reading_C;
    return 1;
}

int cli_same_file(const char *in_path, const char *out_path)
{
    struct stat si;
    struct stat so;
    if (in_path == NULL || out_path == NULL || strcmp(in_path, "-") == 0 || strcmp(out_path, "-") == 0) {
        return 0;
    }
    if (stat(in_path, &si) != 0 || stat(out_path, &so) != 0) {
        return 0;
    }
    return si.st_dev == so.st_dev && si.st_ino == so.st_ino;
}

int cli_make_dirs(const char *dir)
{
    char buf[CLI_PATH_MAX];
    size_t n = strlen(dir);
    size_t k;
    struct stat st;
    if (n == 0u || n >= sizeof buf) {
        errno = n == 0u ? ENOENT : ENAMETOOLONG;
        return -1;
    }
    memcpy(buf, dir, n + 1u);
    for (k = 1; k <= n; ++k) {
        if (buf[k] == '/' || buf[k] == '\0') {
            const char c = buf[k];
            buf[k] = '\0';
            if (stat(buf, &st) != 0) {
                if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
                    return -1;
                }
            } else if (!S_ISDIR(st.st_mode)) {
                errno = ENOTDIR; /* stat succeeded: errno would still say "Success" */
                return -1;
            }
            buf[k] = c;
        }
    }
    return 0;
}

int cli_refuse_output_is_input(const char *prog, const char *in_path, const char *out_path)
{
    if (!cli_same_file(in_path, out_path)) {
        return 0;
    }
    fprintf(stderr, "%s: the output %s is the input log %s: refusing to overwrite it\n", prog, out_path, in_path);
    return 1;
}

FILE *cli_open_input(const char *prog, const char **path)
{
    FILE *in;
    if (*path == NULL || strcmp(*path, "-") == 0) {
        *path = "<stdin>";
        return stdin;
    }
    in = fopen(*path, "rb");
    if (in == NULL) {
        fprintf(stderr, "%s: cannot open %s: %s\n", prog, *path, strerror(errno));
    }
    return in;
}

int cli_on_error(const char *prog, const char *a, const char *v, int *skip)
{
    if (strcmp(v, "stop") == 0 || strcmp(v, "skip") == 0) {
        *skip = strcmp(v, "skip") == 0;
        return 0;
    }
    return cli_usage_error(prog, "option %s: '%s' is not stop or skip", a, v);
}
