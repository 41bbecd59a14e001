#!/usr/bin/env bash
# Firmware report of the Cortex-M4F build: flash and RAM use of the ECU image, the heap guard's
# negative test, the worst-case stack, and the CPU budget counted in emulation.
# Usage: firmware_report.sh BUILD_DIR what...   what: size heap stack bench (default: all)
# Run by the targets firmware_report (all), firmware_size, firmware_stack, firmware_bench of the
# m4f build; CMake writes BUILD_DIR/report/heap_guard_args.sh (the link set-up of the ECU).
set -euo pipefail
b=$1
shift
what=${*:-size heap stack bench}
here=$(cd "$(dirname "$0")" && pwd)
ecu=$b/firmware/ecu/ecu.elf

for w in $what; do
case $w in
size)
  echo "== ECU image (STM32F405/407: 1024 KiB flash, 128 KiB SRAM) =="
  arm-none-eabi-size -A -d "$ecu" | awk '
    $1 ~ /^\.(isr_vector|text|rodata|ARM\.extab|ARM\.exidx|init_array)$/ { code += $2 }
    $1 == ".data" { data = $2 } $1 == ".bss" { bss = $2 } $1 == ".stack" { stack = $2 }
    END {
      printf "  .text %d B (vectors, code, constants)   .data %d B   .bss %d B   stack %d B reserved\n", code, data, bss, stack
      printf "  flash: %6d B of 1048576 (%.1f %%)   .text + .data initial values\n", code + data, 100 * (code + data) / 1048576
      printf "  RAM:   %6d B of  131072 (%.1f %%)   .data + .bss + stack; heap: none (link fails if malloc is used)\n", data + bss + stack, 100 * (data + bss + stack) / 131072
    }'
  echo "  outputs: $(cd "$(dirname "$ecu")" && ls ecu.elf ecu.bin ecu.hex ecu.map ecu.size.txt | tr '\n' ' ')"
  ;;
heap)
  echo "== heap guard (negative link tests) =="
  # shellcheck disable=SC1091
  source "$b/report/heap_guard_args.sh"
  "${HEAP_GUARD_CMD[@]}"
  ;;
stack)
  echo "== stack =="
  "$here/stack_report.py" "$ecu" --level "TIM2_IRQHandler CAN1_TX_IRQHandler CAN1_RX0_IRQHandler" \
    --level "MemManage_Handler BusFault_Handler UsageFault_Handler HardFault_Handler" --level "NMI_Handler"
  echo "  (levels: thread; control + CAN interrupts at priority 1 (they do not preempt each other);"
  echo "   a fault on top; NMI on top of that. Each level adds one 108-byte FPU exception frame.)"
  "$here/stack_report.py" "$b/tests/m4f/qemu_replay.elf" | sed -n '1,2p'
  if command -v qemu-system-arm >/dev/null; then
    q="qemu-system-arm -M mps2-an386 -nographic -monitor none -serial none"
    [ -f "$b/report/bench_in.log" ] || (cd "$b/report" && $q -kernel "$b/tests/m4f/qemu_bench.elf" \
      -semihosting-config enable=on,target=native,arg=qemu_bench,arg=gen,arg=bench_in.log,arg=2000 2>/dev/null)
    (cd "$b/report" && qemu-system-arm -M mps2-an386 -nographic -monitor none -serial none \
      -semihosting-config enable=on,target=native,arg=qemu_replay,arg=bench_in.log,arg=replay_out.bin \
      -kernel "$b/tests/m4f/qemu_replay.elf") 2>&1 | sed 's/^qemu_replay: /  measured in QEMU (painted stack), same image: /'
  fi
  ;;
bench)
  echo "== CPU budget =="
  "$here/bench_qemu.sh" "$b/tests/m4f/qemu_bench.elf" "$b/report"
  ;;
esac
done
