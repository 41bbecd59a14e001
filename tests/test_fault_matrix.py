#!/usr/bin/python3
"""tools/fault_matrix.py on hand-written runs CSVs whose figures are worked out by hand below:
detection, delay percentiles, isolation (first code after the onset), codes before the onset,
the confusion matrix, the healthy totals with a soak summary and the delay from the observable
condition (t_condition_s). Then one real population run with an injected track offset, through the
same script: the CSV columns it relies on exist and the offset is detected with its class; and a
jam and an open winding in population's own runs meet their condition after the onset, their codes
within 100 ms and 10 ms of it. Then the identified section (each unit's filter on the
parameters identify finds in its healthy end-of-line log, diag.identified = 1): friction +25 %,
which the class's filter cannot tell from the +-30 % unit spread, confirmed as P2119 within the
issue's 5 s on two all_varied units of both classes, and the same runs healthy confirm nothing;
their summary's counts of runs missing issue 10's per-run targets match a recount from the runs CSV.
Last, population --params-out: the host_sim command a class-b unit's file names reproduces its run
(the adapted section's with its warm-up)."""
import csv
import json
import os
import subprocess
import sys
import tempfile

import tv_check
from tv_check import check

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "tools", "fault_matrix.py")
HEAD = ["section", "unit", "class", "scenario", "seed", "duration_s", "injected", "dtc_codes"]


