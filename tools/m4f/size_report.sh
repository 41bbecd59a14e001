#!/usr/bin/env bash
# Print .text/.data/.bss of the estimator linked for Cortex-M4F: the estimator probe minus the
# empty probe (same start-up and libc). Usage: size_report.sh <empty.elf> <estimator.elf>
set -euo pipefail
read -r t0 d0 b0 _ < <(arm-none-eabi-size -B "$1" | tail -1)
read -r t1 d1 b1 _ < <(arm-none-eabi-size -B "$2" | tail -1)
echo "Cortex-M4F (-mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard -O3), float estimator incl. libm it pulls in:"
printf '  %-8s %8s bytes\n' ".text" $((t1 - t0)) ".data" $((d1 - d0)) ".bss" $((b1 - b0))
echo "  (.bss is one statically allocated ekf_t with its measurement and result structs)"
