#!/usr/bin/env bash
# CPU budget of the Cortex-M4F build, counted in emulation (QEMU mps2-an386):
#   1. qemu_bench.elf "gen": the host_sim plant in closed loop with the application writes an
#      input stream (tests/m4f/tvlog_gen.h scenario, every mode); not measured;
#   2. qemu_bench.elf "run" replays it under "-d in_asm,exec,nochain"; count_insns.py sums the
#      instructions between the markers around app_step() and ekf_predict()/ekf_correct(), and
#      the 15 functions where the application step's instructions go.
# Deterministic: the counts do not depend on the host or its load.
# Usage: bench_qemu.sh QEMU_BENCH_ELF WORK_DIR [STEPS]
set -euo pipefail
elf=$1 work=$2 steps=${3:-2000}
here=$(cd "$(dirname "$0")" && pwd)
qemu=$(command -v qemu-system-arm || true)
if [ -z "$qemu" ]; then
  echo "  CPU budget: skipped, qemu-system-arm is not installed (Debian package qemu-system-arm)"
  exit 0
fi
mkdir -p "$work"
cd "$work"
q() { "$qemu" -M mps2-an386 -nographic -monitor none -serial none -kernel "$elf" "$@"; }
# (semihosting console output goes to QEMU's stderr)
q -semihosting-config "enable=on,target=native,arg=qemu_bench,arg=gen,arg=bench_in.log,arg=$steps" 2>bench_gen.txt \
  || { cat bench_gen.txt; exit 1; }
q -semihosting-config "enable=on,target=native,arg=qemu_bench,arg=run,arg=bench_in.log" \
  -d in_asm,exec,nochain -D /dev/fd/3 3>&1 2>bench_run.txt | "$here/count_insns.py" --profile 15
sed 's/^qemu_bench: /  (/; s/$/)/' bench_run.txt
