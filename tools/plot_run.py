#!/usr/bin/python3
"""Plot a run: the paper's Figures 6-8 redone from a host_sim run CSV or a replay output CSV.

Usage: plot_run.py RUN.csv [--out DIR] [--zoom T0 T1]

Both executables write the same column names for the same quantities (i_est_A, w_sigma_rad_s,
innov_phi_rad, i_true_A, ...); time is t_s in host_sim and t_us in replay (the raw log's
integer timestamps), and both are read. Comment lines (#) are skipped, an empty field (a channel
not used) is a gap. What a file does not carry is left out of the plots: a replayed bench log
has no truth (then no error figure), replay writes measurements only with --wide.

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
    "i_est_A", "w_est_rad_s", "phi_est_rad",
    "i_sigma_A", "w_sigma_rad_s", "phi_sigma_rad",
    "faults",
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
            if "t_s" not in header and "t_us" not in header:
                missing.insert(0, "t_s or t_us")
            if missing:
                raise CsvError(f"{path}: not a host_sim or replay output: missing column(s) {', '.join(missing)}")
            rows = []
            for lineno, row in enumerate(reader, start=2):
                if not row or row[0].lstrip().startswith("#"):
                    continue
                if len(row) != len(header):
                    raise CsvError(f"{path}:{lineno}: {len(row)} fields, the header has {len(header)}")
                try:
                    rows.append([float(v) if v.strip() != "" else np.nan for v in row])
                except ValueError as e:
                    raise CsvError(f"{path}:{lineno}: not a number ({e})") from None
    except OSError as e:
        raise CsvError(f"cannot read {path}: {e.strerror}") from None
    if len(rows) < 2:
        raise CsvError(f"{path}: needs at least 2 data lines, has {len(rows)}")
    data = np.array(rows, dtype=float)
    d = {name: data[:, k] for k, name in enumerate(header)}
    if "t_s" not in d:
        d["t_s"] = d["t_us"] * 1e-6
    return d


def band(ax, t, centre, sigma, color, label):
    ax.fill_between(t, centre - 3.0 * sigma, centre + 3.0 * sigma, color=color, alpha=0.25, lw=0, label=label)


def title_of(d, stem):
    faults = int(np.max(d["faults"])) if len(d["faults"]) else 0
    mode = ""
    if "mode" in d:
        modes = sorted({int(m) for m in d["mode"]})
        mode = ", mode " + "/".join(MODE_NAMES.get(m, str(m)) for m in modes)
    return f"{stem}{mode}, faults 0x{faults:02x}"


def legend_outside(ax):
    """Legend right of the axes, where it covers no data."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)


