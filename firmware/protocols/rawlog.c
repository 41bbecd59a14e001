/**
 * @file rawlog.c
 * @brief Binary raw-ADC log encoder (see rawlog.h and host_sim/replay/LOG_FORMATS.md).
 */
#include "rawlog.h"

#include <string.h>

#include "tv_status.h"

/* float and double must be IEEE binary32 / binary64 for the bit copies below. */
typedef char rawlog_float_is_4_bytes[(sizeof(float) == 4u) ? 1 : -1];
typedef char rawlog_double_is_8_bytes[(sizeof(double) == 8u) ? 1 : -1];

const uint8_t rawlog_magic[RAWLOG_MAGIC_SIZE] = {'T', 'V', 'R', 'A', 'W', 'L', 'O', 'G'};

/* CRC-32 table of the reflected polynomial 0xEDB88320 (entry k = CRC of the byte k). */
static const uint32_t s_crc_table[256] = {
    0x00000000u, 0x77073096u, 0xEE0E612Cu, 0x990951BAu, 0x076DC419u, 0x706AF48Fu,
    0xE963A535u, 0x9E6495A3u, 0x0EDB8832u, 0x79DCB8A4u, 0xE0D5E91Eu, 0x97D2D988u,
    0x09B64C2Bu, 0x7EB17CBDu, 0xE7B82D07u, 0x90BF1D91u, 0x1DB71064u, 0x6AB020F2u,
    0xF3B97148u, 0x84BE41DEu, 0x1ADAD47Du, 0x6DDDE4EBu, 0xF4D4B551u, 0x83D385C7u,
    0x136C9856u, 0x646BA8C0u, 0xFD62F97Au, 0x8A65C9ECu, 0x14015C4Fu, 0x63066CD9u,
    0xFA0F3D63u, 0x8D080DF5u, 0x3B6E20C8u, 0x4C69105Eu, 0xD56041E4u, 0xA2677172u,
    0x3C03E4D1u, 0x4B04D447u, 0xD20D85FDu, 0xA50AB56Bu, 0x35B5A8FAu, 0x42B2986Cu,
    0xDBBBC9D6u, 0xACBCF940u, 0x32D86CE3u, 0x45DF5C75u, 0xDCD60DCFu, 0xABD13D59u,
    0x26D930ACu, 0x51DE003Au, 0xC8D75180u, 0xBFD06116u, 0x21B4F4B5u, 0x56B3C423u,
    0xCFBA9599u, 0xB8BDA50Fu, 0x2802B89Eu, 0x5F058808u, 0xC60CD9B2u, 0xB10BE924u,
    0x2F6F7C87u, 0x58684C11u, 0xC1611DABu, 0xB6662D3Du, 0x76DC4190u, 0x01DB7106u,
    0x98D220BCu, 0xEFD5102Au, 0x71B18589u, 0x06B6B51Fu, 0x9FBFE4A5u, 0xE8B8D433u,
    0x7807C9A2u, 0x0F00F934u, 0x9609A88Eu, 0xE10E9818u, 0x7F6A0DBBu, 0x086D3D2Du,
    0x91646C97u, 0xE6635C01u, 0x6B6B51F4u, 0x1C6C6162u, 0x856530D8u, 0xF262004Eu,
    0x6C0695EDu, 0x1B01A57Bu, 0x8208F4C1u, 0xF50FC457u, 0x65B0D9C6u, 0x12B7E950u,
    0x8BBEB8EAu, 0xFCB9887Cu, 0x62DD1DDFu, 0x15DA2D49u, 0x8CD37CF3u, 0xFBD44C65u,
    0x4DB26158u, 0x3AB551CEu, 0xA3BC0074u, 0xD4BB30E2u, 0x4ADFA541u, 0x3DD895D7u,
    0xA4D1C46Du, 0xD3D6F4FBu, 0x4369E96Au, 0x346ED9FCu, 0xAD678846u, 0xDA60B8D0u,
    0x44042D73u, 0x33031DE5u, 0xAA0A4C5Fu, 0xDD0D7CC9u, 0x5005713Cu, 0x270241AAu,
    0xBE0B1010u, 0xC90C2086u, 0x5768B525u, 0x206F85B3u, 0xB966D409u, 0xCE61E49Fu,
    0x5EDEF90Eu, 0x29D9C998u, 0xB0D09822u, 0xC7D7A8B4u, 0x59B33D17u, 0x2EB40D81u,
    0xB7BD5C3Bu, 0xC0BA6CADu, 0xEDB88320u, 0x9ABFB3B6u, 0x03B6E20Cu, 0x74B1D29Au,
    0xEAD54739u, 0x9DD277AFu, 0x04DB2615u, 0x73DC1683u, 0xE3630B12u, 0x94643B84u,
    0x0D6D6A3Eu, 0x7A6A5AA8u, 0xE40ECF0Bu, 0x9309FF9Du, 0x0A00AE27u, 0x7D079EB1u,
    0xF00F9344u, 0x8708A3D2u, 0x1E01F268u, 0x6906C2FEu, 0xF762575Du, 0x806567CBu,
    0x196C3671u, 0x6E6B06E7u, 0xFED41B76u, 0x89D32BE0u, 0x10DA7A5Au, 0x67DD4ACCu,
    0xF9B9DF6Fu, 0x8EBEEFF9u, 0x17B7BE43u, 0x60B08ED5u, 0xD6D6A3E8u, 0xA1D1937Eu,
    0x38D8C2C4u, 0x4FDFF252u, 0xD1BB67F1u, 0xA6BC5767u, 0x3FB506DDu, 0x48B2364Bu,
    0xD80D2BDAu, 0xAF0A1B4Cu, 0x36034AF6u, 0x41047A60u, 0xDF60EFC3u, 0xA867DF55u,
    0x316E8EEFu, 0x4669BE79u, 0xCB61B38Cu, 0xBC66831Au, 0x256FD2A0u, 0x5268E236u,
    0xCC0C7795u, 0xBB0B4703u, 0x220216B9u, 0x5505262Fu, 0xC5BA3BBEu, 0xB2BD0B28u,
    0x2BB45A92u, 0x5CB36A04u, 0xC2D7FFA7u, 0xB5D0CF31u, 0x2CD99E8Bu, 0x5BDEAE1Du,
    0x9B64C2B0u, 0xEC63F226u, 0x756AA39Cu, 0x026D930Au, 0x9C0906A9u, 0xEB0E363Fu,
    0x72076785u, 0x05005713u, 0x95BF4A82u, 0xE2B87A14u, 0x7BB12BAEu, 0x0CB61B38u,
    0x92D28E9Bu, 0xE5D5BE0Du, 0x7CDCEFB7u, 0x0BDBDF21u, 0x86D3D2D4u, 0xF1D4E242u,
    0x68DDB3F8u, 0x1FDA836Eu, 0x81BE16CDu, 0xF6B9265Bu, 0x6FB077E1u, 0x18B74777u,
    0x88085AE6u, 0xFF0F6A70u, 0x66063BCAu, 0x11010B5Cu, 0x8F659EFFu, 0xF862AE69u,
    0x616BFFD3u, 0x166CCF45u, 0xA00AE278u, 0xD70DD2EEu, 0x4E048354u, 0x3903B3C2u,
    0xA7672661u, 0xD06016F7u, 0x4969474Du, 0x3E6E77DBu, 0xAED16A4Au, 0xD9D65ADCu,
    0x40DF0B66u, 0x37D83BF0u, 0xA9BCAE53u, 0xDEBB9EC5u, 0x47B2CF7Fu, 0x30B5FFE9u,
    0xBDBDF21Cu, 0xCABAC28Au, 0x53B39330u, 0x24B4A3A6u, 0xBAD03605u, 0xCDD70693u,
    0x54DE5729u, 0x23D967BFu, 0xB3667A2Eu, 0xC4614AB8u, 0x5D681B02u, 0x2A6F2B94u,
    0xB40BBE37u, 0xC30C8EA1u, 0x5A05DF1Bu, 0x2D02EF8Du,
};

