#!/bin/sh
# Bounded libFuzzer run for ctest (label fuzz): fuzz_run.sh FUZZER SEED_DIR WORK_DIR [DICT]
# Runs FUZZER for TV_FUZZ_SECONDS (default 10) on a copy of the seed corpus in WORK_DIR and
# prints libFuzzer's final statistics. Exit 77 (ctest SKIP_RETURN_CODE) when the fuzzer was not
# built because clang's libFuzzer runtime is missing; non-zero when libFuzzer finds a crash, a
# sanitizer report or a broken invariant (the reproducer is left in WORK_DIR).
set -eu
fuzzer=$1
seeds=$2
work=$3
dict=${4:-}
secs=${TV_FUZZ_SECONDS:-10}
if [ ! -x "$fuzzer" ]; then
  echo "skipped: $fuzzer not built (clang with libFuzzer, package libclang-rt-14-dev, not found at configure time)"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work/corpus"
cp "$seeds"/* "$work/corpus/"
set -- -max_total_time="$secs" -max_len=8192 -timeout=10 -rss_limit_mb=1024 -print_final_stats=1 \
  -artifact_prefix="$work/"
if [ -n "$dict" ]; then set -- "$@" -dict="$dict"; fi
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  "$fuzzer" "$@" "$work/corpus" >"$work/log" 2>&1 || { tail -60 "$work/log"; exit 1; }
grep -E '^(#[0-9]+.*DONE|stat::number_of_executed_units|stat::peak_rss_mb|stat::new_units_added)' "$work/log" || true
echo "corpus: $(ls "$work/corpus" | wc -l) inputs after ${secs} s"