def write(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(HEAD)
        for r in rows:
            w.writerow(r)


def synthetic(d):
    os.makedirs(os.path.join(d, "runs"))
    inj = "jam:jam:2.0000"
    write(os.path.join(d, "runs", "jam:3.csv"), [
        # detected after 0.060 s, first code jam: isolated
        ["all_varied", 1, "a", "drive", 1, 8, inj, "P2112:jam:2.0600"],
        # detected after 0.100 s but a friction code came first (2.05): detected, not isolated
        ["all_varied", 2, "a", "drive", 1, 8, inj, "P2119:friction_high:2.0500 P2111:jam:2.1000"],
        # nothing
        ["all_varied", 3, "a", "closed_steps", 1, 8, inj, ""],
        # a code before the onset (early) and the jam after 0.500 s
        ["all_varied", 4, "a", "closed_steps", 1, 8, inj, "P1A02:spring_weak:1.0000 P2112:jam:2.5000"],
        # another section: detected and isolated after 0.040 s
        ["all_varied_identified", 1, "a", "drive", 1, 8, inj, "P2111:jam:2.0400"],
    ])
    write(os.path.join(d, "runs", "healthy.csv"), [
        ["all_varied", 1, "a", "drive", 1, 8, "healthy", ""],
        ["all_varied", 2, "a", "drive", 1, 8, "healthy", "P2119:friction_high:3.0000"],
    ])
    soak = os.path.join(d, "soak.json")
    with open(soak, "w") as f:
        json.dump({"runs": 10, "healthy_seconds": 700.0, "false_alarms_healthy": 0}, f)
    # the healthy runs' population summary with the units' fit baselines (population --fit-baseline on)
    with open(os.path.join(d, "runs", "healthy.json"), "w") as f:
        json.dump({"runs": 2, "all_varied_fit_baseline": {"units": 2, "failed": 1, "r_rel_min": 0.9991,
                                                          "r_rel_max": 1.0012, "nke_rel_min": 0.9950,
                                                          "nke_rel_max": 0.9978},
                   "stops_varied_friction_baseline": {"units": 2, "at_class_bound": 0, "bound_min": 1.132,
                                                      "bound_max": 1.167, "fast_bound_min": 1.16,
                                                      "fast_bound_max": 1.328}}, f)
    subprocess.run([sys.executable, SCRIPT, d, soak], check=True, stdout=subprocess.DEVNULL)
    s = json.load(open(os.path.join(d, "summary.json")))
    check(s["fit_baseline"] == {"all_varied": {"units": 2, "failed": 1, "r_rel_min": 0.9991, "r_rel_max": 1.0012,
                                               "nke_rel_min": 0.9950, "nke_rel_max": 0.9978}},
          "the units' fit baselines, from the healthy runs' population summary")
    check("Fit baseline, all_varied: 2 units, 1 without one; R at 20 degC 0.9991 - 1.0012 of the plant's, n Ke "
          "0.9950 - 0.9978." in open(os.path.join(d, "matrix.md")).read(), "matrix.md names the fit baselines")
    check(s["friction_baseline"] == {"stops_varied": {"units": 2, "at_class_bound": 0, "bound_min": 1.132,
                                                      "bound_max": 1.167, "fast_bound_min": 1.16,
                                                      "fast_bound_max": 1.328}},
          "the units' friction bounds, from the healthy runs' population summary")
    check("Friction bound, stops_varied: 2 units, 0 at the class's; the adapted level's 1.132 - 1.167, the "
          "signature's 1.160 - 1.328." in open(os.path.join(d, "matrix.md")).read(), "matrix.md names the friction bounds")
    j = s["classes"]["jam"]
    check(j["runs"] == 5, "5 jam runs")
    check(abs(j["detection_rate"] - 0.8) < 1e-12, "jam detected in 4 of 5 runs")
    # delays 0.04, 0.06, 0.10, 0.50: nearest-rank median = 0.06, p95 = 0.50
    check(abs(j["delay_median_s"] - 0.06) < 1e-9, "median delay 0.060 s")
    check(abs(j["delay_p95_s"] - 0.50) < 1e-9, "p95 delay 0.500 s")
    # isolated: runs 1 and 4 of all_varied (4's first code AFTER the onset is the jam), and the other section's
    check(abs(j["isolation_rate"] - 0.6) < 1e-12, "isolation 3 of 5")
    check(abs(j["isolation_rate_of_alarms"] - 3.0 / 4.0) < 1e-12, "isolation 3 of the 4 runs with a code")
    check(j["runs_with_a_code_before_onset"] == 1, "one run with a code before the onset")
    check(s["confusion_matrix"]["jam"] == {"jam": 3, "friction_high": 1, "none": 1}, "confusion row of jam")
    # per section: all_varied 3 of 4 detected, 2 of 4 isolated; the identified section 1 of 1
    sa, si = s["per_section"]["jam/all_varied"], s["per_section"]["jam/all_varied_identified"]
    check(sa["runs"] == 4 and abs(sa["detection_rate"] - 0.75) < 1e-12 and abs(sa["isolation_rate"] - 0.5) < 1e-12,
          "per section: all_varied 3 / 2 of 4")
    check(si["runs"] == 1 and si["detection_rate"] == 1.0 and si["isolation_rate"] == 1.0, "per section: identified 1 of 1")
    check(s["per_section"]["all/all_varied"]["runs"] == 4, "per section over all classes")
    check(s["matrix_healthy_runs"] == 2 and s["matrix_healthy_false_alarms"] == 1, "1 false alarm in 2 healthy runs")
    check(s["false_alarms_healthy"] == 1 and abs(s["healthy_seconds"] - 716.0) < 1e-9, "healthy totals with the soak")
    check(s["per_scenario"]["jam/drive"]["detection_rate"] == 1.0, "per scenario: drive 3 of 3")
    check(s["per_scenario"]["jam/closed_steps"]["detection_rate"] == 0.5, "per scenario: closed_steps 1 of 2")
    check("param_rel_err_median" not in j, "no parameter error for a jam")
    # every jam run lasts 8 s from an onset at 2.0 s: 6 s observed
    check(j["observed_after_onset_s"] == [6.0, 6.0], "observed after the onset: 6 s")
    # resistance errors at the end: |5.1/5 - 1| = 2 %, |4.85/5 - 1| = 3 %, |6.6/6 - 1| = 10 %
    head = HEAD[:-2] + ["r_est_ohm", "r_true_ohm"] + HEAD[-2:]
    with open(os.path.join(d, "runs", "winding_resistance_high:1.25.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(head)
        inj = "winding_resistance_high:winding_resistance_high:2.0000"
        for est, true in ((5.1, 5.0), (4.85, 5.0), (6.6, 6.0)):
            w.writerow(["all_varied", 1, "a", "drive", 1, 8, est, true, inj, ""])
    subprocess.run([sys.executable, SCRIPT, d, soak], check=True, stdout=subprocess.DEVNULL)
    r = json.load(open(os.path.join(d, "summary.json")))["classes"]["winding_resistance_high"]
    check(abs(r["param_rel_err_median"] - 0.03) < 1e-9, "resistance error median 3 %")
    check(abs(r["param_rel_err_p95"] - 0.10) < 1e-9, "resistance error p95 10 %")
    check(r["param_within_target"] == 2, "two of three resistance estimates within 3 %")
    # the voltage equation's fit where it took a window, else R + dR: fit 4.0 / plant 4.0 (R + dR
    # 3.0 not used) -> 0; fit nan, R + dR 4.4 / 4.0 -> 10 %; fit 3.8 / 4.0 -> 5 %
    head = HEAD[:-2] + ["r_est_ohm", "r_fit_ohm", "r_true_ohm"] + HEAD[-2:]
    with open(os.path.join(d, "runs", "winding_short:0.2.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(head)
        inj = "winding_short:winding_short:2.0000"
        for est, fit, true in ((3.0, 4.0, 4.0), (4.4, "nan", 4.0), (4.0, 3.8, 4.0)):
            w.writerow(["all_varied", 1, "a", "drive", 1, 8, est, fit, true, inj, ""])
    subprocess.run([sys.executable, SCRIPT, d, soak], check=True, stdout=subprocess.DEVNULL)
    ws = json.load(open(os.path.join(d, "summary.json")))["classes"]["winding_short"]
    check(abs(ws["param_rel_err_median"] - 0.05) < 1e-9 and abs(ws["param_rel_err_p95"] - 0.10) < 1e-9,
          "the fit's R where taken, R + dR where not: errors 0, 10, 5 %")
    check(ws["param_within_target"] == 1, "one of three within 3 %")
    os.remove(os.path.join(d, "runs", "winding_short:0.2.csv"))  # the totals below count without it
    check(r["detection_rate"] == 0.0 and r["runs"] == 3, "no code: not detected")
    md = open(os.path.join(d, "matrix.md")).read()
    check("| winding_resistance_high:1.25 | winding_resistance_high | 3 | 6 | 0 % |" in md,
          "matrix.md gives the time observed after the onset per fault")
    # the delay from the observable condition (column t_condition_s), open winding (target 10 ms):
    # tc 2.100 / code 2.105 -> 5 ms; 2.000 / 2.030 -> 30 ms; never met (nan) with a code: not
    # counted; met, no code; tc 2.200 with the code at 2.190, before it -> 0. Condition met in 4,
    # detected in 3, delays 0, 5, 30 ms: nearest-rank median 5 ms, p95 30 ms, 2 within 10 ms
    head = HEAD[:-2] + ["t_condition_s"] + HEAD[-2:]
    with open(os.path.join(d, "runs", "winding_open.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(head)
        inj = "winding_open:winding_open:2.0000"
        for tc, codes in (("2.1000", "P2100:winding_open:2.1050"), ("2.0000", "P2100:winding_open:2.0300"),
                          ("nan", "P2100:winding_open:2.5000"), ("2.2000", ""), ("2.2000", "P2100:winding_open:2.1900")):
            w.writerow(["all_varied", 1, "a", "drive", 1, 8, tc, inj, codes])
    subprocess.run([sys.executable, SCRIPT, d, soak], check=True, stdout=subprocess.DEVNULL)
    o = json.load(open(os.path.join(d, "summary.json")))["classes"]["winding_open"]
    check(o["condition_runs"] == 4 and o["condition_detected"] == 3, "condition met in 4 runs, detected in 3")
    check(abs(o["delay_from_condition_median_s"] - 0.005) < 1e-9, "delay from the condition: median 5 ms")
    check(abs(o["delay_from_condition_p95_s"] - 0.030) < 1e-9, "delay from the condition: p95 30 ms")
    check(o["within_target_of_condition"] == 2 and o["condition_target_s"] == 0.01, "2 within the 10 ms target")
    check("| winding_open | 5 | 4 | 3 | 5 | 30 | 2 (<= 10 ms) |" in open(os.path.join(d, "matrix.md")).read(),
          "matrix.md's condition table")
    check("condition_runs" not in r, "no condition for a resistance fault")
    # isolated where the condition was met: of the 5 open-winding runs 4 are isolated; the one that
    # never met its condition (nan, isolated all the same) is left out: 3 of 4
    check(o["runs_condition_never_met"] == 1 and abs(o["isolation_rate"] - 0.8) < 1e-12 and
          abs(o["isolation_rate_condition_met"] - 0.75) < 1e-12, "open winding: isolated 4 of 5, 3 of the 4 that met it")
    # supply sag (a condition, no delay target): never met and silent (a 2 V sag from 14 V); met
    # and P0562; met and nothing: isolated 1 of 3, 1 of the 2 that met it
    with open(os.path.join(d, "runs", "supply_sag:2.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(head)
        inj = "supply_sag:supply_sag:2.0000"
        for tc, codes in (("nan", ""), ("2.0000", "P0562:supply_sag:2.4990"), ("2.0000", "")):
            w.writerow(["all_varied", 1, "a", "drive", 1, 8, tc, inj, codes])
    subprocess.run([sys.executable, SCRIPT, d, soak], check=True, stdout=subprocess.DEVNULL)
    s = json.load(open(os.path.join(d, "summary.json")))
    g = s["classes"]["supply_sag"]
    check(g["runs_condition_never_met"] == 1 and abs(g["isolation_rate"] - 1.0 / 3.0) < 1e-12 and
          abs(g["isolation_rate_condition_met"] - 0.5) < 1e-12, "supply sag: isolated 1 of 3, 1 of the 2 that met it")
    check(g["condition_runs"] == 2 and "within_target_of_condition" not in g, "supply sag: met in 2, no delay target")
    # jam (5 runs, no t_condition_s column: never met, 3 isolated), winding_resistance_high (3, none
    # isolated), winding_open (5, 4), supply_sag (3, 1): 8 of 16; leaving out the 5 + 1 + 1 runs
    # that never met a condition (3 + 1 + 0 of them isolated): 4 of 9
    a = s["overall"]
    check(a["runs"] == 16 and abs(a["isolation_rate"] - 0.5) < 1e-12, "overall: isolated 8 of 16")
    check(a["runs_condition_never_met"] == 7 and abs(a["isolation_rate_condition_met"] - 4.0 / 9.0) < 1e-12,
          "overall: 4 of the 9 runs that met a condition or have none")


def real(d, pop):
    os.makedirs(os.path.join(d, "runs"))
    subprocess.run([pop, "--plants", "1", "--seeds", "1", "--sections", "stops", "--scenarios", "drive", "--duration", "3",
                    "--fault", "tps2_offset:-1@1.5", "--runs-csv", os.path.join(d, "runs", "tps2_offset:-1.csv"),
                    "--json", os.path.join(d, "population.json")],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    # the population summary's nominal unit: seed 1 (the figure) and the spread over 20 seeds
    p = json.load(open(os.path.join(d, "population.json")))
    n = p["nominal_paper_sine_over_seeds"]
    check(n["seeds"] == 20, "the nominal unit is run over 20 seeds")
    check(n["min_rad_s"] <= p["nominal_paper_sine_velocity_rmse_rad_s"] <= n["max_rad_s"],
          "seed 1's figure lies within the seeds' range (%s in %s .. %s)" % (p["nominal_paper_sine_velocity_rmse_rad_s"], n["min_rad_s"], n["max_rad_s"]))
    check(n["min_rad_s"] < n["mean_rad_s"] < n["max_rad_s"], "the mean lies strictly inside the range")
    subprocess.run([sys.executable, SCRIPT, d], check=True, stdout=subprocess.DEVNULL)
    s = json.load(open(os.path.join(d, "summary.json")))
    t = s["classes"].get("tps2_fault")
    check(t is not None and t["runs"] == 1, "population's injected column names the class")
    check(t is not None and t["detection_rate"] == 1.0 and t["isolation_rate"] == 1.0, "tps2 offset detected and isolated")
    check(t is not None and 0.0 < t["delay_median_s"] < 0.05, "its delay is below 50 ms (%s)" % (t and t["delay_median_s"]))
    # the observable condition in population's own runs (host_sim/sim/sim_fault_cond.h): none for a
    # track offset; a 10 N m jam in closed-loop driving stalls the plate after the onset and its code
    # confirms within 100 ms of the stall; an open winding meets its condition once the bridge
    # drives, and P2100 confirms within 10 ms of it
    row = list(csv.DictReader(open(os.path.join(d, "runs", "tps2_offset:-1.csv"))))[0]
    check(row["t_condition_s"] == "nan", "no condition for a track offset (%s)" % row["t_condition_s"])
    # a spring broken at 2.0 s in limp_home, whose bridge is off from 1.8 s to 2.4 s: the condition
    # (the bridge drives) is met when the drive resumes, at 2.4 s
    path = os.path.join(d, "c_spring.csv")
    subprocess.run([pop, "--plants", "1", "--seeds", "1", "--sections", "stops", "--scenarios", "limp_home", "--duration", "3",
                    "--fault", "spring_weak:0@2.0", "--runs-csv", path, "--json", os.path.join(d, "c.json")],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    tc = float(list(csv.DictReader(open(path)))[0]["t_condition_s"])
    check(abs(tc - 2.4) < 1.5e-3, "spring broken with the bridge off: condition when the drive resumes (%s s)" % tc)
    for fault, code, target in (("jam:10", ("P2111", "P2112"), 0.1), ("winding_open", ("P2100",), 0.01)):
        path = os.path.join(d, "c_%s.csv" % fault.split(":")[0])
        subprocess.run([pop, "--plants", "1", "--seeds", "1", "--sections", "stops", "--scenarios", "drive", "--duration", "3",
                        "--fault", fault + "@1.5", "--runs-csv", path, "--json", os.path.join(d, "c.json")],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        row = list(csv.DictReader(open(path)))[0]
        tc = float(row["t_condition_s"])
        t_code = min([float(c.split(":")[2]) for c in row["dtc_codes"].split() if c.split(":")[0] in code] or [float("inf")])
        check(1.5 <= tc < 3.0, "%s: condition met after the onset (%s s)" % (fault, tc))
        check(tc <= t_code <= tc + target + 1e-9, "%s: its code within %g s of the condition (%s, codes %s)" % (
            fault, target, tc, row["dtc_codes"]))


def target_counts(summary, rows):
    """The summary's counts of runs that miss the issues' per-run targets, recounted from the
    runs CSV's own figures (ratio, NEES run average, largest 100 ms NEES)."""
    def num(r, k):
        return float(r[k])  # 'nan' and 'inf' parse; a NaN misses every target
    ratio = [num(r, "ratio") for r in rows]
    nees = [num(r, "nees_avg") for r in rows]
    win = [num(r, "nees_window_max") for r in rows]
    want = {
        "runs_ratio_below_2_5": sum(not (x >= 2.5) for x in ratio),
        "runs_nees_below_1_5": sum(x < 1.5 for x in nees),
        "runs_nees_above_6": sum(not (x <= 6.0) for x in nees),
        "runs_nees_window_above_30": sum(not (x <= 30.0) for x in win),
        "runs_breaking_consistency": sum(n < 1.5 or not (n <= 6.0) or not (w <= 30.0) for n, w in zip(nees, win)),
    }
    check(summary["runs"] == len(rows), "the summary counts the CSV's runs (%s, %d)" % (summary["runs"], len(rows)))
    for k, v in want.items():
        check(summary.get(k) == v, "summary %s = %s, recounted from the runs CSV %d" % (k, summary.get(k), v))
    # the comparison has power only if some count is not 0 (here: an identified unit's drive run
    # below NEES 1.5); should the runs change so that none is, this fails rather than pass idly
    check(sum(want.values()) > 0, "the runs miss at least one target, so the counts are exercised (%s)" % want)


def identified(d, pop):
    os.makedirs(d)
    common = [pop, "--plants", "3", "--first-unit", "1000", "--seeds", "1", "--sections", "identified",
              "--scenarios", "drive,paper_sine", "--duration", "8"]
    runs = {}
    for name, fault in (("healthy", []), ("friction", ["--fault", "friction_high:1.25@2"])):
        csv_path = os.path.join(d, name + ".csv")
        subprocess.run(common + fault + ["--runs-csv", csv_path, "--json", os.path.join(d, name + ".json")],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        runs[name] = list(csv.DictReader(open(csv_path)))
    check(len(runs["healthy"]) == 6 and all(r["section"] == "all_varied_identified" for r in runs["healthy"]),
          "identified section: 3 units x 2 scenarios")
    check(sorted({r["class"] for r in runs["healthy"]}) == ["a", "b"], "both classes")
    check(all(r["dtc_confirmed"] == "0" for r in runs["healthy"]), "healthy identified units: no code confirmed")
    target_counts(json.load(open(os.path.join(d, "healthy.json")))["all_varied_identified"], runs["healthy"])
    for r in runs["friction"]:
        codes = [c.split(":") for c in r["dtc_codes"].split() if c]
        first = codes[0] if codes else None
        check(first is not None and first[0] == "P2119" and 2.0 < float(first[2]) <= 7.0,
              "unit %s %s: friction +25 %% confirmed as P2119 within 5 s (%s)" % (r["unit"], r["scenario"], r["dtc_codes"]))


def rerun(d, pop, host_sim):
    """population --params-out: the header of a class-b unit's file names the host_sim command
    that reruns one of its runs, and that command reproduces the run's figure; for the adapted
    section the command carries the warm-up (--warmup 5) and reproduces that run too."""
    os.makedirs(d)
    runs_csv = os.path.join(d, "runs.csv")
    subprocess.run([pop, "--plants", "1", "--first-unit", "1001", "--seeds", "1", "--first-seed", "3", "--sections",
                    "all,adapted", "--scenarios", "drive", "--duration", "2", "--params-out", os.path.join(d, "p"),
                    "--runs-csv", runs_csv, "--json", os.path.join(d, "population.json")],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    rows = {r["section"]: r for r in csv.DictReader(open(runs_csv))}
    check(sorted(rows) == ["all_varied", "all_varied_adapted"], "one run per section (%s)" % sorted(rows))
    for short, section in (("all", "all_varied"), ("adapted", "all_varied_adapted")):
        row = rows.get(section)
        if row is None:
            continue
        check(row["unit"] == "1001" and row["class"] == "b", "unit 1001 is of class b")
        pfile = os.path.join(d, "p", "%s_1001.params" % short)
        cmd = [l[1:].split() for l in open(pfile) if l.startswith("#   host_sim ")]
        check(len(cmd) == 1, "the parameter file names the rerun command")
        if len(cmd) != 1:
            continue
        args = cmd[0][1:]
        check(args[args.index("--plant-class") + 1] == "b" and args[args.index("--params") + 1] == pfile,
              "the command names the class and the file (%s)" % " ".join(args))
        warm = args[args.index("--warmup") + 1] if "--warmup" in args else None
        check(warm == ("5" if short == "adapted" else None), "%s: the command's warm-up is %s" % (section, warm))
        args[args.index("NAME")] = "drive"
        args[args.index("N")] = "3"
        out = os.path.join(d, "o_" + short)
        subprocess.run([host_sim] + args + ["--duration", "2", "--out", out], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        v = json.load(open(os.path.join(out, "drive_metrics.json")))["rmse"]["app"]["velocity_rad_s"]
        check(abs(v / float(row["rmse_filter_rad_s"]) - 1.0) < 1e-4,
              "%s: the rerun reproduces the run's velocity RMSE (%s vs %s rad/s)" % (section, v, row["rmse_filter_rad_s"]))
    # the warm-up's own errors
    for bad, needle in ((["--warmup", "61"], "out of range"), (["--warmup", "-1"], "out of range"),
                        (["--warmup", "1", "--scenario", "stop_learn"], "takes no warm-up")):
        r = subprocess.run([host_sim] + bad, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        check(r.returncode == 2 and needle in r.stderr, "host_sim %s: exit 2 naming it (%d, %s)" % (" ".join(bad), r.returncode, r.stderr.strip()))


def main():
    with tempfile.TemporaryDirectory() as d:
        synthetic(os.path.join(d, "a"))
        if len(sys.argv) > 1:
            real(os.path.join(d, "b"), sys.argv[1])
            identified(os.path.join(d, "c"), sys.argv[1])
        if len(sys.argv) > 2:
            rerun(os.path.join(d, "d"), sys.argv[1], sys.argv[2])
    print("%d failure(s)" % tv_check.failures)
    return 1 if tv_check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
