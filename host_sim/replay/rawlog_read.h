/**
 * @file rawlog_read.h
 * @brief Streaming reader of raw ADC logs in both formats of host_sim/replay/LOG_FORMATS.md: the CSV
 *        text format and the binary TVRAWLOG format (firmware/protocols/rawlog.h).
 *
 * Constant memory whatever the input: one fixed input buffer (RLR_BUF_SIZE), CSV lines of at
 * most RLR_LINE_MAX bytes handled in place, one binary block (RAWLOG_BLOCK_SIZE_MAX). No heap;
 * the reader is a plain struct the caller allocates (it is large: make it static or heap it).
 *
 * Every record is validated before it is delivered: numbers well-formed and finite, counts in
 * 0 .. 2^adc_bits - 1, duty in [-1, 1], flags 0/1, time strictly increasing. Gaps in time
 * (missing samples) are not errors; they are counted (rlr_stats_t::missing_samples, gaps)
 * against the header's sample period and reported per record (rlr_last_gap()).
 *
 * ERRORS. rlr_next() returns a negative status and leaves a message naming the input and the
 * line (CSV) or the byte offset, block and record (binary), and the problem; rlr_error() gives
 * its class. A record-level error (RLR_E_LINE_LONG .. RLR_E_TRUNCATED on a record or block) is
 * recoverable: calling rlr_next() again continues after the bad line / record / block, which is
 * counted per class in rlr_stats_t::errors. Errors in the header, I/O errors and an empty input
 * are fatal: rlr_recoverable() is 0 and rlr_next() keeps returning the same error.
 */
#ifndef RAWLOG_READ_H
#define RAWLOG_READ_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "rawlog.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest CSV line accepted, terminator excluded [bytes]; longer lines are RLR_E_LINE_LONG. */
#define RLR_LINE_MAX 4096u
/** A line longer than RLR_LINE_MAX is skipped (recoverable) up to this many bytes; beyond, or with
 *  a NUL byte in it, the input is not a text log and reading stops (fatal). */
#define RLR_LONG_LINE_SKIP_MAX 67108864u /* 64 MiB */
/** Input buffer [bytes] (holds at least one longest line). */
#define RLR_BUF_SIZE 65536u
/** Longest message [bytes, terminator included]. */
#define RLR_MSG_MAX 400u
/** Most columns of a CSV header. */
#define RLR_COLS_MAX 64u
/** Number of calibration values in a header (the RLR_CAL_* bits of calib_present). */
#define RLR_NCAL 7

/** Input formats. */
typedef enum {
    RLR_FMT_AUTO = 0, /**< the TVRAWLOG magic selects binary, text selects CSV */
    RLR_FMT_CSV = 1,  /**< CSV text */
    RLR_FMT_BIN = 2   /**< binary TVRAWLOG */
} rlr_format_t;

/** Error classes; each has its own exit code in the tools (LOG_FORMATS.md, "Exit codes"). */
typedef enum {
    RLR_E_NONE = 0,     /**< no error */
    RLR_E_IO,           /**< reading failed (fatal) */
    RLR_E_EMPTY,        /**< empty input, no column header, or no sample at all (fatal) */
    RLR_E_HEADER,       /**< bad CSV column header or metadata, bad binary header field or CRC (fatal) */
    RLR_E_MAGIC,        /**< not a TVRAWLOG file (binary data without the magic) (fatal) */
    RLR_E_VERSION,      /**< unsupported format version (fatal) */
    RLR_E_LINE_LONG,    /**< CSV line longer than the line limit */
    RLR_E_COLUMNS,      /**< CSV row with a different number of fields than the header */
    RLR_E_NUMBER,       /**< a field is not a number (or not an integer where one is needed) */
    RLR_E_NONFINITE,    /**< a number is NaN or infinite */
    RLR_E_RANGE,        /**< a count outside the ADC range, |duty| > 1, a flag not 0/1 */
    RLR_E_TIME_BACK,    /**< a timestamp earlier than the previous one */
    RLR_E_TIME_REPEAT,  /**< a timestamp equal to the previous one */
    RLR_E_CRC,          /**< binary block CRC mismatch (the block's records are unreadable) */
    RLR_E_BLOCK,        /**< binary block header invalid (valid-record count 0 or > N) */
    RLR_E_TRUNCATED,    /**< the input ends inside the binary header or a block */
    RLR_E_COUNT         /**< number of classes (not a class) */
} rlr_err_t;

