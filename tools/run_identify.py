#!/usr/bin/python3
"""The identification benchmark (issue 11): `identify` over EVALUATION units of the population.

For each unit (IDs from 1000, every third of class b, spread `all`; host_sim/plant/plant_draw.h):
  1. host_sim --scenario ident records a 30 s raw log of the identification excitation
     (APP_MODE_IDENT) from the unit (plant noise seed --ident-seed);
  2. identify turns it into a parameter file (its wall time is measured);
  3. each identified parameter is compared with the unit's own value (host_sim
     --print-plant-params: the truth, never anything identify computed);
  4. the estimator runs the scoring scenarios on the same unit with another noise seed three
     times: with the class's nominal model (what host_sim --unit does), with the identified
     parameter file, and with the unit's TRUE parameters (plant values; the contact law capped
     at the stiffest law the model keeps stable, 1e4 N m/rad secant at 2.5 mrad, as stop learning
     caps it, with the unit's own damping ratio lambda / k); the velocity RMSEs are compared.
Writes out/identify/summary.json (per-parameter error statistics, the fraction within the
issue's targets, the velocity-RMSE ratios identified / true) and prints the tables.
    usage: tools/run_identify.sh [--units N] [--first-unit ID] [--scenarios a,b] [--out DIR]
"""
import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "host-release", "bin")

# (name, model key, plant key, kind, target): kind "rel" = relative error, "abs" = absolute [rad]
PARAMS = [
    ("R", "model.R_ohm", "plant.R_ohm", "rel", 0.03),
    ("Kt", "model.Kt_Nm_A", "plant.Kt_Nm_A", "rel", 0.03),
    ("Ke", "model.Ke_V_s_rad", "plant.Ke_V_s_rad", "rel", None),
    ("L", "model.L_H", "plant.L_H", "rel", None),
    ("J", "model.J_kg_m2", "plant.J_kg_m2", "rel", 0.10),
    ("c", "model.c_Nm_rad", "plant.c_Nm_rad", "rel", 0.10),
    ("M0", "model.M0_Nm", "plant.M0_Nm", "rel", 0.10),
    ("Mc", "model.Mc_Nm", "plant.Mc_Nm", "rel", 0.15),
    ("Ms", "model.Ms_Nm", "plant.Ms_Nm", "rel", 0.15),
    ("ws", "model.ws_rad_s", "plant.ws_rad_s", "rel", None),
    ("Kv", "model.Kv_Nm_s_rad", "plant.Kv_Nm_s_rad", "rel", None),
    ("phi_closed", "model.phi_closed_rad", "plant.phi_closed_rad", "abs", 0.005),
    ("phi_open", "model.phi_open_rad", "plant.phi_open_rad", "abs", 0.005),
    ("stop_exponent", "model.stop_exponent", "plant.stop_exponent", "abs", None),
    ("stop_damping", "stop_damping_ratio", "stop_damping_ratio", "rel", None),  # lambda / k [s/rad]
]
K_SECANT_MAX = 1e4   # stop learning's k_max (sl_config_default), secant at 2.5 mrad
P_REF = 0.0025


