/**
 * @file log_convert.c
 * @brief log_convert: convert raw ADC logs between the CSV and the binary TVRAWLOG formats
 *        (host_sim/replay/LOG_FORMATS.md), streaming, with the reader's validation (see usage()).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "rawlog_read.h"
#include "rawlog_write.h"
#include "tv_status.h"

static const char *s_prog = "log_convert";

#define usage_error(...) cli_usage_error(s_prog, __VA_ARGS__)

static rlr_t s_reader;
static rlw_t s_writer;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: %s [--from auto|csv|bin] [--to csv|bin] [--block-records N] [--on-error stop|skip]\n"
            "                   [-o OUT | -] [IN | -]\n"
            "\n"
            "Converts a raw ADC log between CSV and binary TVRAWLOG (host_sim/replay/LOG_FORMATS.md), streaming\n"
            "(constant memory). Every record is validated as replay validates it. IN and OUT default to\n"
            "stdin / stdout ('-'); binary output is not written to a terminal.\n"
            "\n"
            "  --from auto|csv|bin     input format (default auto: the TVRAWLOG magic means binary)\n"
            "  --to csv|bin            output format (default: the other one)\n"
            "  --block-records N       records per binary block, 1..%u (default: the input's, or %u)\n"
            "  --on-error stop|skip    stop at the first bad input (default), or skip and count it\n"
            "  --help                  this text\n"
            "\n"
            "Exit codes as replay: 0 ok; 1 I/O error; 2 usage; 5..18 the input error that stopped the\n"
            "conversion (5 empty, 6 bad header, 7 bad magic, 8 version, 9 line too long, 10 column count,\n"
            "11 not a number, 12 non-finite, 13 out of range, 14 time backwards, 15 repeated time,\n"
            "16 CRC mismatch, 17 bad block header, 18 truncated); 19 finished after skipping input.\n",
            s_prog, RAWLOG_BLOCK_RECORDS_MAX, RAWLOG_BLOCK_RECORDS_DEFAULT);
}

int main(int argc, char **argv)
{
    rlr_format_t from = RLR_FMT_AUTO;
    rlr_format_t to = RLR_FMT_AUTO;
    unsigned long block_records = 0;
    int skip = 0;
    const char *in_path = NULL;
    const char *out_path = NULL;
    FILE *in;
    FILE *out;
    rawlog_record_t rec;
    rawlog_header_t h;
    uint64_t skipped = 0;
    int exit_code = RLR_EXIT_OK;
    int rc;
    int k;
    static const char *const takes_value[] = {"--from", "--to", "--block-records", "--on-error", "-o", "--out",
                                              NULL};

    for (k = 1; k < argc; ++k) {
        const char *a = argv[k];
        const char *v = k + 1 < argc ? argv[k + 1] : NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return RLR_EXIT_OK;
        }
        if (strcmp(a, "-") == 0 || a[0] != '-') {
            if (cli_set_input(s_prog, &in_path, a) != 0) {
                return CLI_EXIT_USAGE;
            }
            continue;
        }
        if (cli_option_value(s_prog, a, v, takes_value) != 0 || v == NULL) { /* (v: for the analyser) */
            return CLI_EXIT_USAGE;
        }
        ++k;
        if (strcmp(a, "--from") == 0) {
            if (rlr_format_from_name(v, &from) != TV_OK) {
                return usage_error("option %s: '%s' is not auto, csv or bin", a, v);
            }
        } else if (strcmp(a, "--to") == 0) {
            if (rlr_format_from_name(v, &to) != TV_OK || to == RLR_FMT_AUTO) {
                return usage_error("option %s: '%s' is not csv or bin", a, v);
            }
        } else if (strcmp(a, "--block-records") == 0) {
            unsigned long long n = 0u;
            if (cli_parse_u64(v, &n) != 0 || n < 1u || n > RAWLOG_BLOCK_RECORDS_MAX) {
                return usage_error("option %s: '%s' is not an integer in 1..%u", a, v, RAWLOG_BLOCK_RECORDS_MAX);
            }
            block_records = (unsigned long)n;
        } else if (strcmp(a, "--on-error") == 0) {
            if (cli_on_error(s_prog, a, v, &skip) != 0) {
                return CLI_EXIT_USAGE;
            }
        } else {
            out_path = v;
        }
    }

    if (cli_refuse_output_is_input(s_prog, in_path, out_path)) {
        return RLR_EXIT_USAGE;
    }
    in = cli_open_input(s_prog, &in_path);
    if (in == NULL) {
        return RLR_EXIT_IO;
    }
    rc = rlr_open_file(&s_reader, in, in_path, from, 0u);
    if (rc != TV_OK) {
        fprintf(stderr, "%s: %s\n", s_prog, rlr_message(&s_reader));
        if (in != stdin) {
            (void)fclose(in);
        }
        return rlr_exit_code(rlr_error(&s_reader));
    }
    if (to == RLR_FMT_AUTO) {
        to = s_reader.format == RLR_FMT_CSV ? RLR_FMT_BIN : RLR_FMT_CSV;
    }
    if (out_path == NULL || strcmp(out_path, "-") == 0) {
        out = stdout;
        out_path = "<stdout>";
        if (to == RLR_FMT_BIN && isatty(fileno(stdout))) {
            fprintf(stderr, "%s: not writing binary data to a terminal (use -o FILE or a pipe)\n", s_prog);
            if (in != stdin) {
                (void)fclose(in);
            }
            return RLR_EXIT_USAGE;
        }
    } else {
        out = fopen(out_path, to == RLR_FMT_BIN ? "wb" : "w");
        if (out == NULL) {
            fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, out_path, strerror(errno));
            if (in != stdin) {
                (void)fclose(in);
            }
            return RLR_EXIT_IO;
        }
    }
    h = s_reader.hdr;
    if (block_records > 0u) {
        h.records_per_block = (uint16_t)block_records;
    }
    if ((s_reader.calib_present & RLR_CAL_ALL) != RLR_CAL_ALL) {
        fprintf(stderr, "%s: note: %s lacks calibration metadata; the missing values are written as 0\n", s_prog,
                in_path);
    }
    rc = rlw_open(&s_writer, out, to, &h, "converted by log_convert");
    if (rc != TV_OK) {
        fprintf(stderr, "%s: cannot write the header to %s: %s\n", s_prog, out_path, tv_status_str(rc));
        exit_code = rc == TV_ERR_IO ? RLR_EXIT_IO : RLR_EXIT_CONFIG;
    }
    while (exit_code == RLR_EXIT_OK) {
        rc = rlr_next(&s_reader, &rec);
        if (rc == 0) {
            break;
        }
        if (rc < 0) {
            fprintf(stderr, "%s: %s%s\n", s_prog, rlr_message(&s_reader),
                    skip && rlr_recoverable(&s_reader) ? " [skipped]" : "");
            if (!skip || !rlr_recoverable(&s_reader)) {
                exit_code = rlr_exit_code(rlr_error(&s_reader));
                break;
            }
            ++skipped;
            continue;
        }
        rc = rlw_put(&s_writer, &rec);
        if (rc != TV_OK) {
            fprintf(stderr, "%s: writing %s failed: %s\n", s_prog, out_path, tv_status_str(rc));
            exit_code = RLR_EXIT_IO;
        }
    }
    if (rlw_close(&s_writer) != TV_OK && exit_code == RLR_EXIT_OK) {
        fprintf(stderr, "%s: writing %s failed\n", s_prog, out_path);
        exit_code = RLR_EXIT_IO;
    }
    if (out != stdout && fclose(out) != 0 && exit_code == RLR_EXIT_OK) {
        fprintf(stderr, "%s: writing %s failed\n", s_prog, out_path);
        exit_code = RLR_EXIT_IO;
    }
    if (in != stdin) {
        (void)fclose(in);
    }
    fprintf(stderr, "%s: %s (%s) -> %s (%s): %llu records written, %llu missing samples in %llu gaps", s_prog,
            in_path, rlr_format_name(s_reader.format), out_path, rlr_format_name(to),
            (unsigned long long)s_writer.records, (unsigned long long)s_reader.st.missing_samples,
            (unsigned long long)s_reader.st.gaps);
    if (skipped > 0u) {
        fprintf(stderr, ", %llu bad inputs skipped", (unsigned long long)skipped);
    }
    fputc('\n', stderr);
    if (exit_code == RLR_EXIT_OK && skipped > 0u) {
        exit_code = RLR_EXIT_SKIPPED;
    }
    return exit_code;
}