uint32_t rawlog_crc32(uint32_t crc, const uint8_t *data, size_t n)
{
    size_t k;
    if (data == NULL || n == 0u) {
        return crc;
    }
    crc = ~crc;
    for (k = 0; k < n; ++k) {
        crc = s_crc_table[(crc ^ data[k]) & 0xFFu] ^ (crc >> 8);
    }
    return ~crc;
}

/* Little-endian stores. */
static void put_u16(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)((v >> 8) & 0xFFu);
}

static void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)((v >> 8) & 0xFFu);
    p[2] = (uint8_t)((v >> 16) & 0xFFu);
    p[3] = (uint8_t)((v >> 24) & 0xFFu);
}

static void put_u64(uint8_t *p, uint64_t v)
{
    put_u32(p, (uint32_t)(v & 0xFFFFFFFFu));
    put_u32(p + 4, (uint32_t)(v >> 32));
}

static void put_f32(uint8_t *p, float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    put_u32(p, u);
}

static void put_f64(uint8_t *p, double v)
{
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    put_u64(p, u);
}

/* Finite test that works for double without promotions or <math.h> macros. */
static int finite_d(double v)
{
    return v == v && v - v == 0.0;
}

void rawlog_header_default(rawlog_header_t *h)
{
    if (h == NULL) {
        return;
    }
    memset(h, 0, sizeof *h);
    h->sample_rate_Hz = 1000u;
    h->records_per_block = (uint16_t)RAWLOG_BLOCK_RECORDS_DEFAULT;
    h->adc_bits = 12u;
}

