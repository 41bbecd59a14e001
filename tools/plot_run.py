#!/usr/bin/python3
"""Plot a host_sim run: the paper's Figures 6-8 redone from a run's CSV, with the truth added.

Usage: plot_run.py RUN.csv [--out DIR] [--zoom T0 T1]

Writes, into DIR (default: the CSV's directory), for RUN = the CSV's name without .csv:
  RUN_fig6_states.png     measured vs estimated current, velocity, angle over the whole run
                          (paper Fig. 6/7), with the true signal, the +-3 sigma band of the
                          application filter and the paper-faithful filter's velocity;
  RUN_fig7_zoom.png       the same over a short window (default 0.2 s from the middle of the
                          run; --zoom T0 T1 in seconds), where the bands are visible;
  RUN_fig8_residuals.png  innovations (residuals) of current and angle with +-3 sqrt(S)
                          (paper Fig. 8);
  RUN_errors.png          estimation errors (estimate - truth) with +-3 sigma, and the errors
                          of the measurement / the differentiated angle.
Runs with Debian's /usr/bin/python3 (numpy, matplotlib); no display needed (Agg backend).
Exit status: 0 ok, 2 bad arguments or unreadable / malformed CSV.
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

REQUIRED = [
    "t_s", "i_true_A", "w_true_rad_s", "phi_true_rad",
    "i_meas_A", "w_meas_rad_s", "phi_meas_rad",
    "i_est_A", "w_est_rad_s", "phi_est_rad",
    "i_sigma_A", "w_sigma_rad_s", "phi_sigma_rad",
    "innov_i_A", "innov_phi_rad", "innov_i_sigma_A", "innov_phi_sigma_rad",
    "w_paper_rad_s", "faults",
]

MODE_NAMES = {0: "off", 1: "sine", 2: "steps", 3: "chirp", 4: "position"}


class CsvError(Exception):
    """The run file cannot be used."""


def load(path):
    """Read the CSV into a dict of float arrays; raise CsvError with a clear message."""
    try:
        with open(path, newline="") as f:
            reader = csv.reader(f)
            try:
                header = next(reader)
            except StopIteration:
                raise CsvError(f"{path}: empty file (no header line)") from None
            header = [h.strip() for h in header]
            missing = [c for c in REQUIRED if c not in header]
            if missing:
                raise CsvError(f"{path}: not a host_sim run log: missing column(s) {', '.join(missing)}")
            rows = []
            for lineno, row in enumerate(reader, start=2):
                if not row:
                    continue
                if len(row) != len(header):
                    raise CsvError(f"{path}:{lineno}: {len(row)} fields, the header has {len(header)}")
                try:
                    rows.append([float(v) for v in row])
                except ValueError as e:
                    raise CsvError(f"{path}:{lineno}: not a number ({e})") from None
    except OSError as e:
        raise CsvError(f"cannot read {path}: {e.strerror}") from None
    if len(rows) < 2:
        raise CsvError(f"{path}: needs at least 2 data lines, has {len(rows)}")
    data = np.array(rows, dtype=float)
    return {name: data[:, k] for k, name in enumerate(header)}


def band(ax, t, centre, sigma, color, label):
    ax.fill_between(t, centre - 3.0 * sigma, centre + 3.0 * sigma, color=color, alpha=0.25, lw=0, label=label)


def title_of(d, stem):
    faults = int(np.max(d["faults"])) if len(d["faults"]) else 0
    mode = ""
    if "mode" in d:
        modes = sorted({int(m) for m in d["mode"]})
        mode = ", mode " + "/".join(MODE_NAMES.get(m, str(m)) for m in modes)
    return f"{stem}{mode}, faults 0x{faults:02x}"


def states_figure(d, stem, sel, path, subtitle):
    t = d["t_s"][sel]
    fig, axes = plt.subplots(3, 1, figsize=(12, 10), sharex=True)
    panels = [
        ("i", "A", "motor current [A]"),
        ("w", "rad_s", "angular velocity [rad/s]"),
        ("phi", "rad", "plate angle [rad]"),
    ]
    for ax, (s, unit, ylabel) in zip(axes, panels):
        meas = d[f"{s}_meas_{unit}"][sel]
        est = d[f"{s}_est_{unit}"][sel]
        sig = d[f"{s}_sigma_{unit}"][sel]
        true = d[f"{s}_true_{unit}"][sel]
        mlabel = "measured (differentiated angle)" if s == "w" else "measured"
        ax.plot(t, meas, color="tab:blue", lw=0.8, label=mlabel)
        ax.plot(t, true, color="black", lw=1.0, label="true (plant)")
        band(ax, t, est, sig, "tab:red", "app filter +-3 sigma")
        ax.plot(t, est, color="tab:red", lw=1.2, ls="--", label="app filter estimate")
        if s == "w":
            ax.plot(t, d["w_paper_rad_s"][sel], color="tab:green", lw=1.0, ls=":",
                    label="paper set-up filter (3 meas, paper Q/R)")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize=8, ncol=2)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{title_of(d, stem)}: measured vs estimated states{subtitle}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def residual_figure(d, stem, path):
    t = d["t_s"]
    fig, axes = plt.subplots(2, 1, figsize=(12, 7), sharex=True)
    for ax, (col, scol, ylabel, color) in zip(axes, [
        ("innov_i_A", "innov_i_sigma_A", "current residual [A]", "tab:blue"),
        ("innov_phi_rad", "innov_phi_sigma_rad", "angle residual [rad]", "tab:cyan"),
    ]):
        s = d[scol]
        used = s > 0
        ax.fill_between(t, np.where(used, -3 * s, np.nan), np.where(used, 3 * s, np.nan),
                        color="gray", alpha=0.25, lw=0, label="+-3 sqrt(S)")
        ax.plot(t, np.where(used, d[col], np.nan), color=color, lw=0.8, label="residual z - x_pred")
        # scale to the settled part (the first corrections carry the large initial P0)
        settled = used & (t >= t[0] + min(0.2, 0.1 * (t[-1] - t[0])))
        if np.count_nonzero(settled) > 10:
            lim = 1.3 * max(np.percentile(np.abs(d[col][settled]), 99.9), 3.0 * np.percentile(s[settled], 99))
            if lim > 0:
                ax.set_ylim(-lim, lim)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{title_of(d, stem)}: residuals of the app filter (paper Fig. 8)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def error_figure(d, stem, path):
    t = d["t_s"]
    fig, axes = plt.subplots(3, 1, figsize=(12, 10), sharex=True)
    for ax, (s, unit, ylabel) in zip(axes, [
        ("i", "A", "current error [A]"),
        ("w", "rad_s", "velocity error [rad/s]"),
        ("phi", "rad", "angle error [rad]"),
    ]):
        true = d[f"{s}_true_{unit}"]
        err_meas = d[f"{s}_meas_{unit}"] - true
        err = d[f"{s}_est_{unit}"] - true
        sig = d[f"{s}_sigma_{unit}"]
        ax.plot(t, err_meas, color="tab:blue", lw=0.6, alpha=0.6,
                label="measured - true" if s != "w" else "differentiated angle - true")
        band(ax, t, np.zeros_like(t), sig, "tab:red", "+-3 sigma (app filter)")
        ax.plot(t, err, color="tab:red", lw=1.0, label="app filter - true")
        if s == "w":
            ax.plot(t, d["w_paper_rad_s"] - true, color="tab:green", lw=0.8, ls=":",
                    label="paper set-up filter - true")
            lim = 4.0 * max(np.nanpercentile(np.abs(err_meas), 99), 1e-3)
            ax.set_ylim(-lim, lim)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize=8, ncol=2)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{title_of(d, stem)}: estimation errors against the plant truth")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv):
    ap = argparse.ArgumentParser(description="Plot a host_sim run CSV (paper Figures 6-8, with the truth).")
    ap.add_argument("csv", metavar="RUN.csv", help="run log written by host_sim")
    ap.add_argument("--out", metavar="DIR", help="output directory (default: the CSV's directory)")
    ap.add_argument("--zoom", nargs=2, type=float, metavar=("T0", "T1"),
                    help="window of the zoomed figure [s] (default: 0.2 s from the middle of the run)")
    args = ap.parse_args(argv)
    try:
        d = load(args.csv)
    except CsvError as e:
        print(f"plot_run.py: error: {e}", file=sys.stderr)
        return 2
    out_dir = args.out if args.out else (os.path.dirname(os.path.abspath(args.csv)))
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as e:
        print(f"plot_run.py: error: cannot create {out_dir}: {e.strerror}", file=sys.stderr)
        return 2
    stem = os.path.splitext(os.path.basename(args.csv))[0]
    t = d["t_s"]
    if args.zoom:
        t0, t1 = args.zoom
        if not t1 > t0:
            print(f"plot_run.py: error: --zoom {t0} {t1}: T1 must be greater than T0", file=sys.stderr)
            return 2
    else:
        t0 = t[0] + 0.5 * (t[-1] - t[0])
        t1 = t0 + 0.2
    sel = (t >= t0) & (t <= t1)
    if np.count_nonzero(sel) < 2:
        print(f"plot_run.py: error: --zoom {t0} {t1} selects fewer than 2 samples "
              f"(run spans {t[0]:g} .. {t[-1]:g} s)", file=sys.stderr)
        return 2
    paths = [os.path.join(out_dir, f"{stem}_{n}.png") for n in ("fig6_states", "fig7_zoom", "fig8_residuals", "errors")]
    states_figure(d, stem, np.ones_like(t, dtype=bool), paths[0], "")
    states_figure(d, stem, sel, paths[1], f" ({t0:.3f} .. {t1:.3f} s)")
    residual_figure(d, stem, paths[2])
    error_figure(d, stem, paths[3])
    for p in paths:
        print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
