/**
 * @file test_replay_reader.c
 * @brief Tests of the raw-log reader and writer (host_sim/replay/rawlog_read.h, rawlog_write.h) and of
 *        the number formatter: good logs in both formats, and every kind of bad input, each
 *        with its error class, the line or byte offset in the message, fatal or recoverable,
 *        and what skipping delivers afterwards. The values are integers and bit copies: every
 *        comparison is exact.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "numfmt.h"
#include "rawlog.h"
#include "rawlog_read.h"
#include "rawlog_write.h"
#include "tv_status.h"
#include "tv_test.h"

static rlr_t s_r;
static rlw_t s_w;

/* A small valid CSV log: header first, metadata, 5 samples 1 ms apart. */
static const char s_good_csv[] =
    "t_us,duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault,bridge_enable\n"
    "# format: tvrawlog-csv\n"
    "# version: 1\n"
    "# sample_rate_Hz: 1000\n"
    "# adc_bits: 12\n"
    "# current_offset_counts: 2048\n"
    "0,0,2048,633,3463,2794,0,1\n"
    "1000,0.25,2050,640,3456,2790,0,1\n"
    "2000,-0.5,2052,650,3446,2791,0,1\n"
    "3000,1,2054,660,3436,2792,1,0\n"
    "4000,-1,2056,670,3426,2793,0,1\n";

/* Header line + metadata of a CSV log followed by the given data lines. */
static char s_text[8192];

static const char *csv_with(const char *data)
{
    (void)snprintf(s_text, sizeof s_text,
                   "t_us,duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault\n"
                   "# sample_rate_Hz: 1000\n# adc_bits: 12\n%s",
                   data);
    return s_text;
}

static int open_text(const char *text, rlr_format_t fmt)
{
    return rlr_open_mem(&s_r, (const uint8_t *)text, strlen(text), "t.csv", fmt, 0u);
}

/* Read to the end, skipping recoverable errors; returns the records delivered. */
static uint64_t drain(rlr_t *r)
{
    rawlog_record_t rec;
    uint64_t n = 0;
    for (;;) {
        const int rc = rlr_next(r, &rec);
        if (rc == 1) {
            ++n;
        } else if (rc == 0 || !rlr_recoverable(r)) {
            break;
        }
    }
    return n;
}

/* The first error of a CSV text: its class; message must contain want (may be NULL). */
static rlr_err_t first_error(const char *text, const char *want)
{
    rawlog_record_t rec;
    int rc = open_text(text, RLR_FMT_AUTO);
    while (rc == TV_OK || rc == 1) {
        rc = rlr_next(&s_r, &rec);
        if (rc == 0) {
            return RLR_E_NONE;
        }
    }
    if (want != NULL && strstr(rlr_message(&s_r), want) == NULL) {
        fprintf(stderr, "message '%s' lacks '%s'\n", rlr_message(&s_r), want);
        TV_CHECK(0);
    }
    return rlr_error(&s_r);
}

/* ------------------------------------------------------------------------------------------ */
/* CSV: good input                                                                             */
/* ------------------------------------------------------------------------------------------ */

static void test_csv_good_log_reads_every_record_and_the_metadata(void)
{
    rawlog_record_t rec;
    TV_CHECK_EQ_INT(open_text(s_good_csv, RLR_FMT_AUTO), TV_OK);
    TV_CHECK_EQ_INT(s_r.format, RLR_FMT_CSV);
    TV_CHECK_EQ_INT(s_r.hdr.sample_rate_Hz, 1000);
    TV_CHECK_EQ_INT(s_r.adc_max_counts, 4095);
    TV_CHECK_EQ_INT(s_r.calib_present, RLR_CAL_CURRENT_OFFSET);
    TV_CHECK(s_r.hdr.current_offset_counts == 2048.0);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK(rec.t_us == 1000u && rec.duty == 0.25f && rec.adc[0] == 2050u && rec.adc[3] == 2790u);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK(rec.duty == 1.0f && rec.driver_fault == 1u && rec.bridge_enable == 0u);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK(rec.duty == -1.0f);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 0);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 0);
    TV_CHECK_EQ_INT(s_r.st.records, 5);
    TV_CHECK_EQ_INT(s_r.st.missing_samples, 0);
}

static void test_csv_accepts_crlf_bom_quotes_metadata_first(void)
{
    static const char text[] = "\xEF\xBB\xBF# adc_bits: 10\r\n"
                               "# a free comment: with a colon\r\n"
                               "\r\n"
                               " \"t_us\" , duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault,extra\r\n"
                               "0, 0.5 ,1023,0,1,2,0,whatever\r\n"
                               "# a comment between samples\r\n"
                               "\r\n"
                               "1000,0,1,2,3,4,0,x\r\n";
    rawlog_record_t rec;
    TV_CHECK_EQ_INT(open_text(text, RLR_FMT_AUTO), TV_OK);
    TV_CHECK_EQ_INT(s_r.adc_max_counts, 1023);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK(rec.duty == 0.5f && rec.adc[0] == 1023u && rec.bridge_enable == 1u); /* no column: enabled */
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK(rec.t_us == 1000u && rec.adc[3] == 4u);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 0);
}