def run(cmd, **kw):
    return subprocess.run(cmd, check=False, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def read_keys(text):
    """key = value lines (comments and commented-out keys ignored)."""
    out = {}
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        m = re.match(r"^([A-Za-z0-9_.]+)\s*=\s*(\S+)$", line)
        if m:
            out[m.group(1)] = float(m.group(2))
    return out


def true_params(plant):
    """The unit's own values as a model parameter file."""
    keys = {
        "model.R_ohm": plant["plant.R_ohm"], "model.L_H": plant["plant.L_H"],
        "model.Ke_V_s_rad": plant["plant.Ke_V_s_rad"], "model.Kt_Nm_A": plant["plant.Kt_Nm_A"],
        "model.J_kg_m2": plant["plant.J_kg_m2"], "model.n_gear": plant["plant.n_gear"],
        "model.Mc_Nm": plant["plant.Mc_Nm"], "model.Ms_Nm": plant["plant.Ms_Nm"],
        "model.ws_rad_s": plant["plant.ws_rad_s"], "model.Kv_Nm_s_rad": plant["plant.Kv_Nm_s_rad"],
        "model.M0_Nm": plant["plant.M0_Nm"], "model.c_Nm_rad": plant["plant.c_Nm_rad"],
        "model.phi_closed_rad": plant["plant.phi_closed_rad"], "model.phi_open_rad": plant["plant.phi_open_rad"],
    }
    e = plant["plant.stop_exponent"]
    k = min(plant["plant.stop_k_Nm_rad"], K_SECANT_MAX * P_REF ** (1.0 - e))
    keys["model.stop_exponent"] = e
    keys["model.k_stop_Nm_rad"] = k
    keys["model.d_stop_Nm_s_rad"] = plant["plant.stop_lambda_Nm_s_rad"] / plant["plant.stop_k_Nm_rad"] * k
    # the same estimator as identify's file configures: the law known, no online impact learning
    keys["impact_learn.enable"] = 0
    return "".join("%s = %.17g\n" % kv for kv in keys.items())


def velocity_rmse(unit, cls, scn, seed, params, tmp):
    cmd = [os.path.join(BIN, "host_sim"), "--scenario", scn, "--unit", str(unit), "--plant-class", cls,
           "--spread", "all", "--seed", str(seed), "--out", tmp]
    if params is not None:
        cmd += ["--params", params]
    r = run(cmd)
    if r.returncode != 0:
        raise RuntimeError("host_sim failed: %s\n%s" % (" ".join(cmd), r.stderr))
    with open(os.path.join(tmp, scn + "_metrics.json")) as f:
        return json.load(f)["rmse"]["app"]["velocity_rad_s"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--units", type=int, default=30, help="units (default 30; every third of class b)")
    ap.add_argument("--first-unit", type=int, default=1000, help="first unit ID (default 1000, the evaluation set)")
    ap.add_argument("--ident-seed", type=int, default=1, help="plant noise seed of the identification log")
    ap.add_argument("--seed", type=int, default=2, help="plant noise seed of the scoring runs")
    ap.add_argument("--scenarios", default="paper_sine,slow_sine,open_steps,chirp",
                    help="scoring scenarios (default paper_sine,slow_sine,open_steps,chirp)")
    ap.add_argument("--format", default="bin", choices=["csv", "bin"], help="raw-log format (default bin)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "identify"), help="output directory")
    a = ap.parse_args()
    scns = [s for s in a.scenarios.split(",") if s]
    os.makedirs(a.out, exist_ok=True)
    units = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in range(a.units):
            unit = a.first_unit + n
            cls = "b" if unit % 3 == 2 else "a"
            log = os.path.join(tmp, "ident_%d.%s" % (unit, a.format))
            pfile = os.path.join(a.out, "unit_%d.params" % unit)
            tfile = os.path.join(tmp, "true_%d.params" % unit)
            r = run([os.path.join(BIN, "host_sim"), "--scenario", "ident", "--unit", str(unit), "--plant-class", cls,
                     "--spread", "all", "--seed", str(a.ident_seed), "--out", tmp, "--raw-log", log, "--raw-format",
                     a.format])
            if r.returncode != 0:
                sys.exit("host_sim --scenario ident failed for unit %d:\n%s" % (unit, r.stderr))
            t0 = time.monotonic()
            r = run([os.path.join(BIN, "identify"), "--quiet", log, "-o", pfile])
            t_ident = time.monotonic() - t0
            if r.returncode != 0:
                sys.exit("identify failed for unit %d (exit %d):\n%s%s" % (unit, r.returncode, r.stdout, r.stderr))
            with open(pfile) as f:
                ident = read_keys(f.read())
            plant = read_keys(run([os.path.join(BIN, "host_sim"), "--unit", str(unit), "--plant-class", cls, "--spread",
                                   "all", "--print-plant-params"]).stdout)
            with open(tfile, "w") as f:
                f.write(true_params(plant))
            # the damping ratio lambda / k: the model's d_stop / k_stop, the plant's lambda / k
            if "model.d_stop_Nm_s_rad" in ident and ident.get("model.k_stop_Nm_rad", 0.0) > 0.0:
                ident["stop_damping_ratio"] = ident["model.d_stop_Nm_s_rad"] / ident["model.k_stop_Nm_rad"]
            plant["stop_damping_ratio"] = plant["plant.stop_lambda_Nm_s_rad"] / plant["plant.stop_k_Nm_rad"]
            errs = {}
            for name, mkey, pkey, kind, _ in PARAMS:
                if mkey not in ident:
                    errs[name] = None  # not identified
                elif kind == "rel":
                    errs[name] = ident[mkey] / plant[pkey] - 1.0
                else:
                    errs[name] = ident[mkey] - plant[pkey]
            rm = {}
            for scn in scns:
                rm[scn] = {
                    "nominal": velocity_rmse(unit, cls, scn, a.seed, None, tmp),
                    "identified": velocity_rmse(unit, cls, scn, a.seed, pfile, tmp),
                    "true": velocity_rmse(unit, cls, scn, a.seed, tfile, tmp),
                }
            units.append({"unit": unit, "class": cls, "identify_s": t_ident, "errors": errs, "velocity_rmse": rm})
            worst = max(v["identified"] / v["true"] for v in rm.values())
            print("unit %d (%s): identify %.2f s; R %+.2f %%, Kt %+.2f %%, J %+.1f %%, Mc %+.1f %%, Ms %s; "
                  "worst velocity ratio identified/true %.2f" %
                  (unit, cls, t_ident, 100 * errs["R"], 100 * errs["Kt"], 100 * errs["J"], 100 * errs["Mc"],
                   "n/a" if errs["Ms"] is None else "%+.1f %%" % (100 * errs["Ms"]), worst), flush=True)

    summary = {"units": len(units), "first_unit": a.first_unit, "spread": "all", "ident_seed": a.ident_seed,
               "scoring_seed": a.seed, "scenarios": scns, "parameters": {}, "velocity_rmse": {}, "runs": units}
    print("\n%-14s %8s %12s %12s %10s %s" % ("parameter", "target", "max |err|", "median|err|", "in target", "identified"))
    for name, _, _, kind, target in PARAMS:
        vals = [u["errors"][name] for u in units]
        got = [abs(v) for v in vals if v is not None]
        within = sum(1 for v in vals if v is not None and target is not None and abs(v) <= target)
        scale, unit_txt = (100.0, "%") if kind == "rel" else (1000.0, "mrad")
        entry = {"kind": "relative" if kind == "rel" else "absolute_rad", "target": target,
                 "identified": len(got), "max_abs_error": max(got) if got else None,
                 "median_abs_error": statistics.median(got) if got else None,
                 "fraction_within_target": (within / len(units)) if target is not None else None}
        summary["parameters"][name] = entry
        print("%-14s %8s %12s %12s %10s %d/%d" % (
            name, "-" if target is None else ("%g %s" % (target * scale, unit_txt)),
            "-" if not got else "%.3g %s" % (max(got) * scale, unit_txt),
            "-" if not got else "%.3g %s" % (statistics.median(got) * scale, unit_txt),
            "-" if target is None else "%d/%d" % (within, len(units)), len(got), len(units)))
    print("\nvelocity RMSE of the estimator [rad/s], median over units (ratio identified / true: max, median, "
          "runs <= 1.2)")
    print("%-12s %10s %10s %10s %10s %10s %8s" % ("scenario", "nominal", "identified", "true", "max ratio",
                                                  "med ratio", "<= 1.2"))
    all_ratios = []
    for scn in scns:
        ratios = [u["velocity_rmse"][scn]["identified"] / u["velocity_rmse"][scn]["true"] for u in units]
        all_ratios += ratios
        med = {k: statistics.median(u["velocity_rmse"][scn][k] for u in units) for k in ("nominal", "identified", "true")}
        summary["velocity_rmse"][scn] = {"median_nominal": med["nominal"], "median_identified": med["identified"],
                                         "median_true": med["true"], "max_ratio_identified_true": max(ratios),
                                         "median_ratio_identified_true": statistics.median(ratios),
                                         "fraction_ratio_within_1_2": sum(1 for x in ratios if x <= 1.2) / len(ratios)}
        print("%-12s %10.4f %10.4f %10.4f %10.2f %10.2f %5d/%d" % (scn, med["nominal"], med["identified"], med["true"],
                                                                    max(ratios), statistics.median(ratios),
                                                                    sum(1 for x in ratios if x <= 1.2), len(ratios)))
    summary["velocity_rmse"]["all"] = {"max_ratio_identified_true": max(all_ratios),
                                       "median_ratio_identified_true": statistics.median(all_ratios),
                                       "fraction_ratio_within_1_2": sum(1 for x in all_ratios if x <= 1.2) / len(all_ratios)}
    times = [u["identify_s"] for u in units]
    summary["identify_seconds"] = {"max": max(times), "mean": sum(times) / len(times)}
    print("\nall runs: ratio identified / true max %.2f, median %.2f, %d/%d within 1.2; identify wall time max %.2f s, "
          "mean %.2f s (30 s logs)" % (max(all_ratios), statistics.median(all_ratios),
                                       sum(1 for x in all_ratios if x <= 1.2), len(all_ratios), max(times),
                                       sum(times) / len(times)))
    path = os.path.join(a.out, "summary.json")
    with open(path, "w") as f:
        json.dump(summary, f, indent=1)
    print("summary: %s; parameter files: %s/unit_*.params" % (path, a.out))


if __name__ == "__main__":
    main()