int rawlog_header_check(const rawlog_header_t *h)
{
    if (h == NULL) {
        return TV_ERR_NULL;
    }
    if (!finite_d(h->current_offset_counts) || !finite_d(h->current_A_per_count) ||
        !finite_d(h->tps1_counts_at_zero) || !finite_d(h->tps1_rad_per_count) || !finite_d(h->tps2_counts_at_zero) ||
        !finite_d(h->tps2_rad_per_count) || !finite_d(h->supply_V_per_count)) {
        return TV_ERR_NONFINITE;
    }
    if ((h->flags & ~(uint32_t)RAWLOG_FLAG_TRUTH) != 0u || h->sample_rate_Hz < RAWLOG_RATE_MIN_HZ ||
        h->sample_rate_Hz > RAWLOG_RATE_MAX_HZ || h->records_per_block == 0u ||
        h->records_per_block > RAWLOG_BLOCK_RECORDS_MAX || h->adc_bits < RAWLOG_ADC_BITS_MIN ||
        h->adc_bits > RAWLOG_ADC_BITS_MAX) {
        return TV_ERR_RANGE;
    }
    return TV_OK;
}

size_t rawlog_record_size(uint32_t flags)
{
    return (flags & RAWLOG_FLAG_TRUTH) != 0u ? RAWLOG_RECORD_SIZE_TRUTH : RAWLOG_RECORD_SIZE;
}