/* A log cut while written ends in a partial line ("...,27" for "...,2793") that still parses:
 * a last line without its newline is refused as truncated, never replayed (issue 9). */
static void test_csv_last_line_without_newline_is_truncated(void)
{
    rawlog_record_t rec;
    TV_CHECK_EQ_INT(open_text(csv_with("0,0.1,2048,633,3463,2794,0\n1000,0.1,2048,633,3463,27"), RLR_FMT_CSV), TV_OK);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK_EQ_INT(rec.t_us, 0);
    TV_CHECK(rlr_next(&s_r, &rec) < 0);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_TRUNCATED);
    TV_CHECK(!rlr_recoverable(&s_r));
    TV_CHECK(strstr(rlr_message(&s_r), "the last line has no final newline") != NULL);
    TV_CHECK_EQ_INT(rlr_exit_code(rlr_error(&s_r)), 18);
}

/* Binary data read as CSV (or /dev/zero): a NUL byte stops the reader at once instead of
 * consuming one endless line. */
static void test_csv_nul_byte_is_fatal(void)
{
    static const char text[] = "t_us,duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault\n"
                               "0,0.1,2048,633,3463,2794,0\n"
                               "1000,0.1\0\0\0\0";
    rawlog_record_t rec;
    TV_CHECK_EQ_INT(rlr_open_mem(&s_r, (const uint8_t *)text, sizeof text - 1u, "t.csv", RLR_FMT_CSV, 0u), TV_OK);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK(rlr_next(&s_r, &rec) < 0);
    TV_CHECK(strstr(rlr_message(&s_r), "a NUL byte") != NULL);
    TV_CHECK(!rlr_recoverable(&s_r));
}

static void test_csv_integral_fields_may_be_written_in_floating_point(void)
{
    rawlog_record_t rec;
    TV_CHECK_EQ_INT(open_text(csv_with("1.0e3,0,2.048000000000000000e+03,633.0,3463,2794,0.0\n"), RLR_FMT_CSV), TV_OK);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK(rec.t_us == 1000u && rec.adc[0] == 2048u && rec.adc[1] == 633u);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,2048.5,633,3463,2794,0\n"), "line 4: column 3 (current_counts)"),
                    RLR_E_NUMBER);
}

static void test_csv_gap_is_counted_as_missing_samples_not_an_error(void)
{
    rawlog_record_t rec;
    TV_CHECK_EQ_INT(open_text(csv_with("0,0,1,1,1,1,0\n1000,0,1,1,1,1,0\n5000,0,1,1,1,1,0\n5900,0,1,1,1,1,0\n"),
                              RLR_FMT_CSV),
                    TV_OK);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK_EQ_INT(rlr_last_gap(&s_r), 0);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK_EQ_INT(rlr_last_gap(&s_r), 3); /* 1000 -> 5000 us: samples 2000, 3000, 4000 missing */
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK_EQ_INT(rlr_last_gap(&s_r), 0); /* 900 us: jitter, one period */
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 0);
    TV_CHECK_EQ_INT(s_r.st.missing_samples, 3);
    TV_CHECK_EQ_INT(s_r.st.gaps, 1);
}

/* ------------------------------------------------------------------------------------------ */
/* CSV: bad input, one test per kind                                                           */
/* ------------------------------------------------------------------------------------------ */

static void test_csv_empty_input_is_an_error(void)
{
    TV_CHECK_EQ_INT(first_error("", "empty input (0 bytes)"), RLR_E_EMPTY);
    TV_CHECK(!rlr_recoverable(&s_r));
    TV_CHECK_EQ_INT(first_error("# only\n# comments\n\n", "no column header"), RLR_E_EMPTY);
    /* a header but no sample */
    TV_CHECK_EQ_INT(first_error(csv_with("# nothing\n"), "no samples"), RLR_E_EMPTY);
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_EMPTY), 5);
}

static void test_csv_malformed_line_is_not_a_number_naming_line_and_column(void)
{
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,1,1,1,0\n1000,abc,1,1,1,1,0\n"), "t.csv: line 5: column 2 (duty): 'abc'"),
                    RLR_E_NUMBER);
    TV_CHECK(rlr_recoverable(&s_r));
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,12x,1,1,1,0\n"), "column 3 (current_counts): '12x' is not"),
                    RLR_E_NUMBER);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,,1,1,0\n"), "column 4 (tps1_counts): '' is empty"), RLR_E_NUMBER);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0x,1,1,1,1,0\n"), "line 4"), RLR_E_NUMBER);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,1,1,1,0\x01\n"), "line 4"), RLR_E_NUMBER);
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_NUMBER), 11);
}

static void test_csv_wrong_column_count_is_an_error(void)
{
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,1,1,1\n"), "line 4: 6 fields, the column header has 7"), RLR_E_COLUMNS);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,1,1,1,0,9\n"), "line 4: 8 fields"), RLR_E_COLUMNS);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,1,1,1,0,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,\n"),
                                "fields, the column header has 7"),
                    RLR_E_COLUMNS);
    TV_CHECK(rlr_recoverable(&s_r));
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_COLUMNS), 10);
}

