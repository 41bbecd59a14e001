#!/usr/bin/python3
"""Count guest instructions between benchmark markers in a QEMU "-d in_asm,exec,nochain" log.

    qemu-system-arm ... -d in_asm,exec,nochain -D /dev/fd/3 3>&1 1>&2 | count_insns.py [--budget N]

QEMU prints each translation block's instructions once when it translates it (in_asm: "IN:",
then one line per guest instruction) and one "Trace" line each time a block runs (exec; with
nochain every block passes through the main loop, so none is missed). The number of guest
instructions executed is the sum, over Trace lines, of the length of the block that ran. This
is deterministic: it does not depend on the host, its load or QEMU's speed.

Markers (tests/m4f/qemu_bench.c): a block in bench_app_<category>, bench_pred or bench_corr
opens a measurement, a block in bench_end closes it. Instructions in the markers themselves and
in the driver (--exclude, default main,run,bench_contact) are not counted: what remains is the measured
function and everything it calls (library included).

--profile N also prints the N functions that execute the most instructions per application step
(self counts: a block is charged to the function it lies in; the steps after lost samples are
left out, as from the application step's mean), to show where the budget goes.
"""
import argparse
import re
import sys

TRACE = re.compile(r"^Trace \d+: \S+ \[[0-9a-f]+/([0-9a-f]+)/[0-9a-f]+/[0-9a-f]+\] ?(\S*)")
INSN = re.compile(r"^0x([0-9a-f]+):\s")


def fmt(n):
    return "{:,}".format(int(round(n)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--budget", type=int, default=16800, help="cycles per step (default 16800)")
    ap.add_argument("--exclude", default="main,run,bench_contact", help="driver functions not counted")
    ap.add_argument("--profile", type=int, default=0, metavar="N",
                    help="also print the N functions with the most instructions per application step")
    a = ap.parse_args()
    exclude = set(a.exclude.split(","))

    tb_len = {}
    in_block = False
    block_pc = None
    block_n = 0
    cur_cat = None
    cur_n = 0
    results = {}  # category -> list of counts
    ekf_pairs = []
    pending_pred = None
    blocks_total = 0
    prof = {}  # function -> instructions over the application steps (not after gaps)
    prof_cur = {}  # ... of the step being measured
    prof_steps = 0
    app_cats = ["sine", "steps", "chirp", "position", "off", "safe"]  # the application step's modes
    for line in sys.stdin:
        if in_block:
            m = INSN.match(line)
            if m:
                if block_pc is None:
                    block_pc = int(m.group(1), 16)
                block_n += 1
                continue
            if block_pc is not None:
                tb_len[block_pc] = block_n
            in_block = False
        if line.startswith("IN:"):
            in_block, block_pc, block_n = True, None, 0
            continue
        m = TRACE.match(line)
        if not m:
            continue
        blocks_total += 1
        pc = int(m.group(1), 16)
        sym = m.group(2)
        if sym.startswith("bench_"):
            if sym == "bench_end":
                if cur_cat is not None:
                    results.setdefault(cur_cat, []).append(cur_n)
                    if cur_cat in app_cats:
                        prof_steps += 1
                        for f, c in prof_cur.items():
                            prof[f] = prof.get(f, 0) + c
                    prof_cur = {}
                    if cur_cat == "pred":
                        pending_pred = cur_n
                    elif cur_cat == "corr" and pending_pred is not None:
                        ekf_pairs.append(pending_pred + cur_n)
                        pending_pred = None
                cur_cat = None
            else:
                cur_cat = sym[len("bench_app_"):] if sym.startswith("bench_app_") else sym[len("bench_"):]
                cur_n = 0
                prof_cur = {}
            continue
        if cur_cat is not None and sym not in exclude:
            n = tb_len.get(pc)
            if n is None:
                sys.exit("count_insns: block at 0x%x ran before its disassembly was seen" % pc)
            cur_n += n
            key = sym or "0x%x" % pc
            prof_cur[key] = prof_cur.get(key, 0) + n

    if not results:
        sys.exit("count_insns: no markers found in the log (%d blocks)" % blocks_total)

    budget = a.budget
    print("Cortex-M4F CPU budget: instructions counted in QEMU mps2-an386 (Cortex-M4 + FPU), same -O3 code as the ECU")
    print("  budget: %s cycles per 1 ms step = 10 %% of a 168 MHz core at 1 kHz" % fmt(budget))
    print("  %-44s %6s %9s %9s %9s %11s" % ("instructions per call", "calls", "mean", "min", "max", "max/budget"))
    app_all = []
    order = app_cats + ["gap"]
    for cat in order + sorted(set(results) - set(order) - {"pred", "corr", "pred_hc", "fit"}):
        v = results.get(cat)
        if not v:
            continue
        app_all.extend(v if cat != "gap" else [])
        label = "app_step, mode %s" % cat
        if cat == "safe":
            label = "app_step, faults latched (safe state)"
        if cat == "gap":
            label = "app_step after lost samples (n+1 predicts)"
        print("  %-44s %6d %9s %9s %9s %9.1f %%" % (label, len(v), fmt(sum(v) / len(v)), fmt(min(v)), fmt(max(v)),
                                                   100.0 * max(v) / budget))
    if app_all:
        print("  %-44s %6d %9s %9s %9s %9.1f %%" % ("APPLICATION STEP (all except after gaps)", len(app_all),
                                                   fmt(sum(app_all) / len(app_all)), fmt(min(app_all)),
                                                   fmt(max(app_all)), 100.0 * max(app_all) / budget))
    for cat, label in (("pred", "ekf_predict (map + Jacobian, 10 sub-steps)"), ("corr", "ekf_correct (current + angle)"),
                       ("pred_hc", "ekf_predict in contact, Hunt-Crossley law"),
                       ("fit", "stop learning's contact-law fit, per period")):
        v = results.get(cat)
        if v:
            print("  %-44s %6d %9s %9s %9s %9.1f %%" % (label, len(v), fmt(sum(v) / len(v)), fmt(min(v)), fmt(max(v)),
                                                       100.0 * max(v) / budget))
    if ekf_pairs:
        v = ekf_pairs
        print("  %-44s %6d %9s %9s %9s %9.1f %%" % ("EKF STEP (predict + correct)", len(v), fmt(sum(v) / len(v)),
                                                   fmt(min(v)), fmt(max(v)), 100.0 * max(v) / budget))
    if a.profile > 0 and prof_steps:
        total = sum(prof.values())
        print("  where the application step's mean goes (self instructions per step, the %d largest of %d functions):"
              % (min(a.profile, len(prof)), len(prof)))
        for f, c in sorted(prof.items(), key=lambda kv: -kv[1])[:a.profile]:
            print("    %-42s %9s %6.1f %%" % (f, fmt(c / prof_steps), 100.0 * c / total))
    print("  Instructions are a proxy for cycles until measured with the DWT on a board (the ECU keeps")
    print("  worst/mean cycles of every step and sends them in TV_LOOP and TV_ECU_CPU): on a Cortex-M4F")
    print("  most instructions take 1 cycle, but loads 2, taken branches 2-4, VDIV/VSQRT 14, and flash")
    print("  wait states (5 at 168 MHz, mostly hidden by the ART accelerator) add more.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
