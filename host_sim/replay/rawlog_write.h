/**
 * @file rawlog_write.h
 * @brief Streaming writer of raw ADC logs to a stdio stream, in either format of
 *        host_sim/replay/LOG_FORMATS.md: CSV text, or binary TVRAWLOG blocks through the firmware
 *        encoder (firmware/protocols/rawlog.h). Constant memory: one block buffer.
 */
#ifndef RAWLOG_WRITE_H
#define RAWLOG_WRITE_H

#include <stdint.h>
#include <stdio.h>

#include "rawlog.h"
#include "rawlog_read.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Writer state; allocate it anywhere (about 50 KiB), initialise with rlw_open(). */
typedef struct {
    FILE *f;                    /**< output stream (the caller's) */
    rlr_format_t format;        /**< RLR_FMT_CSV or RLR_FMT_BIN */
    rawlog_header_t hdr;        /**< header written */
    uint32_t adc_max_counts;    /**< 2^adc_bits - 1 */
    rawlog_writer_t bw;         /**< binary block assembly */
    uint8_t block[RAWLOG_BLOCK_SIZE_MAX]; /**< binary block buffer */
    uint64_t records;           /**< records written */
    int io_error;               /**< 1 after a failed write */
} rlw_t;

/**
 * Start a log: write the CSV metadata and column header, or the binary header.
 * @param format  RLR_FMT_CSV or RLR_FMT_BIN
 * @param h       header: rate, ADC bits, calibration, RAWLOG_FLAG_TRUTH (truth columns / block),
 *                records per block (binary)
 * @param comment NULL, or one line of provenance written as a CSV comment (ignored in binary)
 * @return 0; TV_ERR_NULL; TV_ERR_RANGE (format); rawlog_header_check()'s error; TV_ERR_IO.
 */
int rlw_open(rlw_t *w, FILE *f, rlr_format_t format, const rawlog_header_t *h, const char *comment);

/**
 * Append one record. Values are checked as the binary encoder checks them (rawlog_pack_record()),
 * in both formats, so a CSV log written here always reads back.
 * @return 0; TV_ERR_NULL; TV_ERR_NONFINITE / TV_ERR_RANGE (record not written); TV_ERR_IO.
 */
int rlw_put(rlw_t *w, const rawlog_record_t *r);

/**
 * Finish: seal and write a partial binary block, flush the stream (not closed).
 * @return 0; TV_ERR_NULL; TV_ERR_IO (this or an earlier write failed).
 */
int rlw_close(rlw_t *w);

#ifdef __cplusplus
}
#endif

#endif /* RAWLOG_WRITE_H */
