#!/usr/bin/python3
"""Summarise a fault matrix (tools/run_fault_matrix.sh): one population runs CSV per injected
fault, plus the healthy one, into a table per fault kind: runs, runs whose EXPECTED code was
confirmed (detected), runs with only other codes (mis-isolated), runs with none (missed), the
latency of the first confirmation after the onset (median and largest over the detected runs),
and the codes seen. Expected codes are those of the README's DTC table; a kind without a
detector expects none (its row counts what the other detectors did with it).

usage: fault_matrix.py DIR ONSET_S   (DIR holds healthy.csv and <spec>.csv files; writes DIR/matrix.md)
"""
import csv
import math
import os
import sys

CODES = ["P0121", "P0221", "P2135", "P2111", "P2112", "P2100", "P2101", "P1A01", "P2119", "P1A02"]  # bit order of diag_dtc_t
EXPECTED = {
    "tps1_": {"P0121"}, "tps2_": {"P0221"}, "jam": {"P2111", "P2112"}, "winding_open": {"P2100"},
    "winding_resistance_high": {"P2101"}, "winding_short": {"P1A01"}, "friction_high": {"P2119"},
    "spring_weak": {"P1A02"},
}


def expected_codes(kind):
    for prefix, codes in EXPECTED.items():
        if kind.startswith(prefix):
            return codes
    return set()


def codes_of(mask):
    return {c for b, c in enumerate(CODES) if (mask >> b) & 1}


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    d, onset = sys.argv[1], float(sys.argv[2])
    rows = []
    for name in sorted(os.listdir(d)):
        if not name.endswith(".csv"):
            continue
        spec = name[:-4]
        kind = "healthy" if spec == "healthy" else spec.split(":")[0].split("@")[0]
        exp = expected_codes(kind)
        n = det = mis = missed = 0
        lat = []
        seen = {}
        with open(os.path.join(d, name)) as f:
            for r in csv.DictReader(f):
                n += 1
                got = codes_of(int(r["dtc_confirmed"]))
                for c in got:
                    seen[c] = seen.get(c, 0) + 1
                if exp and got & exp:
                    det += 1
                    t = float(r["dtc_first_s"])
                    if math.isfinite(t):
                        lat.append(t - onset)
                elif got:
                    mis += 1
                else:
                    missed += 1
        lat.sort()
        med = "%.0f" % (1e3 * lat[len(lat) // 2]) if lat else "-"
        worst = "%.0f" % (1e3 * lat[-1]) if lat else "-"
        rows.append((spec, n, ",".join(sorted(exp)) or "none", det, mis, missed, med, worst,
                     " ".join("%s:%d" % (c, seen[c]) for c in CODES if c in seen) or "-"))
    out = ["| fault | runs | expected | detected | other codes only | nothing | latency median [ms] | latency max [ms] | codes confirmed (runs) |",
           "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append("| %s | %d | %s | %d | %d | %d | %s | %s | %s |" % r)
    text = "\n".join(out) + "\n"
    with open(os.path.join(d, "matrix.md"), "w") as f:
        f.write(text)
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
