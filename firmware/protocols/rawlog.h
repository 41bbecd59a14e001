/**
 * @file rawlog.h
 * @brief Binary raw-ADC log format "TVRAWLOG" version 1: the encoder a firmware logger uses
 *        (header, record packing, CRC-32, block assembly into a caller-supplied buffer).
 *
 * Platform-neutral C99: no heap, no stdio, no HAL, no scalar type of the estimator (the
 * calibration is stored as IEEE float64 whatever the build). The host reads these files with
 * host_sim/replay/rawlog_read.h; the byte-exact specification with offsets is host_sim/replay/LOG_FORMATS.md.
 *
 * FILE = header (RAWLOG_HEADER_SIZE bytes) followed by blocks of identical size. All multi-byte
 * fields are little-endian; floats are IEEE 754 binary32 / binary64.
 *
 * HEADER (128 bytes)
 *   0  u8[8] magic "TVRAWLOG"          24 u8  adc_bits (8..16)
 *   8  u16 version (1)                 25 u8[7] reserved, 0
 *   10 u16 header size (128)           32 f64 current_offset_counts     40 f64 current_A_per_count
 *   12 u16 record size (24 or 48)      48 f64 tps1_counts_at_zero       56 f64 tps1_rad_per_count
 *   14 u16 records per block N         64 f64 tps2_counts_at_zero       72 f64 tps2_rad_per_count
 *   16 u32 flags (RAWLOG_FLAG_*)       80 f64 supply_V_per_count
 *   20 u32 sample rate [Hz]            88 u8[36] reserved, 0       124 u32 CRC-32 of bytes 0..123
 *
 * RECORD (24 bytes, 48 with RAWLOG_FLAG_TRUTH)
 *   0 u64 t_us   8 f32 duty   12 u16 current   14 u16 tps1   16 u16 tps2   18 u16 supply [counts]
 *   20 u8 flags (bit 0 driver fault input, bit 1 bridge enabled)   21 u8[3] reserved, 0
 *   24 f64 i_true_A   32 f64 w_true_rad_s   40 f64 phi_true_rad   (truth block, optional)
 *
 * BLOCK (8 + N * record size + 4 bytes, every block the same size)
 *   0 u32 sequence number (0, 1, 2, ...)   4 u16 valid records n (1..N)   6 u16 reserved, 0
 *   8 N record slots; slots n..N-1 are zero-filled (only the last block of a file is partial)
 *   8 + N * record size: u32 CRC-32 of the block's bytes before it
 *
 * CRC-32 is IEEE 802.3 (the zlib / PNG / Ethernet CRC): reflected polynomial 0xEDB88320, initial
 * value 0xFFFFFFFF, final XOR 0xFFFFFFFF; rawlog_crc32() of "123456789" is 0xCBF43926.
 */