static void test_csv_non_finite_fields_are_errors(void)
{
    TV_CHECK_EQ_INT(first_error(csv_with("0,nan,1,1,1,1,0\n"), "column 2 (duty): 'nan' is not finite"), RLR_E_NONFINITE);
    TV_CHECK_EQ_INT(first_error(csv_with("0,-inf,1,1,1,1,0\n"), "is not finite"), RLR_E_NONFINITE);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,inf,1,1,1,0\n"), "column 3"), RLR_E_NONFINITE);
    {
        static const char truth[] = "t_us,duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault,"
                                    "i_true_A,w_true_rad_s,phi_true_rad\n0,0,1,1,1,1,0,0,NaN,0\n";
        TV_CHECK_EQ_INT(first_error(truth, "column 9 (w_true_rad_s)"), RLR_E_NONFINITE);
    }
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_NONFINITE), 12);
}

static void test_csv_counts_outside_the_adc_range_are_errors(void)
{
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,4096,1,1,1,0\n"), "'4096' is outside the ADC range 0..4095"), RLR_E_RANGE);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,-1,1,1,0\n"), "column 4 (tps1_counts): '-1'"), RLR_E_RANGE);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,1,1,99999999999999999999999,0\n"), "supply_counts"), RLR_E_RANGE);
    /* the range follows the metadata's resolution */
    TV_CHECK_EQ_INT(first_error("t_us,duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault\n"
                                "# adc_bits: 10\n0,0,1023,1,1,1,0\n1000,0,1024,1,1,1,0\n",
                                "line 4: column 3 (current_counts): '1024' is outside the ADC range 0..1023"),
                    RLR_E_RANGE);
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_RANGE), 13);
}

static void test_csv_duty_and_flags_outside_their_range_are_errors(void)
{
    TV_CHECK_EQ_INT(first_error(csv_with("0,1.5,1,1,1,1,0\n"), "'1.5' is outside [-1, 1]"), RLR_E_RANGE);
    TV_CHECK_EQ_INT(first_error(csv_with("0,-1.0000001,1,1,1,1,0\n"), "duty"), RLR_E_RANGE);
    TV_CHECK_EQ_INT(first_error(csv_with("0,1e99,1,1,1,1,0\n"), "duty"), RLR_E_RANGE);
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,1,1,1,2\n"), "column 7 (driver_fault): '2' is not 0 or 1"), RLR_E_RANGE);
    TV_CHECK_EQ_INT(first_error(csv_with("99999999999999999999999,0,1,1,1,1,0\n"), "t_us"), RLR_E_RANGE);
}

static void test_csv_timestamp_going_backwards_is_an_error(void)
{
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,1,1,1,0\n5000,0,1,1,1,1,0\n3000,0,1,1,1,1,0\n"),
                                "line 6: t_us 3000 is 2000 us earlier than the previous sample's 5000"),
                    RLR_E_TIME_BACK);
    TV_CHECK(rlr_recoverable(&s_r));
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_TIME_BACK), 14);
}

static void test_csv_repeated_timestamp_is_an_error(void)
{
    TV_CHECK_EQ_INT(first_error(csv_with("0,0,1,1,1,1,0\n1000,0,1,1,1,1,0\n1000,0,1,1,1,1,0\n"),
                                "line 6: t_us 1000 repeats"),
                    RLR_E_TIME_REPEAT);
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_TIME_REPEAT), 15);
}

static void test_csv_line_of_megabytes_is_rejected_in_bounded_memory(void)
{
    const size_t big = 3u * 1024u * 1024u;
    char *text = (char *)malloc(big + 512u);
    size_t n;
    rawlog_record_t rec;
    TV_CHECK(text != NULL);
    if (text == NULL) {
        return;
    }
    n = (size_t)snprintf(text, 512u, "%s", csv_with("0,0,1,1,1,1,0\n"));
    memset(text + n, '7', big);
    n += big;
    n += (size_t)snprintf(text + n, 512u, "\n2000,0,1,1,1,1,0\n");
    TV_CHECK_EQ_INT(rlr_open_mem(&s_r, (const uint8_t *)text, n, "big.csv", RLR_FMT_CSV, 0u), TV_OK);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_LINE_LONG);
    TV_CHECK(strstr(rlr_message(&s_r), "big.csv: line 5: 3145728 bytes, longer than the 4096-byte line limit") != NULL);
    TV_CHECK(rlr_recoverable(&s_r));
    /* skipping goes on after the long line */
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK(rec.t_us == 2000u);
    TV_CHECK_EQ_INT(s_r.st.missing_samples, 1);
    /* the reader is a fixed-size struct: no buffer grows with the line */
    TV_CHECK_LE(sizeof(rlr_t), 200u * 1024u);
    /* a header line that long is fatal */
    memset(text, 'x', big);
    TV_CHECK_EQ_INT(rlr_open_mem(&s_r, (const uint8_t *)text, big, "big.csv", RLR_FMT_CSV, 0u), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_LINE_LONG);
    TV_CHECK(!rlr_recoverable(&s_r));
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_LINE_LONG), 9);
    free(text);
}

