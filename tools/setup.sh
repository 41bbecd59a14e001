#!/usr/bin/env bash
# Install the Debian 12 packages this project needs (idempotent: installs only what is missing).
# Why each one is here: see README.md, "Dependencies".
set -euo pipefail

PKGS=(
  cmake make gcc g++                     # host build
  libeigen3-dev                          # C++ reference EKF with AutoDiff Jacobians (tests only)
  libgsl-dev                             # identify: least squares with covariance, Brent minimiser
  python3-numpy python3-matplotlib       # tools/: plots and log conversion
  valgrind                               # callgrind instruction counts (benchmarks)
  gcc-arm-none-eabi libnewlib-arm-none-eabi  # Cortex-M4F cross build
  qemu-system-arm                        # Cortex-M4F in emulation: host-vs-QEMU ctest, ECU boot, CPU budget
  clang libclang-rt-14-dev               # libFuzzer targets, sanitizer runtime
  cppcheck clang-tidy                    # static analysis in the test command
  libgpiod-dev                           # Linux controller: GPIO through libgpiod 1.6 (static lib for the VM test)
  can-utils                              # candump: telemetry capture in the VM test and on the bench
  qemu-system-x86 busybox-static cpio acpica-tools  # VM test: Debian kernel under QEMU, initramfs, GPIO ACPI table (iasl)
)

missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: ${#missing[@]} of ${#PKGS[@]} packages missing: ${missing[*]}" >&2
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  echo "setup: apt-get update ..." >&2
  $SUDO apt-get update -qq
  # One progress line per package unpacked and set up (apt's own lines, filtered), so a first
  # install of several hundred MB does not look like a hang.
  echo "setup: installing (this can take several minutes the first time) ..." >&2
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}" 2>&1 |
    grep --line-buffered -E '^(Get:|Setting up|Need to get|E:)' | sed -u 's/^/setup:   /' >&2 || true
  still=()
  for p in "${missing[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || still+=("$p")
  done
  if ((${#still[@]})); then
    echo "setup: could not install: ${still[*]}" >&2
    exit 1
  fi
  echo "setup: done, all ${#PKGS[@]} packages present" >&2
else
  echo "setup: all ${#PKGS[@]} packages present" >&2
fi
