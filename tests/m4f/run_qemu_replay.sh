#!/usr/bin/env bash
# ctest m4f_qemu_replay (label qemu): the float application on the Cortex-M4F, emulated by QEMU
# (mps2-an386, Cortex-M4 with FPU), against the host float build (app_f32) on one input stream.
#
#   run_qemu_replay.sh SRC_DIR WORK_DIR HOST_TOOL HOST_TOOL_PORTABLE
#
# 1. builds the cross images itself: configures the m4f preset into SRC_DIR/build/m4f if needed,
#    builds qemu_replay.elf and qemu_replay_portable.elf (serialised by a lock file);
# 2. generates the input stream on the host (host_sim plant in closed loop, every mode, a gap,
#    faults) and replays it on both sides;
# 3. portable pair (expf/sinf replaced by one float-only implementation on both sides): every
#    output word of every record must be bit-identical;
#    native pair (glibc vs newlib libm, what the ECU really runs): discrete outputs identical,
#    floats within the tolerances documented in m4f_replay_host.c.
# Exit 77 (ctest SKIP) only when qemu-system-arm is not installed.
set -euo pipefail
src=$1 work=$2 host=$3 hostp=$4
qemu=$(command -v qemu-system-arm || true)
if [ -z "$qemu" ]; then
  echo "SKIP: qemu-system-arm is not installed (Debian package qemu-system-arm)"
  exit 77
fi
m4f="$src/build/m4f"
mkdir -p "$work" "$src/build"
log="$work/m4f_build.log"
(
  flock 9
  if [ ! -f "$m4f/CMakeCache.txt" ]; then
    (cd "$src" && cmake --preset m4f) >"$log" 2>&1 || { cat "$log"; exit 1; }
  fi
  cmake --build "$m4f" --target qemu_replay qemu_replay_portable >>"$log" 2>&1 || { cat "$log"; exit 1; }
) 9>"$src/build/.m4f.lock"

cd "$work"
run_qemu() { # image out
  timeout 300 "$qemu" -M mps2-an386 -nographic -monitor none -serial none \
    -semihosting-config "enable=on,target=native,arg=qemu_replay,arg=in.log,arg=$2" -kernel "$1"
}
"$host" gen in.log
"$host" run in.log host_native.bin
"$hostp" run in.log host_portable.bin
t0=$(date +%s%N)
run_qemu "$m4f/tests/m4f/qemu_replay.elf" qemu_native.bin
run_qemu "$m4f/tests/m4f/qemu_replay_portable.elf" qemu_portable.bin
echo "qemu: two replays in $(( ($(date +%s%N) - t0) / 1000000 )) ms"

echo "== portable expf/sinf on both sides: host x86-64 SSE vs Cortex-M4F FPU =="
"$host" compare host_portable.bin qemu_portable.bin exact
echo "== native libm (glibc on the host, newlib on the Cortex-M4F) =="
"$host" compare host_native.bin qemu_native.bin tol