static void test_csv_bad_header_and_metadata_are_fatal(void)
{
    TV_CHECK_EQ_INT(first_error("0,0,1,1,1,1,0\n", "line 1: the column header has no 't_us' column"), RLR_E_HEADER);
    TV_CHECK(!rlr_recoverable(&s_r));
    TV_CHECK_EQ_INT(first_error("t_us,duty,duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault\n",
                                "column 'duty' appears twice (columns 2 and 3)"),
                    RLR_E_HEADER);
    TV_CHECK_EQ_INT(first_error("t_us,duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault,i_true_A\n",
                                "truth block needs all of"),
                    RLR_E_HEADER);
    TV_CHECK_EQ_INT(first_error("# adc_bits: 17\nt_us\n", "line 1: metadata 'adc_bits': 17 is outside 8..16"), RLR_E_HEADER);
    TV_CHECK_EQ_INT(first_error("# sample_rate_Hz: 1000\n# sample_rate_Hz: 500\n", "line 2: metadata key 'sample_rate_Hz' given twice (first on line 1)"),
                    RLR_E_HEADER);
    TV_CHECK_EQ_INT(first_error("# tps1_rad_per_count: fast\n", "metadata 'tps1_rad_per_count': 'fast' is not a finite number"),
                    RLR_E_HEADER);
    TV_CHECK_EQ_INT(first_error("# tps1_rad_per_count: inf\n", "not a finite number"), RLR_E_HEADER);
    TV_CHECK_EQ_INT(first_error("# format: something-else\n", "is not tvrawlog-csv"), RLR_E_HEADER);
    TV_CHECK_EQ_INT(first_error("# version: 2\n", "line 1: format version 2 is not supported"), RLR_E_VERSION);
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_HEADER), 6);
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_VERSION), 8);
}

static void test_csv_skip_mode_delivers_the_good_lines_and_counts_each_kind(void)
{
    const char *text = csv_with("0,0,1,1,1,1,0\n"
                                "1000,x,1,1,1,1,0\n"     /* not a number */
                                "1000,0,1,1,1\n"         /* columns */
                                "1000,nan,1,1,1,1,0\n"   /* non-finite */
                                "1000,0,5000,1,1,1,0\n"  /* range */
                                "1000,0,1,1,1,1,0\n"     /* good */
                                "1000,0,1,1,1,1,0\n"     /* repeated */
                                "500,0,1,1,1,1,0\n"      /* backwards */
                                "2000,0,1,1,1,1,0\n");   /* good */
    TV_CHECK_EQ_INT(open_text(text, RLR_FMT_CSV), TV_OK);
    TV_CHECK_EQ_INT(drain(&s_r), 3);
    TV_CHECK_EQ_INT(s_r.st.errors[RLR_E_NUMBER], 1);
    TV_CHECK_EQ_INT(s_r.st.errors[RLR_E_COLUMNS], 1);
    TV_CHECK_EQ_INT(s_r.st.errors[RLR_E_NONFINITE], 1);
    TV_CHECK_EQ_INT(s_r.st.errors[RLR_E_RANGE], 1);
    TV_CHECK_EQ_INT(s_r.st.errors[RLR_E_TIME_REPEAT], 1);
    TV_CHECK_EQ_INT(s_r.st.errors[RLR_E_TIME_BACK], 1);
    TV_CHECK_EQ_INT(s_r.st.records, 3);
}

/* ------------------------------------------------------------------------------------------ */
/* Binary                                                                                      */
/* ------------------------------------------------------------------------------------------ */

static uint8_t s_bin[65536];

/* A binary log of n records (1 ms apart, 4 per block, truth) written by the host writer. */
static size_t make_bin(uint32_t n)
{
    rawlog_header_t h;
    FILE *f = tmpfile();
    uint32_t k;
    size_t len;
    rawlog_header_default(&h);
    h.flags = RAWLOG_FLAG_TRUTH;
    h.records_per_block = 4u;
    h.current_A_per_count = 0.008;
    h.tps1_rad_per_count = 4.4e-4;
    h.tps2_rad_per_count = -4.4e-4;
    h.supply_V_per_count = 0.0048;
    TV_CHECK(f != NULL);
    if (f == NULL) {
        return 0u;
    }
    TV_CHECK_EQ_INT(rlw_open(&s_w, f, RLR_FMT_BIN, &h, NULL), TV_OK);
    for (k = 0; k < n; ++k) {
        rawlog_record_t r;
        memset(&r, 0, sizeof r);
        r.t_us = 1000u * k;
        r.duty = (float)k / 100.0f;
        r.adc[0] = (uint16_t)(2000u + k);
        r.adc[1] = 600u;
        r.adc[2] = 3400u;
        r.adc[3] = 2790u;
        r.bridge_enable = 1u;
        r.truth[0] = 0.1 * (double)k;
        TV_CHECK_EQ_INT(rlw_put(&s_w, &r), TV_OK);
    }
    TV_CHECK_EQ_INT(rlw_close(&s_w), TV_OK);
    rewind(f);
    len = fread(s_bin, 1u, sizeof s_bin, f);
    (void)fclose(f);
    return len;
}

static int open_bin(size_t len)
{
    return rlr_open_mem(&s_r, s_bin, len, "t.bin", RLR_FMT_AUTO, 0u);
}

