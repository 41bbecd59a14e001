#!/usr/bin/env bash
# Replay throughput benchmark (issue 4): a 1-hour, 1 kHz raw log (3.6 M samples) replayed on one
# core from CSV and from binary. Prints samples per second, the share of time outside the
# estimator (measured inside replay around app_step(), and as a parse-only pass against the
# full replay), and peak RSS (getrusage ru_maxrss), also for a 60 s log to show that memory
# does not grow with the length. Targets: the hour in < 10 s from CSV, < 5 s from binary,
# peak RSS < 16 MiB. Never fails on the numbers; fails only if a step cannot run.
#   usage: tools/bench_replay.sh <build dir (host-release)> [seconds, default 3600]
# The logs are generated once by rawlog_gen (streaming, the plant driven open loop) into
# <build dir>/bench_replay/ and kept there (not in the source tree).
set -euo pipefail
build=${1:?usage: bench_replay.sh <build dir> [seconds]}
secs=${2:-3600}
gen=$build/bin/rawlog_gen
rep=$build/bin/replay
dir=$build/bench_replay
mkdir -p "$dir"

now() { date +%s.%N; }
calc() { awk "BEGIN { printf \"%.6f\", $1 }"; } # arithmetic without bc

for fmt in csv bin; do
  for s in "$secs" 60; do
    f=$dir/log_${s}s.$fmt
    if [ ! -s "$f" ] || [ "$gen" -nt "$f" ]; then
      t0=$(now)
      "$gen" --seconds "$s" --format "$fmt" -o "$f.tmp" 2>/dev/null
      mv "$f.tmp" "$f"
      printf 'generated %s (%s s of log) in %.1f s\n' "$f" "$s" "$(calc "$(now) - $t0")"
    fi
  done
done

field() { # field <regex with one group> <text>
  sed -n "s|.*$1.*|\\1|p" <<<"$2" | head -1
}

printf '\nreplay throughput, %s s log at 1 kHz, one core (%s, %s)\n' "$secs" "$(basename "$build")" \
  "$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)"
printf '%-6s %10s %9s %12s %10s %9s %11s %11s %10s %8s\n' format samples "wall [s]" "samples/s" \
  "parse [s]" "parse %" "estimator %" "outside %" "RSS [KiB]" target
for fmt in csv bin; do
  f=$dir/log_${secs}s.$fmt
  target=10
  [ "$fmt" = bin ] && target=5
  # 1. the replay as a user runs it (output formatted and written), wall clock outside
  t0=$(now)
  "$rep" --quiet "$f" -o /dev/null
  wall=$(calc "$(now) - $t0")
  # 2. the same with the time inside app_step() measured (adds ~4 clock reads per sample)
  timing=$("$rep" --quiet --timing "$f" -o /dev/null 2>&1 | grep 'timing:')
  est_pct=$(field 'app_step [0-9.]* s (\([0-9.]*\) %)' "$timing")
  out_pct=$(field 'outside the estimator \([0-9.]*\) %' "$timing")
  rss=$(field 'peak RSS \([0-9]*\) KiB' "$timing")
  samples=$(field 'timing: [0-9.]* s total, \([0-9]*\) samples/s' "$timing")
  # 3. read and validate only
  t0=$(now)
  "$rep" --quiet --parse-only "$f"
  parse=$(calc "$(now) - $t0")
  n=$((secs * 1000))
  printf '%-6s %10d %9.2f %12.0f %10.2f %9.1f %11s %11s %10s %8s\n' "$fmt" "$n" "$wall" \
    "$(calc "$n / $wall")" "$parse" "$(calc "100 * $parse / $wall")" "$est_pct" "$out_pct" "$rss" \
    "$(awk "BEGIN { print ($wall < $target) ? \"<${target}s ok\" : \"<${target}s MISSED\" }")"
  : "$samples"
done
for fmt in csv bin; do
  timing=$("$rep" --quiet --timing "$dir/log_60s.$fmt" -o /dev/null 2>&1 | grep 'timing:')
  printf 'peak RSS replaying 60 s of %s: %s KiB (constant memory: compare with the hour above; target < 16384)\n' \
    "$fmt" "$(field 'peak RSS \([0-9]*\) KiB' "$timing")"
done
printf '(parse %% = a read-and-validate-only pass against the full replay; estimator %% = time inside app_step(),\n'
printf ' outside %% = everything else: reading, parsing, CRC, output formatting and writing)\n'
