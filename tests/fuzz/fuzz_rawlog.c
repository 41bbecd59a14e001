/**
 * @file fuzz_rawlog.c
 * @brief libFuzzer target of the raw-log reader (host_sim/replay/rawlog_read.h), CSV or binary by the
 *        macro FUZZ_FORMAT (RLR_FMT_CSV / RLR_FMT_BIN), built with clang
 *        -fsanitize=fuzzer,address,undefined (tests/fuzz/CMakeLists.txt).
 *
 * Reads the input to the end as `replay --on-error skip` does (continuing after every
 * recoverable error) and checks what the reader promises about every record it delivers: it
 * re-encodes (rawlog_pack_record() accepts it: counts in range, duty finite in [-1, 1], flags
 * 0/1, truth finite), time strictly increases, and the error text is a bounded C string. A
 * broken promise aborts (a finding); so does any sanitizer report.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rawlog.h"
#include "rawlog_read.h"

#ifndef FUZZ_FORMAT
#define FUZZ_FORMAT RLR_FMT_CSV
#endif

/* A small line limit so that long-line handling is reached with small inputs. */
#define FUZZ_LINE_MAX 256u

static rlr_t s_r;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void put_crc(uint8_t *p, uint32_t c)
{
    p[0] = (uint8_t)(c & 0xFFu);
    p[1] = (uint8_t)((c >> 8) & 0xFFu);
    p[2] = (uint8_t)((c >> 16) & 0xFFu);
    p[3] = (uint8_t)(c >> 24);
}

/*
 * Binary inputs almost never carry valid CRCs after a mutation, which would keep the fuzzer at
 * the CRC checks. A second pass reads a copy with the header and block CRCs recomputed, so
 * the header fields, block headers and record values behind the CRCs are fuzzed too.
 */
static size_t fix_crcs(const uint8_t *data, size_t size, uint8_t *out, size_t cap)
{
    size_t n = size < cap ? size : cap;
    size_t at;
    size_t bs;
    uint32_t per;
    uint32_t rs;
    memcpy(out, data, n);
    if (n < RAWLOG_HEADER_SIZE || memcmp(out, rawlog_magic, RAWLOG_MAGIC_SIZE) != 0) {
        return n;
    }
    put_crc(out + RAWLOG_HEADER_CRC_OFFSET, rawlog_crc32(0u, out, RAWLOG_HEADER_CRC_OFFSET));
    per = (uint32_t)out[14] | ((uint32_t)out[15] << 8);
    rs = (uint32_t)out[12] | ((uint32_t)out[13] << 8);
    if (per == 0u || per > RAWLOG_BLOCK_RECORDS_MAX || (rs != RAWLOG_RECORD_SIZE && rs != RAWLOG_RECORD_SIZE_TRUTH)) {
        return n;
    }
    bs = RAWLOG_BLOCK_SIZE(per, rs);
    for (at = RAWLOG_HEADER_SIZE; at + bs <= n; at += bs) {
        put_crc(out + at + bs - 4u, rawlog_crc32(0u, out + at, bs - 4u));
    }
    return n;
}

static void read_all(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static uint8_t fixed[1u << 16];
    read_all(data, size);
    if (FUZZ_FORMAT == RLR_FMT_BIN) {
        read_all(fixed, fix_crcs(data, size, fixed, sizeof fixed));
    }
    return 0;
}

static void read_all(const uint8_t *data, size_t size)
{
    rawlog_record_t rec;
    uint8_t packed[RAWLOG_RECORD_SIZE_TRUTH];
    uint64_t last = 0;
    int have_last = 0;
    unsigned long guard = 0;
    int rc = rlr_open_mem(&s_r, data, size, "fuzz", FUZZ_FORMAT, FUZZ_LINE_MAX);
    if (memchr(s_r.msg, '\0', sizeof s_r.msg) == NULL) {
        abort();
    }
    if (rc != 0) {
        return;
    }
    for (;;) {
        rc = rlr_next(&s_r, &rec);
        if (++guard > 4u * (size + 16u)) {
            abort(); /* no progress: every call must consume input */
        }
        if (rc == 0) {
            break;
        }
        if (rc < 0) {
            if (rlr_error(&s_r) == RLR_E_NONE || memchr(s_r.msg, '\0', sizeof s_r.msg) == NULL) {
                abort();
            }
            if (!rlr_recoverable(&s_r)) {
                break;
            }
            continue;
        }
        if (rawlog_pack_record(&rec, s_r.hdr.flags, s_r.adc_max_counts, packed, sizeof packed) != 0) {
            abort();
        }
        if (have_last && rec.t_us <= last) {
            abort();
        }
        last = rec.t_us;
        have_last = 1;
    }
}
