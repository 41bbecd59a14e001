#!/usr/bin/python3
"""Checks of the closed-loop run inside the test VM (called by run_vm_test.sh).

    check_closed_loop.py --dbc tools/throttle.dbc --candump candump.log --truth truth.csv
                         --app app.txt --plant plant.txt

The candump -L log of vcan0 is decoded through the DBC with tools/can_decode.py, and what the
controller reported is compared with what the plant really did (truth.csv, vm_plant).

Alignment. Each TV_EST_STATE is paired with the TV_TIME sent in the same tick; its SampleTime
plus the controller's clock origin (printed by throttle_linux) is the CLOCK_MONOTONIC instant
the controller read the ADC files. The plant's sample then read is the last truth row written
before that instant (truth t_mono_s is taken just before vm_plant writes the files). So every
estimate is compared with the true state at the instant of the sample it was computed from.
Phases are located from the commands in the log itself (candump and truth share
CLOCK_REALTIME inside the VM), not from nominal script times.

Tolerances (each one stated where it is checked):
  at rest / holding position: |estimate - truth| <= 5 sigma + q, sigma the filter's own standard
      deviation from TV_EST_SIGMA of that tick, q the quantisation: telemetry half a count plus
      half an ADC count (current 0.004 A, angle 2.2e-4 rad per track); a consistent filter is
      inside 3 sigma almost always, 5 sigma leaves no room for flukes in ~500 samples.
  moving (12 V / 5 Hz sine, up to ~16 rad/s, hitting the closed stop): RMS bounds of a few
      sigma. The VM runs with -icount (guest time = instructions executed), so its timing is
      deterministic: the controller wakes within microseconds and reads the sample the plant
      wrote 0.9 ms earlier. What remains is the filter's model (firmware/estimator/tv_model.h) against
      the high-fidelity plant (host_sim/plant/plant.h: stick-slip, Hunt-Crossley stops) and the
      plant taking up a new duty at its next 1 ms step. Filter sigma while moving: current
      0.010 A, velocity 0.06 rad/s, angle 1.1e-4 rad. Bounds: current 0.05 A (5 sigma),
      velocity 0.5 rad/s (8 sigma: stop impacts change the velocity within a step), angle
      1e-3 rad (9 sigma, two ADC counts of one track). The estimator's own accuracy is
      established by the host tests with exact timing; this checks the data path end to end.
  timings: fault, clear and timeout are seen in TV_STATUS, sent every 10 ms; bounds allow one
      STATUS period plus 10 ms.
"""

import argparse
import bisect
import csv
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import can_decode  # noqa: E402

results = []


def check(ok, name, detail):
    results.append(ok)
    print("%s %s: %s" % ("PASS" if ok else "FAIL", name, detail))
    return ok


def rms(v):
    return math.sqrt(sum(x * x for x in v) / len(v)) if v else float("nan")