/* Recompute the CRC of block k after an edit (to test checks behind the CRC). */
static void fix_block_crc(size_t k)
{
    const size_t bs = RAWLOG_BLOCK_SIZE(4, RAWLOG_RECORD_SIZE_TRUTH);
    uint8_t *b = s_bin + RAWLOG_HEADER_SIZE + k * bs;
    const uint32_t c = rawlog_crc32(0u, b, bs - 4u);
    b[bs - 4u] = (uint8_t)(c & 0xFFu);
    b[bs - 3u] = (uint8_t)((c >> 8) & 0xFFu);
    b[bs - 2u] = (uint8_t)((c >> 16) & 0xFFu);
    b[bs - 1u] = (uint8_t)(c >> 24);
}

static void fix_header_crc(void)
{
    const uint32_t c = rawlog_crc32(0u, s_bin, RAWLOG_HEADER_CRC_OFFSET);
    s_bin[124] = (uint8_t)(c & 0xFFu);
    s_bin[125] = (uint8_t)((c >> 8) & 0xFFu);
    s_bin[126] = (uint8_t)((c >> 16) & 0xFFu);
    s_bin[127] = (uint8_t)(c >> 24);
}

static void test_bin_written_log_reads_back_bit_for_bit_with_a_partial_last_block(void)
{
    const size_t len = make_bin(10u); /* blocks of 4: 4 + 4 + 2 */
    rawlog_record_t rec;
    uint32_t k;
    TV_CHECK_EQ_INT(len, RAWLOG_HEADER_SIZE + 3u * RAWLOG_BLOCK_SIZE(4, RAWLOG_RECORD_SIZE_TRUTH));
    TV_CHECK_EQ_INT(open_bin(len), TV_OK);
    TV_CHECK_EQ_INT(s_r.format, RLR_FMT_BIN);
    TV_CHECK(s_r.has_truth && s_r.calib_present == RLR_CAL_ALL && s_r.hdr.tps2_rad_per_count == -4.4e-4);
    for (k = 0; k < 10u; ++k) {
        TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
        TV_CHECK(rec.t_us == 1000u * k && rec.duty == (float)k / 100.0f && rec.adc[0] == 2000u + k &&
                 rec.truth[0] == 0.1 * (double)k && rec.bridge_enable == 1u && rec.driver_fault == 0u);
    }
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 0);
    TV_CHECK_EQ_INT(s_r.st.blocks, 3);
}

static void test_bin_empty_input_is_an_error(void)
{
    TV_CHECK_EQ_INT(rlr_open_mem(&s_r, s_bin, 0u, "t.bin", RLR_FMT_BIN, 0u), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_EMPTY);
    TV_CHECK_EQ_INT(rlr_open_mem(&s_r, NULL, 0u, "t.bin", RLR_FMT_AUTO, 0u), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_EMPTY);
    /* a header and no block */
    {
        rawlog_record_t rec;
        (void)make_bin(1u);
        TV_CHECK_EQ_INT(open_bin(RAWLOG_HEADER_SIZE), TV_OK);
        TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), TV_ERR_FORMAT);
        TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_EMPTY);
    }
}

static void test_bin_bad_magic_is_an_error(void)
{
    const size_t len = make_bin(3u);
    s_bin[3] = 'X';
    TV_CHECK_EQ_INT(rlr_open_mem(&s_r, s_bin, len, "t.bin", RLR_FMT_BIN, 0u), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_MAGIC);
    TV_CHECK(strstr(rlr_message(&s_r), "t.bin: byte offset 0: bad magic 'TVRXWLOG'") != NULL);
    /* auto-detection: binary data without the magic is not taken for CSV */
    TV_CHECK_EQ_INT(open_bin(len), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_MAGIC);
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_MAGIC), 7);
}

static void test_bin_unsupported_version_is_an_error(void)
{
    const size_t len = make_bin(3u);
    s_bin[8] = 2u;
    fix_header_crc();
    TV_CHECK_EQ_INT(open_bin(len), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_VERSION);
    TV_CHECK(strstr(rlr_message(&s_r), "byte offset 8: format version 2 is not supported") != NULL);
}

static void test_bin_header_crc_and_fields_are_checked(void)
{
    size_t len = make_bin(3u);
    s_bin[20] ^= 0x01u; /* sample rate bit: CRC catches it */
    TV_CHECK_EQ_INT(open_bin(len), TV_ERR_FORMAT);
    /* a header CRC mismatch is a bad header (exit 6, LOG_FORMATS.md), not a block CRC (16) */
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_HEADER);
    TV_CHECK_EQ_INT(rlr_exit_code(rlr_error(&s_r)), 6);
    TV_CHECK(strstr(rlr_message(&s_r), "byte offset 124: header CRC mismatch") != NULL);
    TV_CHECK(!rlr_recoverable(&s_r));
    len = make_bin(3u);
    s_bin[12] = 24u; /* record size contradicting the truth flag, CRC made valid */
    fix_header_crc();
    TV_CHECK_EQ_INT(open_bin(len), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_HEADER);
    TV_CHECK(strstr(rlr_message(&s_r), "byte offset 12: record size 24") != NULL);
    len = make_bin(3u);
    s_bin[14] = 0u; /* records per block 0 */
    s_bin[15] = 0u;
    fix_header_crc();
    TV_CHECK_EQ_INT(open_bin(len), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_HEADER);
    len = make_bin(3u);
    memset(s_bin + 32, 0xFF, 8); /* current offset = NaN */
    fix_header_crc();
    TV_CHECK_EQ_INT(open_bin(len), TV_ERR_FORMAT);
    TV_CHECK(strstr(rlr_message(&s_r), "byte offset 32: calibration current_offset_counts is not finite") != NULL);
}

