/**
 * @file test_rawlog.c
 * @brief Tests of the binary raw-log encoder (firmware/protocols/rawlog.h): CRC-32, header and record
 *        byte layout at the offsets of host_sim/replay/LOG_FORMATS.md, value checks, block assembly.
 *        Exact comparisons throughout: the encoder copies bits, it computes nothing.
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "rawlog.h"
#include "rawlog_read.h"
#include "tv_status.h"
#include "tv_test.h"

static uint32_t le16(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8);
}

static uint32_t le32(const uint8_t *p)
{
    return le16(p) | (le16(p + 2) << 16);
}

static uint64_t le64(const uint8_t *p)
{
    return (uint64_t)le32(p) | ((uint64_t)le32(p + 4) << 32);
}

static double f64_at(const uint8_t *p)
{
    const uint64_t u = le64(p);
    double v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static float f32_at(const uint8_t *p)
{
    const uint32_t u = le32(p);
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static void header_example(rawlog_header_t *h)
{
    rawlog_header_default(h);
    h->flags = RAWLOG_FLAG_TRUTH;
    h->records_per_block = 3u;
    h->current_offset_counts = 2048.0;
    h->current_A_per_count = 0.0080566406249999983;
    h->tps1_counts_at_zero = 633.10810319187965;
    h->tps1_rad_per_count = 0.00044741107177734377;
    h->tps2_counts_at_zero = 3462.8918968081207;
    h->tps2_rad_per_count = -0.00044741107177734377;
    h->supply_V_per_count = 0.0048339843749999993;
}

static rawlog_record_t record_example(uint64_t t_us)
{
    rawlog_record_t r;
    memset(&r, 0, sizeof r);
    r.t_us = t_us;
    r.duty = -0.123456789f;
    r.adc[0] = 2047u;
    r.adc[1] = 633u;
    r.adc[2] = 3463u;
    r.adc[3] = 4095u;
    r.driver_fault = 1u;
    r.bridge_enable = 1u;
    r.truth[0] = 1.25;
    r.truth[1] = -3.5e-7;
    r.truth[2] = 0.3;
    return r;
}

static void test_crc32_is_ieee_802_3_with_check_value_cbf43926(void)
{
    static const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
    uint8_t buf[300];
    size_t k;
    /* The catalogued check value of CRC-32/ISO-HDLC (zlib, PNG, Ethernet). */
    TV_CHECK_EQ_INT(rawlog_crc32(0u, check, sizeof check), 0xCBF43926L);
    TV_CHECK_EQ_INT(rawlog_crc32(0u, NULL, 0u), 0);
    /* incremental == one shot; the host's slicing-by-8 == the firmware's byte-wise table */
    for (k = 0; k < sizeof buf; ++k) {
        buf[k] = (uint8_t)(k * 7u + 3u);
    }
    TV_CHECK_EQ_INT(rawlog_crc32(rawlog_crc32(0u, buf, 100u), buf + 100, 200u), rawlog_crc32(0u, buf, 300u));
    for (k = 0; k <= sizeof buf; k += 13u) {
        TV_CHECK_EQ_INT(rlr_crc32(buf, k), rawlog_crc32(0u, buf, k));
    }
}

