# throttle_cmd script of the closed-loop VM test (times from the start of throttle_cmd).
# tests/vm/check_closed_loop.py checks what each phase must show.
0.0  set mode=position target=0.3 duty_limit=0.95 amplitude=12 freq=5
3.0  set mode=sine
5.0  bad crc
5.1  bad dlc
5.2  bad repeat
5.3  bad stale
5.4  bad range
5.5  bad unknown
6.5  set mode=position target=1.2   # springs (0.25 + 0.059 x 1.2 N m) beat stiction (0.3 N m): without drive it moves back
# vm_plant pulls nFAULT low for 50 ms at 8.0 s of its own time: the controller latches the driver fault
9.0  clear
10.0 silence
11.0 end