static void test_bin_truncated_file_is_an_error(void)
{
    const size_t bs = RAWLOG_BLOCK_SIZE(4, RAWLOG_RECORD_SIZE_TRUTH);
    const size_t len = make_bin(10u);
    rawlog_record_t rec;
    int k;
    /* inside the header */
    TV_CHECK_EQ_INT(open_bin(100u), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_TRUNCATED);
    TV_CHECK(strstr(rlr_message(&s_r), "truncated header: 100 of 128 bytes") != NULL);
    TV_CHECK_EQ_INT(open_bin(5u), TV_ERR_FORMAT); /* "TVRAW": a prefix of the magic */
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_TRUNCATED);
    /* inside the second block: the first block is delivered, then the error, then the end */
    TV_CHECK_EQ_INT(open_bin(RAWLOG_HEADER_SIZE + bs + 50u), TV_OK);
    for (k = 0; k < 4; ++k) {
        TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    }
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_TRUNCATED);
    TV_CHECK(strstr(rlr_message(&s_r), "byte offset 332: block 1 truncated: 50 of 204 bytes") != NULL);
    TV_CHECK(rlr_recoverable(&s_r));
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 0);
    /* at a block boundary the log is just shorter */
    TV_CHECK_EQ_INT(open_bin(RAWLOG_HEADER_SIZE + bs), TV_OK);
    TV_CHECK_EQ_INT(drain(&s_r), 4);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_NONE);
    TV_CHECK(len > RAWLOG_HEADER_SIZE + bs);
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_TRUNCATED), 18);
}

static void test_bin_crc_mismatch_skips_exactly_that_block(void)
{
    const size_t bs = RAWLOG_BLOCK_SIZE(4, RAWLOG_RECORD_SIZE_TRUTH);
    const size_t len = make_bin(12u);
    rawlog_record_t rec;
    uint64_t t[12];
    int n = 0;
    int rc;
    s_bin[RAWLOG_HEADER_SIZE + bs + 30u] ^= 0x40u; /* a bit of block 1 */
    TV_CHECK_EQ_INT(open_bin(len), TV_OK);
    while ((rc = rlr_next(&s_r, &rec)) != 0) {
        if (rc == 1) {
            t[n++] = rec.t_us;
        } else {
            TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_CRC);
            TV_CHECK(strstr(rlr_message(&s_r), "byte offset 332: block 1 CRC mismatch") != NULL);
            TV_CHECK(rlr_recoverable(&s_r));
        }
    }
    TV_CHECK_EQ_INT(n, 8);
    TV_CHECK(t[3] == 3000u && t[4] == 8000u); /* records 4..7 lost */
    TV_CHECK_EQ_INT(s_r.st.missing_samples, 4);
    TV_CHECK_EQ_INT(s_r.st.errors[RLR_E_CRC], 1);
    TV_CHECK_EQ_INT(s_r.st.blocks_missing, 0); /* the damaged block is not also "missing" */
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_CRC), 16);
}

static void test_bin_bad_block_header_is_an_error(void)
{
    const size_t bs = RAWLOG_BLOCK_SIZE(4, RAWLOG_RECORD_SIZE_TRUTH);
    const size_t len = make_bin(8u);
    s_bin[RAWLOG_HEADER_SIZE + 4u] = 5u; /* 5 valid records in a block of 4 */
    fix_block_crc(0u);
    TV_CHECK_EQ_INT(open_bin(len), TV_OK);
    TV_CHECK_EQ_INT(drain(&s_r), 4);
    TV_CHECK_EQ_INT(s_r.st.errors[RLR_E_BLOCK], 1);
    TV_CHECK(strstr(rlr_message(&s_r), "byte offset 132: block 0 claims 5 valid records") != NULL);
    TV_CHECK(bs == 204u); /* 8 + 4 * 48 + 4 */
    TV_CHECK_EQ_INT(rlr_exit_code(RLR_E_BLOCK), 17);
}

static void test_bin_record_values_are_validated_behind_a_good_crc(void)
{
    const size_t len = make_bin(8u);
    const size_t rec1 = RAWLOG_HEADER_SIZE + RAWLOG_BLOCK_HEADER_SIZE + RAWLOG_RECORD_SIZE_TRUTH;
    rawlog_record_t rec;
    memset(s_bin + rec1 + 8u, 0xFF, 4u); /* duty of record 1: NaN */
    s_bin[RAWLOG_HEADER_SIZE + RAWLOG_BLOCK_HEADER_SIZE + 2u * RAWLOG_RECORD_SIZE_TRUTH + 13u] = 0x10u; /* 4096+ */
    fix_block_crc(0u);
    TV_CHECK_EQ_INT(open_bin(len), TV_OK);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), 1);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_NONFINITE);
    TV_CHECK(strstr(rlr_message(&s_r), "byte offset 184 (block 0, record 1): duty is not finite") != NULL);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_RANGE);
    TV_CHECK(strstr(rlr_message(&s_r), "(block 0, record 2): current_counts") != NULL);
    TV_CHECK_EQ_INT(drain(&s_r), 5); /* records 3..7 */
}

