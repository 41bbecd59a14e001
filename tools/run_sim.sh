#!/usr/bin/env bash
# The main job (the README's first command): set up, build, run the host simulation of the
# paper's experiment (12 V / 5 Hz sine, paper parameters, 2 s) against the plant model, and
# write the log, the metrics and the plots to out/. Extra arguments go to host_sim.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
cmake --preset host-release >/dev/null
cmake --build build/host-release -j"$(nproc 2>/dev/null || echo 2)" --target host_sim >/dev/null
mkdir -p out
build/host-release/bin/host_sim --out out "$@"
/usr/bin/python3 tools/plot_run.py out/paper_sine.csv --out out
echo "log, metrics and plots are in out/"
