#!/usr/bin/python3
"""Choose the EKF's measurement and process noise by a fixed, documented procedure.

1. R from the sensor model, not by hand: each channel's variance is its noise variance plus the
   quantisation variance LSB^2 / 12 of the 12-bit ADC as seen in that channel's units
   (current: 0.01 A noise, LSB = Vref / 4096 / gain; angle: 1e-4 rad noise, LSB = travel /
   (4096 * 0.8 * 5 V * divider / Vref). The two position tracks quantise with identical errors
   (their counts are complementary), so averaging them does not reduce the quantisation term.
2. Q from two continuous densities (ekf_q_from_spectral: voltage noise qu on the armature,
   torque noise qT on the plate), searched on a logarithmic grid.
3. For every grid pair, a Monte Carlo of the default scenario over TRAINING seeds (1001 ..
   1000 + M, disjoint from the evaluation seeds 1 .. 100 that tests use) gives the average NEES
   and the velocity RMSE. Among the pairs whose ANEES lies in the inner half of the two-sided
   95 % chi-square band of an M-run average (half the band's width around its centre: a margin,
   so that the choice stays consistent on other seeds), the one with the smallest velocity RMSE
   wins; if none qualifies, the pair whose ANEES is closest to 3 (in log ratio) wins.
4. The result is printed as the two #defines of firmware/estimator/ekf.h and the R values of
   ekf_config_default(); the README records the run that set the defaults.

Usage: tools/tune_noise.py [--host-sim PATH] [--seeds M] [--scenario NAME]
"""
import argparse
import itertools
import json
import math
import os
import subprocess
import sys
import tempfile

# Sensor front end of host_sim/plant/plant.h (defaults) and the paper's noise levels.
ADC_REF_V, ADC_COUNTS = 3.3, 4096
CURRENT_GAIN_V_A, CURRENT_NOISE_A = 0.1, 0.01
TRAVEL_RAD = 84.0 * math.pi / 180.0
TPS_SPAN_FRAC, TPS_SUPPLY_V, TPS_DIVIDER = 0.8, 5.0, 0.66
ANGLE_NOISE_RAD = 1e-4


def r_from_sensor_model():
    lsb_current_A = ADC_REF_V / ADC_COUNTS / CURRENT_GAIN_V_A
    counts_per_travel = TPS_SPAN_FRAC * TPS_SUPPLY_V * TPS_DIVIDER / ADC_REF_V * ADC_COUNTS
    lsb_angle_rad = TRAVEL_RAD / counts_per_travel
    return (CURRENT_NOISE_A ** 2 + lsb_current_A ** 2 / 12.0,
            ANGLE_NOISE_RAD ** 2 + lsb_angle_rad ** 2 / 12.0)


def run_mc(host_sim, scenario, seeds, qu, qT, r_i, r_phi, outdir):
    cmd = [host_sim, "--scenario", scenario, "--mc", str(seeds), "--seed", "1001",
           "--qu", repr(qu), "--qT", repr(qT), "--r-current", repr(r_i), "--r-angle", repr(r_phi),
           "--out", outdir]
    res = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if res.returncode != 0:
        sys.exit(f"tune_noise: {' '.join(cmd)} failed ({res.returncode}): {res.stderr.strip()}")
    with open(os.path.join(outdir, f"{scenario}_mc_metrics.json"), encoding="utf-8") as fh:
        m = json.load(fh)
    c = m["consistency"] if "consistency" in m else m
    return c["anees"], tuple(c["band95_m_run_average"]), m["rmse_mean"]["app"]["velocity_rad_s"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--host-sim", default="build/host-release/bin/host_sim")
    ap.add_argument("--seeds", type=int, default=50)
    ap.add_argument("--scenario", default="paper_sine")
    a = ap.parse_args()
    if not os.access(a.host_sim, os.X_OK):
        sys.exit(f"tune_noise: {a.host_sim} is not an executable (build the host-release preset first)")
    if not 2 <= a.seeds <= 10000:
        sys.exit(f"tune_noise: --seeds must be 2..10000, got {a.seeds}")
    r_i, r_phi = r_from_sensor_model()
    print(f"R from the sensor model: current {r_i:.4g} A^2, angle {r_phi:.4g} rad^2")
    grid = [m * 10.0 ** e for e in range(-7, -4) for m in (1.0, 2.0, 5.0)] + [1e-4]
    grid_qu = grid
    grid_qT = grid
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n, (qu, qT) in enumerate(itertools.product(grid_qu, grid_qT), 1):
            anees, band, vel = run_mc(a.host_sim, a.scenario, a.seeds, qu, qT, r_i, r_phi, tmp)
            centre, half = (band[0] + band[1]) / 2.0, (band[1] - band[0]) / 2.0
            ok = abs(anees - centre) <= half / 2.0
            rows.append((qu, qT, anees, band, vel, ok))
            print(f"[{n:2d}/{len(grid_qu) * len(grid_qT)}] qu {qu:7.1e} qT {qT:7.1e}  ANEES {anees:7.3f} "
                  f"band [{band[0]:.3f}, {band[1]:.3f}] {'ok ' if ok else '-- '}  velocity RMSE {vel:.4f} rad/s",
                  file=sys.stderr)
    consistent = [r for r in rows if r[5]]
    if consistent:
        best = min(consistent, key=lambda r: r[4])
        why = f"{len(consistent)} pairs inside the inner half of the band; smallest velocity RMSE"
    else:
        best = min(rows, key=lambda r: abs(math.log(r[2] / 3.0)))
        why = "no pair consistent; ANEES closest to 3"
    qu, qT, anees, band, vel, _ = best
    print(f"chosen ({why}): qu = {qu:g} V^2 s, qT = {qT:g} N^2 m^2 s -> ANEES {anees:.3f} "
          f"(band [{band[0]:.3f}, {band[1]:.3f}]), velocity RMSE {vel:.4f} rad/s over {a.seeds} training seeds")
    print(f"#define EKF_DEFAULT_QU_V2_S TV_R({qu:.1e})")
    print(f"#define EKF_DEFAULT_QT_NM2_S TV_R({qT:.1e})")
    print(f"r = ({r_i:.4g}, 1, {r_phi:.4g})")


if __name__ == "__main__":
    main()
