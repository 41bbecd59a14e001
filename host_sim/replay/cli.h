/**
 * @file cli.h
 * @brief Command-line helpers shared by host_sim, replay and log_convert: number parsing, the
 *        one-line usage error, the process- and measurement-noise overrides (--qu, --qT,
 *        --r-current, --r-angle, --r-velocity) and the check that an output is not the input.
 */
#ifndef CLI_H
#define CLI_H

#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Exit code of a usage error, the same in every executable. */
#define CLI_EXIT_USAGE 2

/** Parse a finite decimal double (the whole string); 0 on success, -1 otherwise. */
int cli_parse_double(const char *s, double *out);

/** Longest directory path cli_make_dirs() builds [chars]. */
#define CLI_PATH_MAX 4096

/**
 * mkdir -p: create dir and its missing parents.
 * @return 0; -1 with errno set (ENOTDIR when a part exists and is not a directory).
 */
int cli_make_dirs(const char *dir);

/**
 * Parse an unsigned decimal integer (digits only, no sign, no 0x, no octal meaning of a leading
 * 0); 0 on success, -1 not a number, -2 too large for unsigned long long.
 */
int cli_parse_u64(const char *s, unsigned long long *out);

/**
 * Print "PROG: MESSAGE" and one hint line ("try 'PROG --help'") on stderr, never the whole
 * help. printf-style message.
 * @return CLI_EXIT_USAGE
 */