def main():
    ap = argparse.ArgumentParser()
    for a in ("--dbc", "--candump", "--truth", "--app", "--plant"):
        ap.add_argument(a, required=True)
    args = ap.parse_args()
    dbc = can_decode.load_dbc(args.dbc)

    app_text = open(args.app, encoding="utf-8", errors="replace").read()
    plant_text = open(args.plant, encoding="utf-8", errors="replace").read()
    m = re.search(r"SampleTime 0 = CLOCK_MONOTONIC (\d+) ns", app_text)
    if not m:
        check(False, "controller clock origin", "throttle_linux did not print it")
        return 1
    t0_mono = int(m.group(1)) * 1e-9

    truth = list(csv.DictReader(open(args.truth)))
    tr_mono = [float(r["t_mono_s"]) for r in truth]
    tr_real = [float(r["t_real_s"]) for r in truth]
    col = {k: [float(r[k]) for r in truth] for k in ("current_A", "velocity_rad_s", "angle_rad", "duty")}
    tr_enable = [int(r["enable"]) for r in truth]
    tr_fault = [int(r["fault_pin"]) for r in truth]

    def truth_real_index(t):  # last truth row at or before realtime t
        return max(0, bisect.bisect_right(tr_real, t) - 1)

    # ---- decode the log ----------------------------------------------------------------------
    frames = []
    bad_lines = 0
    for line in open(args.candump, encoding="utf-8", errors="replace"):
        f = can_decode.parse_candump_line(line)
        if f is None:
            bad_lines += line.strip() != ""
            continue
        d = can_decode.decode_frame(dbc, f)
        if d is not None:
            frames.append((f.timestamp, d))
    # Telemetry every controller sends; TV_ECU_CPU (0x1A0) is the Cortex-M4F ECU's own frame.
    ecu_only = {0x1A0}
    tele_ids = {m.id for m in dbc.values() if m.sender == "TV" and m.id not in ecu_only}
    counts = {}
    crc_bad = 0
    jumps = 0
    last_ctr = {}
    for ts, d in frames:
        if "error" in d:
            continue
        if d["id"] in tele_ids:
            counts[d["message"]] = counts.get(d["message"], 0) + 1
            crc_bad += not d["crc_ok"]
            prev = last_ctr.get(d["id"])
            if prev is not None and d["counter"] != (prev + 1) % 16:
                jumps += 1
            last_ctr[d["id"]] = d["counter"]
    span = frames[-1][0] - frames[0][0] if frames else 0.0
    check(len(counts) == len(tele_ids) and crc_bad == 0 and jumps == 0 and bad_lines == 0,
          "telemetry decoded through the DBC",
          "%d frames over %.1f s, %d of %d telemetry ids (%s), %d CRC failures, %d counter jumps, "
          "%d unreadable lines" % (len(frames), span, len(counts), len(tele_ids),
                                   ", ".join("%s %d" % kv for kv in sorted(counts.items())), crc_bad, jumps,
                                   bad_lines))

    # commands as sent (decoded through the DBC too)
    controls = [(ts, d["signals"]) for ts, d in frames
                if d["message"] == "TV_CMD_CONTROL" and "signals" in d and d.get("crc_ok") and d["signals"]["Mode"] <= 4]
    if not controls:
        check(False, "commands", "no TV_CMD_CONTROL in the log")
        return 1
    t_first = controls[0][0]
    t_sine = next(ts for ts, s in controls if s["Mode"] == 1)
    t_pos2 = next(ts for ts, s in controls if ts > t_sine and s["Mode"] == 4)
    target2 = next(s["TargetAngle"] for ts, s in controls if ts >= t_pos2)
    t_last = controls[-1][0]
    k_fault = next((k for k, v in enumerate(tr_fault) if v == 0), None)
    t_fault = tr_real[k_fault] if k_fault is not None else None
    t_clear = next((ts for ts, s in controls if t_fault and ts > t_fault and s["FaultClear"] == 1), None)

    # ---- per-tick telemetry, aligned on the sample actually read -------------------------------
    ticks = []
    state = sigma = None
    for ts, d in frames:
        name = d["message"]
        if "signals" not in d:
            continue
        if name == "TV_EST_STATE":
            state = (ts, d["signals"])
        elif name == "TV_EST_SIGMA":
            sigma = d["signals"]
        elif name == "TV_TIME" and state is not None and sigma is not None:
            t_read = t0_mono + d["signals"]["SampleTime"] * 1e-6
            k = bisect.bisect_right(tr_mono, t_read) - 1
            if k >= 0:
                ticks.append({"ts": state[0], "est": state[1], "sigma": sigma, "k": k, "age": t_read - tr_mono[k]})
            state = None
    statuses = [(ts, d["signals"]) for ts, d in frames if d["message"] == "TV_STATUS" and "signals" in d]

    chans = (("EstCurrent", "current_A", "SigmaCurrent", 0.004 + 0.0005, "A"),
             ("EstVelocity", "velocity_rad_s", "SigmaVelocity", 0.005, "rad/s"),
             ("EstAngle", "angle_rad", "SigmaAngle", 2.2e-4 + 5e-5, "rad"))

    def still_phase(name, lo, hi, target):
        sel = [t for t in ticks if lo <= t["ts"] < hi]
        ang = [col["angle_rad"][t["k"]] for t in sel]
        if not sel:
            check(False, name, "no telemetry in the window")
            return
        mean_ang = sum(ang) / len(ang)
        check(abs(mean_ang - target) <= 0.01, name + ": the plant holds the commanded angle",
              "true angle %.4f rad for target %.4f (within 0.01 rad: PWM files -> plant -> IIO files -> "
              "controller closes the loop)" % (mean_ang, target))
        for est, tr, sg, q, unit in chans:
            worst = max(abs(t["est"][est] - col[tr][t["k"]]) - (5.0 * t["sigma"][sg] + q) for t in sel)
            err = [abs(t["est"][est] - col[tr][t["k"]]) for t in sel]
            check(worst <= 0.0, "%s: %s vs truth" % (name, est),
                  "%d samples, max |error| %.3g %s, RMS %.3g, all within 5 sigma + %.2g"
                  % (len(sel), max(err), unit, rms(err), q) if worst <= 0.0 else
                  "%d samples, max |error| %.3g %s exceeds 5 sigma + %.2g by %.3g" % (len(sel), max(err), unit, q, worst))

    still_phase("position 0.3 rad", t_first + 1.0, t_sine, 0.3)

    # moving: RMS bounds (see the module docstring)
    sel = [t for t in ticks if t_sine + 0.5 <= t["ts"] < t_pos2]
    ang = [col["angle_rad"][t["k"]] for t in sel]
    wmax = max(abs(col["velocity_rad_s"][t["k"]]) for t in sel) if sel else 0.0
    check(bool(sel) and max(ang) - min(ang) >= 0.5, "sine 12 V / 5 Hz: the plant moves",
          "true angle %.3f .. %.3f rad, |velocity| up to %.1f rad/s" % (min(ang), max(ang), wmax) if sel else "no data")
    for (est, tr, sg, q, unit), bound in zip(chans, (0.05, 0.5, 1e-3)):
        err = [t["est"][est] - col[tr][t["k"]] for t in sel]
        check(bool(err) and rms(err) <= bound, "sine: %s vs truth" % est,
              "%d samples, RMS error %.3g %s (bound %.3g), max %.3g" % (len(err), rms(err), unit, bound,
                                                                     max(abs(e) for e in err) if err else float("nan")))

    if t_fault is None:
        check(False, "driver fault", "vm_plant never pulled nFAULT low")
    else:
        still_phase("position %.2f rad" % target2, t_pos2 + 0.7, t_fault, target2)
        # driver fault through the real GPIO chip: latched, bridge disabled, plate springs back
        st = next(((ts, s) for ts, s in statuses if ts >= t_fault and int(s["Faults"]) & 0x20), None)
        k_off = next((k for k in range(k_fault, len(truth)) if tr_enable[k] == 0), None)
        ok = st is not None and st[0] - t_fault <= 0.02 and st[1]["BridgeEnable"] == 0 and k_off is not None \
            and tr_real[k_off] - t_fault <= 0.02
        check(ok, "driver fault (nFAULT low on the GPIO chip for 50 ms)",
              "TV_STATUS Faults bit 5 after %.1f ms, bridge enable seen off by the plant after %.1f ms (<= 20 ms)"
              % ((st[0] - t_fault) * 1e3 if st else float("nan"),
                 (tr_real[k_off] - t_fault) * 1e3 if k_off is not None else float("nan")))
        a_fault = col["angle_rad"][k_fault]
        a_later = col["angle_rad"][truth_real_index(t_fault + 0.5)]
        check(a_fault - a_later >= 0.1, "safe state: the springs take the plate back",
              "true angle %.3f rad at the fault, %.3f rad 0.5 s later" % (a_fault, a_later))
        latched = all(int(s["Faults"]) & 0x20 for ts, s in statuses if t_fault + 0.1 <= ts < (t_clear or t_last))
        check(latched, "the fault stays latched until FaultClear", "while nFAULT is high again")
        if t_clear is None:
            check(False, "fault clear", "no FaultClear command after the fault")
        else:
            st = next(((ts, s) for ts, s in statuses if ts >= t_clear and int(s["Faults"]) == 0
                       and s["BridgeEnable"] == 1), None)
            k = truth_real_index(t_clear + 1.0)
            check(st is not None and st[0] - t_clear <= 0.05 and abs(col["angle_rad"][k] - target2) <= 0.05,
                  "FaultClear edge over CAN",
                  "faults 0 and bridge on %.1f ms after it (<= 50 ms); true angle %.3f rad 1 s later (target %.2f)"
                  % ((st[0] - t_clear) * 1e3 if st else float("nan"), col["angle_rad"][k], target2))

    # command timeout: silence is the fail-safe signal
    # The node latches the timeout after that tick's app_tick() (can_proto.h: receive, update and
    # transmit run after the step), so the mode is OFF from the next tick on. A STATUS frame
    # sent in the very tick of the expiry therefore reports CmdTimeout together with the duty
    # that was truly applied during that tick; the bridge must be off in the next STATUS
    # (10 ms later; 15 ms allows for the capture timestamps' jitter), and the plant check below
    # verifies what the actuator saw.
    idx = next((i for i, (ts, s) in enumerate(statuses) if ts > t_last and s["CmdTimeout"] == 1), None)
    st = statuses[idx] if idx is not None else None
    nxt = statuses[idx + 1] if idx is not None and idx + 1 < len(statuses) else None
    delay = st[0] - t_last if st else float("nan")
    off = lambda s: s["BridgeEnable"] == 0 and abs(s["Duty"]) < 1e-9
    ok = st is not None and 0.1 <= delay <= 0.12 and st[1]["Mode"] == 0 and \
        (off(st[1]) or (nxt is not None and nxt[0] - st[0] <= 0.015 and nxt[1]["Mode"] == 0 and off(nxt[1])))
    check(ok, "command timeout (can.cmd_timeout_ms = 100)",
          "CmdTimeout and mode OFF reported %.1f ms after the last command (in 100 .. 120 ms: the timeout, one "
          "10 ms STATUS period, 10 ms slack); bridge off and duty 0 %s" %
          (delay * 1e3, "in the same frame" if st and off(st[1]) else "in the next STATUS frame"))
    k_after = truth_real_index(t_last + 0.12)
    on_after = sum(1 for k in range(k_after + 1, len(truth)) if tr_enable[k] or abs(col["duty"][k]) > 0)
    check(on_after == 0, "after the timeout the plant sees the bridge off and duty 0",
          "%d truth rows with the bridge on or a duty after it" % on_after)

    # bad command frames, counted by the controller and reported over CAN
    stats = [d["signals"] for ts, d in frames if d["message"] == "TV_CMD_STATS" and "signals" in d]
    want = {"CrcErrors": 1, "DlcErrors": 1, "CounterErrors": 2, "RangeErrors": 1, "UnknownIds": 1, "Timeouts": 1}
    got = {k: int(stats[-1][k]) for k in want} if stats else {}
    check(got == want, "bad command frames rejected and counted (TV_CMD_STATS)",
          "%s (expected %s)" % (got, want))

    # outputs at exit, as the plant saw them
    m = re.search(r"FINAL pwm0 duty (\d+) enable (\d+), pwm1 duty (\d+) enable (\d+), gpio enable (\d+)", plant_text)
    check(m is not None and all(int(x) == 0 for x in m.groups()), "safe state after SIGTERM",
          "PWM duty and enable 0 on both channels, bridge enable line low" if m else "no FINAL line from vm_plant")
    m = re.search(r"io errors (\d+), can tx errors (\d+)", app_text)
    check(m is not None and m.group(1) == "0" and m.group(2) == "0", "no I/O errors in the controller",
          "io errors %s, can tx errors %s" % m.groups() if m else "no summary line")

    loops = [d["signals"] for ts, d in frames if d["message"] == "TV_LOOP" and "signals" in d]
    ekf = [d["signals"]["NisMean"] for ts, d in frames if d["message"] == "TV_EKF_STATS" and "signals" in d]
    if loops:
        print("INFO loop statistics over CAN (TV_LOOP, last): overruns %d, worst wake-up latency %d us, worst tick "
              "%d us" % (loops[-1]["Overruns"], loops[-1]["LatencyMax"], loops[-1]["ExecMax"]))
    if ekf:
        print("INFO TV_EKF_STATS NisMean: median %.2f over %d windows (2 channels: chi-square mean 2)"
              % (sorted(ekf)[len(ekf) // 2], len(ekf)))
    ages = sorted(t["age"] for t in ticks)
    if ages:
        print("INFO age of the sample read (plant write -> controller read): median %.2f ms, max %.2f ms"
              % (ages[len(ages) // 2] * 1e3, ages[-1] * 1e3))
    print("%d checks, %d failed" % (len(results), results.count(False)))
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main())
