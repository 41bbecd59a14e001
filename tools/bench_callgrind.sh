#!/usr/bin/env bash
# Instructions per EKF step, counted by valgrind's callgrind (repeatable, unlike wall time on a
# shared machine). Counts only what runs inside bench_run() of each workload, divided by the
# number of steps. Usage: tools/bench_callgrind.sh <build dir (host-release)> [steps]
# Prints one table; never fails on the numbers (it fails only if a workload cannot run).
set -euo pipefail
build=${1:?usage: bench_callgrind.sh <build dir> [steps]}
steps=${2:-2000}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

count() { # count <label> <toggle function> <cmd...>
  local label=$1 fn=$2; shift 2
  valgrind --tool=callgrind --toggle-collect="$fn" --callgrind-out-file="$tmp/cg.out" "$@" \
    >"$tmp/stdout" 2>"$tmp/stderr" || { echo "bench: '$*' failed:" >&2; cat "$tmp/stderr" >&2; exit 1; }
  local total
  total=$(awk '/^summary:/ {print $2}' "$tmp/cg.out")
  printf '%-58s %10d\n' "$label" $((total / steps))
}

echo "instructions per EKF step (x86-64, $(basename "$build"), valgrind callgrind, $steps steps)"
printf '%-58s %10s\n' "workload" "instr/step"
for v in f32 f64; do
  count "C $v filter arithmetic only, current+angle" bench_run "$build/bin/bench_ekf_$v" filter "$steps" 2
  count "C $v filter arithmetic only, current+velocity+angle" bench_run "$build/bin/bench_ekf_$v" filter "$steps" 3
  count "C $v filter + model (predict+correct), current+angle" bench_run "$build/bin/bench_ekf_$v" full "$steps" 2
  count "C $v filter + model, current+velocity+angle" bench_run "$build/bin/bench_ekf_$v" full "$steps" 3
done
if [ -x "$build/bin/bench_ref" ]; then
  count "Eigen reference filter arithmetic only" bench_loop_filter "$build/bin/bench_ref" filter "$steps"
  count "Eigen reference filter + model (AutoDiff Jacobian)" bench_loop_full "$build/bin/bench_ref" full "$steps"
fi