static void test_bin_time_going_backwards_is_an_error(void)
{
    const size_t len = make_bin(8u);
    /* record 5 (block 1, record 1): t_us 5000 -> 1000 = 0x03E8 */
    const size_t at = RAWLOG_HEADER_SIZE + RAWLOG_BLOCK_SIZE(4, RAWLOG_RECORD_SIZE_TRUTH) + RAWLOG_BLOCK_HEADER_SIZE +
                      RAWLOG_RECORD_SIZE_TRUTH;
    s_bin[at] = 0xE8u;
    s_bin[at + 1u] = 0x03u;
    fix_block_crc(1u);
    TV_CHECK_EQ_INT(open_bin(len), TV_OK);
    TV_CHECK_EQ_INT(drain(&s_r), 7);
    TV_CHECK_EQ_INT(s_r.st.errors[RLR_E_TIME_BACK], 1);
    TV_CHECK(strstr(rlr_message(&s_r), "(block 1, record 1): t_us 1000 is 3000 us earlier") != NULL);
}

static void test_fatal_errors_stay_fatal(void)
{
    rawlog_record_t rec;
    TV_CHECK_EQ_INT(open_text("# version: 9\n", RLR_FMT_CSV), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &rec), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_VERSION);
    TV_CHECK_EQ_INT(rlr_open_mem(NULL, NULL, 0u, NULL, RLR_FMT_AUTO, 0u), TV_ERR_NULL);
    TV_CHECK_EQ_INT(rlr_open_mem(&s_r, (const uint8_t *)"x", 1u, NULL, RLR_FMT_AUTO, RLR_LINE_MAX + 1u), TV_ERR_RANGE);
}

