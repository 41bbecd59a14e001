#!/usr/bin/python3
"""tools/tune_noise.py --population on three training units with two settings that differ only
in the consistency-driven inflation (ekf.nis_inflate_threshold 0 = off, 1.2 = the default): the
tool runs both, writes both rows with the threshold each used, the settings reach the filter
(the rows' NEES figures differ, and the inflated one is not the more overconfident), and the
chosen row is one of them with the rule's reason. usage: test_tune_noise.py POPULATION HOST_SIM"""
import json
import os
import subprocess
import sys
import tempfile

import tv_check
from tv_check import check

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "tools", "tune_noise.py")


def main():
    pop, host_sim = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "population.json")
        subprocess.run([sys.executable, SCRIPT, "--population", "--population-exe", pop, "--host-sim", host_sim,
                        "--plants", "3", "--grid-qu", "5e-6", "--grid-qT", "5e-6", "--grid-qc", "1e-5", "--grid-qrel", "0",
                        "--grid-inflate", "0,1.2", "--json", out], check=True, stdout=subprocess.DEVNULL)
        j = json.load(open(out))
    rows = j["rows"]
    check(len(rows) == 2, "two settings run (%d)" % len(rows))
    if len(rows) != 2:
        return 1
    off, on = sorted(rows, key=lambda r: r["nis_inflate_threshold"])
    check(off["nis_inflate_threshold"] == 0.0 and on["nis_inflate_threshold"] == 1.2, "each row names its threshold")
    check(off["nees_run_avg_max"] != on["nees_run_avg_max"] or off["nees_window_max"] != on["nees_window_max"],
          "the inflation reached the filter (NEES %.3g / %.3g vs %.3g / %.3g)"
          % (off["nees_run_avg_max"], off["nees_window_max"], on["nees_run_avg_max"], on["nees_window_max"]))
    check(on["nees_run_avg_max"] <= off["nees_run_avg_max"], "inflated, the largest run-average NEES is not higher")
    check(j["chosen"] in rows and j["why"], "a row is chosen, with the rule's reason")
    return 1 if tv_check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
