#!/usr/bin/env bash
# The population benchmark (issue 10): the estimator over the EVALUATION units of the throttle
# population (host_sim/plant/plant_draw.h; units 1000.., two classes) and the scenario mix, in
# three sections (stops_varied, all_varied, all_varied_adapted). Prints a table per scenario and writes
# out/population/summary.json (and out/population/runs.csv, one line per run).
#   usage: tools/run_population.sh [--quick] [--plants N] [--seeds S] [--duration S] [--params FILE] ...
# Default: 30 units per section x 8 scenarios x 3 seeds (2,160 runs, about 35 s on one core);
# --quick: 6 units x 1 seed (a few seconds). Every option goes to the population executable
# (population --help). Never fails on the figures; fails only if a step cannot run.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset host-release >/dev/null
cmake --build build/host-release -j"$(nproc 2>/dev/null || echo 2)" --target population >/dev/null
mkdir -p out/population
build/host-release/bin/population --json out/population/summary.json --runs-csv out/population/runs.csv "$@"
echo "summary: out/population/summary.json, per run: out/population/runs.csv"
