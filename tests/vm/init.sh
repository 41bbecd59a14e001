#!/bin/busybox sh
# /init of the test VM (tests/vm/run_vm_test.sh builds the initramfs around it). Results go to
# the console as "VMTEST <name> <status>"; logs go to QEMU's debugcon (I/O port 0xE9, vm_dump)
# between "===BEGIN <name>===" / "===END <name>===" markers.
/bin/busybox --install -s /bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
mount -t tmpfs tmp /tmp
mkdir -p /run && mount -t tmpfs run /run
mount -t debugfs debugfs /sys/kernel/debug 2>/dev/null
result() { echo "VMTEST $1 $2"; }
blob() { { echo "===BEGIN $1==="; cat "$2"; echo "===END $1==="; } | /bin/vm_dump; }

echo "VMTEST kernel $(uname -r)"
for m in can can-raw can-dev vcan gpio-generic gpio-amdpt; do
    insmod /lib/modules/$m.ko || result insmod-$m 1
done
ip link add dev vcan0 type vcan && ip link set vcan0 up && result vcan0 0
ip link add dev vcan1 type vcan    # left down: an error path of the SocketCAN test
ls /dev/gpiochip0 >/dev/null 2>&1 && result gpiochip 0 || result gpiochip 1

# 1. SocketCAN over vcan
/bin/test_vm_can > /tmp/can.txt 2>&1; result socketcan $?
blob test_vm_can /tmp/can.txt

# 2. libgpiod against the gpio-amdpt chip
/bin/test_vm_gpio 0x10000000 > /tmp/gpio.txt 2>&1; result gpio $?
blob test_vm_gpio /tmp/gpio.txt

# 3. closed loop: throttle_linux <-> files <-> vm_plant, commands and telemetry on vcan0
/bin/vm_plant --root /run/plant --gpio-phys 0x10000000 --enable-line 0 --fault-line 1 \
    --duration-s 13 --fault-at 8.0 --fault-len 0.05 --truth /tmp/truth.csv > /tmp/plant.txt 2>&1 &
PLANT=$!
i=0; while [ ! -f /run/plant/ready ] && [ $i -lt 100 ]; do sleep 0.05; i=$((i+1)); done
candump -L vcan0 > /tmp/candump.log &
DUMP=$!
/bin/throttle_linux -c /etc/vm.conf > /tmp/app.txt 2>&1 &
APP=$!
sleep 0.2
/bin/throttle_cmd -i vcan0 --script /etc/scenario.cmd > /tmp/cmd.txt 2>&1 &
CMD=$!
sleep 2
cat /sys/kernel/debug/gpio > /tmp/debug_gpio.txt 2>&1
wait $CMD; result throttle_cmd $?
sleep 0.5
kill -TERM $APP
wait $APP; result throttle_linux $?
sleep 0.2
kill -TERM $DUMP
wait $DUMP
wait $PLANT; result vm_plant $?
# 4. --check: configuration and every device opened, outputs safe, exit 0
/bin/throttle_linux -c /etc/vm.conf --check > /tmp/check.txt 2>&1; result check $?

# 5. a fatal I/O fault while driving: the ADC file stops holding a count -> rt.max_io_errors
#    failed ticks -> safe state (PWM 0 and disabled, bridge disabled) -> exit status 3
/bin/throttle_linux -c /etc/vm.conf > /tmp/app2.txt 2>&1 &
APP=$!
sleep 0.2
/bin/throttle_cmd -i vcan0 --mode sine --amplitude 12 --freq 5 --duration-s 3 > /dev/null 2>&1 &
CMD=$!
sleep 1
P=/run/plant/pwmchip0
# the enable pin: bit 0 of the chip's OUTPUTDATA register (0x10000008)
pins() { echo "pwm0 duty/enable $(head -1 $P/pwm0/duty_cycle)/$(head -1 $P/pwm0/enable), pwm1 $(head -1 $P/pwm1/duty_cycle)/$(head -1 $P/pwm1/enable), enable pin $(( $(devmem 0x10000008 32) & 1 ))"; }
echo "before: $(pins)" > /tmp/fault.txt
echo garbage > "/run/plant/iio:device0/in_voltage1_raw"
wait $APP; rc=$?
echo "exit status $rc" >> /tmp/fault.txt
echo "after:  $(pins)" >> /tmp/fault.txt
kill $CMD 2>/dev/null; wait $CMD
if [ $rc -eq 3 ] && [ "$(head -1 $P/pwm0/enable)$(head -1 $P/pwm1/enable)$(head -1 $P/pwm0/duty_cycle)$(head -1 $P/pwm1/duty_cycle)" = "0000" ] \
   && [ $(( $(devmem 0x10000008 32) & 1 )) -eq 0 ]; then
    result io_fault 0
else
    result io_fault 1
fi
cat /tmp/app2.txt >> /tmp/fault.txt

blob app /tmp/app.txt
blob check /tmp/check.txt
blob io_fault /tmp/fault.txt
blob cmd /tmp/cmd.txt
blob plant /tmp/plant.txt
blob debug_gpio /tmp/debug_gpio.txt
blob truth /tmp/truth.csv
blob candump /tmp/candump.log
result done 0
sync
poweroff -f
