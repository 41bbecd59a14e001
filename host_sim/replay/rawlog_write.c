/**
 * @file rawlog_write.c
 * @brief Streaming raw-log writer, CSV and binary (see rawlog_write.h).
 */
#include "rawlog_write.h"

#include <string.h>

#include "numfmt.h"
#include "tv_status.h"

/* The CSV columns, with the truth block. */
static const char s_columns[] = "t_us,duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault,bridge_enable";
static const char s_truth_columns[] = ",i_true_A,w_true_rad_s,phi_true_rad";

static int put_bytes(rlw_t *w, const void *p, size_t n)
{
    if (fwrite(p, 1u, n, w->f) != n) {
        w->io_error = 1;
        return TV_ERR_IO;
    }
    return TV_OK;
}

/* Column header first (numpy.genfromtxt(names=True) takes the first line), then the metadata. */
static int csv_header(rlw_t *w, const char *comment)
{
    const rawlog_header_t *h = &w->hdr;
    char num[NUMFMT_MAX];
    int k;
    fputs(s_columns, w->f);
    if ((h->flags & RAWLOG_FLAG_TRUTH) != 0u) {
        fputs(s_truth_columns, w->f);
    }
    fputc('\n', w->f);
    fputs("# tvrawlog-csv: raw ADC stream of the throttle-valve actuator, one sample per line "
          "(host_sim/replay/LOG_FORMATS.md)\n",
          w->f);
    if (comment != NULL && comment[0] != '\0') {
        fputs("# ", w->f);
        for (k = 0; comment[k] != '\0' && comment[k] != '\n'; ++k) {
            fputc(comment[k], w->f);
        }
        fputc('\n', w->f);
    }
    fprintf(w->f, "# format: tvrawlog-csv\n# version: %u\n# sample_rate_Hz: %lu\n# adc_bits: %u\n", RAWLOG_VERSION,
            (unsigned long)h->sample_rate_Hz, (unsigned)h->adc_bits);
    for (k = 0; k < RLR_NCAL; ++k) {
        (void)numfmt_g17(num, rlr_calib_value(h, k));
        fprintf(w->f, "# %s: %s\n", rlr_calib_name(k), num);
    }
    fputs("# units: t_us [us]; duty [-1, 1] (float32, applied over the next period); *_counts [ADC counts]; "
          "driver_fault, bridge_enable [0/1]",
          w->f);
    if ((h->flags & RAWLOG_FLAG_TRUTH) != 0u) {
        fputs("; i_true_A [A]; w_true_rad_s [rad/s]; phi_true_rad [rad]", w->f);
    }
    fputc('\n', w->f);
    if (ferror(w->f)) {
        w->io_error = 1;
        return TV_ERR_IO;
    }
    return TV_OK;
}

int rlw_open(rlw_t *w, FILE *f, rlr_format_t format, const rawlog_header_t *h, const char *comment)
{
    int rc;
    if (w == NULL || f == NULL || h == NULL) {
        return TV_ERR_NULL;
    }
    if (format != RLR_FMT_CSV && format != RLR_FMT_BIN) {
        return TV_ERR_RANGE;
    }
    rc = rawlog_header_check(h);
    if (rc != TV_OK) {
        return rc;
    }
    memset(w, 0, sizeof *w);
    w->f = f;
    w->format = format;
    w->hdr = *h;
    w->adc_max_counts = (1u << h->adc_bits) - 1u;
    if (format == RLR_FMT_CSV) {
        return csv_header(w, comment);
    }
    {
        uint8_t hb[RAWLOG_HEADER_SIZE];
        rc = rawlog_encode_header(h, hb, sizeof hb);
        if (rc == TV_OK) {
            rc = rawlog_writer_init(&w->bw, h, w->block, sizeof w->block);
        }
        if (rc == TV_OK) {
            rc = put_bytes(w, hb, sizeof hb);
        }
        return rc;
    }
}

int rlw_put(rlw_t *w, const rawlog_record_t *r)
{
    int rc;
    if (w == NULL || r == NULL || w->f == NULL) {
        return TV_ERR_NULL;
    }
    if (w->format == RLR_FMT_BIN) {
        rc = rawlog_writer_add(&w->bw, r);
        if (rc < 0) {
            return rc;
        }
        ++w->records;
        return rc == 1 ? put_bytes(w, w->block, w->bw.block_size) : TV_OK;
    }
    {
        uint8_t scratch[RAWLOG_RECORD_SIZE_TRUTH];
        char line[256];
        size_t n = 0;
        int k;
        rc = rawlog_pack_record(r, w->hdr.flags, w->adc_max_counts, scratch, sizeof scratch);
        if (rc != TV_OK) {
            return rc;
        }
        n += numfmt_u64(line + n, r->t_us);
        line[n++] = ',';
        n += numfmt_g9(line + n, (double)r->duty);
        for (k = 0; k < RAWLOG_NCH; ++k) {
            line[n++] = ',';
            n += numfmt_u64(line + n, r->adc[k]);
        }
        line[n++] = ',';
        line[n++] = r->driver_fault ? '1' : '0';
        line[n++] = ',';
        line[n++] = r->bridge_enable ? '1' : '0';
        if ((w->hdr.flags & RAWLOG_FLAG_TRUTH) != 0u) {
            for (k = 0; k < 3; ++k) {
                line[n++] = ',';
                n += numfmt_g17(line + n, r->truth[k]);
            }
        }
        line[n++] = '\n';
        ++w->records;
        return put_bytes(w, line, n);
    }
}

int rlw_close(rlw_t *w)
{
    if (w == NULL || w->f == NULL) {
        return TV_ERR_NULL;
    }
    if (w->format == RLR_FMT_BIN && rawlog_writer_flush(&w->bw) == 1) {
        (void)put_bytes(w, w->block, w->bw.block_size);
    }
    if (fflush(w->f) != 0 || ferror(w->f)) {
        w->io_error = 1;
    }
    return w->io_error ? TV_ERR_IO : TV_OK;
}
