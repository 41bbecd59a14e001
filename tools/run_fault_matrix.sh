#!/usr/bin/env bash
# Fault-matrix benchmark (issue 12, first version): every fault kind of host_sim --fault at one
# magnitude, from ONSET s, injected into the population benchmark's runs (population --fault),
# plus the healthy population; tools/fault_matrix.py tabulates per fault the runs whose expected
# diagnostic code was confirmed, mis-isolated, missed, and the latency of the first
# confirmation. Writes out/fault_matrix/<spec>.csv (one line per run), matrix.md, population.log.
#   usage: tools/run_fault_matrix.sh [population options, e.g. --quick | --plants N --seeds S]
# Default: 10 units per section x 8 scenarios x 1 seed per fault (160 runs, a few seconds each).
# Never fails on the figures; fails only if a step cannot run.
set -euo pipefail
cd "$(dirname "$0")/.."
ONSET=1.0
cmake --preset host-release >/dev/null
cmake --build build/host-release -j"$(nproc 2>/dev/null || echo 2)" --target population >/dev/null
dir=out/fault_matrix
rm -rf "$dir"
mkdir -p "$dir"
# the two sections whose runs start at the scenario (all_varied_adapted begins with 5 s of open-loop
# warm-up, which would count a closed-loop detector's wait for the scenario as its latency)
args=(--plants 10 --seeds 1 --sections stops,all)
if (($#)); then args=(--sections stops,all "$@"); fi
specs=(friction_high:2 jam:10 spring_weak:0.3 winding_resistance_high:1.5 winding_open winding_short:0.5
  tps1_offset:1 tps1_gain:5 tps1_stuck tps1_intermittent:0.1 tps2_offset:-1 tps2_gain:-5 tps2_stuck
  tps2_intermittent:0.1 current_offset:0.05 current_gain:5 bridge_pos_lost bridge_neg_lost supply_sag:3)
build/host-release/bin/population "${args[@]}" --json "$dir/healthy.json" --runs-csv "$dir/healthy.csv" >/dev/null 2>"$dir/population.log"
for s in "${specs[@]}"; do
  build/host-release/bin/population "${args[@]}" --fault "$s@$ONSET" --json "$dir/$s.json" --runs-csv "$dir/$s.csv" >/dev/null 2>>"$dir/population.log"
  rm -f "$dir/$s.json"
done
rm -f "$dir/healthy.json"
/usr/bin/python3 tools/fault_matrix.py "$dir" "$ONSET"
echo "per run: $dir/<fault>.csv; table: $dir/matrix.md"
