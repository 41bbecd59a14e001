#!/usr/bin/env bash
# The Linux controller against a real kernel (ctest test_vm, label "vm"): boots Debian 12's
# PREEMPT_RT kernel under qemu-system-x86_64 (TCG: software emulation, no KVM needed) with a
# busybox initramfs holding the CAN and GPIO modules and the static test binaries, and runs
# there (tests/vm/init.sh):
#   1. test_vm_can   SocketCAN module (hal/linux/lx_can) over vcan0, errors from the real kernel
#   2. test_vm_gpio  libgpiod module (hal/linux/lx_gpio) against the gpio-amdpt chip declared by
#                    gpio_ssdt.asl, pins observed through /dev/mem
#   3. closed loop   throttle_linux (SCHED_FIFO, mlockall) <-> PWM/IIO files <-> vm_plant, GPIO
#                    through the real chip, commands from throttle_cmd and telemetry on vcan0,
#                    recorded with candump -L; then, on this host, check_closed_loop.py decodes
#                    the log through tools/throttle.dbc and checks it against the plant's truth.
#   4. throttle_linux --check, and a fatal I/O fault while driving (exit 3, outputs safe).
#
#   run_vm_test.sh <source dir> <work dir> <throttle_linux> <throttle_cmd> <vm_plant>
#                  <test_vm_can> <test_vm_gpio> <vm_dump>
#
# The kernel package (linux-image-<abi>-rt-amd64, the one linux-image-rt-amd64 depends on) is
# fetched with apt-get download only when not cached: cache directory $TV_VM_CACHE, else
# /var/cache/throttle-ekf-vm when writable, else <work dir>/cache. $TV_VM_KERNEL_PKG picks
# another package. Exit 0 pass, 1 fail, 77 skip (only when qemu-system-x86_64 cannot run).
set -euo pipefail

