/**
 * @file qemu_replay.c
 * @brief QEMU mps2-an386 (Cortex-M4F) test image: runs the application step over an input
 *        stream read from a host file through semihosting and writes its outputs to another,
 *        with the record format and replay step of tvlog.h. The host runs the same step on
 *        the same file (m4f_replay_host) and compares.
 *
 * Usage (QEMU): -semihosting-config enable=on,target=native,arg=qemu_replay,arg=IN,arg=OUT
 * Exit status: 0 ok, 2 usage / file error, 3 fault.
 * Prints the stack high-water mark of the run (the stack is painted at reset).
 */
#include <stddef.h>
#include <stdint.h>

#include "app.h"
#include "semihost.h"
#include "startup.h"
#include "tvlog.h"

/** Records per semihosting read/write. */
#define CHUNK 64u

static app_t s_app;
static uint8_t s_in[CHUNK * TVLOG_IN_BYTES];
static uint8_t s_out[CHUNK * TVLOG_OUT_BYTES];
static char s_cmdline[512];

void startup_fault_hook(uint32_t exception_number)
{
    sh_puts("qemu_replay: fault, exception ");
    sh_put_u32(exception_number);
    sh_puts("\n");
    sh_exit(3);
}

static void fail(const char *what)
{
    sh_puts("qemu_replay: ");
    sh_puts(what);
    sh_puts("\n");
    sh_exit(2);
}

int main(void)
{
    char *argv[4];
    uint8_t hdr[TVLOG_HEADER_BYTES];
    uint32_t n_rec;
    uint32_t done = 0u;
    int32_t fin;
    int32_t fout;
    app_output_t out;

    if (sh_get_cmdline(s_cmdline, sizeof s_cmdline) != 0 || sh_split_words(s_cmdline, argv, 4u) != 3u) {
        fail("usage: qemu_replay IN OUT");
    }
    fin = sh_open(argv[1], SH_MODE_RB);
    fout = sh_open(argv[2], SH_MODE_WB);
    if (fin < 0 || fout < 0) {
        fail("cannot open the input or output file");
    }
    if (sh_read(fin, hdr, sizeof hdr) != (int32_t)sizeof hdr ||
        tvlog_header_decode(hdr, TVLOG_MAGIC_IN, TVLOG_IN_BYTES, &n_rec) != 0) {
        fail("bad input header");
    }
    if (tvlog_replay_init(&s_app, 1) != 0) {
        fail("app_init failed");
    }
    tvlog_header_encode(hdr, TVLOG_MAGIC_OUT, n_rec, TVLOG_OUT_BYTES);
    if (sh_write(fout, hdr, sizeof hdr) != 0) {
        fail("write failed");
    }
    while (done < n_rec) {
        uint32_t n = n_rec - done;
        uint32_t k;
        if (n > CHUNK) {
            n = CHUNK;
        }
        if (sh_read(fin, s_in, n * TVLOG_IN_BYTES) != (int32_t)(n * TVLOG_IN_BYTES)) {
            fail("short input file");
        }
        for (k = 0u; k < n; ++k) {
            tvlog_in_t rec;
            tvlog_in_decode(&s_in[k * TVLOG_IN_BYTES], &rec);
            tvlog_replay_step(&s_app, &rec, done + k, &out, &s_out[k * TVLOG_OUT_BYTES]);
        }
        if (sh_write(fout, s_out, n * TVLOG_OUT_BYTES) != 0) {
            fail("write failed");
        }
        done += n;
    }
    (void)sh_close(fin);
    (void)sh_close(fout);
    sh_puts("qemu_replay: ");
    sh_put_u32(done);
    sh_puts(" steps; stack high-water ");
    sh_put_u32(startup_stack_high_water_bytes());
    sh_puts(" of ");
    sh_put_u32(startup_stack_size_bytes());
    sh_puts(" bytes\n");
    sh_exit(0);
}