/** Calibration-present bits (rlr_t::calib_present), in rawlog_header_t field order. */
enum {
    RLR_CAL_CURRENT_OFFSET = 1u << 0,
    RLR_CAL_CURRENT_GAIN = 1u << 1,
    RLR_CAL_TPS1_ZERO = 1u << 2,
    RLR_CAL_TPS1_GAIN = 1u << 3,
    RLR_CAL_TPS2_ZERO = 1u << 4,
    RLR_CAL_TPS2_GAIN = 1u << 5,
    RLR_CAL_SUPPLY_GAIN = 1u << 6,
    RLR_CAL_ALL = (1u << RLR_NCAL) - 1u
};

/** Counters of one read. */
typedef struct {
    uint64_t records;          /**< records delivered */
    uint64_t missing_samples;  /**< samples missing in time gaps (period from the header) */
    uint64_t gaps;             /**< gaps (time steps of more than 1.5 periods) */
    uint64_t errors[RLR_E_COUNT]; /**< errors per class (skipped lines, records, blocks) */
    uint64_t blocks;           /**< binary blocks read with a good CRC */
    uint64_t blocks_missing;   /**< binary: jumps in the block sequence numbers (blocks lost) */
    uint64_t lines;            /**< CSV lines read */
} rlr_stats_t;

/** rlr_t::col_field of a column that is not read. */
#define RLR_COL_IGNORED 0xFFu

/**
 * Reader state. Initialise with rlr_open_file() or rlr_open_mem(). Large (about 120 KiB, fixed):
 * allocate it statically. Fields are ordered by alignment (no padding holes).
 */
typedef struct {
    /* source */
    FILE *file;                 /**< file source, or NULL */
    const uint8_t *mem;         /**< memory source, or NULL */
    const char *name;           /**< input name for messages (not copied) */
    char *pending;              /**< first data line, read while looking for the end of the header */
    size_t mem_len, mem_pos;    /**< memory source size and read position */
    size_t line_max;            /**< CSV line limit in force, <= RLR_LINE_MAX */
    size_t pos, len;            /**< unread input bytes are buf[pos .. len) */
    size_t pending_len;         /**< length of the pending line */
    size_t block_size, record_size; /**< binary sizes from the header */
    /* what was read */
    rawlog_header_t hdr;        /**< header (CSV: metadata, defaults where absent) */
    rlr_stats_t st;             /**< counters */
    uint64_t base_offset;       /**< input offset of buf[0] */
    uint64_t line;              /**< number of the line last read (1-based) */
    uint64_t block_index;       /**< index of the block in block[] (0 = first after the header) */
    uint64_t next_block;        /**< index of the next block to read */
    uint64_t block_offset;      /**< input offset of the block in block[] */
    uint64_t cur_offset;        /**< input offset of the record being decoded */
    uint64_t last_t_us;         /**< time of the last delivered record */
    uint64_t last_gap;          /**< samples missing before the last delivered record */
    rlr_format_t format;        /**< RLR_FMT_CSV or RLR_FMT_BIN once opened */
    rlr_err_t err;              /**< class of the last error */
    unsigned calib_present;     /**< RLR_CAL_* bits of the calibration values the log gave */
    uint64_t calib_line[RLR_NCAL]; /**< CSV: metadata line of each calibration value (0: binary header or not given) */
    uint32_t adc_max_counts;    /**< 2^adc_bits - 1 */
    uint32_t period_us;         /**< sample period from the header, rounded [us] */
    uint32_t next_sequence;     /**< binary: expected block sequence number */
    int has_truth;              /**< 1: records carry the true state */
    int eof;                    /**< no more input after buf[len] */
    int ncols;                  /**< CSV columns of the header */
    int have_block;             /**< 1 while block[] has undelivered records */
    int have_last;              /**< a record was delivered */
    int fatal;                  /**< 1: nothing more can be read */
    int done;                   /**< 1: end reached */
    uint16_t block_n, block_pos; /**< valid records in block[], next to deliver */
    uint16_t cur_rec;           /**< index in its block of the record being decoded */
    uint8_t col_field[RLR_COLS_MAX]; /**< CSV field of each column, RLR_COL_IGNORED if not read */
    char msg[RLR_MSG_MAX];      /**< message of the last error */
    uint8_t buf[RLR_BUF_SIZE + 1]; /**< input bytes (+1 for a terminator of the last line) */
    uint8_t block[RAWLOG_BLOCK_SIZE_MAX]; /**< the binary block being read */
} rlr_t;

