#!/usr/bin/env python3
"""Tests of `identify` (issue 11): parameters recovered from simulated logs of population units
of both classes (truth: the unit's own plant parameters, host_sim --print-plant-params, never
anything identify computes) against the issue's targets; the written file accepted by replay
--params and host_sim --params; a standstill log refused; bad input with the same exit codes
and messages as replay.

usage: test_identify.py BIN_DIR WORK_DIR   (BIN_DIR holds host_sim, identify, replay of one build)
Standard library only.
"""
import json
import os
import re
import shutil
import subprocess
import sys

BIN = sys.argv[1]
WORK = sys.argv[2]
FAILED = []
CHECKS = [0]

# The targets: relative for the motor and mechanics, absolute [rad] for the stops.
TARGETS = [
    ("model.R_ohm", "plant.R_ohm", "rel", 0.03),
    ("model.Kt_Nm_A", "plant.Kt_Nm_A", "rel", 0.03),
    ("model.Ke_V_s_rad", "plant.Ke_V_s_rad", "rel", 0.03),
    ("model.J_kg_m2", "plant.J_kg_m2", "rel", 0.10),
    ("model.c_Nm_rad", "plant.c_Nm_rad", "rel", 0.10),
    ("model.M0_Nm", "plant.M0_Nm", "rel", 0.10),
    ("model.Mc_Nm", "plant.Mc_Nm", "rel", 0.15),
    ("model.Ms_Nm", "plant.Ms_Nm", "rel", 0.15),
    ("model.phi_closed_rad", "plant.phi_closed_rad", "abs", 0.005),
    ("model.phi_open_rad", "plant.phi_open_rad", "abs", 0.005),
]


def exe(name):
    return os.path.join(BIN, name)


def path(name):
    return os.path.join(WORK, name)


def run(args):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=120)
    return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")


def check(cond, what):
    CHECKS[0] += 1
    if not cond:
        FAILED.append(what)
        print("FAIL:", what)


def keys(text):
    """key = value lines; comment lines (and keys written as comments: not identified) ignored."""
    out = {}
    for line in text.splitlines():
        m = re.match(r"^([A-Za-z0-9_.]+)\s*=\s*(\S+)", line.split("#", 1)[0].strip())
        if m:
            out[m.group(1)] = float(m.group(2))
    return out


def expect(args, code, *needles):
    rc, out, err = run(args)
    check(rc == code, "%s: exit %d, expected %d\n%s" % (" ".join(args), rc, code, err[-800:]))
    for n in needles:
        check(n in err or n in out, "%s: output lacks %r:\n%s" % (" ".join(args), n, err[-800:]))
    return rc, out, err