def states_figure(d, stem, sel, path, subtitle):
    t = d["t_s"][sel]
    fig, axes = plt.subplots(3, 1, figsize=(14, 10), sharex=True)
    panels = [
        ("i", "A", "motor current [A]"),
        ("w", "rad_s", "angular velocity [rad/s]"),
        ("phi", "rad", "plate angle [rad]"),
    ]
    for ax, (s, unit, ylabel) in zip(axes, panels):
        est = d[f"{s}_est_{unit}"][sel]
        sig = d[f"{s}_sigma_{unit}"][sel]
        if f"{s}_meas_{unit}" in d:
            mlabel = "measured (differentiated angle)" if s == "w" else "measured"
            ax.plot(t, d[f"{s}_meas_{unit}"][sel], color="tab:blue", lw=0.8, label=mlabel)
        if f"{s}_true_{unit}" in d:
            ax.plot(t, d[f"{s}_true_{unit}"][sel], color="black", lw=1.0, label="true (plant)")
        band(ax, t, est, sig, "tab:red", "app filter +-3 sigma")
        ax.plot(t, est, color="tab:red", lw=1.2, ls="--", label="app filter estimate")
        if s == "w" and "w_paper_rad_s" in d:
            ax.plot(t, d["w_paper_rad_s"][sel], color="tab:green", lw=1.0, ls=":",
                    label="paper set-up filter\n(3 meas, paper Q/R)")
        if s == "phi" and "target_rad" in d and np.any(np.isfinite(d["target_rad"][sel])):
            ax.plot(t, d["target_rad"][sel], color="tab:purple", lw=1.0, ls="-.", label="target")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        legend_outside(ax)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{title_of(d, stem)}: measured vs estimated states{subtitle}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def residual_figure(d, stem, path):
    t = d["t_s"]
    fig, axes = plt.subplots(2, 1, figsize=(14, 7), sharex=True)
    for ax, (col, scol, ylabel, color) in zip(axes, [
        ("innov_i_A", "innov_i_sigma_A", "current residual [A]", "tab:blue"),
        ("innov_phi_rad", "innov_phi_sigma_rad", "angle residual [rad]", "tab:cyan"),
    ]):
        if col not in d:
            ax.set_visible(False)
            continue
        # replay writes the innovation sigmas with --wide only: no band without them
        s = d[scol] if scol in d else np.full_like(t, np.nan)
        used = np.isfinite(d[col]) & (np.isnan(s) | (s > 0))
        ax.fill_between(t, np.where(used, -3 * s, np.nan), np.where(used, 3 * s, np.nan),
                        color="gray", alpha=0.25, lw=0, label="+-3 sqrt(S)")
        ax.plot(t, np.where(used, d[col], np.nan), color=color, lw=0.8, label="residual z - x_pred")
        # scale to the settled part (the first corrections carry the large initial P0)
        settled = used & (t >= t[0] + min(0.2, 0.1 * (t[-1] - t[0])))
        if np.count_nonzero(settled) > 10:
            sig99 = np.nanpercentile(s[settled], 99) if np.any(np.isfinite(s[settled])) else 0.0
            lim = 1.3 * max(np.percentile(np.abs(d[col][settled]), 99.9), 3.0 * sig99)
            if lim > 0:
                ax.set_ylim(-lim, lim)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        legend_outside(ax)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{title_of(d, stem)}: residuals of the app filter (paper Fig. 8)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def error_figure(d, stem, path):
    """Errors against the truth with the filter's +-3 sigma band. Each panel is scaled to the
    filter's band and error, so the band is visible; the measurement's (or the differentiated
    angle's) error is drawn behind it and, where it leaves that scale, clipped: the legend says so."""
    t = d["t_s"]
    fig, axes = plt.subplots(3, 1, figsize=(14, 10), sharex=True)
    settle = t >= t[0] + min(0.2, 0.1 * (t[-1] - t[0]))
    for ax, (s, unit, ylabel) in zip(axes, [
        ("i", "A", "current error [A]"),
        ("w", "rad_s", "velocity error [rad/s]"),
        ("phi", "rad", "angle error [rad]"),
    ]):
        true = d[f"{s}_true_{unit}"]
        err = d[f"{s}_est_{unit}"] - true
        sig = d[f"{s}_sigma_{unit}"]
        lim = 1.5 * max(np.nanpercentile(np.abs(err[settle]), 99.5), 3.0 * np.nanpercentile(sig[settle], 99), 1e-9)
        if f"{s}_meas_{unit}" in d:
            err_meas = d[f"{s}_meas_{unit}"] - true
            clipped = np.nanmax(np.abs(err_meas[settle])) > lim
            what = "differentiated angle - true" if s == "w" else "measured - true"
            ax.plot(t, np.clip(err_meas, -lim, lim), color="tab:blue", lw=0.6, alpha=0.5,
                    label=what + (f"\n(clipped at +-{lim:.3g})" if clipped else ""))
        band(ax, t, np.zeros_like(t), sig, "tab:red", "+-3 sigma (app filter)")
        beyond = np.nanmax(np.abs(err[settle])) > lim
        ax.plot(t, np.clip(err, -lim, lim), color="tab:red", lw=1.0,
                label="app filter - true" + (f"\n(peaks clipped at +-{lim:.3g})" if beyond else ""))
        if s == "w" and "w_paper_rad_s" in d:
            ax.plot(t, np.clip(d["w_paper_rad_s"] - true, -lim, lim), color="tab:green", lw=0.8, ls=":",
                    label="paper set-up filter - true\n(clipped to the same scale)")
        ax.set_ylim(-lim, lim)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        legend_outside(ax)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{title_of(d, stem)}: estimation errors against the plant truth, scaled to the filter's band "
                 f"(the first {min(0.2, 0.1 * (t[-1] - t[0])):.2g} s of convergence may leave the scale)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv):
    ap = argparse.ArgumentParser(description="Plot a host_sim run CSV or a replay output (paper Figures 6-8).")
    ap.add_argument("csv", metavar="RUN.csv", help="run log written by host_sim, or replay's output")
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
    has_truth = all(c in d for c in ("i_true_A", "w_true_rad_s", "phi_true_rad"))
    names = ["fig6_states", "fig7_zoom", "fig8_residuals"] + (["errors"] if has_truth else [])
    paths = [os.path.join(out_dir, f"{stem}_{n}.png") for n in names]
    states_figure(d, stem, np.ones_like(t, dtype=bool), paths[0], "")
    states_figure(d, stem, sel, paths[1], f" ({t0:.3f} .. {t1:.3f} s)")
    residual_figure(d, stem, paths[2])
    if has_truth:
        error_figure(d, stem, paths[3])
    else:
        print("no truth columns (a bench log): no error figure")
    for p in paths:
        print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
