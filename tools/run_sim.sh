#!/usr/bin/env bash
# The main job (the README's first command): set up, build, run the host simulation of the
# paper's experiment (12 V / 5 Hz sine, paper parameters, 2 s) against the plant model, and
# write the log, the metrics and the plots to out/. Extra arguments go to host_sim.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
cmake --preset host-release >/dev/null
cmake --build build/host-release -j"$(nproc 2>/dev/null || echo 2)" --target host_sim >/dev/null
# The scenario that runs and the output folder, as host_sim will see them, so the plot is of the
# run just made (not of a stale out/paper_sine.csv): the last --scenario / --out given wins.
scenario=paper_sine
outdir=out
mc=0
args=("$@")
for ((k = 0; k < ${#args[@]}; ++k)); do
  case "${args[k]}" in
    --scenario) scenario=${args[k + 1]:-paper_sine} ;;
    --out) outdir=${args[k + 1]:-out} ;;
    --mc) mc=1 ;;
    --help | -h | --print-params) exec build/host-release/bin/host_sim "$@" ;;
  esac
done
mkdir -p "$outdir"
build/host-release/bin/host_sim --out "$outdir" "$@"
if ((mc)); then
  echo "Monte Carlo metrics are in $outdir/ (${scenario}_mc_metrics.txt, .json); a Monte Carlo run writes no log to plot"
else
  /usr/bin/python3 tools/plot_run.py "$outdir/$scenario.csv" --out "$outdir"
  echo "log, metrics and plots of $scenario are in $outdir/"
fi
