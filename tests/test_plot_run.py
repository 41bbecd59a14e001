#!/usr/bin/python3
"""tools/plot_run.py on both kinds of run file (issue 9: it refused replay's output): a host_sim
run log, a replay output with --wide and truth, and a narrow replay output; every figure is
written and is a real picture (a PNG of more than 20 kB: an empty 14 x 10 in axes is ~15 kB),
and a file that is neither is refused with exit 2 and a message naming the missing columns.

usage: test_plot_run.py BIN_DIR WORK_DIR
"""
import os
import shutil
import subprocess
import sys

BIN, WORK = sys.argv[1], sys.argv[2]
HERE = os.path.dirname(os.path.abspath(__file__))
PLOT = os.path.join(HERE, "..", "tools", "plot_run.py")
FAILED = []


def check(cond, what):
    if not cond:
        FAILED.append(what)
        print("FAIL:", what)


def run(args):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=300)
    return p.returncode, p.stdout.decode(), p.stderr.decode()


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    raw = os.path.join(WORK, "raw.csv")
    rc, _, err = run([os.path.join(BIN, "host_sim"), "--duration", "0.6", "--out", WORK, "--raw-log", raw])
    check(rc == 0, "host_sim ran: " + err[-400:])
    rc, _, err = run([os.path.join(BIN, "replay"), "--wide", raw, "-o", os.path.join(WORK, "wide.csv")])
    check(rc == 0, "replay --wide ran: " + err[-400:])
    rc, _, err = run([os.path.join(BIN, "replay"), raw, "-o", os.path.join(WORK, "narrow.csv")])
    check(rc == 0, "replay ran: " + err[-400:])
    for stem in ("paper_sine", "wide", "narrow"):
        rc, out, err = run(["/usr/bin/python3", PLOT, os.path.join(WORK, stem + ".csv"), "--out", WORK])
        check(rc == 0, "plot_run.py %s.csv: exit %d %s" % (stem, rc, err[-400:]))
        for fig in ("fig6_states", "fig7_zoom", "fig8_residuals", "errors"):
            png = os.path.join(WORK, "%s_%s.png" % (stem, fig))
            size = os.path.getsize(png) if os.path.exists(png) else 0
            check(size > 20000, "%s: %d bytes" % (png, size))
    bad = os.path.join(WORK, "bad.csv")
    with open(bad, "w") as f:
        f.write("a,b,c\n1,2,3\n")
    rc, _, err = run(["/usr/bin/python3", PLOT, bad, "--out", WORK])
    check(rc == 2 and "missing column(s) t_s or t_us" in err, "a foreign CSV is refused: %d %s" % (rc, err))
    print("%d failed" % len(FAILED))
    return 1 if FAILED else 0


if __name__ == "__main__":
    sys.exit(main())