def recovered(unit, cls, fmt):
    """A 30 s ident log of one unit: every target parameter within its target."""
    log = path("u%d_%s.%s" % (unit, cls, fmt))
    prm = path("u%d_%s.params" % (unit, cls))
    unit_args = ["--unit", str(unit), "--plant-class", cls, "--spread", "all"]
    expect([exe("host_sim"), "--scenario", "ident", "--out", path("sim")] + unit_args +
           ["--raw-log", log, "--raw-format", fmt], 0)
    _, out, _ = expect([exe("identify"), log, "-o", prm], 0, "fit quality")
    with open(prm) as f:
        got = keys(f.read())
    _, plant_txt, _ = expect([exe("host_sim"), "--print-plant-params"] + unit_args, 0)
    truth = keys(plant_txt)
    for mkey, pkey, kind, tol in TARGETS:
        if mkey not in got:
            check(False, "unit %d (%s): %s not identified\n%s" % (unit, cls, mkey, out))
            continue
        err = got[mkey] / truth[pkey] - 1.0 if kind == "rel" else got[mkey] - truth[pkey]
        check(abs(err) <= tol, "unit %d (%s): %s = %.6g, the unit's %.6g: error %.4g beyond %g" %
              (unit, cls, mkey, got[mkey], truth[pkey], err, tol))
    # step 4, the contact law by the impacts: the damping ratio lambda / k is the unit's within
    # 25 % (over the 30 evaluation units of tools/run_identify.sh the median error is 4 %; the
    # ratio of a law capped at the stiffest the model keeps stable can be off more: unit 1007)
    with open(prm) as f:
        ptxt = f.read()
    check("identified by the impacts" in ptxt, "unit %d (%s): the stop damping identified by the impacts" % (unit, cls))
    if "model.d_stop_Nm_s_rad" in got and "model.k_stop_Nm_rad" in got:
        ratio = got["model.d_stop_Nm_s_rad"] / got["model.k_stop_Nm_rad"]
        true_ratio = truth["plant.stop_lambda_Nm_s_rad"] / truth["plant.stop_k_Nm_rad"]
        check(abs(ratio / true_ratio - 1.0) <= 0.25, "unit %d (%s): damping ratio %.4g s/rad, the unit's %.4g" %
              (unit, cls, ratio, true_ratio))
    else:
        check(False, "unit %d (%s): no contact law written" % (unit, cls))
    # the start-up stop learning keeps that law (exponent fixed, stiffness band +-1 % around it
    # as a secant at 2.5 mrad, the damping ratio) and re-learns the onsets only
    e = got.get("model.stop_exponent")
    check(e is not None and got.get("stop_learn.e_min") == e and got.get("stop_learn.e_max") == e,
          "unit %d (%s): stop learning's exponent fixed at the identified one" % (unit, cls))
    if e is not None and "stop_learn.k_min_Nm_rad" in got and "stop_learn.k_max_Nm_rad" in got:
        ksec = got["model.k_stop_Nm_rad"] * 0.0025 ** (e - 1.0)
        check(abs(got["stop_learn.k_min_Nm_rad"] / ksec - 0.99) < 1e-6 and abs(got["stop_learn.k_max_Nm_rad"] / ksec - 1.01) < 1e-6,
              "unit %d (%s): stop learning's stiffness band around the identified law" % (unit, cls))
    else:
        check(False, "unit %d (%s): stop learning's stiffness band not written" % (unit, cls))
    check(re.search(r"impacts RMS angle error \S+ rad \((\d+) impacts\)", out) is not None,
          "unit %d: the impacts' fit quality printed" % unit)
    # motor, inertia, friction and springs all identified: the file asks for the diagnostic bounds
    # relative to this model (diag.identified = 1, diag_detect_config_identified())
    check(got.get("diag.identified") == 1.0, "unit %d (%s): diag.identified = 1 written" % (unit, cls))
    # the law identified by the impacts is kept in service: no online impact learning
    check(got.get("impact_learn.enable") == 0.0, "unit %d (%s): impact_learn.enable = 0 written" % (unit, cls))
    # every estimate is printed with its standard deviation, and the fit quality
    check(re.search(r"^R\s+\S+\s+\S+", out, re.M) is not None and "armature R^2" in out,
          "unit %d: estimates with sigma and the fit quality printed" % unit)
    # the file is what replay and host_sim take
    expect([exe("replay"), "--params", prm, "-o", path("replay_out.csv"), log], 0)
    expect([exe("host_sim"), "--scenario", "paper_sine", "--duration", "0.5", "--out", path("sim2"), "--params", prm]
           + unit_args, 0)
    return got, truth


