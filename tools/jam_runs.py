#!/usr/bin/python3
"""Per-run analysis of a jam fault's population runs (issue 12: "jam or stuck plate, >= 0.035 rad
from target: confirmed <= 100 ms").

Reruns every run of a `population --fault jam:M@ONSET --runs-csv RUNS --params-out PARAMS` with
host_sim (the same unit, class, spread, filter parameters, seed, scenario, fault and duration)
writing its trace and events to WORK/, and finds in the PLANT'S TRUTH when the jammed plate is
first STALLED at >= 0.035 rad from its target: the bridge drives, the plate moved < 0.5 mrad over
8 ms, and the target is >= 0.035 rad away (closed loop: the target clamped 0.05 rad inside the
plant's stops, as the application clamps it inside the learned ones; open loop, which has no
target: the stop the voltage pushes toward, counted only while the voltage exceeds the healthy
unit's own breakaway in that direction, Ms + the springs when they oppose, so a healthy plate
would move), the stall lasting 100 ms or until a code's action ends it. Per scenario it prints
the runs stalled, those never stalled (a plate jammed at its target, or a sticky plate that
still follows: not what the target asks for), detected (a jam code confirmed), within 100 ms of
the stall, the delay from the stall (median, p95) and the runs whose first code after the onset
is not a jam code; -v lists the runs missed, slow or mis-isolated. The fault matrix computes the
same stall time in population itself (host_sim/sim/sim_fault_cond.h, the runs CSV's
t_condition_s, summary.json's delay_from_condition_*); this tool gives the traces and the listing.

usage: tools/jam_runs.py BIN_DIR RUNS_CSV PARAMS_DIR SPEC ONSET DURATION WORK_DIR [-v]
  e.g. population --plants 10 --seeds 1 --sections stops,all \
         --scenarios drive,closed_steps,paper_sine,slow_sine,limp_home --duration 8 \
         --fault jam:1@2.0 --runs-csv /tmp/j1.csv --json /tmp/j1.json --params-out /tmp/jp
       tools/jam_runs.py build/host-release/bin /tmp/j1.csv /tmp/jp jam:1 2.0 8 /tmp/jw -v
"""
import concurrent.futures as cf
import csv
import json
import math
import os
import subprocess
import sys
from collections import defaultdict


def plant_params(bindir, unit, spread, cls):
    r = subprocess.run([f"{bindir}/host_sim", "--plant-class", cls, "--unit", unit, "--spread", spread,
                        "--print-plant-params"], capture_output=True, text=True, check=True)
    p = {}
    for ln in r.stdout.splitlines():
        if ln.startswith("plant."):
            k, v = ln[6:].split("=")
            p[k.strip()] = float(v)
    return p


def one(args):
    bindir, params, spec, onset, dur, work, row = args
    sec = row["section"]
    spread = "stops" if sec.startswith("stops") else "all"
    unit, sc, cls = row["unit"], row["scenario"], row["class"]
    d = f"{work}/{spec}_{sec}_{unit}_{sc}_{row['seed']}"
    os.makedirs(d, exist_ok=True)
    subprocess.run([f"{bindir}/host_sim", "--plant-class", cls, "--unit", unit, "--spread", spread, "--params",
                    f"{params}/{spread}_{unit}.params", "--scenario", sc, "--duration", str(dur), "--seed", row["seed"],
                    "--fault", f"{spec}@{onset}", "--out", d, "--events", d + "/ev.csv"],
                   capture_output=True, text=True, check=True)
    pp = plant_params(bindir, unit, spread, cls)
    ev = list(csv.DictReader(open(d + "/ev.csv")))
    conf = [(int(e["t_us"]) / 1e6, e["dtc"], e["fault_class"]) for e in ev if e["status"] == "confirmed"]
    conf_after = [c for c in conf if c[0] >= onset]
    conf_times = [c[0] for c in conf_after]
    jam_t = next((c[0] for c in conf_after if c[2] == "jam"), None)
    nkt = pp["n_gear"] * pp["Kt_Nm_A"]
    hist = []
    seg_start = None
    stall = None
    phi_jam = None
    for x in csv.DictReader(open(f"{d}/{sc}.csv")):
        t = float(x["t_s"])
        ph = float(x["phi_true_rad"])
        hist.append(ph)
        if t < onset - 1e-9 or stall is not None:
            continue
        if phi_jam is None:
            phi_jam = ph
        demand = False
        if x["bridge_enable"] == "1":
            tgt = float(x["target_rad"])
            u = float(x["u_applied_V"])
            if not math.isnan(tgt):
                tgt = min(max(tgt, pp["phi_closed_rad"] + 0.05), pp["phi_open_rad"] - 0.05)
                demand = abs(tgt - ph) >= 0.035
            else:
                s = 1 if u > 0 else -1
                stop = pp["phi_open_rad"] if s > 0 else pp["phi_closed_rad"]
                spring = pp["M0_Nm"] * (1 if ph > 0 else -1) + pp["c_Nm_rad"] * ph
                need = pp["Ms_Nm"] + max(0.0, s * spring)
                demand = abs(stop - ph) >= 0.035 and nkt * abs(u) / pp["R_ohm"] >= need
        still = len(hist) > 8 and abs(hist[-1] - hist[-9]) < 5e-4
        ended_by_code = seg_start is not None and any(seg_start <= c <= t + 0.0015 for c in conf_times)
        if demand and still:
            if seg_start is None:
                seg_start = t
            if t - seg_start >= 0.1 - 1e-9 or ended_by_code:
                stall = seg_start
        else:
            if ended_by_code:
                stall = seg_start
            seg_start = None
    return dict(section=sec, unit=unit, cls=cls, scenario=sc, phi_jam=phi_jam, t_stall=stall, jam_confirmed=jam_t,
                first=conf_after[0] if conf_after else None, codes=conf_after,
                delay_from_stall=(jam_t - stall) if (jam_t is not None and stall is not None) else None)