/**
 * Open a stream (a file or stdin) and read the header. The stream stays the caller's.
 * @param name   name for messages ("-" or "<stdin>" for standard input); must outlive r
 * @param format RLR_FMT_AUTO, RLR_FMT_CSV or RLR_FMT_BIN
 * @param line_max CSV line limit, 0 for RLR_LINE_MAX, at most RLR_LINE_MAX
 * @return 0; TV_ERR_NULL; TV_ERR_RANGE (bad format or line_max); TV_ERR_IO / TV_ERR_FORMAT with
 *         rlr_error() and rlr_message() telling which (always fatal).
 */
int rlr_open_file(rlr_t *r, FILE *f, const char *name, rlr_format_t format, size_t line_max);

/** As rlr_open_file() on a memory buffer (tests, fuzzing); data must outlive r. */
int rlr_open_mem(rlr_t *r, const uint8_t *data, size_t n, const char *name, rlr_format_t format, size_t line_max);

/**
 * Next record.
 * @return 1 a record in *rec; 0 end of input; TV_ERR_FORMAT or TV_ERR_IO on an error (class
 *         rlr_error(), text rlr_message(); call again to continue when rlr_recoverable()).
 *         At the end, RLR_E_EMPTY when neither a record nor an error was seen.
 */
int rlr_next(rlr_t *r, rawlog_record_t *rec);

/** Class of the last error (RLR_E_NONE if none). */
rlr_err_t rlr_error(const rlr_t *r);

/** Message of the last error ("" if none). */
const char *rlr_message(const rlr_t *r);

/** 1 when reading can go on after the last error, 0 when it was fatal. */
int rlr_recoverable(const rlr_t *r);

/** Samples missing before the last delivered record (0: it followed its predecessor). */
uint64_t rlr_last_gap(const rlr_t *r);

/**
 * Where the last record (or error) is: "line N" (CSV) or "byte offset B (block K, record J)"
 * (binary), for messages.
 */
void rlr_where(const rlr_t *r, char *out, size_t cap);

/** Exit codes of the tools (replay, log_convert), documented in LOG_FORMATS.md and --help. */
enum {
    RLR_EXIT_OK = 0,        /**< everything read (and replayed) */
    RLR_EXIT_IO = 1,        /**< cannot open / read / write a file */
    RLR_EXIT_USAGE = 2,     /**< bad command line */
    RLR_EXIT_PARAMS = 3,    /**< parameter file invalid */
    RLR_EXIT_CONFIG = 4,    /**< configuration rejected (log rate or calibration unusable by the application) */
    /* 5 .. 18: the input error class that stopped the run, RLR_E_EMPTY + 3 .. RLR_E_TRUNCATED + 3 */
    RLR_EXIT_SKIPPED = 19   /**< finished with --on-error skip, and input was skipped */
};

/** Exit code of an error class: RLR_EXIT_IO for RLR_E_IO, class + 3 for the others, 0 for none. */
int rlr_exit_code(rlr_err_t e);

/**
 * The CRC-32 of rawlog_crc32() (same value), computed 8 bytes at a time (slicing-by-8, 8 KiB of
 * tables built on first use) for the host's throughput.
 */
uint32_t rlr_crc32(const uint8_t *data, size_t n);

/** Short name of an error class ("CRC mismatch", ...); "?" if invalid. */
const char *rlr_err_name(rlr_err_t e);

/** Format name ("csv", "bin", "auto"). */
const char *rlr_format_name(rlr_format_t f);

/** Parse a format name ("auto", "csv", "bin"). @return 0; TV_ERR_NULL; TV_ERR_RANGE. */
int rlr_format_from_name(const char *s, rlr_format_t *out);

/** Calibration value k (0 .. RLR_NCAL - 1) of a header, in rawlog_header_t order. */
double rlr_calib_value(const rawlog_header_t *h, int k);

/** Name of calibration value k as in the CSV metadata and the parameter file ("current_offset_counts", ...). */
const char *rlr_calib_name(int k);

#ifdef __cplusplus
}
#endif

#endif /* RAWLOG_READ_H */
