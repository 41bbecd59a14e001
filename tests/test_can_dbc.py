#!/usr/bin/python3
"""DBC-vs-C agreement test (ctest test_can_dbc).

    test_can_dbc.py <can_dbc_vectors executable> <throttle.dbc>

Runs the C vector generator (tests/can_dbc_vectors.c), then proves with tools/can_decode.py:
  1. the DBC and the C signal table list the same messages (name, id, DLC) and the same signals
     with the same start bit, length, signedness, scale, offset, min, max and unit;
  2. every FRAME the C encoders produced, read back from its candump line (log and default
     formats alternate), decodes through the DBC to the EXPECTed value of every signal within
     the stated tolerance (half a count of the scale for the typed encoders: their rounding),
     and its CRC checks;
  3. every DBC signal is exercised by the typed encoders (a signal no encoder writes would be
     a signal the DBC promises but the controller never sends);
  4. the DBC's value tables of the code-index signals (TV_DIAG LastDtc, TV_DIAG_FREEZE FreezeDtc)
     name the firmware's code table (DTC lines) index by index, 15 being NONE, and every signal
     of the health and diagnostic frames has a unit where it has one and a comment;
  5. the candump line parser handles the formats it promises (log, default, timestamps,
     extended ids, remote requests, CAN FD) and rejects what is not a frame.
Prints what it checked; exit 0 when everything agrees.
"""

import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import can_decode  # noqa: E402

failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL " + msg)


def close(a, b, rel=1e-6):
    return abs(a - b) <= rel * max(1.0, abs(a), abs(b))


def check_tables(c_msgs, c_sigs, dbc):
    by_name = {m.name: m for m in dbc.values()}
    if set(c_msgs) != set(by_name):
        fail("messages differ: only in C %s, only in DBC %s"
             % (sorted(set(c_msgs) - set(by_name)), sorted(set(by_name) - set(c_msgs))))
    for name, (frame_id, dlc) in c_msgs.items():
        m = by_name.get(name)
        if m is None:
            continue
        if m.id != frame_id or m.dlc != dlc or m.extended:
            fail("%s: C id 0x%X dlc %d, DBC id 0x%X dlc %d extended %s" % (name, frame_id, dlc, m.id, m.dlc, m.extended))
        dbc_names = [s.name for s in m.signals]
        c_names = [s[0] for s in c_sigs[name]]
        if dbc_names != c_names:
            fail("%s: signals differ: C %s, DBC %s" % (name, c_names, dbc_names))
            continue
        for (sname, start, length, signed, scale, offset, vmin, vmax, unit), s in zip(c_sigs[name], m.signals):
            got = (s.start, s.length, int(s.signed), s.unit)
            want = (start, length, signed, unit)
            if got != want or not all(close(a, b) for a, b in
                                      ((s.scale, scale), (s.offset, offset), (s.min, vmin), (s.max, vmax))):
                fail("%s.%s: C start|len %d|%d signed %d scale %g offset %g [%g|%g] '%s'; DBC %d|%d %d %g %g [%g|%g] '%s'"
                     % (name, sname, start, length, signed, scale, offset, vmin, vmax, unit,
                        s.start, s.length, int(s.signed), s.scale, s.offset, s.min, s.max, s.unit))


def check_parser():
    p = can_decode.parse_candump_line
    f = p("(1700000000.123456) vcan0 183#0102030405060708")
    ok = f is not None and f.id == 0x183 and not f.extended and f.dlc == 8 and f.data == bytes(range(1, 9)) \
        and f.timestamp == 1700000000.123456 and f.iface == "vcan0"
    f = p("  can0  183   [8]  01 02 03 04 05 06 07 08")
    ok = ok and f is not None and f.id == 0x183 and f.data == bytes(range(1, 9)) and f.timestamp is None
    f = p(" (1700000000.000001)  can0  12345678   [2]  AB CD")
    ok = ok and f is not None and f.extended and f.id == 0x12345678 and f.data == b"\xab\xcd"
    f = p("(1.000000) can0 12345678#R")
    ok = ok and f is not None and f.remote and f.extended
    f = p("  can0  100   [8]  remote request")
    ok = ok and f is not None and f.remote and f.dlc == 8
    f = p("(1.000000) can0 123##1112233")
    ok = ok and f is not None and f.fd and f.data == bytes.fromhex("112233")
    ok = ok and p("interface vcan0 is down") is None and p("(1.0) can0 183#123") is None \
        and p("  can0  183   [8]  01 02") is None and p("") is None
    if not ok:
        fail("candump line parser")
    dec = can_decode.decode_frame(can_decode.load_dbc(), p("(1.000000) vcan0 183#00"))
    if dec is None or "error" not in dec:
        fail("a short frame of a known id must be reported as a DLC error")
    return ok