static void test_file_and_stream_input_match_memory_input(void)
{
    FILE *f = tmpfile();
    rawlog_record_t rec;
    TV_CHECK(f != NULL);
    if (f == NULL) {
        return;
    }
    fputs(s_good_csv, f);
    rewind(f);
    TV_CHECK_EQ_INT(rlr_open_file(&s_r, f, "file.csv", RLR_FMT_AUTO, 0u), TV_OK);
    TV_CHECK_EQ_INT(drain(&s_r), 5);
    (void)fclose(f);
    /* a small line limit (the fuzzers use one) */
    TV_CHECK_EQ_INT(rlr_open_mem(&s_r, (const uint8_t *)s_good_csv, strlen(s_good_csv), "t.csv", RLR_FMT_CSV, 40u),
                    TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(rlr_error(&s_r), RLR_E_LINE_LONG);
    (void)rec;
}

static void test_csv_writer_output_reads_back_identically(void)
{
    rawlog_header_t h;
    FILE *f = tmpfile();
    static char text[4096];
    size_t n;
    rawlog_record_t in;
    rawlog_record_t out;
    TV_CHECK(f != NULL);
    if (f == NULL) {
        return;
    }
    rawlog_header_default(&h);
    h.flags = RAWLOG_FLAG_TRUTH;
    h.current_A_per_count = 0.0080566406249999983;
    memset(&in, 0, sizeof in);
    in.t_us = 18446744073709551615ull;
    in.duty = 0.1f; /* not a short decimal in binary: %.9g must round-trip it */
    in.adc[0] = 4095u;
    in.truth[0] = 0.1;
    in.truth[1] = -1e-300;
    in.truth[2] = 5e-324;
    TV_CHECK_EQ_INT(rlw_open(&s_w, f, RLR_FMT_CSV, &h, "test"), TV_OK);
    TV_CHECK_EQ_INT(rlw_put(&s_w, &in), TV_OK);
    in.duty = NAN;
    TV_CHECK_EQ_INT(rlw_put(&s_w, &in), TV_ERR_NONFINITE); /* never written */
    TV_CHECK_EQ_INT(rlw_close(&s_w), TV_OK);
    rewind(f);
    n = fread(text, 1u, sizeof text - 1u, f);
    (void)fclose(f);
    TV_CHECK_EQ_INT(rlr_open_mem(&s_r, (const uint8_t *)text, n, "w.csv", RLR_FMT_AUTO, 0u), TV_OK);
    TV_CHECK(s_r.hdr.current_A_per_count == h.current_A_per_count); /* %.17g: exact */
    TV_CHECK_EQ_INT(rlr_next(&s_r, &out), 1);
    TV_CHECK(out.t_us == 18446744073709551615ull && out.duty == 0.1f && out.adc[0] == 4095u);
    TV_CHECK(out.truth[0] == 0.1 && out.truth[1] == -1e-300 && out.truth[2] == 5e-324);
    TV_CHECK_EQ_INT(rlr_next(&s_r, &out), 0);
}

/* ------------------------------------------------------------------------------------------ */
/* Number formatting                                                                           */
/* ------------------------------------------------------------------------------------------ */

static uint64_t s_rng = 0x9E3779B97F4A7C15ull;

static uint64_t rnd(void)
{
    s_rng ^= s_rng << 13;
    s_rng ^= s_rng >> 7;
    s_rng ^= s_rng << 17;
    return s_rng;
}

static void test_numfmt_g9_is_byte_identical_to_printf(void)
{
    static const double special[] = {0.0, -0.0, 1.0, -1.0, 0.1, 1e-5, 1e-4, 9.9999999949999e-5, 1e8, 1e9, 999999999.5,
                                     999999999.4, 123456789012.0, 1e-14, 9.99999999e-15, 1e30, 1e31, 5e-324,
                                     1.7976931348623157e308, 0.5, 2.5, 1234.5, 0.0001234565};
    char a[NUMFMT_MAX];
    char b[64];
    long bad = 0;
    long k;
    size_t i;
    for (i = 0; i < sizeof special / sizeof special[0]; ++i) {
        (void)numfmt_g9(a, special[i]);
        (void)snprintf(b, sizeof b, "%.9g", special[i]);
        bad += strcmp(a, b) != 0;
    }
    (void)numfmt_g9(a, (double)NAN);
    (void)snprintf(b, sizeof b, "%.9g", (double)NAN);
    bad += strcmp(a, b) != 0;
    (void)numfmt_g9(a, -(double)INFINITY);
    bad += strcmp(a, "-inf") != 0;
    /* random bit patterns, values of every decade, floats (the duty), short decimals (ties) */
    for (k = 0; k < 300000; ++k) {
        const uint64_t u = rnd();
        double v;
        switch (k % 4) {
        case 0: memcpy(&v, &u, sizeof v); break;
        case 1: v = ldexp((double)(u >> 11), (int)(u % 140u) - 123); break;
        case 2: v = (double)(float)((double)(int64_t)u / 9.2e18); break;
        default: v = (double)(int64_t)(u % 2000001u) / 1000.0 - 1000.0; break;
        }
        (void)numfmt_g9(a, v);
        (void)snprintf(b, sizeof b, "%.9g", v);
        if (strcmp(a, b) != 0) {
            if (bad < 5) {
                fprintf(stderr, "numfmt_g9(%a) = %s, printf %s\n", v, a, b);
            }
            ++bad;
        }
    }
    TV_CHECK_EQ_INT(bad, 0);
    TV_CHECK_EQ_INT(numfmt_u64(a, 0u), 1);
    TV_CHECK(strcmp(a, "0") == 0);
    (void)numfmt_u64(a, 18446744073709551615ull);
    TV_CHECK(strcmp(a, "18446744073709551615") == 0);
    (void)numfmt_i64(a, -9223372036854775807LL - 1LL);
    TV_CHECK(strcmp(a, "-9223372036854775808") == 0);
}

int main(void)
{
    TV_TEST_RUN(test_csv_good_log_reads_every_record_and_the_metadata);
    TV_TEST_RUN(test_csv_accepts_crlf_bom_quotes_metadata_first);
    TV_TEST_RUN(test_csv_last_line_without_newline_is_truncated);
    TV_TEST_RUN(test_csv_nul_byte_is_fatal);
    TV_TEST_RUN(test_csv_integral_fields_may_be_written_in_floating_point);
    TV_TEST_RUN(test_csv_gap_is_counted_as_missing_samples_not_an_error);
    TV_TEST_RUN(test_csv_empty_input_is_an_error);
    TV_TEST_RUN(test_csv_malformed_line_is_not_a_number_naming_line_and_column);
    TV_TEST_RUN(test_csv_wrong_column_count_is_an_error);
    TV_TEST_RUN(test_csv_non_finite_fields_are_errors);
    TV_TEST_RUN(test_csv_counts_outside_the_adc_range_are_errors);
    TV_TEST_RUN(test_csv_duty_and_flags_outside_their_range_are_errors);
    TV_TEST_RUN(test_csv_timestamp_going_backwards_is_an_error);
    TV_TEST_RUN(test_csv_repeated_timestamp_is_an_error);
    TV_TEST_RUN(test_csv_line_of_megabytes_is_rejected_in_bounded_memory);
    TV_TEST_RUN(test_csv_bad_header_and_metadata_are_fatal);
    TV_TEST_RUN(test_csv_skip_mode_delivers_the_good_lines_and_counts_each_kind);
    TV_TEST_RUN(test_bin_written_log_reads_back_bit_for_bit_with_a_partial_last_block);
    TV_TEST_RUN(test_bin_empty_input_is_an_error);
    TV_TEST_RUN(test_bin_bad_magic_is_an_error);
    TV_TEST_RUN(test_bin_unsupported_version_is_an_error);
    TV_TEST_RUN(test_bin_header_crc_and_fields_are_checked);
    TV_TEST_RUN(test_bin_truncated_file_is_an_error);
    TV_TEST_RUN(test_bin_crc_mismatch_skips_exactly_that_block);
    TV_TEST_RUN(test_bin_bad_block_header_is_an_error);
    TV_TEST_RUN(test_bin_record_values_are_validated_behind_a_good_crc);
    TV_TEST_RUN(test_bin_time_going_backwards_is_an_error);
    TV_TEST_RUN(test_fatal_errors_stay_fatal);
    TV_TEST_RUN(test_file_and_stream_input_match_memory_input);
    TV_TEST_RUN(test_csv_writer_output_reads_back_identically);
    TV_TEST_RUN(test_numfmt_g9_is_byte_identical_to_printf);
    return tv_test_summary();
}
