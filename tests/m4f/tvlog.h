/**
 * @file tvlog.h
 * @brief Binary input stream and output record of the host-vs-Cortex-M4F replay comparison,
 *        and the one replay step both sides run (so the host and the QEMU image cannot differ
 *        in anything but the compiler, the FPU and the libm).
 *
 * Files (all integers little-endian, floats as their IEEE-754 binary32 bit patterns):
 *   header  16 bytes: magic[8] ("TVLOGIN1" input / "TVLOGOU1" output), uint32 record count,
 *           uint32 record size in bytes
 *   input record (TVLOG_IN_BYTES): uint64 t_us, uint16 adc[4] (hal.h order), uint8
 *           driver_fault, uint8 cmd (TVLOG_CMD_*), uint16 reserved (0), float cmd_arg
 *   output record (TVLOG_OUT_WORDS 32-bit words): see tvlog_out_word_name().
 */
#ifndef TVLOG_H
#define TVLOG_H

#include <stdint.h>

#include "app.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TVLOG_HEADER_BYTES 16u
#define TVLOG_IN_BYTES 24u
#define TVLOG_OUT_WORDS 28u
#define TVLOG_OUT_BYTES 112u /**< 4 * TVLOG_OUT_WORDS */
#define TVLOG_MAGIC_IN "TVLOGIN1"
#define TVLOG_MAGIC_OUT "TVLOGOU1"

/** Commands carried by an input record, applied before its step. */
enum {
    TVLOG_CMD_NONE = 0,
    TVLOG_CMD_CLEAR_FAULTS = 1,
    /** TVLOG_CMD_MODE + app_mode_t: change mode (POSITION: cmd_arg = target [rad]) */
    TVLOG_CMD_MODE = 0x10
};

/** One input record. */
typedef struct {
    uint64_t t_us;        /**< sample time [us] */
    uint16_t adc[4];      /**< raw counts: current, tps1, tps2, supply */
    uint8_t driver_fault; /**< driver fault input */
    uint8_t cmd;          /**< TVLOG_CMD_* */
    float cmd_arg;        /**< command argument */
} tvlog_in_t;

/** Encode / decode the 16-byte header. decode returns 0, or -1 on a wrong magic or size. */
void tvlog_header_encode(uint8_t b[TVLOG_HEADER_BYTES], const char magic[8], uint32_t count, uint32_t rec_bytes);
int tvlog_header_decode(const uint8_t b[TVLOG_HEADER_BYTES], const char magic[8], uint32_t rec_bytes,
                        uint32_t *count);

/** Encode / decode an input record. */
void tvlog_in_encode(uint8_t b[TVLOG_IN_BYTES], const tvlog_in_t *r);
void tvlog_in_decode(const uint8_t b[TVLOG_IN_BYTES], tvlog_in_t *r);

/** Initialise the application as the replay runs it (app_config_default()). @return app_init()'s code. */
/* stops_known: 1 = the ECU has its stops stored (sl_nvm_t), so the stop envelope of never-learned
 * stops (stop_track.h) is off: the replay comparison of the native builds (glibc vs newlib libm)
 * needs it off, because the envelope is a threshold decision that an ulp of libm difference can
 * move by a sample (measured: 2x the tolerances from record 5353 on; the portable pair stays
 * bit-identical with it on); 0 = the default configuration, envelope on (qemu_bench: the cost of
 * a first start). */
int tvlog_replay_init(app_t *app, int stops_known);

/** Apply the record's command (TVLOG_CMD_*) to the application. */
void tvlog_apply_cmd(app_t *app, const tvlog_in_t *in);

/**
 * Apply the record's command, run app_step() on it, encode the outputs.
 * @param index  record number, stored in word 0
 * @param out    filled with the step's outputs (may be used by the caller)
 * @param b      the encoded output record
 */
void tvlog_replay_step(app_t *app, const tvlog_in_t *in, uint32_t index, app_output_t *out,
                       uint8_t b[TVLOG_OUT_BYTES]);

/** Name of output word k (e.g. "x[1]"), "" when out of range. */
const char *tvlog_out_word_name(uint32_t k);

/** 1 when output word k holds a float, 0 when it holds an integer or flags. */
int tvlog_out_word_is_float(uint32_t k);

/** Read little-endian 32-bit word k of an encoded output record. */
uint32_t tvlog_out_word(const uint8_t b[TVLOG_OUT_BYTES], uint32_t k);

#ifdef __cplusplus
}
#endif

#endif /* TVLOG_H */
