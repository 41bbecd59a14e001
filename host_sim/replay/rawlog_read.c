/**
 * @file rawlog_read.c
 * @brief Streaming, bounded-memory reader of raw ADC logs, CSV and binary (see rawlog_read.h).
 */
#include "rawlog_read.h"

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "tv_status.h"

/* CSV fields (the record's channels); the column header maps names onto these. */
enum {
    F_T_US = 0,
    F_DUTY,
    F_CURRENT,
    F_TPS1,
    F_TPS2,
    F_SUPPLY,
    F_DRIVER_FAULT,
    F_BRIDGE_ENABLE,
    F_I_TRUE,
    F_W_TRUE,
    F_PHI_TRUE,
    F_COUNT,
    F_REQUIRED = F_BRIDGE_ENABLE /* fields 0 .. F_REQUIRED - 1 must be present */
};

static const char *const s_field_names[F_COUNT] = {
    "t_us",        "duty",         "current_counts", "tps1_counts",  "tps2_counts", "supply_counts",
    "driver_fault", "bridge_enable", "i_true_A",      "w_true_rad_s", "phi_true_rad"};

static const char *const s_err_names[RLR_E_COUNT] = {
    "no error",          "I/O error",          "empty input",          "bad header",
    "bad magic",         "unsupported version", "line too long",        "wrong column count",
    "not a number",      "non-finite value",   "value out of range",   "timestamp going backwards",
    "repeated timestamp", "CRC mismatch",       "bad block header",     "truncated input"};

static const char *const s_calib_names[RLR_NCAL] = {"current_offset_counts", "current_A_per_count",
                                                    "tps1_counts_at_zero",   "tps1_rad_per_count",
                                                    "tps2_counts_at_zero",   "tps2_rad_per_count",
                                                    "supply_V_per_count"};

/* Largest integer a double holds exactly (integral fields given in floating-point notation). */
#define RLR_EXACT_INT_MAX 9007199254740992.0

/* ------------------------------------------------------------------------------------------ */
/* Names                                                                                       */
/* ------------------------------------------------------------------------------------------ */

const char *rlr_err_name(rlr_err_t e)
{
    return (unsigned)e < (unsigned)RLR_E_COUNT ? s_err_names[e] : "?";
}

const char *rlr_format_name(rlr_format_t f)
{
    switch (f) {
    case RLR_FMT_CSV: return "csv";
    case RLR_FMT_BIN: return "bin";
    case RLR_FMT_AUTO:
    default: return "auto";
    }
}

