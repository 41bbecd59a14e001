#!/usr/bin/env bash
# ctest m4f_qemu_ecu_boot (label qemu): boots the ECU firmware (its trace build, ecu_trace.elf:
# the same code as ecu.elf plus semihosting prints) on QEMU's netduinoplus2 (STM32F405) and
# checks what that machine can show:
#   - the reset handler and main() run from the vector table at 0x08000000 (VTOR set);
#   - the clock set-up runs to completion: QEMU 7.2 models no RCC, so HSE and PLL never report
#     ready and the bounded waits take the documented fallback (HSI, flagged, outputs OFF);
#   - the 1 kHz control interrupt (TIM2, IRQ 28 = exception 44) is taken through the vector
#     table and runs app_tick(); QEMU models no ADC injected conversions and no TIM1, so the
#     tick finds no fresh sample and drives the safe state (duty 0, bridge disabled), and the
#     main loop reloads the watchdog after each tick.
# Usage: run_qemu_ecu_boot.sh SRC_DIR WORK_DIR. Exit 77 (skip) only without qemu-system-arm.
set -euo pipefail
src=$1 work=$2
qemu=$(command -v qemu-system-arm || true)
if [ -z "$qemu" ]; then
  echo "SKIP: qemu-system-arm is not installed (Debian package qemu-system-arm)"
  exit 77
fi
m4f="$src/build/m4f"
mkdir -p "$work" "$src/build"
log="$work/m4f_build_boot.log"
(
  flock 9
  if [ ! -f "$m4f/CMakeCache.txt" ]; then
    (cd "$src" && cmake --preset m4f) >"$log" 2>&1 || { cat "$log"; exit 1; }
  fi
  cmake --build "$m4f" --target ecu_trace >>"$log" 2>&1 || { cat "$log"; exit 1; }
) 9>"$src/build/.m4f.lock"

cd "$work"
# Semihosting prints go to stderr with the -d log; split them by prefix.
timeout 60 "$qemu" -M netduinoplus2 -nographic -monitor none -serial none \
  -semihosting-config enable=on,target=native -kernel "$m4f/firmware/ecu/ecu_trace.elf" \
  -d int -D ecu_boot_qemu.log 2>ecu_boot.txt
cat ecu_boot.txt
fail=0
need() { # pattern description
  if grep -q -- "$1" ecu_boot.txt; then echo "ok: $2"; else echo "FAILED: $2"; fail=1; fi
}
need ".data initialised in RAM" ".data copied from flash by the reset handler (QEMU loads it at its flash address only)"
need "FPU enabled" "FPU enabled by the reset handler (CPACR)"
need "vector table at 0x08000000, VTOR 0x08000000" "vector table at the start of flash, VTOR points at it"
need "clock set-up rc" "clock set-up returned (bounded waits, fallback flagged)"
need "control ticks (TIM2 interrupt -> app_tick) 2[0-9]" "20 control interrupts ran app_tick()"
taken=$(grep -c "loading from element 44 of non-secure vector table at 0x80000b0" ecu_boot_qemu.log || true)
echo "QEMU: TIM2 interrupt (exception 44) taken through the vector table entry at 0x080000b0: $taken times"
((taken >= 20)) || { echo "FAILED: too few TIM2 interrupts"; fail=1; }
# The writes to the peripherals QEMU does not model (TIM1 CCR1 = ARR + 1: 0 % duty, GPIOB BSRR:
# bridge disabled, IWDG KR = 0xAAAA: reload) are visible with "-d unimp"; not checked here
# because that log slows the emulated timers down (about 7 s instead of under 1 s).
exit $fail