static void test_header_bytes_sit_at_the_documented_offsets(void)
{
    rawlog_header_t h;
    uint8_t b[RAWLOG_HEADER_SIZE + 4];
    size_t k;
    int zero = 1;
    header_example(&h);
    memset(b, 0xAA, sizeof b);
    TV_CHECK_EQ_INT(rawlog_encode_header(&h, b, sizeof b), TV_OK);
    TV_CHECK(memcmp(b, "TVRAWLOG", 8) == 0);
    TV_CHECK_EQ_INT(le16(b + 8), 1);                       /* version */
    TV_CHECK_EQ_INT(le16(b + 10), 128);                    /* header size */
    TV_CHECK_EQ_INT(le16(b + 12), RAWLOG_RECORD_SIZE_TRUTH);
    TV_CHECK_EQ_INT(le16(b + 14), 3);                      /* records per block */
    TV_CHECK_EQ_INT(le32(b + 16), RAWLOG_FLAG_TRUTH);
    TV_CHECK_EQ_INT(le32(b + 20), 1000);                   /* sample rate */
    TV_CHECK_EQ_INT(b[24], 12);                            /* ADC bits */
    TV_CHECK(f64_at(b + 32) == h.current_offset_counts);  /* exact: bits copied */
    TV_CHECK(f64_at(b + 40) == h.current_A_per_count);
    TV_CHECK(f64_at(b + 48) == h.tps1_counts_at_zero);
    TV_CHECK(f64_at(b + 56) == h.tps1_rad_per_count);
    TV_CHECK(f64_at(b + 64) == h.tps2_counts_at_zero);
    TV_CHECK(f64_at(b + 72) == h.tps2_rad_per_count);
    TV_CHECK(f64_at(b + 80) == h.supply_V_per_count);
    for (k = 25; k < 32; ++k) {
        zero = zero && b[k] == 0u;
    }
    for (k = 88; k < 124; ++k) {
        zero = zero && b[k] == 0u;
    }
    TV_CHECK(zero); /* reserved bytes */
    TV_CHECK_EQ_INT(le32(b + 124), rawlog_crc32(0u, b, 124u));
    TV_CHECK_EQ_INT(b[128], 0xAA); /* nothing written past the header */
    TV_CHECK_EQ_INT(rawlog_encode_header(&h, b, RAWLOG_HEADER_SIZE - 1u), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(rawlog_encode_header(NULL, b, sizeof b), TV_ERR_NULL);
}

static void test_header_check_rejects_each_bad_field(void)
{
    rawlog_header_t h;
    header_example(&h);
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_OK);
    h.sample_rate_Hz = 0u;
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_ERR_RANGE);
    header_example(&h);
    h.sample_rate_Hz = RAWLOG_RATE_MAX_HZ + 1u;
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_ERR_RANGE);
    header_example(&h);
    h.adc_bits = 7u;
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_ERR_RANGE);
    h.adc_bits = 17u;
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_ERR_RANGE);
    header_example(&h);
    h.records_per_block = 0u;
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_ERR_RANGE);
    h.records_per_block = (uint16_t)(RAWLOG_BLOCK_RECORDS_MAX + 1u);
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_ERR_RANGE);
    header_example(&h);
    h.flags = 2u;
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_ERR_RANGE);
    header_example(&h);
    h.tps2_rad_per_count = (double)NAN;
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_ERR_NONFINITE);
    h.tps2_rad_per_count = (double)INFINITY;
    TV_CHECK_EQ_INT(rawlog_header_check(&h), TV_ERR_NONFINITE);
}

static void test_record_bytes_sit_at_the_documented_offsets(void)
{
    const rawlog_record_t r = record_example(0x0102030405060708ull);
    uint8_t b[RAWLOG_RECORD_SIZE_TRUTH];
    memset(b, 0xAA, sizeof b);
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, RAWLOG_FLAG_TRUTH, 4095u, b, sizeof b), TV_OK);
    TV_CHECK(le64(b) == 0x0102030405060708ull);
    TV_CHECK(f32_at(b + 8) == r.duty);
    TV_CHECK_EQ_INT(le16(b + 12), 2047);
    TV_CHECK_EQ_INT(le16(b + 14), 633);
    TV_CHECK_EQ_INT(le16(b + 16), 3463);
    TV_CHECK_EQ_INT(le16(b + 18), 4095);
    TV_CHECK_EQ_INT(b[20], RAWLOG_REC_DRIVER_FAULT | RAWLOG_REC_BRIDGE_ENABLE);
    TV_CHECK(b[21] == 0u && b[22] == 0u && b[23] == 0u);
    TV_CHECK(f64_at(b + 24) == 1.25);
    TV_CHECK(f64_at(b + 32) == -3.5e-7);
    TV_CHECK(f64_at(b + 40) == 0.3);
    /* without truth: 24 bytes, nothing beyond */
    memset(b, 0xAA, sizeof b);
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, 0u, 4095u, b, RAWLOG_RECORD_SIZE), TV_OK);
    TV_CHECK_EQ_INT(b[RAWLOG_RECORD_SIZE], 0xAA);
    TV_CHECK_EQ_INT(rawlog_record_size(0u), 24);
    TV_CHECK_EQ_INT(rawlog_record_size(RAWLOG_FLAG_TRUTH), 48);
}