SKIP=77
if (($# != 8)); then
    echo "usage: $0 <source dir> <work dir> <throttle_linux> <throttle_cmd> <vm_plant> <test_vm_can> <test_vm_gpio> <vm_dump>" >&2
    exit 2
fi
SRC=$(cd "$1" && pwd)
WORK=$2
BINS=("$3" "$4" "$5" "$6" "$7" "$8")
BIN_NAMES=(throttle_linux throttle_cmd vm_plant test_vm_can test_vm_gpio vm_dump)
VM=$SRC/tests/vm
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)

say() { printf 'vm: %s\n' "$*"; }
die() { printf 'vm: FAIL: %s\n' "$*"; exit 1; }

# ---- can QEMU run at all? (the only reason to skip) ---------------------------------------------
QEMU=$(command -v qemu-system-x86_64 || true)
if [[ -z $QEMU ]]; then
    say "SKIP: qemu-system-x86_64 is not installed (Debian package qemu-system-x86)"
    exit $SKIP
fi
if ! "$QEMU" -accel help 2>/dev/null | grep -qx tcg; then
    say "SKIP: $QEMU has no TCG accelerator"
    exit $SKIP
fi
"$QEMU" -accel tcg -machine none -nodefaults -no-user-config -display none -monitor none -serial none -S \
    </dev/null >"$WORK/qemu-probe.txt" 2>&1 &
probe=$!
sleep 1
if ! kill -0 "$probe" 2>/dev/null; then
    wait "$probe" || true
    say "SKIP: $QEMU cannot run here: $(head -3 "$WORK/qemu-probe.txt")"
    exit $SKIP
fi
kill "$probe" 2>/dev/null || true
wait "$probe" 2>/dev/null || true

for tool in iasl cpio gzip busybox candump python3; do
    command -v "$tool" >/dev/null || die "$tool not found (tools/setup.sh installs it)"
done
BUSYBOX=$(command -v busybox)
ldd_out=$(ldd "$BUSYBOX" 2>&1 || true) # ldd fails on a static binary: that is the answer wanted
[[ $ldd_out == *"not a dynamic executable"* ]] || die "$BUSYBOX is dynamically linked (install busybox-static)"

# ---- kernel: cached or downloaded ------------------------------------------------------------
if [[ -n ${TV_VM_CACHE:-} ]]; then
    CACHE=$TV_VM_CACHE
elif mkdir -p /var/cache/throttle-ekf-vm 2>/dev/null && [[ -w /var/cache/throttle-ekf-vm ]]; then
    CACHE=/var/cache/throttle-ekf-vm
else
    CACHE=$WORK/cache
fi
mkdir -p "$CACHE"
MODS=(net/can/can.ko net/can/can-raw.ko drivers/net/can/dev/can-dev.ko drivers/net/can/vcan.ko
      drivers/gpio/gpio-generic.ko drivers/gpio/gpio-amdpt.ko)
exec 9>"$CACHE/.lock"
flock 9
if [[ ! -s $CACHE/kernel/vmlinuz || ! -s $CACHE/kernel/gpio-amdpt.ko ]]; then
    PKG=${TV_VM_KERNEL_PKG:-$(apt-cache depends linux-image-rt-amd64 2>/dev/null |
                              awk '/Depends: linux-image-[0-9]/ {print $2; exit}')}
    [[ -n $PKG ]] || die "cannot resolve the kernel package (apt-cache depends linux-image-rt-amd64); set TV_VM_KERNEL_PKG"
    say "downloading $PKG (once; cached in $CACHE)"
    rm -rf "$CACHE/dl" "$CACHE/kernel.new"
    mkdir -p "$CACHE/dl" "$CACHE/kernel.new"
    if ! (cd "$CACHE/dl" && apt-get download "$PKG" >/dev/null 2>"$CACHE/dl/apt.err"); then
        say "apt-get download failed; updating the package lists once"
        apt-get update -qq >/dev/null 2>&1 || true
        PKG=${TV_VM_KERNEL_PKG:-$(apt-cache depends linux-image-rt-amd64 2>/dev/null |
                                  awk '/Depends: linux-image-[0-9]/ {print $2; exit}')}
        (cd "$CACHE/dl" && apt-get download "$PKG" >/dev/null 2>"$CACHE/dl/apt.err") ||
            { cat "$CACHE/dl/apt.err"; die "apt-get download $PKG failed (no network to the Debian mirror?)"; }
    fi
    dpkg -x "$CACHE"/dl/*.deb "$CACHE/dl/x"
    cp "$CACHE"/dl/x/boot/vmlinuz-* "$CACHE/kernel.new/vmlinuz"
    rel=$(basename "$CACHE"/dl/x/lib/modules/*)
    for m in "${MODS[@]}"; do
        f=$CACHE/dl/x/lib/modules/$rel/kernel/$m
        if [[ -f $f ]]; then
            cp "$f" "$CACHE/kernel.new/"
        elif [[ -f $f.xz ]]; then
            xz -dc "$f.xz" >"$CACHE/kernel.new/$(basename "$m")"
        else
            die "$PKG has no $m"
        fi
    done
    echo "$PKG $rel" >"$CACHE/kernel.new/release"
    rm -rf "$CACHE/kernel" "$CACHE/dl"
    mv "$CACHE/kernel.new" "$CACHE/kernel"
fi
flock -u 9
KDIR=$CACHE/kernel
say "kernel $(cat "$KDIR/release")"

# ---- initramfs ---------------------------------------------------------------------------------
ROOT=$WORK/initramfs
rm -rf "$ROOT"
mkdir -p "$ROOT"/{bin,lib/modules,etc,dev,proc,sys,tmp,run,lib64}
cp "$BUSYBOX" "$ROOT/bin/busybox"
for i in "${!BINS[@]}"; do
    [[ -x ${BINS[$i]} ]] || die "missing ${BINS[$i]}"
    cp "${BINS[$i]}" "$ROOT/bin/${BIN_NAMES[$i]}"
done
# candump (can-utils) is dynamically linked: bring its libraries along
CANDUMP=$(command -v candump)
cp "$CANDUMP" "$ROOT/bin/candump"
ldd "$CANDUMP" | awk '/=> \// {print $3} /^\t\/lib/ {print $1}' | while read -r lib; do
    mkdir -p "$ROOT$(dirname "$lib")"
    cp -L "$lib" "$ROOT$lib"
done
cp "$KDIR"/*.ko "$ROOT/lib/modules/"
cp "$VM/init.sh" "$ROOT/init"
cp "$VM/vm.conf" "$ROOT/etc/vm.conf"
cp "$VM/scenario.cmd" "$ROOT/etc/scenario.cmd"
chmod +x "$ROOT/init"
(cd "$ROOT" && find . | cpio -o -H newc --quiet | gzip -1 >"$WORK/initrd.gz")
iasl -p "$WORK/gpio_ssdt" "$VM/gpio_ssdt.asl" >"$WORK/iasl.log" 2>&1 || { cat "$WORK/iasl.log"; die "iasl failed"; }

# ---- boot ----------------------------------------------------------------------------------------
CONSOLE=$WORK/console.txt
DATA=$WORK/data.txt
rm -f "$CONSOLE" "$DATA"
say "booting (qemu-system-x86_64 -accel tcg -icount shift=0,sleep=off, 1 vCPU)"
t0=$(date +%s)
set +e
# -icount shift=0,sleep=off: the guest clock follows the instructions executed (1 ns each, an
# idealised 1 GHz machine), and idle time jumps straight to the next timer, so the guest's
# timing is deterministic and independent of whatever else this host runs (plain TCG missed
# half the 1 ms periods on a loaded 2-core host). It needs one vCPU thread (-smp 1): the
# controller (SCHED_FIFO 80) preempts the plant simulation (SCHED_FIFO 70) there.
timeout 480 "$QEMU" -accel tcg ${TV_VM_QEMU_ARGS--icount shift=0,sleep=off} -M q35 -m 512 -smp ${TV_VM_SMP:-1} -nographic -no-reboot -monitor none -nic none \
    -kernel "$KDIR/vmlinuz" -initrd "$WORK/initrd.gz" -acpitable file="$WORK/gpio_ssdt.aml" \
    -append "console=ttyS0 quiet panic=-1 memmap=4K\$0x10000000 iomem=relaxed" \
    -serial file:"$CONSOLE" -debugcon file:"$DATA" </dev/null >"$WORK/qemu.txt" 2>&1
qrc=$?
set -e
say "VM ran $(($(date +%s) - t0)) s (qemu exit $qrc)"
tr -d '\r' <"$CONSOLE" >"$CONSOLE.clean"
tr -d '\r' <"$DATA" >"$DATA.clean"
grep '^VMTEST' "$CONSOLE.clean" | sed 's/^/vm: /' || true

# ---- results -----------------------------------------------------------------------------------
extract() { # name -> file
    awk -v n="$1" '$0 == "===BEGIN " n "===" {on=1; next} $0 == "===END " n "===" {on=0} on' "$DATA.clean" >"$WORK/$1.out"
}
for b in test_vm_can test_vm_gpio app cmd plant debug_gpio truth candump check io_fault; do
    extract "$b"
done
status() { awk -v n="$1" '$1 == "VMTEST" && $2 == n {print $3}' "$CONSOLE.clean" | tail -1; }
fails=0
check() { # name description
    local s
    s=$(status "$1")
    if [[ $s == 0 ]]; then
        say "PASS $2"
    else
        say "FAIL $2 (status '${s:-none}')"
        fails=$((fails + 1))
    fi
}
check vcan0 "vcan0 created (modules can, can-raw, can-dev, vcan)"
check gpiochip "gpio-amdpt bound to the SSDT device: /dev/gpiochip0"
check socketcan "SocketCAN module over vcan0 (test_vm_can)"
check gpio "libgpiod module on the real GPIO chip (test_vm_gpio)"
check throttle_cmd "throttle_cmd script"
check throttle_linux "throttle_linux exit status 0 after SIGTERM"
check vm_plant "vm_plant"
check check "throttle_linux --check: configuration and devices OK"
check io_fault "fatal I/O fault (ADC file garbage while driving): exit 3, PWM 0 and disabled, bridge line low"
check done "VM ran to the end"
for t in test_vm_can test_vm_gpio; do
    grep -E '^(PASS|FAIL)|failed|passed|^  ' "$WORK/$t.out" | sed "s/^/vm:   $t: /" || true
done
sed 's/^/vm:   /' "$WORK/app.out" "$WORK/plant.out" "$WORK/cmd.out" "$WORK/check.out" "$WORK/io_fault.out" 2>/dev/null || true
grep -E 'AMDIF|gpio-|gpiochip' "$WORK/debug_gpio.out" | sed 's/^/vm:   debugfs: /' || true
if [[ -s $WORK/candump.out && -s $WORK/truth.out ]]; then
    if /usr/bin/python3 "$VM/check_closed_loop.py" --dbc "$SRC/tools/throttle.dbc" --candump "$WORK/candump.out" \
            --truth "$WORK/truth.out" --app "$WORK/app.out" --plant "$WORK/plant.out" | sed 's/^/vm: /'; then
        :
    fi
    if [[ ${PIPESTATUS[0]} -ne 0 ]]; then
        fails=$((fails + 1))
    fi
else
    say "FAIL no candump log or truth came out of the VM"
    fails=$((fails + 1))
fi
if ((fails)); then
    say "$fails failures; console: $CONSOLE, logs: $WORK/*.out"
    tail -30 "$CONSOLE.clean" | sed 's/^/vm: console: /'
    exit 1
fi
say "all VM checks passed"