int rlr_format_from_name(const char *s, rlr_format_t *out)
{
    if (s == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    if (strcmp(s, "auto") == 0) {
        *out = RLR_FMT_AUTO;
    } else if (strcmp(s, "csv") == 0) {
        *out = RLR_FMT_CSV;
    } else if (strcmp(s, "bin") == 0) {
        *out = RLR_FMT_BIN;
    } else {
        return TV_ERR_RANGE;
    }
    return TV_OK;
}

const char *rlr_calib_name(int k)
{
    return k >= 0 && k < RLR_NCAL ? s_calib_names[k] : "?";
}

double rlr_calib_value(const rawlog_header_t *h, int k)
{
    switch (k) {
    case 0: return h->current_offset_counts;
    case 1: return h->current_A_per_count;
    case 2: return h->tps1_counts_at_zero;
    case 3: return h->tps1_rad_per_count;
    case 4: return h->tps2_counts_at_zero;
    case 5: return h->tps2_rad_per_count;
    case 6: return h->supply_V_per_count;
    default: return 0.0;
    }
}

static void set_calib(rawlog_header_t *h, int k, double v)
{
    switch (k) {
    case 0: h->current_offset_counts = v; break;
    case 1: h->current_A_per_count = v; break;
    case 2: h->tps1_counts_at_zero = v; break;
    case 3: h->tps1_rad_per_count = v; break;
    case 4: h->tps2_counts_at_zero = v; break;
    case 5: h->tps2_rad_per_count = v; break;
    case 6: h->supply_V_per_count = v; break;
    default: break;
    }
}

rlr_err_t rlr_error(const rlr_t *r)
{
    return r != NULL ? r->err : RLR_E_NONE;
}

const char *rlr_message(const rlr_t *r)
{
    return r != NULL ? r->msg : "";
}

int rlr_recoverable(const rlr_t *r)
{
    return r != NULL && !r->fatal;
}

uint64_t rlr_last_gap(const rlr_t *r)
{
    return r != NULL ? r->last_gap : 0u;
}

static void where(const rlr_t *r, char *out, size_t cap);

/* ------------------------------------------------------------------------------------------ */
/* Errors                                                                                      */
/* ------------------------------------------------------------------------------------------ */

/* Record an error: "<name>: <text>" (the caller puts the line / offset in the text). */
static int fail(rlr_t *r, rlr_err_t e, int fatal, const char *fmt, ...)
{
    va_list ap;
    int n;
    r->err = e;
    r->fatal = r->fatal || fatal;
    ++r->st.errors[e];
    n = snprintf(r->msg, sizeof r->msg, "%s: ", r->name);
    if (n < 0 || (size_t)n >= sizeof r->msg) {
        n = 0;
    }
    va_start(ap, fmt);
    /* va_start is right above: a false positive of clang-analyzer-valist.Uninitialized */
    (void)vsnprintf(r->msg + n, sizeof r->msg - (size_t)n, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized) */
    va_end(ap);
    return e == RLR_E_IO ? TV_ERR_IO : TV_ERR_FORMAT;
}

/* Printable excerpt of a field for messages: at most 40 bytes, non-printables as '?'. */
static const char *excerpt(const char *s, size_t n, char out[48])
{
    size_t k;
    size_t m = 0;
    for (k = 0; k < n && k < 40u; ++k) {
        const unsigned char c = (unsigned char)s[k];
        out[m++] = (char)((c >= 32u && c < 127u) ? c : (unsigned char)'?');
    }
    if (n > 40u) {
        out[m++] = '.';
        out[m++] = '.';
        out[m++] = '.';
    }
    out[m] = '\0';
    return out;
}

/* ------------------------------------------------------------------------------------------ */
/* Input buffer                                                                                */
/* ------------------------------------------------------------------------------------------ */

/* Move the unread bytes to the front and read more. 1 read something, 0 nothing more, <0 I/O. */
static int fill(rlr_t *r)
{
    size_t n;
    if (r->pos > 0u) {
        memmove(r->buf, r->buf + r->pos, r->len - r->pos);
        r->base_offset += r->pos;
        r->len -= r->pos;
        r->pos = 0u;
    }
    if (r->eof || r->len >= RLR_BUF_SIZE) {
        return 0;
    }
    if (r->mem != NULL) {
        n = r->mem_len - r->mem_pos;
        if (n > RLR_BUF_SIZE - r->len) {
            n = RLR_BUF_SIZE - r->len;
        }
        if (n > 0u) {
            memcpy(r->buf + r->len, r->mem + r->mem_pos, n);
        }
        r->mem_pos += n;
    } else {
        n = fread(r->buf + r->len, 1u, RLR_BUF_SIZE - r->len, r->file);
        if (n == 0u && ferror(r->file)) {
            r->eof = 1;
            return fail(r, RLR_E_IO, 1, "read error at byte offset %llu: %s",
                        (unsigned long long)r->base_offset + r->len, strerror(errno));
        }
    }
    if (n == 0u) {
        r->eof = 1;
        return 0;
    }
    r->len += n;
    return 1;
}

/* Copy up to n bytes of input into dst. Returns the count copied (< n only at the end), <0 on I/O. */
static long read_bytes(rlr_t *r, uint8_t *dst, size_t n)
{
    size_t got = 0;
    while (got < n) {
        size_t avail = r->len - r->pos;
        if (avail == 0u) {
            const int rc = fill(r);
            if (rc < 0) {
                return rc;
            }
            if (rc == 0) {
                break;
            }
            continue;
        }
        if (avail > n - got) {
            avail = n - got;
        }
        memcpy(dst + got, r->buf + r->pos, avail);
        r->pos += avail;
        got += avail;
    }
    return (long)got;
}

/* ------------------------------------------------------------------------------------------ */
/* CSV lines                                                                                   */
/* ------------------------------------------------------------------------------------------ */

/*
 * Next line, NUL-terminated in place, '\n' and a '\r' before it removed.
 * 1: *line / *n; 0: end of input; <0: error (line too long: consumed, recoverable in the data).
 */
static int next_line(rlr_t *r, char **line, size_t *n)
{
    for (;;) {
        const size_t avail = r->len - r->pos;
        const size_t scan = avail < r->line_max + 1u ? avail : r->line_max + 1u;
        uint8_t *start = r->buf + r->pos;
        const uint8_t *nl = (const uint8_t *)memchr(start, '\n', scan);
        if (nl == NULL && r->eof && avail > 0u && avail <= r->line_max) {
            /* The last line has no final newline: the log was cut while being written (e.g.
             * "...,27" for "...,2793"); a number that lost its last digits still parses, so the
             * line is refused rather than read. Consumed: it ends the input. */
            r->pos = r->len;
            ++r->line;
            ++r->st.lines;
            return fail(r, RLR_E_TRUNCATED, 1, "line %llu: the last line has no final newline (truncated log?)",
                        (unsigned long long)r->line);
        }
        if (memchr(start, '\0', nl != NULL ? (size_t)(nl - start) : scan) != NULL) {
            /* Text logs hold no NUL byte: binary data read as CSV (or /dev/zero) would otherwise
             * be consumed forever as one endless line. */
            ++r->line;
            ++r->st.lines;
            return fail(r, RLR_E_NUMBER, 1, "line %llu: a NUL byte: binary data, not a CSV log",
                        (unsigned long long)r->line);
        }
        if (nl != NULL) {
            size_t len = (size_t)(nl - start);
            r->pos += len + 1u;
            start[len] = '\0'; /* the '\n' */
            if (len > 0u && start[len - 1u] == '\r') {
                start[--len] = '\0';
            }
            ++r->line;
            ++r->st.lines;
            *line = (char *)start;
            *n = len;
            return 1;
        }
        if (avail > r->line_max) {
            /* too long: consume it up to its end, counting its length */
            uint64_t total = 0;
            ++r->line;
            ++r->st.lines;
            for (;;) {
                const size_t a = r->len - r->pos;
                const uint8_t *q = (const uint8_t *)memchr(r->buf + r->pos, '\n', a);
                const size_t chunk = q != NULL ? (size_t)(q - (r->buf + r->pos)) : a;
                if (total + chunk > RLR_LONG_LINE_SKIP_MAX || memchr(r->buf + r->pos, '\0', chunk) != NULL) {
                    /* no newline in sight, or binary data: not a text log (e.g. /dev/zero); stop
                     * instead of reading on */
                    r->pos = r->len;
                    return fail(r, RLR_E_LINE_LONG, 1,
                                "line %llu: more than %lu bytes without a newline, or a NUL byte: not a CSV log",
                                (unsigned long long)r->line, (unsigned long)RLR_LONG_LINE_SKIP_MAX);
                }
                if (q != NULL) {
                    total += (uint64_t)(q - (r->buf + r->pos));
                    r->pos = (size_t)(q - r->buf) + 1u;
                    break;
                }
                total += a;
                r->pos = r->len;
                if (r->eof) {
                    break;
                }
                if (fill(r) < 0) {
                    return TV_ERR_IO;
                }
            }
            return fail(r, RLR_E_LINE_LONG, 0, "line %llu: %llu bytes, longer than the %lu-byte line limit",
                        (unsigned long long)r->line, (unsigned long long)total, (unsigned long)r->line_max);
        }
        if (r->eof) {
            return 0; /* avail == 0 */
        }
        {
            const int rc = fill(r);
            if (rc < 0) {
                return rc;
            }
        }
    }
}

static int is_space(char c)
{
    return c == ' ' || c == '\t';
}

/* Trim spaces and tabs at both ends of s[0..n), in place (writes a terminator). */
static char *trim(char *s, size_t *n)
{
    size_t len = *n;
    while (len > 0u && is_space(*s)) {
        ++s;
        --len;
    }
    while (len > 0u && is_space(s[len - 1u])) {
        --len;
    }
    s[len] = '\0';
    *n = len;
    return s;
}

/* ------------------------------------------------------------------------------------------ */
/* Numbers                                                                                     */
/* ------------------------------------------------------------------------------------------ */

/* Parse a whole field as a double: 0 ok, else the error class (NUMBER, NONFINITE, RANGE). */
static rlr_err_t parse_double(const char *s, size_t n, double *out)
{
    char *end = NULL;
    double v;
    if (n == 0u) {
        return RLR_E_NUMBER;
    }
    errno = 0;
    v = strtod(s, &end);
    if (end != s + n) {
        return RLR_E_NUMBER;
    }
    if (!(v == v)) {
        return RLR_E_NONFINITE;
    }
    if (v - v != 0.0) {
        return errno == ERANGE ? RLR_E_RANGE : RLR_E_NONFINITE; /* overflow of a finite text: range */
    }
    *out = v;
    return RLR_E_NONE;
}

/* Parse an unsigned integer field <= max (digits, or an integral floating-point form). */
static rlr_err_t parse_uint(const char *s, size_t n, uint64_t max, uint64_t *out)
{
    uint64_t v = 0;
    size_t k;
    double d = 0.0;
    rlr_err_t e;
    if (n == 0u) {
        return RLR_E_NUMBER;
    }
    for (k = 0; k < n; ++k) {
        const unsigned c = (unsigned)(unsigned char)s[k] - (unsigned)'0';
        if (c > 9u) {
            break;
        }
        if (v > (UINT64_MAX - c) / 10u) {
            return RLR_E_RANGE;
        }
        v = v * 10u + c;
    }
    if (k == n) {
        if (v > max) {
            return RLR_E_RANGE;
        }
        *out = v;
        return RLR_E_NONE;
    }
    e = parse_double(s, n, &d);
    if (e != RLR_E_NONE) {
        return e;
    }
    if (d < 0.0 || d > (double)max || d > RLR_EXACT_INT_MAX) {
        return RLR_E_RANGE;
    }
    if (d != (double)(uint64_t)d) {
        return RLR_E_NUMBER;
    }
    *out = (uint64_t)d;
    return RLR_E_NONE;
}

/* Parse a duty as the float the PWM gets (strtof: correctly rounded). */
static rlr_err_t parse_duty(const char *s, size_t n, float *out)
{
    char *end = NULL;
    float v;
    if (n == 0u) {
        return RLR_E_NUMBER;
    }
    errno = 0;
    v = strtof(s, &end);
    if (end != s + n) {
        return RLR_E_NUMBER;
    }
    if (!(v == v)) {
        return RLR_E_NONFINITE;
    }
    if (v - v != 0.0f) {
        return errno == ERANGE ? RLR_E_RANGE : RLR_E_NONFINITE;
    }
    if (!(v >= -1.0f && v <= 1.0f)) {
        return RLR_E_RANGE;
    }
    *out = v;
    return RLR_E_NONE;
}

/* ------------------------------------------------------------------------------------------ */
/* Time                                                                                        */
/* ------------------------------------------------------------------------------------------ */

int rlr_exit_code(rlr_err_t e)
{
    if (e == RLR_E_NONE) {
        return RLR_EXIT_OK;
    }
    if (e == RLR_E_IO || (unsigned)e >= (unsigned)RLR_E_COUNT) {
        return RLR_EXIT_IO;
    }
    return (int)e + 3;
}

void rlr_where(const rlr_t *r, char *out, size_t cap)
{
    if (r == NULL || out == NULL || cap == 0u) {
        return;
    }
    where(r, out, cap);
}

/* Where the record being checked is, for messages (only built on an error). */
static void where(const rlr_t *r, char *out, size_t cap)
{
    if (r->format == RLR_FMT_CSV) {
        (void)snprintf(out, cap, "line %llu", (unsigned long long)r->line);
    } else {
        (void)snprintf(out, cap, "byte offset %llu (block %llu, record %u)", (unsigned long long)r->cur_offset,
                       (unsigned long long)r->block_index, (unsigned)r->cur_rec);
    }
}

/* Accept a record's time: order and gaps. 0 ok, else an error (the record is not delivered). */
static int accept_time(rlr_t *r, uint64_t t_us)
{
    r->last_gap = 0u;
    if (r->have_last) {
        if (t_us <= r->last_t_us) {
            char loc[96];
            where(r, loc, sizeof loc);
            if (t_us == r->last_t_us) {
                return fail(r, RLR_E_TIME_REPEAT, 0, "%s: t_us %llu repeats the previous sample's timestamp", loc,
                            (unsigned long long)t_us);
            }
            return fail(r, RLR_E_TIME_BACK, 0, "%s: t_us %llu is %llu us earlier than the previous sample's %llu",
                        loc, (unsigned long long)t_us, (unsigned long long)(r->last_t_us - t_us),
                        (unsigned long long)r->last_t_us);
        }
        {
            const uint64_t dt = t_us - r->last_t_us;
            const uint64_t periods = dt / r->period_us + ((dt % r->period_us) * 2u >= r->period_us ? 1u : 0u);
            if (periods > 1u) {
                r->last_gap = periods - 1u;
                r->st.missing_samples += periods - 1u;
                ++r->st.gaps;
            }
        }
    }
    r->have_last = 1;
    r->last_t_us = t_us;
    return TV_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* CSV                                                                                         */
/* ------------------------------------------------------------------------------------------ */

/* One "# key: value" metadata line (anything else after '#' is a free comment). */
static int csv_metadata(rlr_t *r, char *s, size_t n, uint64_t seen_line[RLR_NCAL + 4])
{
    static const char *const extra[4] = {"format", "version", "sample_rate_Hz", "adc_bits"};
    char *key;
    char *val;
    size_t klen = 0;
    size_t vlen;
    int idx = -1;
    int k;
    char ex[48];
    ++s;
    --n;
    s = trim(s, &n);
    key = s;
    while (klen < n && (s[klen] == '_' || (s[klen] >= 'a' && s[klen] <= 'z') || (s[klen] >= 'A' && s[klen] <= 'Z') ||
                        (s[klen] >= '0' && s[klen] <= '9'))) {
        ++klen;
    }
    val = s + klen;
    vlen = n - klen;
    val = trim(val, &vlen);
    if (klen == 0u || vlen == 0u || val[0] != ':') {
        return TV_OK; /* a free comment */
    }
    ++val;
    --vlen;
    val = trim(val, &vlen);
    key[klen] = '\0';
    for (k = 0; k < RLR_NCAL; ++k) {
        if (strcmp(key, s_calib_names[k]) == 0) {
            idx = k;
        }
    }
    for (k = 0; k < 4; ++k) {
        if (strcmp(key, extra[k]) == 0) {
            idx = RLR_NCAL + k;
        }
    }
    if (idx < 0) {
        return TV_OK; /* unknown keys are comments (units, provenance, ...) */
    }
    if (seen_line[idx] != 0u) {
        return fail(r, RLR_E_HEADER, 1, "line %llu: metadata key '%s' given twice (first on line %llu)",
                    (unsigned long long)r->line, key, (unsigned long long)seen_line[idx]);
    }
    seen_line[idx] = r->line;
    if (idx < RLR_NCAL) {
        double v = 0.0;
        if (parse_double(val, vlen, &v) != RLR_E_NONE) {
            return fail(r, RLR_E_HEADER, 1, "line %llu: metadata '%s': '%s' is not a finite number",
                        (unsigned long long)r->line, key, excerpt(val, vlen, ex));
        }
        set_calib(&r->hdr, idx, v);
        r->calib_present |= 1u << idx;
        r->calib_line[idx] = r->line;
        return TV_OK;
    }
    if (idx == RLR_NCAL) { /* format */
        if (strcmp(val, "tvrawlog-csv") != 0) {
            return fail(r, RLR_E_HEADER, 1, "line %llu: metadata 'format': '%s' is not tvrawlog-csv",
                        (unsigned long long)r->line, excerpt(val, vlen, ex));
        }
        return TV_OK;
    }
    {
        uint64_t u = 0;
        const uint64_t lo = idx == RLR_NCAL + 1 ? 0u : (idx == RLR_NCAL + 2 ? RAWLOG_RATE_MIN_HZ : RAWLOG_ADC_BITS_MIN);
        const uint64_t hi = idx == RLR_NCAL + 1 ? 65535u : (idx == RLR_NCAL + 2 ? RAWLOG_RATE_MAX_HZ : RAWLOG_ADC_BITS_MAX);
        if (parse_uint(val, vlen, UINT64_MAX, &u) != RLR_E_NONE) {
            return fail(r, RLR_E_HEADER, 1, "line %llu: metadata '%s': '%s' is not an unsigned integer",
                        (unsigned long long)r->line, key, excerpt(val, vlen, ex));
        }
        if (idx == RLR_NCAL + 1) {
            if (u != RAWLOG_VERSION) {
                return fail(r, RLR_E_VERSION, 1, "line %llu: format version %llu is not supported (this reader reads version %u)",
                            (unsigned long long)r->line, (unsigned long long)u, RAWLOG_VERSION);
            }
            return TV_OK;
        }
        if (u < lo || u > hi) {
            return fail(r, RLR_E_HEADER, 1, "line %llu: metadata '%s': %llu is outside %llu..%llu",
                        (unsigned long long)r->line, key, (unsigned long long)u, (unsigned long long)lo,
                        (unsigned long long)hi);
        }
        if (idx == RLR_NCAL + 2) {
            r->hdr.sample_rate_Hz = (uint32_t)u;
        } else {
            r->hdr.adc_bits = (uint8_t)u;
        }
    }
    return TV_OK;
}

/* The column header: map names to fields. */
static int csv_columns(rlr_t *r, char *s, size_t n)
{
    int have[F_COUNT];
    int col = 0;
    int k;
    char ex[48];
    size_t pos = 0;
    (void)excerpt(s, n, ex); /* before the fields are cut in place */
    for (k = 0; k < F_COUNT; ++k) {
        have[k] = -1;
    }
    for (;;) {
        char *f = s + pos;
        const char *comma = (const char *)memchr(f, ',', n - pos);
        size_t flen = comma != NULL ? (size_t)(comma - f) : n - pos;
        const size_t next = pos + flen + 1u;
        int id = -1;
        if (col >= (int)RLR_COLS_MAX) {
            return fail(r, RLR_E_HEADER, 1, "line %llu: more than %u columns in the column header",
                        (unsigned long long)r->line, RLR_COLS_MAX);
        }
        f = trim(f, &flen);
        if (flen >= 2u && f[0] == '"' && f[flen - 1u] == '"') { /* "name" as some tools quote it */
            ++f;
            flen -= 2u;
            f[flen] = '\0';
        }
        for (k = 0; k < F_COUNT; ++k) {
            if (strcmp(f, s_field_names[k]) == 0) {
                id = k;
            }
        }
        if (id >= 0) {
            if (have[id] >= 0) {
                return fail(r, RLR_E_HEADER, 1, "line %llu: column '%s' appears twice (columns %d and %d)",
                            (unsigned long long)r->line, s_field_names[id], have[id] + 1, col + 1);
            }
            have[id] = col;
        }
        r->col_field[col] = id < 0 ? RLR_COL_IGNORED : (uint8_t)id;
        ++col;
        if (comma == NULL) {
            break;
        }
        pos = next;
    }
    r->ncols = col;
    for (k = 0; k < F_REQUIRED; ++k) {
        if (have[k] < 0) {
            return fail(r, RLR_E_HEADER, 1,
                        "line %llu: the column header has no '%s' column (expected t_us,duty,current_counts,"
                        "tps1_counts,tps2_counts,supply_counts,driver_fault[,bridge_enable][,i_true_A,w_true_rad_s,"
                        "phi_true_rad]; the line reads '%s')",
                        (unsigned long long)r->line, s_field_names[k], ex);
        }
    }
    {
        const int nt = (have[F_I_TRUE] >= 0) + (have[F_W_TRUE] >= 0) + (have[F_PHI_TRUE] >= 0);
        if (nt != 0 && nt != 3) {
            return fail(r, RLR_E_HEADER, 1, "line %llu: the truth block needs all of i_true_A, w_true_rad_s, phi_true_rad",
                        (unsigned long long)r->line);
        }
        r->has_truth = nt == 3;
    }
    return TV_OK;
}

/* Blank or comment line (not a sample). */
static int csv_is_comment_or_blank(const char *line, size_t n)
{
    size_t k = 0;
    while (k < n && is_space(line[k])) {
        ++k;
    }
    return k == n || line[k] == '#';
}

/*
 * Header: metadata comments ("# key: value") and the column header, in any order, up to the
 * first data line (kept for csv_next()). The writers put the column header first, so that
 * numpy.genfromtxt(names=True, comments='#') and pandas.read_csv(comment='#') read the file as it is.
 */
static int csv_open(rlr_t *r)
{
    uint64_t seen[RLR_NCAL + 4];
    char *line = NULL;
    size_t n = 0;
    int have_columns = 0;
    memset(seen, 0, sizeof seen);
    for (;;) {
        int rc = next_line(r, &line, &n);
        if (rc < 0) {
            r->fatal = 1; /* a header line too long, or I/O */
            return rc;
        }
        if (rc == 0) {
            if (have_columns) {
                break; /* no data: rlr_next() reports it */
            }
            if (r->line == 0u) {
                return fail(r, RLR_E_EMPTY, 1, "empty input (0 bytes)");
            }
            return fail(r, RLR_E_EMPTY, 1, "no column header line in %llu lines (only comments or blank lines)",
                        (unsigned long long)r->line);
        }
        if (r->line == 1u && n >= 3u && (unsigned char)line[0] == 0xEFu && (unsigned char)line[1] == 0xBBu &&
            (unsigned char)line[2] == 0xBFu) {
            line += 3; /* UTF-8 byte order mark */
            n -= 3u;
        }
        if (!have_columns && memchr(line, '\0', n) != NULL) {
            return fail(r, RLR_E_HEADER, 1, "line %llu: NUL byte in a text header (binary data?)",
                        (unsigned long long)r->line);
        }
        if (csv_is_comment_or_blank(line, n)) {
            line = trim(line, &n);
            if (n > 0u) {
                rc = csv_metadata(r, line, n, seen);
                if (rc != TV_OK) {
                    return rc;
                }
            }
            continue;
        }
        if (have_columns) {
            r->pending = line; /* the first data line */
            r->pending_len = n;
            break;
        }
        line = trim(line, &n);
        rc = csv_columns(r, line, n);
        if (rc != TV_OK) {
            return rc;
        }
        have_columns = 1;
    }
    if (r->has_truth) {
        r->hdr.flags |= RAWLOG_FLAG_TRUTH;
    }
    return TV_OK;
}

static int csv_next(rlr_t *r, rawlog_record_t *rec)
{
    for (;;) {
        char *line = NULL;
        size_t n = 0;
        size_t start[RLR_COLS_MAX + 1u];
        int col = 0;
        int commas = 0;
        int rc;
        if (r->pending != NULL) {
            line = r->pending;
            n = r->pending_len;
            r->pending = NULL;
        } else {
            rc = next_line(r, &line, &n);
            if (rc <= 0) {
                return rc;
            }
            if (csv_is_comment_or_blank(line, n)) {
                continue;
            }
        }
        /* field boundaries in one pass: field c is line[start[c] .. start[c + 1] - 1) */
        {
            size_t k;
            start[0] = 0u;
            for (k = 0; k < n; ++k) {
                if (line[k] == ',') {
                    ++commas;
                    if (commas < (int)RLR_COLS_MAX) {
                        start[commas] = k + 1u;
                    }
                }
            }
        }
        if (commas + 1 != r->ncols) {
            return fail(r, RLR_E_COLUMNS, 0, "line %llu: %d fields, the column header has %d",
                        (unsigned long long)r->line, commas + 1, r->ncols);
        }
        start[commas + 1] = n + 1u;
        memset(rec, 0, sizeof *rec);
        rec->bridge_enable = 1u; /* when the log has no bridge_enable column */
        for (col = 0; col < r->ncols; ++col) {
            char *f = line + start[col];
            size_t flen = start[col + 1] - 1u - start[col];
            const unsigned fid = r->col_field[col];
            const int id = (int)fid;
            rlr_err_t e = RLR_E_NONE;
            uint64_t u = 0;
            if (fid == RLR_COL_IGNORED) {
                continue;
            }
            f = trim(f, &flen);
            switch (id) {
            case F_T_US:
                e = parse_uint(f, flen, UINT64_MAX, &u);
                rec->t_us = u;
                break;
            case F_DUTY:
                e = parse_duty(f, flen, &rec->duty);
                break;
            case F_CURRENT:
            case F_TPS1:
            case F_TPS2:
            case F_SUPPLY:
                e = parse_uint(f, flen, r->adc_max_counts, &u);
                rec->adc[id - F_CURRENT] = (uint16_t)u;
                break;
            case F_DRIVER_FAULT:
                e = parse_uint(f, flen, 1u, &u);
                rec->driver_fault = (uint8_t)u;
                break;
            case F_BRIDGE_ENABLE:
                e = parse_uint(f, flen, 1u, &u);
                rec->bridge_enable = (uint8_t)u;
                break;
            default: /* truth */
                e = parse_double(f, flen, &rec->truth[id - F_I_TRUE]);
                break;
            }
            if (e != RLR_E_NONE) {
                char ex[48];
                const char *what = e == RLR_E_NUMBER     ? "is not a number"
                                   : e == RLR_E_NONFINITE ? "is not finite"
                                                         : "is out of range";
                if (e == RLR_E_RANGE) {
                    what = id == F_DUTY                                       ? "is outside [-1, 1]"
                           : (id == F_DRIVER_FAULT || id == F_BRIDGE_ENABLE) ? "is not 0 or 1"
                           : id == F_T_US                                    ? "does not fit 64 bits"
                           : id >= F_I_TRUE                                  ? "overflows a double"
                                                                             : "is outside the ADC range";
                } else if (e == RLR_E_NUMBER && flen > 0u && id != F_DUTY && id < F_I_TRUE) {
                    what = "is not an unsigned integer";
                }
                if (e == RLR_E_RANGE && id >= F_CURRENT && id <= F_SUPPLY) {
                    return fail(r, e, 0, "line %llu: column %d (%s): '%s' %s 0..%lu", (unsigned long long)r->line,
                                col + 1, s_field_names[id], excerpt(f, flen, ex), what, (unsigned long)r->adc_max_counts);
                }
                return fail(r, e, 0, "line %llu: column %d (%s): '%s' %s", (unsigned long long)r->line, col + 1,
                            s_field_names[id], flen == 0u ? "" : excerpt(f, flen, ex), flen == 0u ? "is empty" : what);
            }
        }
        rc = accept_time(r, rec->t_us);
        if (rc != TV_OK) {
            return rc;
        }
        return 1;
    }
}

/* ------------------------------------------------------------------------------------------ */
/* Binary                                                                                      */
/* ------------------------------------------------------------------------------------------ */

static uint32_t get_u16(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8);
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static uint64_t get_u64(const uint8_t *p)
{
    return (uint64_t)get_u32(p) | ((uint64_t)get_u32(p + 4) << 32);
}

static double get_f64(const uint8_t *p)
{
    const uint64_t u = get_u64(p);
    double v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static float get_f32(const uint8_t *p)
{
    const uint32_t u = get_u32(p);
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

/* Slicing-by-8 tables of the CRC-32 (built on first use; the tools are single-threaded). */
static uint32_t s_crc_tab[8][256];
static int s_crc_ready;

static void crc_tables(void)
{
    uint32_t i;
    int k;
    for (i = 0; i < 256u; ++i) {
        const uint8_t b = (uint8_t)i;
        s_crc_tab[0][i] = ~rawlog_crc32(0xFFFFFFFFu, &b, 1u); /* the plain table entry of byte i */
    }
    for (k = 1; k < 8; ++k) {
        for (i = 0; i < 256u; ++i) {
            const uint32_t prev = s_crc_tab[k - 1][i];
            s_crc_tab[k][i] = (prev >> 8) ^ s_crc_tab[0][prev & 0xFFu];
        }
    }
    s_crc_ready = 1;
}

uint32_t rlr_crc32(const uint8_t *p, size_t n)
{
    uint32_t crc = 0xFFFFFFFFu;
    if (!s_crc_ready) {
        crc_tables();
    }
    while (n >= 8u) {
        const uint32_t one = crc ^ ((uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
                                    ((uint32_t)p[3] << 24));
        const uint32_t two = (uint32_t)p[4] | ((uint32_t)p[5] << 8) | ((uint32_t)p[6] << 16) | ((uint32_t)p[7] << 24);
        crc = s_crc_tab[7][one & 0xFFu] ^ s_crc_tab[6][(one >> 8) & 0xFFu] ^ s_crc_tab[5][(one >> 16) & 0xFFu] ^
              s_crc_tab[4][one >> 24] ^ s_crc_tab[3][two & 0xFFu] ^ s_crc_tab[2][(two >> 8) & 0xFFu] ^
              s_crc_tab[1][(two >> 16) & 0xFFu] ^ s_crc_tab[0][two >> 24];
        p += 8;
        n -= 8u;
    }
    while (n > 0u) {
        crc = s_crc_tab[0][(crc ^ *p++) & 0xFFu] ^ (crc >> 8);
        --n;
    }
    return ~crc;
}

static int bin_open(rlr_t *r)
{
    uint8_t h[RAWLOG_HEADER_SIZE];
    const long got = read_bytes(r, h, sizeof h);
    uint32_t version;
    uint32_t crc_stored;
    uint32_t crc;
    uint32_t rec_size;
    int k;
    if (got < 0) {
        return TV_ERR_IO;
    }
    if (got == 0) {
        return fail(r, RLR_E_EMPTY, 1, "empty input (0 bytes)");
    }
    if (memcmp(h, rawlog_magic, (size_t)got < RAWLOG_MAGIC_SIZE ? (size_t)got : RAWLOG_MAGIC_SIZE) != 0) {
        char shown[RAWLOG_MAGIC_SIZE + 4];
        for (k = 0; k < (int)RAWLOG_MAGIC_SIZE; ++k) {
            shown[k] = (char)(k < got && h[k] >= 32u && h[k] < 127u ? h[k] : (uint8_t)'?');
        }
        shown[RAWLOG_MAGIC_SIZE] = '\0';
        return fail(r, RLR_E_MAGIC, 1, "byte offset 0: bad magic '%s' (a binary log starts with TVRAWLOG)", shown);
    }
    if ((size_t)got < RAWLOG_HEADER_SIZE) {
        return fail(r, RLR_E_TRUNCATED, 1, "truncated header: %ld of %u bytes", got, RAWLOG_HEADER_SIZE);
    }
    version = get_u16(h + 8);
    if (version != RAWLOG_VERSION) {
        return fail(r, RLR_E_VERSION, 1, "byte offset 8: format version %u is not supported (this reader reads version %u)",
                    (unsigned)version, RAWLOG_VERSION);
    }
    crc_stored = get_u32(h + RAWLOG_HEADER_CRC_OFFSET);
    crc = rawlog_crc32(0u, h, RAWLOG_HEADER_CRC_OFFSET);
    if (crc != crc_stored) {
        return fail(r, RLR_E_HEADER, 1, "byte offset %u: header CRC mismatch (stored 0x%08lx, computed 0x%08lx)",
                    RAWLOG_HEADER_CRC_OFFSET, (unsigned long)crc_stored, (unsigned long)crc);
    }
    r->hdr.flags = get_u32(h + 16);
    r->hdr.sample_rate_Hz = get_u32(h + 20);
    r->hdr.records_per_block = (uint16_t)get_u16(h + 14);
    r->hdr.adc_bits = h[24];
    for (k = 0; k < RLR_NCAL; ++k) {
        set_calib(&r->hdr, k, get_f64(h + 32 + 8u * (size_t)k));
    }
    r->calib_present = RLR_CAL_ALL;
    rec_size = get_u16(h + 12);
    if (get_u16(h + 10) != RAWLOG_HEADER_SIZE) {
        return fail(r, RLR_E_HEADER, 1, "byte offset 10: header size %u, expected %u", (unsigned)get_u16(h + 10),
                    RAWLOG_HEADER_SIZE);
    }
    if ((r->hdr.flags & ~(uint32_t)RAWLOG_FLAG_TRUTH) != 0u) {
        return fail(r, RLR_E_HEADER, 1, "byte offset 16: unknown flags 0x%08lx", (unsigned long)r->hdr.flags);
    }
    if (rec_size != rawlog_record_size(r->hdr.flags)) {
        return fail(r, RLR_E_HEADER, 1, "byte offset 12: record size %u does not match the flags (expected %u)",
                    (unsigned)rec_size, (unsigned)rawlog_record_size(r->hdr.flags));
    }
    if (r->hdr.records_per_block == 0u || r->hdr.records_per_block > RAWLOG_BLOCK_RECORDS_MAX) {
        return fail(r, RLR_E_HEADER, 1, "byte offset 14: %u records per block (allowed 1..%u)",
                    (unsigned)r->hdr.records_per_block, RAWLOG_BLOCK_RECORDS_MAX);
    }
    if (r->hdr.sample_rate_Hz < RAWLOG_RATE_MIN_HZ || r->hdr.sample_rate_Hz > RAWLOG_RATE_MAX_HZ) {
        return fail(r, RLR_E_HEADER, 1, "byte offset 20: sample rate %lu Hz (allowed %u..%u)",
                    (unsigned long)r->hdr.sample_rate_Hz, RAWLOG_RATE_MIN_HZ, RAWLOG_RATE_MAX_HZ);
    }
    if (r->hdr.adc_bits < RAWLOG_ADC_BITS_MIN || r->hdr.adc_bits > RAWLOG_ADC_BITS_MAX) {
        return fail(r, RLR_E_HEADER, 1, "byte offset 24: ADC resolution %u bits (allowed %u..%u)",
                    (unsigned)r->hdr.adc_bits, RAWLOG_ADC_BITS_MIN, RAWLOG_ADC_BITS_MAX);
    }
    for (k = 0; k < RLR_NCAL; ++k) {
        const double v = rlr_calib_value(&r->hdr, k);
        if (!(v == v) || v - v != 0.0) {
            return fail(r, RLR_E_HEADER, 1, "byte offset %d: calibration %s is not finite", 32 + 8 * k,
                        s_calib_names[k]);
        }
    }
    r->has_truth = (r->hdr.flags & RAWLOG_FLAG_TRUTH) != 0u;
    r->record_size = rec_size;
    r->block_size = RAWLOG_BLOCK_SIZE(r->hdr.records_per_block, rec_size);
    return TV_OK;
}

/* Read the next block into r->block. 1 ok, 0 end, <0 error. */
static int bin_read_block(rlr_t *r)
{
    const uint64_t offset = r->base_offset + r->pos;
    const long got = read_bytes(r, r->block, r->block_size);
    const size_t crc_at = r->block_size - RAWLOG_BLOCK_TRAILER_SIZE;
    uint32_t crc;
    uint32_t stored;
    uint32_t seq;
    uint32_t n;
    if (got < 0) {
        return TV_ERR_IO;
    }
    if (got == 0) {
        return 0;
    }
    r->block_index = r->next_block++;
    r->block_offset = offset;
    if ((size_t)got < r->block_size) {
        r->done = 1;
        return fail(r, RLR_E_TRUNCATED, 0,
                    "byte offset %llu: block %llu truncated: %ld of %lu bytes (its records are lost; the input ends here)",
                    (unsigned long long)offset, (unsigned long long)r->block_index, got, (unsigned long)r->block_size);
    }
    stored = get_u32(r->block + crc_at);
    crc = rlr_crc32(r->block, crc_at);
    if (crc != stored) {
        ++r->next_sequence; /* presumably the expected block, unreadable: not also "missing" */
        return fail(r, RLR_E_CRC, 0,
                    "byte offset %llu: block %llu CRC mismatch (stored 0x%08lx, computed 0x%08lx); its up to %u records are skipped",
                    (unsigned long long)offset, (unsigned long long)r->block_index, (unsigned long)stored,
                    (unsigned long)crc, (unsigned)r->hdr.records_per_block);
    }
    seq = get_u32(r->block);
    n = get_u16(r->block + 4);
    if (n == 0u || n > r->hdr.records_per_block) {
        r->next_sequence = seq + 1u;
        return fail(r, RLR_E_BLOCK, 0, "byte offset %llu: block %llu claims %lu valid records (allowed 1..%u)",
                    (unsigned long long)offset + 4u, (unsigned long long)r->block_index, (unsigned long)n,
                    (unsigned)r->hdr.records_per_block);
    }
    if (seq != r->next_sequence && seq > r->next_sequence) {
        r->st.blocks_missing += seq - r->next_sequence;
    }
    r->next_sequence = seq + 1u;
    ++r->st.blocks;
    r->block_n = (uint16_t)n;
    r->block_pos = 0u;
    r->have_block = 1;
    return 1;
}

static int bin_next(rlr_t *r, rawlog_record_t *rec)
{
    for (;;) {
        const uint8_t *p;
        int k;
        int rc;
        if (!r->have_block || r->block_pos >= r->block_n) {
            r->have_block = 0;
            if (r->done) {
                return 0;
            }
            rc = bin_read_block(r);
            if (rc <= 0) {
                return rc;
            }
        }
        r->cur_rec = r->block_pos;
        r->cur_offset = r->block_offset + RAWLOG_BLOCK_HEADER_SIZE + (uint64_t)r->block_pos * r->record_size;
        p = r->block + RAWLOG_BLOCK_HEADER_SIZE + (size_t)r->block_pos * r->record_size;
        ++r->block_pos; /* this record is consumed, good or bad */
        memset(rec, 0, sizeof *rec);
        rec->t_us = get_u64(p);
        rec->duty = get_f32(p + 8);
        for (k = 0; k < RAWLOG_NCH; ++k) {
            rec->adc[k] = (uint16_t)get_u16(p + 12 + 2u * (size_t)k);
        }
        rec->driver_fault = (p[20] & RAWLOG_REC_DRIVER_FAULT) != 0u ? 1u : 0u;
        rec->bridge_enable = (p[20] & RAWLOG_REC_BRIDGE_ENABLE) != 0u ? 1u : 0u;
        if (r->has_truth) {
            rec->truth[0] = get_f64(p + 24);
            rec->truth[1] = get_f64(p + 32);
            rec->truth[2] = get_f64(p + 40);
        }
        {
            const float d = rec->duty;
            char loc[96];
            if (!(d == d) || d - d != 0.0f) {
                where(r, loc, sizeof loc);
                return fail(r, RLR_E_NONFINITE, 0, "%s: duty is not finite", loc);
            }
            if (!(d >= -1.0f && d <= 1.0f)) {
                where(r, loc, sizeof loc);
                return fail(r, RLR_E_RANGE, 0, "%s: duty %.9g is outside [-1, 1]", loc, (double)d);
            }
            for (k = 0; k < RAWLOG_NCH; ++k) {
                if (rec->adc[k] > r->adc_max_counts) {
                    where(r, loc, sizeof loc);
                    return fail(r, RLR_E_RANGE, 0, "%s: %s %u is outside the ADC range 0..%lu", loc,
                                s_field_names[F_CURRENT + k], (unsigned)rec->adc[k], (unsigned long)r->adc_max_counts);
                }
            }
            for (k = 0; r->has_truth && k < 3; ++k) {
                if (!(rec->truth[k] == rec->truth[k]) || rec->truth[k] - rec->truth[k] != 0.0) {
                    where(r, loc, sizeof loc);
                    return fail(r, RLR_E_NONFINITE, 0, "%s: %s is not finite", loc, s_field_names[F_I_TRUE + k]);
                }
            }
        }
        rc = accept_time(r, rec->t_us);
        if (rc != TV_OK) {
            return rc;
        }
        return 1;
    }
}

/* ------------------------------------------------------------------------------------------ */
/* Open, next                                                                                  */
/* ------------------------------------------------------------------------------------------ */

static int open_common(rlr_t *r, rlr_format_t format)
{
    int rc;
    rawlog_header_default(&r->hdr);
    if (format == RLR_FMT_AUTO) {
        rc = fill(r);
        if (rc < 0) {
            return rc;
        }
        while (rc > 0 && r->len < RAWLOG_MAGIC_SIZE) { /* short reads from pipes */
            rc = fill(r);
            if (rc < 0) {
                return rc;
            }
        }
        if (r->len == 0u) {
            return fail(r, RLR_E_EMPTY, 1, "empty input (0 bytes)");
        }
        if (memcmp(r->buf, rawlog_magic, r->len < RAWLOG_MAGIC_SIZE ? r->len : RAWLOG_MAGIC_SIZE) == 0) {
            format = RLR_FMT_BIN;
        } else if (memchr(r->buf, '\0', r->len < 1024u ? r->len : 1024u) != NULL) {
            char shown[RAWLOG_MAGIC_SIZE + 1];
            size_t k;
            for (k = 0; k < RAWLOG_MAGIC_SIZE; ++k) {
                shown[k] = (char)(k < r->len && r->buf[k] >= 32u && r->buf[k] < 127u ? r->buf[k] : (uint8_t)'?');
            }
            shown[RAWLOG_MAGIC_SIZE] = '\0';
            return fail(r, RLR_E_MAGIC, 1,
                        "byte offset 0: binary data with a bad magic '%s' (a binary log starts with TVRAWLOG; a CSV log is text)",
                        shown);
        } else {
            format = RLR_FMT_CSV;
        }
    }
    r->format = format;
    rc = format == RLR_FMT_BIN ? bin_open(r) : csv_open(r);
    if (rc != TV_OK) {
        r->fatal = 1;
        return rc;
    }
    r->adc_max_counts = (1u << r->hdr.adc_bits) - 1u;
    r->period_us = (uint32_t)((1000000u + r->hdr.sample_rate_Hz / 2u) / r->hdr.sample_rate_Hz);
    if (r->period_us == 0u) {
        r->period_us = 1u;
    }
    return TV_OK;
}

static int init_common(rlr_t *r, const char *name, rlr_format_t format, size_t line_max)
{
    if (r == NULL) {
        return TV_ERR_NULL;
    }
    if ((unsigned)format > (unsigned)RLR_FMT_BIN || line_max > RLR_LINE_MAX) {
        return TV_ERR_RANGE;
    }
    memset(r, 0, sizeof *r);
    r->name = name != NULL ? name : "<input>";
    r->line_max = line_max == 0u ? RLR_LINE_MAX : line_max;
    return TV_OK;
}

int rlr_open_file(rlr_t *r, FILE *f, const char *name, rlr_format_t format, size_t line_max)
{
    const int rc = init_common(r, name, format, line_max);
    if (rc != TV_OK) {
        return rc;
    }
    if (f == NULL) {
        return TV_ERR_NULL;
    }
    r->file = f;
    return open_common(r, format);
}

int rlr_open_mem(rlr_t *r, const uint8_t *data, size_t n, const char *name, rlr_format_t format, size_t line_max)
{
    const int rc = init_common(r, name, format, line_max);
    if (rc != TV_OK) {
        return rc;
    }
    if (data == NULL && n > 0u) {
        return TV_ERR_NULL;
    }
    r->mem = data != NULL ? data : (const uint8_t *)"";
    r->mem_len = n;
    return open_common(r, format);
}

int rlr_next(rlr_t *r, rawlog_record_t *rec)
{
    int rc;
    if (r == NULL || rec == NULL) {
        return TV_ERR_NULL;
    }
    if (r->fatal) {
        return r->err == RLR_E_IO ? TV_ERR_IO : TV_ERR_FORMAT;
    }
    if (r->format == RLR_FMT_BIN) {
        rc = bin_next(r, rec);
    } else {
        rc = csv_next(r, rec);
    }
    if (rc == 1) {
        ++r->st.records;
        return 1;
    }
    if (rc == 0) {
        int e;
        uint64_t errors = 0;
        r->done = 1;
        for (e = 0; e < (int)RLR_E_COUNT; ++e) {
            errors += r->st.errors[e];
        }
        if (r->st.records == 0u && errors == 0u) {
            return fail(r, RLR_E_EMPTY, 1, "no samples after the header");
        }
        return 0;
    }
    if (r->err == RLR_E_IO) {
        r->fatal = 1;
    }
    return rc;
}