#ifndef RAWLOG_H
#define RAWLOG_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Length of the magic at offset 0 [bytes]. */
#define RAWLOG_MAGIC_SIZE 8u
/** Format version this encoder writes (and the host reader accepts). */
#define RAWLOG_VERSION 1u
/** Header size [bytes]. */
#define RAWLOG_HEADER_SIZE 128u
/** Offset of the header CRC (the CRC covers bytes 0 .. RAWLOG_HEADER_CRC_OFFSET - 1). */
#define RAWLOG_HEADER_CRC_OFFSET 124u
/** Record size without / with the truth block [bytes]. */
#define RAWLOG_RECORD_SIZE 24u
/** Record size with RAWLOG_FLAG_TRUTH [bytes]. */
#define RAWLOG_RECORD_SIZE_TRUTH 48u
/** Block header size (sequence, valid count, reserved) [bytes]. */
#define RAWLOG_BLOCK_HEADER_SIZE 8u
/** Block trailer size (CRC-32) [bytes]. */
#define RAWLOG_BLOCK_TRAILER_SIZE 4u
/** Largest number of records per block. */
#define RAWLOG_BLOCK_RECORDS_MAX 1024u
/** Records per block of rawlog_header_default(). */
#define RAWLOG_BLOCK_RECORDS_DEFAULT 64u
/** Size of one block of n records of rec_size bytes [bytes]. */
#define RAWLOG_BLOCK_SIZE(n, rec_size) (RAWLOG_BLOCK_HEADER_SIZE + (size_t)(n) * (size_t)(rec_size) + RAWLOG_BLOCK_TRAILER_SIZE)
/** Largest block size a reader must hold [bytes]. */
#define RAWLOG_BLOCK_SIZE_MAX RAWLOG_BLOCK_SIZE(RAWLOG_BLOCK_RECORDS_MAX, RAWLOG_RECORD_SIZE_TRUTH)
/** Number of ADC channels in a record (hal.h order: current, tps1, tps2, supply). */
#define RAWLOG_NCH 4
/** Sample-rate bounds of the header [Hz]. */
#define RAWLOG_RATE_MIN_HZ 1u
/** Highest sample rate of the header [Hz]. */
#define RAWLOG_RATE_MAX_HZ 1000000u
/** ADC resolution bounds of the header [bits]. */
#define RAWLOG_ADC_BITS_MIN 8u
/** Highest ADC resolution of the header [bits]. */
#define RAWLOG_ADC_BITS_MAX 16u

/** Header flags. */
enum {
    RAWLOG_FLAG_TRUTH = 1u << 0 /**< records carry the true state (simulated logs) */
};

/** Record flag bits (byte 20 of a record). */
enum {
    RAWLOG_REC_DRIVER_FAULT = 1u << 0, /**< the H-bridge driver's fault input was active */
    RAWLOG_REC_BRIDGE_ENABLE = 1u << 1 /**< the bridge was enabled over the period after the sample */
};

/** The magic, RAWLOG_MAGIC_SIZE bytes, no terminator in the file. */
extern const uint8_t rawlog_magic[RAWLOG_MAGIC_SIZE];

/** Header contents (the calibration is the one of app_calib_t, in float64). */
typedef struct {
    uint32_t flags;              /**< RAWLOG_FLAG_* */
    uint32_t sample_rate_Hz;     /**< RAWLOG_RATE_MIN_HZ .. RAWLOG_RATE_MAX_HZ */
    uint16_t records_per_block;  /**< N, 1 .. RAWLOG_BLOCK_RECORDS_MAX */
    uint8_t adc_bits;            /**< RAWLOG_ADC_BITS_MIN .. RAWLOG_ADC_BITS_MAX; counts are 0 .. 2^bits - 1 */
    double current_offset_counts; /**< counts at 0 A */
    double current_A_per_count;  /**< [A/count], nonzero */
    double tps1_counts_at_zero;  /**< track 1 counts at phi = 0 */
    double tps1_rad_per_count;   /**< [rad/count] */
    double tps2_counts_at_zero;  /**< track 2 counts at phi = 0 */
    double tps2_rad_per_count;   /**< [rad/count] */
    double supply_V_per_count;   /**< [V/count] */
} rawlog_header_t;

/** One sample. */
typedef struct {
    uint64_t t_us;              /**< sample time [us] */
    float duty;                 /**< PWM duty command applied over the following period, [-1, 1] */
    uint16_t adc[RAWLOG_NCH];   /**< raw counts: current, tps1, tps2, supply, 0 .. 2^adc_bits - 1 */
    uint8_t driver_fault;       /**< driver fault input, 0 or 1 */
    uint8_t bridge_enable;      /**< bridge enabled over the following period, 0 or 1 */
    double truth[3];            /**< true (i [A], w [rad/s], phi [rad]); only with RAWLOG_FLAG_TRUTH */
} rawlog_record_t;