def contact_law_fits(unit, cls, scenario, exp_tol=None):
    """Step 4's joint refinement of the contact law (exponent, stiffness, damping ratio, onsets
    between the grid's points): the estimator with the identified parameters within the issue's
    1.2x of the same estimator with the unit's true ones on a scenario that hits both stops. Unit
    1011 was 1.95x with the grid's law alone (0.6 / 0.8 mrad onset errors, exponent 0.23 low);
    the truth's file is tools/run_identify.py's, scored as that benchmark scores (seed 2)."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
    import run_identify  # noqa: E402 (the benchmark's own truth file and scoring)
    log = path("u%d_%s_law.csv" % (unit, cls))
    prm = path("u%d_%s_law.params" % (unit, cls))
    tru = path("u%d_%s_true.params" % (unit, cls))
    unit_args = ["--unit", str(unit), "--plant-class", cls, "--spread", "all"]
    expect([exe("host_sim"), "--scenario", "ident", "--out", path("sim")] + unit_args + ["--raw-log", log], 0)
    _, out, _ = expect([exe("identify"), log, "-o", prm], 0, "joint refinement")
    _, plant_txt, _ = expect([exe("host_sim"), "--print-plant-params"] + unit_args, 0)
    with open(tru, "w") as f:
        f.write(run_identify.true_params(run_identify.read_keys(plant_txt)))
    rm = {}
    for name, f in (("identified", prm), ("true", tru)):
        _, _, _ = expect([exe("host_sim"), "--scenario", scenario, "--seed", "2", "--out", path("law_" + name),
                          "--params", f] + unit_args, 0)
        with open(os.path.join(path("law_" + name), scenario + "_metrics.json")) as fh:
            rm[name] = json.load(fh)["rmse"]["app"]["velocity_rad_s"]
    check(rm["identified"] <= 1.2 * rm["true"], "unit %d (%s) %s: velocity RMSE %.4g with the identified law, %.4g with "
          "the true one (more than 1.2x)\n%s" % (unit, cls, scenario, rm["identified"], rm["true"], out))
    if exp_tol is not None:
        with open(prm) as fh:
            got = keys(fh.read())
        truth = run_identify.read_keys(plant_txt)
        err = got.get("model.stop_exponent", float("nan")) - truth["plant.stop_exponent"]
        check(abs(err) <= exp_tol, "unit %d (%s): stop exponent %.4g, the unit's %.4g (beyond %g)" %
              (unit, cls, got.get("model.stop_exponent", float("nan")), truth["plant.stop_exponent"], exp_tol))


PLATE_KEYS = (("model.J_kg_m2", "plant.J_kg_m2", 0.3), ("model.M0_Nm", "plant.M0_Nm", 0.3),
              ("model.c_Nm_rad", "plant.c_Nm_rad", 0.3), ("model.Mc_Nm", "plant.Mc_Nm", 0.3),
              ("model.Ms_Nm", "plant.Ms_Nm", 0.3), ("model.Kv_Nm_s_rad", "plant.Kv_Nm_s_rad", 0.5))


def other_log(unit, cls, scenario):
    """identify on a 30 s log of another scenario than the recommended one: what it writes."""
    unit_args = ["--unit", str(unit), "--plant-class", cls, "--spread", "all"]
    log = path("other_%d_%s.csv" % (unit, scenario))
    prm = path("other_%d_%s.params" % (unit, scenario))
    expect([exe("host_sim"), "--scenario", scenario, "--duration", "30", "--out", path("sim")] + unit_args +
           ["--raw-log", log], 0)
    _, out, _ = expect([exe("identify"), "--quiet", log, "-o", prm], 0)
    with open(prm) as f:
        ptxt = f.read()
    got = keys(ptxt)
    ident = set(m.group(1) for m in re.finditer(r"^([A-Za-z0-9_.]+) = \S+\s+# identified", ptxt, re.M))
    _, plant_txt, _ = expect([exe("host_sim"), "--print-plant-params"] + unit_args, 0)
    truth = keys(plant_txt)
    # whatever such a log lets identify call identified is near the unit's (before: a stop 0.2 rad
    # inside the travel, J, M0 and c 75 % low, Kv 27x, each with a sigma of a few per cent)
    for mkey, pkey, tol in PLATE_KEYS:
        if mkey in ident:
            check(abs(got[mkey] / truth[pkey] - 1.0) <= tol, "%d %s: %s = %.4g written, the unit's %.4g" %
                  (unit, scenario, mkey, got[mkey], truth[pkey]))
    for side in ("closed", "open"):
        mkey = "model.phi_%s_rad" % side
        if mkey in got:
            check(abs(got[mkey] - truth["plant.phi_%s_rad" % side]) <= 0.005, "%d %s: %s = %.4f written, the unit's %.4f" %
                  (unit, scenario, mkey, got[mkey], truth["plant.phi_%s_rad" % side]))
    # the sliding friction's two halves are written together or not at all, unless Kv was held at
    # its default for too little speed (Mc is then fitted with it)
    check(("model.Mc_Nm" in got) == ("model.Kv_Nm_s_rad" in got) or
          re.search(r"^Kv .*NOT IDENTIFIED: too little excitation: \d+ samples at \|w\| >=", out, re.M) is not None,
          "%d %s: Mc and Kv written together" % (unit, scenario))
    return got, out + ptxt


def other_logs():
    """Logs of other scenarios (training units 3, class a, and 7, class b): identify says what they
    cannot give instead of writing it (each check failed before this release's rules)."""
    # closed-loop driving holds the plate at its lowest and highest targets: friction holds those
    # rests, no stop does (unit 3: the open stop was written 0.2 rad inside the travel; unit 1:
    # 0.039 and 1.217 rad, its stops at -0.077 and 1.473); and the friction law's halves trade
    # (Mc negative, Kv 3.8x and 27x, or Kv 90 % low: speeds below 5 rad/s cannot tell the viscous
    # slope from the Stribeck drop, so Kv keeps its default and Mc is fitted with it)
    got, out = other_log(3, "a", "drive")
    check("model.phi_open_rad" not in got and "model.phi_closed_rad" not in got, "3 drive: no stop angle written")
    got, out = other_log(1, "a", "drive")
    check("model.phi_open_rad" not in got and "model.phi_closed_rad" not in got, "1 drive: no stop angle written")
    check(re.search(r"^phi_open .*no rest at 1\.2\d\d rad held more push than friction can", out, re.M) is not None,
          "1 drive: why the rest at the end of the travel is no stop")
    got, out = other_log(7, "b", "drive")
    check("model.Kv_Nm_s_rad" not in got and "model.Mc_Nm" in got, "7 drive: Kv held at its default, Mc identified with it")
    # +-10 V steps: the plate fit comes out non-physical (Kv negative): no plate parameter written
    got, out = other_log(3, "a", "open_steps")
    check(not any(k in got for k, _, _ in PLATE_KEYS), "3 open_steps: no plate parameter written")
    check("the plate fit is not physical" in out, "3 open_steps: says why")
    # the 5 V slow sine: no acceleration above 50 rad/s^2, J held at the default (it read 91 % low)
    # and the rest fitted with it
    got, out = other_log(7, "b", "slow_sine")
    check("model.J_kg_m2" not in got and "dw/dt" in out, "7 slow_sine: J not identified (too little acceleration)")
    check(all(k in got for k in ("model.M0_Nm", "model.c_Nm_rad", "model.Mc_Nm")), "7 slow_sine: M0, c, Mc identified")
    # the 12 V chirp has no free motion slower than 2 rad/s: no static friction (it read Ms = Mc,
    # 48 % below the unit's)
    got, out = other_log(7, "b", "chirp")
    check("static friction not identified" in out and re.search(r"^Ms .*NOT IDENTIFIED", out, re.M) is not None,
          "7 chirp: Ms not identified")


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)

    # recovered parameters: three evaluation units of the population, both classes, both formats
    recovered(1000, "a", "csv")
    recovered(1001, "b", "bin")
    recovered(1003, "a", "bin")
    contact_law_fits(1011, "a", "paper_sine")
    # step 4's replay of the impacts: with 0.1 ms sub-steps throughout and the measured current
    # interpolated across each period it preferred exponents near 1 (unit 1004: 1.08 for its
    # 1.18, paper sine 1.82x the true law's error; unit 1023: 1.04 for its 1.26); with the
    # armature's current and 10 us sub-steps near the stops 1.15 (0.95x) and 1.17
    contact_law_fits(1004, "b", "paper_sine", exp_tol=0.1)
    contact_law_fits(1023, "a", "open_steps", exp_tol=0.15)
    recovered(1004, "b", "csv")
    # training unit 21 has no Stribeck drop (its Ms = Mc): the plate fit's drop runs to the top
    # of the ws search, where it traded with Mc (+4.7 %); identify finds Ms = Mc (a finding, not
    # a lack of excitation), refits without the drop, and so identifies the contact law and
    # writes diag.identified (both need Ms; recovered() checks them)
    got, truth = recovered(21, "a", "csv")
    check(abs(got.get("model.Mc_Nm", 0.0) / truth["plant.Mc_Nm"] - 1.0) <= 0.01,
          "unit 21: Mc within 1 %% without the drop (%s vs %s)" % (got.get("model.Mc_Nm"), truth["plant.Mc_Nm"]))
    check(got.get("model.Ms_Nm") == got.get("model.Mc_Nm"), "unit 21: Ms = Mc written")

    # a warm winding (90 degC: copper's R x 1.2751): the log's R as it is without the temperature,
    # referred to 20 degC with it (identify --winding-temp), within 3 % of the unit's either way
    unit_args = ["--unit", "1000", "--plant-class", "a", "--spread", "all"]
    warm = path("warm90.bin")
    expect([exe("host_sim"), "--scenario", "ident", "--out", path("sim"), "--winding-temp", "90", "--raw-log", warm,
            "--raw-format", "bin"] + unit_args, 0)
    _, plant_txt, _ = expect([exe("host_sim"), "--print-plant-params"] + unit_args, 0)
    r20 = keys(plant_txt)["plant.R_ohm"]
    for temp, want in ((None, r20 * (1.0 + 0.00393 * 70.0)), ("90", r20)):
        prm = path("warm90_%s.params" % (temp or "untold"))
        expect([exe("identify"), warm, "-o", prm, "--quiet"] + (["--winding-temp", temp] if temp else []), 0)
        with open(prm) as fh:
            txt = fh.read()
        got = keys(txt).get("model.R_ohm", float("nan"))
        check(abs(got / want - 1.0) <= 0.03, "warm log, temperature %s: R %.4g, expected %.4g" % (temp, got, want))
        check(("referred from the log's 90 degC" in txt) == (temp is not None), "warm log: the file says how R was referred")
    expect([exe("identify"), "--winding-temp", "181", warm, "-o", path("x.params")], 2, "--winding-temp")

    # a log that excites nothing: standstill (1.5 V, the plate never breaks away) is refused
    log = path("standstill.bin")
    expect([exe("host_sim"), "--scenario", "standstill", "--duration", "20", "--out", path("sim"), "--raw-log", log,
            "--raw-format", "bin"], 0)
    out_prm = path("standstill.params")
    _, out, _ = expect([exe("identify"), log, "-o", out_prm], 20, "too little excitation", "nothing written")
    check(not os.path.exists(out_prm), "standstill: no parameter file written")
    check("NOT IDENTIFIED" in out, "standstill: the parameters it could not identify are named")

    other_logs()

    # bad input: the same exit codes and messages as replay
    good = path("u1000_a.csv")
    expect([exe("identify"), path("missing.csv"), "-o", path("x.params")], 1, "cannot open")
    expect([exe("identify"), good], 2, "-o PARAMS is required")
    expect([exe("identify"), good, "-o", good], 2, "refusing to overwrite")
    expect([exe("identify"), "--gear", "-3", good, "-o", path("x.params")], 2, "--gear")
    with open(good) as f:
        lines = f.read().splitlines(True)
    head = [l for l in lines if l.startswith("#") or l.startswith("t_us")]
    data = [l for l in lines if not (l.startswith("#") or l.startswith("t_us"))]
    bad_cases = [
        ("empty.csv", "", None),
        ("not_number.csv", "".join(head + data[:100] + ["1000000,0.1,abc,1,2,3,0,1,0,0,0\n"] + data[100:200]), 100),
        ("backwards.csv", "".join(head + data[:100] + [data[50]] + data[100:200]), 100),
        ("columns.csv", "".join(head + data[:100] + ["1,2,3\n"]), 100),
    ]
    for name, text, _ in bad_cases:
        p = path(name)
        with open(p, "w") as f:
            f.write(text)
        rrc, _, rerr = run([exe("replay"), "--parse-only", p])
        irc, _, ierr = run([exe("identify"), p, "-o", path("x.params")])
        check(rrc != 0 and irc == rrc, "%s: identify exits %d, replay %d" % (name, irc, rrc))
        first = [l for l in rerr.splitlines() if name in l][:1]
        check(bool(first) and first[0].split(": ", 1)[-1] in ierr,
              "%s: identify names the problem as replay does:\n%s\n%s" % (name, rerr[-400:], ierr[-400:]))
    check(not os.path.exists(path("x.params")), "bad input: nothing written")

    print("%d checks, %d failed" % (CHECKS[0], len(FAILED)))
    return 1 if FAILED else 0


if __name__ == "__main__":
    sys.exit(main())