int cli_usage_error(const char *prog, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/** 1 when a is one of the NULL-terminated names (an option that takes a value), else 0. */
int cli_is_one_of(const char *a, const char *const *names);

/**
 * Check an option that takes a value: a must be one of takes_value (NULL-terminated) and its
 * value v (the next argument, NULL when there is none) must be present.
 * @return 0; or CLI_EXIT_USAGE after a one-line usage error ("unknown option", "needs a value")
 */
int cli_option_value(const char *prog, const char *a, const char *v, const char *const *takes_value);

/**
 * Take a positional argument as the one input path: *in_path is set the first time.
 * @return 0; or CLI_EXIT_USAGE after a usage error naming both when an input was already given
 */
int cli_set_input(const char *prog, const char **in_path, const char *a);

/** The noise overrides, by index. */
typedef enum {
    CLI_NOISE_QU = 0,     /**< --qu: armature voltage noise density [V^2 s], >= 0 */
    CLI_NOISE_QT,         /**< --qT: plate torque noise density [N^2 m^2 s], >= 0 */
    CLI_NOISE_R_CURRENT,  /**< --r-current: current measurement variance [A^2], > 0 */
    CLI_NOISE_R_ANGLE,    /**< --r-angle: angle measurement variance [rad^2], > 0 */
    CLI_NOISE_R_VELOCITY, /**< --r-velocity: differentiated-velocity variance [(rad/s)^2], > 0 */
    CLI_NOISE_N
} cli_noise_t;

/** The noise overrides given on a command line. */
typedef struct {
    int given[CLI_NOISE_N];   /**< 1 when the option was given */
    double value[CLI_NOISE_N]; /**< its value, in the unit above */
} cli_noise_overrides_t;

/** Index of a noise option name (e.g. "--qu"), or -1 when a is not one. */
int cli_noise_index(const char *a);

/** Parameter-file key of a noise override (e.g. "ekf.qu_V2_s"). */
const char *cli_noise_param_key(cli_noise_t idx);

/**
 * Parse and check the value v of noise option a (cli_noise_index(a) >= 0) into *ov: a finite
 * number, >= 0 for a density and > 0 for a variance, given once.
 * @return 0; or CLI_EXIT_USAGE after a one-line usage error naming the option and the value.
 */
int cli_noise_set(const char *prog, cli_noise_overrides_t *ov, const char *a, const char *v);

/** The winding-temperature options of host_sim, population and identify. */
typedef enum {
    CLI_TEMP_NONE = 0,  /**< the application is not told the temperature (unknown) */
    CLI_TEMP_VALUE = 1, /**< it is told reading_C */
    CLI_TEMP_PLANT = 2  /**< it is told the plant's (winding_C) */
} cli_temp_reading_t;

typedef struct {
    double winding_C;           /**< --winding-temp: the plant winding's temperature [degC], default 20 */
    cli_temp_reading_t reading; /**< --temp-reading: plant, none or a value; default none */
    double reading_C;           /**< that value [degC] */
    int given[2];               /**< 1 when --winding-temp, --temp-reading were given */
} cli_temps_t;

/** The options' help lines (host_sim, population). */
#define CLI_TEMP_HELP                                                                                          \
    "  --winding-temp C  the plant winding's temperature [degC], -40 .. 180 (default 20): its\n"                \
    "                    resistance is the unit's at 20 degC times 1 + 0.00393 (C - 20) (copper)\n"           \
    "  --temp-reading T  what the application is told of it (the CAN command's WindingTemp):\n"              \
    "                    plant (the plant's), none (default: unknown) or a temperature [degC];\n"             \
    "                    with it the resistance check refers R to 20 degC (firmware/app/app.h)\n"

/** app_set_winding_temp()'s range (APP_WINDING_TEMP_MIN_C .. MAX_C of firmware/app/app.h; this
 *  library has no scalar type and does not include it) [degC]. */
#define CLI_TEMP_MIN_C (-40.0)
#define CLI_TEMP_MAX_C 180.0

/** Parse a winding temperature [degC]: a finite number within CLI_TEMP_MIN_C .. CLI_TEMP_MAX_C.
 *  @return 0, or -1 (nothing written). */
int cli_parse_temp(const char *s, double *out);

/** Defaults: the winding at 20 degC, the temperature not told. */
void cli_temps_default(cli_temps_t *t);

/** 1 when a is "--winding-temp" or "--temp-reading". */
int cli_is_temp_option(const char *a);

/**
 * Parse the value v of a temperature option a: --winding-temp DEGC (-40 .. 180), --temp-reading
 * plant | none | DEGC (-40 .. 180), each given once.
 * @return 0; or CLI_EXIT_USAGE after a one-line usage error naming the option and the value.
 */
int cli_temp_set(const char *prog, cli_temps_t *t, const char *a, const char *v);

/** The temperature the application is told: 1 and *c when told, 0 when not. */
int cli_temp_told(const cli_temps_t *t, double *c);

/**
 * Refuse to write an output file that is the input (same device and inode, whatever the path:
 * another spelling, a hard or a symbolic link). "-" or NULL (stdin/stdout) never clash, nor does
 * an output that does not exist yet. Call before the output is opened for writing.
 * @return 1 when out_path names the input file, else 0
 */
int cli_same_file(const char *in_path, const char *out_path);

/**
 * cli_same_file() with the message: print "PROG: the output OUT is the input log IN: refusing to
 * overwrite it" when out_path names the input.
 * @return 1 when it does (the tool exits with CLI_EXIT_USAGE), else 0
 */
int cli_refuse_output_is_input(const char *prog, const char *in_path, const char *out_path);

/**
 * Open the input log: NULL or "-" is standard input (*path becomes "<stdin>"), any other path is
 * opened for binary reading; on failure "PROG: cannot open PATH: reason" is printed.
 * @return the stream (the caller closes it unless it is stdin), or NULL after the message
 */
FILE *cli_open_input(const char *prog, const char **path);

/**
 * Parse the value v of --on-error (option name a): "stop" sets *skip to 0, "skip" to 1.
 * @return 0; or CLI_EXIT_USAGE after a one-line usage error naming the value
 */
int cli_on_error(const char *prog, const char *a, const char *v, int *skip);

#ifdef __cplusplus
}
#endif

#endif /* CLI_H */