static void test_pack_rejects_bad_values_and_writes_nothing(void)
{
    uint8_t b[RAWLOG_RECORD_SIZE_TRUTH];
    uint8_t ref[RAWLOG_RECORD_SIZE_TRUTH];
    rawlog_record_t r;
    memset(ref, 0x5C, sizeof ref);
    memcpy(b, ref, sizeof b);
    r = record_example(1u);
    r.duty = NAN;
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, 0u, 4095u, b, sizeof b), TV_ERR_NONFINITE);
    r.duty = INFINITY;
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, 0u, 4095u, b, sizeof b), TV_ERR_RANGE);
    r.duty = 1.0001f;
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, 0u, 4095u, b, sizeof b), TV_ERR_RANGE);
    r = record_example(1u);
    r.adc[2] = 4096u;
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, 0u, 4095u, b, sizeof b), TV_ERR_RANGE);
    r = record_example(1u);
    r.driver_fault = 2u;
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, 0u, 4095u, b, sizeof b), TV_ERR_RANGE);
    r = record_example(1u);
    r.truth[1] = (double)NAN;
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, RAWLOG_FLAG_TRUTH, 4095u, b, sizeof b), TV_ERR_NONFINITE);
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, 0u, 4095u, b, sizeof b), TV_OK); /* truth not stored: not checked */
    memcpy(b, ref, sizeof b);
    r = record_example(1u);
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, RAWLOG_FLAG_TRUTH, 4095u, b, 47u), TV_ERR_RANGE);
    TV_CHECK(memcmp(b, ref, sizeof b) == 0);
    /* the limits themselves are valid */
    r.duty = -1.0f;
    r.adc[0] = 4095u;
    TV_CHECK_EQ_INT(rawlog_pack_record(&r, 0u, 4095u, b, sizeof b), TV_OK);
}

static void test_blocks_fill_seal_and_pad_with_sequence_numbers(void)
{
    rawlog_header_t h;
    rawlog_writer_t w;
    uint8_t buf[RAWLOG_BLOCK_SIZE(3, RAWLOG_RECORD_SIZE_TRUTH)];
    const size_t bs = sizeof buf;
    int rcs[7];
    uint64_t k;
    header_example(&h); /* 3 records per block, truth */
    TV_CHECK_EQ_INT(rawlog_writer_init(&w, &h, buf, bs - 1u), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(rawlog_writer_init(&w, &h, buf, bs), TV_OK);
    TV_CHECK_EQ_INT(w.block_size, 8 + 3 * 48 + 4);
    for (k = 0; k < 7u; ++k) {
        const rawlog_record_t r = record_example(1000u * k);
        rcs[k] = rawlog_writer_add(&w, &r);
        if (rcs[k] == 1) {
            /* a complete block: header, records, CRC */
            TV_CHECK_EQ_INT(le32(buf), k / 3u);
            TV_CHECK_EQ_INT(le16(buf + 4), 3);
            TV_CHECK_EQ_INT(le16(buf + 6), 0);
            TV_CHECK(le64(buf + 8 + 2 * 48) == 1000u * k);
            TV_CHECK_EQ_INT(le32(buf + bs - 4u), rawlog_crc32(0u, buf, bs - 4u));
        }
    }
    TV_CHECK(rcs[0] == 0 && rcs[1] == 0 && rcs[2] == 1 && rcs[3] == 0 && rcs[4] == 0 && rcs[5] == 1 && rcs[6] == 0);
    /* the partial block: one valid record, the other two slots zero */
    TV_CHECK_EQ_INT(rawlog_writer_flush(&w), 1);
    TV_CHECK_EQ_INT(le32(buf), 2);
    TV_CHECK_EQ_INT(le16(buf + 4), 1);
    TV_CHECK(le64(buf + 8) == 6000u);
    {
        size_t j;
        int zero = 1;
        for (j = 8 + 48; j < bs - 4u; ++j) {
            zero = zero && buf[j] == 0u;
        }
        TV_CHECK(zero);
    }
    TV_CHECK_EQ_INT(le32(buf + bs - 4u), rawlog_crc32(0u, buf, bs - 4u));
    TV_CHECK_EQ_INT(rawlog_writer_flush(&w), 0); /* nothing new */
    {
        rawlog_record_t bad = record_example(7000u);
        bad.duty = NAN;
        TV_CHECK_EQ_INT(rawlog_writer_add(&w, &bad), TV_ERR_NONFINITE);
        TV_CHECK_EQ_INT(rawlog_writer_flush(&w), 0); /* the bad record was not stored */
    }
    TV_CHECK_EQ_INT(rawlog_writer_add(NULL, NULL), TV_ERR_NULL);
}

int main(void)
{
    TV_TEST_RUN(test_crc32_is_ieee_802_3_with_check_value_cbf43926);
    TV_TEST_RUN(test_header_bytes_sit_at_the_documented_offsets);
    TV_TEST_RUN(test_header_check_rejects_each_bad_field);
    TV_TEST_RUN(test_record_bytes_sit_at_the_documented_offsets);
    TV_TEST_RUN(test_pack_rejects_bad_values_and_writes_nothing);
    TV_TEST_RUN(test_blocks_fill_seal_and_pad_with_sequence_numbers);
    return tv_test_summary();
}