int rawlog_encode_header(const rawlog_header_t *h, uint8_t *out, size_t cap)
{
    int rc;
    if (h == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    rc = rawlog_header_check(h);
    if (rc != TV_OK) {
        return rc;
    }
    if (cap < RAWLOG_HEADER_SIZE) {
        return TV_ERR_RANGE;
    }
    memset(out, 0, RAWLOG_HEADER_SIZE);
    memcpy(out, rawlog_magic, RAWLOG_MAGIC_SIZE);
    put_u16(out + 8, RAWLOG_VERSION);
    put_u16(out + 10, RAWLOG_HEADER_SIZE);
    put_u16(out + 12, (uint32_t)rawlog_record_size(h->flags));
    put_u16(out + 14, h->records_per_block);
    put_u32(out + 16, h->flags);
    put_u32(out + 20, h->sample_rate_Hz);
    out[24] = h->adc_bits;
    put_f64(out + 32, h->current_offset_counts);
    put_f64(out + 40, h->current_A_per_count);
    put_f64(out + 48, h->tps1_counts_at_zero);
    put_f64(out + 56, h->tps1_rad_per_count);
    put_f64(out + 64, h->tps2_counts_at_zero);
    put_f64(out + 72, h->tps2_rad_per_count);
    put_f64(out + 80, h->supply_V_per_count);
    put_u32(out + RAWLOG_HEADER_CRC_OFFSET, rawlog_crc32(0u, out, RAWLOG_HEADER_CRC_OFFSET));
    return TV_OK;
}

int rawlog_pack_record(const rawlog_record_t *r, uint32_t flags, uint32_t adc_max_counts, uint8_t *out, size_t cap)
{
    const size_t size = rawlog_record_size(flags);
    const int truth = (flags & RAWLOG_FLAG_TRUTH) != 0u;
    int k;
    if (r == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    /* NaN fails both comparisons; +-Inf fails the range. */
    if (!(r->duty == r->duty) ||
        (truth && (!finite_d(r->truth[0]) || !finite_d(r->truth[1]) || !finite_d(r->truth[2])))) {
        return TV_ERR_NONFINITE;
    }
    if (!(r->duty >= -1.0f && r->duty <= 1.0f) || r->driver_fault > 1u || r->bridge_enable > 1u || cap < size) {
        return TV_ERR_RANGE;
    }
    for (k = 0; k < RAWLOG_NCH; ++k) {
        if (r->adc[k] > adc_max_counts) {
            return TV_ERR_RANGE;
        }
    }
    memset(out, 0, size);
    put_u64(out, r->t_us);
    put_f32(out + 8, r->duty);
    for (k = 0; k < RAWLOG_NCH; ++k) {
        put_u16(out + 12 + 2u * (size_t)k, r->adc[k]);
    }
    out[20] = (uint8_t)((r->driver_fault ? RAWLOG_REC_DRIVER_FAULT : 0u) |
                        (r->bridge_enable ? RAWLOG_REC_BRIDGE_ENABLE : 0u));
    if (truth) {
        put_f64(out + 24, r->truth[0]);
        put_f64(out + 32, r->truth[1]);
        put_f64(out + 40, r->truth[2]);
    }
    return TV_OK;
}

int rawlog_writer_init(rawlog_writer_t *w, const rawlog_header_t *h, uint8_t *buf, size_t cap)
{
    int rc;
    size_t rs;
    size_t bs;
    if (w == NULL || h == NULL || buf == NULL) {
        return TV_ERR_NULL;
    }
    rc = rawlog_header_check(h);
    if (rc != TV_OK) {
        return rc;
    }
    rs = rawlog_record_size(h->flags);
    bs = RAWLOG_BLOCK_SIZE(h->records_per_block, rs);
    if (cap < bs) {
        return TV_ERR_RANGE;
    }
    memset(w, 0, sizeof *w);
    w->buf = buf;
    w->block_size = bs;
    w->record_size = rs;
    w->flags = h->flags;
    w->adc_max_counts = (1u << h->adc_bits) - 1u;
    w->per_block = h->records_per_block;
    return TV_OK;
}

/* Finish the block in buf: header, zero padding of the unused slots, CRC. */
static void seal(rawlog_writer_t *w)
{
    const size_t used = RAWLOG_BLOCK_HEADER_SIZE + (size_t)w->n * w->record_size;
    const size_t crc_at = w->block_size - RAWLOG_BLOCK_TRAILER_SIZE;
    put_u32(w->buf, w->sequence);
    put_u16(w->buf + 4, w->n);
    put_u16(w->buf + 6, 0u);
    memset(w->buf + used, 0, crc_at - used);
    put_u32(w->buf + crc_at, rawlog_crc32(0u, w->buf, crc_at));
    w->sealed = 1u;
}

int rawlog_writer_add(rawlog_writer_t *w, const rawlog_record_t *r)
{
    int rc;
    if (w == NULL || r == NULL || w->buf == NULL) {
        return TV_ERR_NULL;
    }
    if (w->sealed) {
        /* the previous block was handed out: start the next one */
        w->sealed = 0u;
        w->n = 0u;
        ++w->sequence;
    }
    rc = rawlog_pack_record(r, w->flags, w->adc_max_counts,
                            w->buf + RAWLOG_BLOCK_HEADER_SIZE + (size_t)w->n * w->record_size, w->record_size);
    if (rc != TV_OK) {
        return rc;
    }
    ++w->n;
    if (w->n == w->per_block) {
        seal(w);
        return 1;
    }
    return 0;
}

int rawlog_writer_flush(rawlog_writer_t *w)
{
    if (w == NULL || w->buf == NULL) {
        return TV_ERR_NULL;
    }
    if (w->sealed || w->n == 0u) {
        return 0;
    }
    seal(w);
    return 1;
}