# frames whose every signal (CRC and Counter aside) must carry a DBC comment
COMMENTED = ("TV_HEALTH_1", "TV_HEALTH_2", "TV_HEALTH_3", "TV_HEALTH_4", "TV_HEALTH_5", "TV_DIAG",
             "TV_DIAG_FREEZE")


def check_dtc_tables(dtc, dbc):
    by_name = {m.name: m for m in dbc.values()}
    want = dict(dtc)
    want[15] = "NONE"
    for msg, sig in (("TV_DIAG", "LastDtc"), ("TV_DIAG_FREEZE", "FreezeDtc")):
        m = by_name.get(msg)
        s = next((x for x in m.signals if x.name == sig), None) if m else None
        got = getattr(s, "values", None) if s else None
        if got != want:
            fail("%s.%s value table %s, firmware code table %s" % (msg, sig, got, want))
    for msg in COMMENTED:
        m = by_name.get(msg)
        if m is None or not m.comment:
            fail("%s: no message comment" % msg)
            continue
        for s in m.signals:
            if s.name not in ("CRC", "Counter") and not s.comment:
                fail("%s.%s: no comment" % (msg, s.name))


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    exe, dbc_path = sys.argv[1], sys.argv[2]
    dbc = can_decode.load_dbc(dbc_path)
    out = subprocess.run([exe], check=True, capture_output=True, text=True).stdout.splitlines()
    c_msgs = {}
    c_sigs = {}
    frame = None
    decoded = None
    n_frames = n_expect = 0
    typed_signals = set()
    dtc = []
    in_sweep = False
    for line in out:
        word, _, rest = line.partition(" ")
        if word == "MESSAGE":
            name, frame_id, dlc = rest.split()
            c_msgs[name] = (int(frame_id), int(dlc))
            c_sigs[name] = []
        elif word == "SIGNAL":
            head, unit = rest.rsplit(" ", 1)
            f = head.split()
            c_sigs[f[0]].append((f[1], int(f[2]), int(f[3]), int(f[4]), float(f[5]), float(f[6]),
                                 float(f[7]), float(f[8]), unit.strip('"')))
        elif word == "FRAME":
            n_frames += 1
            frame = can_decode.parse_candump_line(rest)
            decoded = can_decode.decode_frame(dbc, frame) if frame else None
            if decoded is None or "signals" not in decoded:
                fail("cannot decode %r" % rest)
                decoded = None
            elif not decoded.get("crc_ok", False):
                fail("CRC of %r does not check" % rest)
        elif word == "EXPECT":
            n_expect += 1
            f = rest.split()
            msg, sig, value, tol = f[0], f[1], float(f[2]), float(f[3])
            if decoded is None:
                continue
            if decoded["message"] != msg:
                fail("EXPECT %s after a %s frame" % (msg, decoded["message"]))
                continue
            got = decoded["signals"].get(sig)
            if got is None or not math.isfinite(got) or abs(got - value) > tol:
                fail("%s.%s: C encoded %.9g, DBC decodes %s (tolerance %.3g)" % (msg, sig, value, got, tol))
            if not in_sweep:
                typed_signals.add((msg, sig))
        elif word == "DTC":
            idx, code = rest.split()
            dtc.append((int(idx), code))
        elif word == "SWEEP":
            in_sweep = True
        elif word == "ERROR":
            fail("generator: " + rest)
    check_tables(c_msgs, c_sigs, dbc)
    if not dtc:
        fail("the generator printed no code table")
    check_dtc_tables(dtc, dbc)
    every = {(m.name, s.name) for m in dbc.values() for s in m.signals if s.name != "CRC"}
    missing = sorted(every - typed_signals)
    if missing:
        fail("DBC signals no typed encoder writes: %s" % missing)
    parser_ok = check_parser()
    print("checked %d messages, %d signals against the C table; %d frames, %d signal values decoded through "
          "the DBC (%d signals by the typed encoders); candump parser %s"
          % (len(c_msgs), sum(len(v) for v in c_sigs.values()), n_frames, n_expect, len(typed_signals),
             "ok" if parser_ok else "FAILED"))
    print("%d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