def pct(a, q):
    a = sorted(a)
    if not a:
        return None
    k = (len(a) - 1) * q
    f = int(k)
    c = min(f + 1, len(a) - 1)
    return a[f] + (a[c] - a[f]) * (k - f)


def main():
    if len(sys.argv) < 8:
        sys.exit(__doc__)
    bindir, runs, params, spec, onset, dur, work = sys.argv[1:8]
    verbose = "-v" in sys.argv[8:]
    rows = list(csv.DictReader(open(runs)))
    with cf.ThreadPoolExecutor(2) as ex:
        res = list(ex.map(one, [(bindir, params, spec, float(onset), dur, work, r) for r in rows]))
    json.dump(res, open(f"{work}/{spec}_analysis.json", "w"), indent=1)
    by = defaultdict(list)
    for r in res:
        by[r["scenario"]].append(r)
    tot = defaultdict(int)
    fmt = lambda v: "-" if v is None else f"{v * 1e3:.0f}"
    print(f"{spec}: scenario | runs | stalled >= 0.035 rad | never stalled (jam code / other code / none) | detected | "
          f"<= 100 ms of the stall | delay from the stall median / p95 [ms] | first code not jam")
    for sc, rs in sorted(by.items()):
        st = [r for r in rs if r["t_stall"] is not None]
        ns = [r for r in rs if r["t_stall"] is None]
        det = [r for r in st if r["jam_confirmed"] is not None]
        d = [r["delay_from_stall"] for r in det]
        fast = [x for x in d if x <= 0.1]
        wrong = [r for r in rs if r["first"] and r["first"][2] != "jam"]
        ns_j = sum(1 for r in ns if r["first"] and r["first"][2] == "jam")
        ns_o = sum(1 for r in ns if r["first"] and r["first"][2] != "jam")
        print(f"{sc} | {len(rs)} | {len(st)} | {len(ns)} ({ns_j} / {ns_o} / {len(ns) - ns_j - ns_o}) | {len(det)} | "
              f"{len(fast)} | {fmt(pct(d, .5))} / {fmt(pct(d, .95))} | {len(wrong)}")
        for k, v in (("runs", len(rs)), ("stalled", len(st)), ("never", len(ns)), ("detected", len(det)),
                     ("within_100ms", len(fast)), ("first_not_jam", len(wrong))):
            tot[k] += v
        if verbose:
            for r in rs:
                slow = r["t_stall"] is not None and (r["jam_confirmed"] is None or r["delay_from_stall"] > 0.1)
                if slow or (r["first"] and r["first"][2] != "jam"):
                    print(f"    {r['section']} {r['unit']} ({r['cls']}) jammed at {r['phi_jam']:.3f} rad, stall "
                          f"{r['t_stall']}, jam code {r['jam_confirmed']}, codes "
                          f"{[(round(c[0], 3), c[1]) for c in r['codes']][:4]}")
    print("all:", dict(tot))


if __name__ == "__main__":
    main()