/** Block assembly state. Initialise with rawlog_writer_init(); the caller owns the buffer. */
typedef struct {
    uint8_t *buf;               /**< the caller's block buffer */
    size_t block_size;          /**< bytes of one block */
    size_t record_size;         /**< bytes of one record */
    uint32_t flags;             /**< header flags (truth block or not) */
    uint32_t adc_max_counts;    /**< 2^adc_bits - 1 */
    uint32_t sequence;          /**< sequence number of the block being filled */
    uint16_t per_block;         /**< N */
    uint16_t n;                 /**< records in the block being filled */
    uint8_t sealed;             /**< 1: buf holds a complete block, not yet consumed */
} rawlog_writer_t;

/**
 * CRC-32 (IEEE 802.3, reflected 0xEDB88320, init and final XOR 0xFFFFFFFF), incremental:
 * crc = rawlog_crc32(0, a, na); crc = rawlog_crc32(crc, b, nb) equals the CRC of a then b.
 * Byte-wise with a 256-entry constant table (1 KiB of read-only data).
 * @param crc  0 to start, or a previous result to continue
 * @return the CRC of everything so far; crc unchanged when data is NULL or n is 0
 */
uint32_t rawlog_crc32(uint32_t crc, const uint8_t *data, size_t n);

/**
 * Header defaults: 1000 Hz, 12-bit ADC, RAWLOG_BLOCK_RECORDS_DEFAULT records per block, no
 * truth, calibration zero (the caller sets it from its app_calib_t).
 */
void rawlog_header_default(rawlog_header_t *h);

/**
 * Check a header's fields: rate, ADC bits, records per block in range, flags known, every
 * calibration value finite.
 * @return 0 (TV_OK); TV_ERR_NULL; TV_ERR_NONFINITE (a calibration value); TV_ERR_RANGE.
 */
int rawlog_header_check(const rawlog_header_t *h);

/** Record size [bytes] for header flags: RAWLOG_RECORD_SIZE or RAWLOG_RECORD_SIZE_TRUTH. */
size_t rawlog_record_size(uint32_t flags);

/**
 * Encode the header (RAWLOG_HEADER_SIZE bytes, CRC included) into out.
 * @return 0; TV_ERR_NULL; TV_ERR_RANGE (cap < RAWLOG_HEADER_SIZE); rawlog_header_check()'s error.
 */
int rawlog_encode_header(const rawlog_header_t *h, uint8_t *out, size_t cap);

/**
 * Pack one record (rawlog_record_size(flags) bytes) into out. Checks the values first and
 * writes nothing when one is bad.
 * @param adc_max_counts  2^adc_bits - 1 of the header
 * @return 0; TV_ERR_NULL; TV_ERR_NONFINITE (duty, or truth with RAWLOG_FLAG_TRUTH);
 *         TV_ERR_RANGE (|duty| > 1, a count > adc_max_counts, a flag not 0/1, cap too small).
 */
int rawlog_pack_record(const rawlog_record_t *r, uint32_t flags, uint32_t adc_max_counts, uint8_t *out, size_t cap);

/**
 * Start block assembly. buf must hold RAWLOG_BLOCK_SIZE(h->records_per_block, record size).
 * @return 0; TV_ERR_NULL; TV_ERR_RANGE (buffer too small); rawlog_header_check()'s error.
 */
int rawlog_writer_init(rawlog_writer_t *w, const rawlog_header_t *h, uint8_t *buf, size_t cap);

/**
 * Add a record to the block being filled. When it fills the block, the block is sealed
 * (valid count, zero padding, CRC) and 1 is returned: w->buf then holds w->block_size bytes to
 * write out before the next call, which starts the next block (sequence + 1).
 * @return 1 block complete; 0 stored; TV_ERR_NULL; rawlog_pack_record()'s error (nothing stored).
 */
int rawlog_writer_add(rawlog_writer_t *w, const rawlog_record_t *r);

/**
 * Seal a partially filled block (zero padding, valid count, CRC), e.g. at the end of a log.
 * @return 1 a block was sealed (write w->block_size bytes of w->buf); 0 nothing to seal (no
 *         record since the last complete block); TV_ERR_NULL.
 */
int rawlog_writer_flush(rawlog_writer_t *w);

#ifdef __cplusplus
}
#endif

#endif /* RAWLOG_H */
