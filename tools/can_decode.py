#!/usr/bin/python3
"""Decode candump output with a DBC file (default: tools/throttle.dbc next to this script).

    candump -L can0 | tools/can_decode.py            # live, log format
    candump -ta can0 | tools/can_decode.py           # live, default format with timestamps
    tools/can_decode.py candump.log                   # a saved log
    tools/can_decode.py --format jsonl candump.log    # one JSON object per frame

Both candump output formats are read, line by line, mixed freely:
  log format (candump -L / -l):   (1700000000.123456) can0 183#0A1B2C3D4E5F6071
  default format (candump, -t*):  [(1700000000.123456)]  can0  183   [8]  0A 1B 2C 3D 4E 5F 60 71
Extended ids are 8 hex digits; remote requests (R / "remote request") and CAN FD frames (##) are
reported as such and not decoded. Lines that are neither are passed over (counted on stderr).

For each known frame the tool checks the protection header of firmware/protocols/can_proto.h: CRC-8 SAE
J1850 (poly 0x1D, init 0xFF, xorout 0xFF) over the id (low byte, high byte) and data[1..7],
reported as crc=ok/BAD, and the 4-bit counter, reported with "jump" when it did not step by 1
from the previous frame of that id.

DBC SUBSET understood (Debian 12 has no python3-cantools; this parser covers what
tools/throttle.dbc uses and rejects what it does not understand rather than mis-decode):
  BO_ <id> <name>: <dlc> <sender>          message (id decimal; bit 31 set = extended)
  SG_ <name> : <start>|<len>@1<+|-> (<scale>,<offset>) [<min>|<max>] "<unit>" <receivers>
                                           little-endian (Intel) signals only; @0 (Motorola)
                                           and multiplexed signals (M / mN) are refused
  CM_ ...;                                 comments (may span lines), kept for messages/signals
  VAL_ <id> <signal> <n> "<text>" ... ;    value tables, shown next to the value
  BA_ "GenMsgCycleTime" BO_ <id> <ms>;     cycle time, kept
  VERSION, NS_, BS_, BU_, BA_DEF_, BA_DEF_DEF_ and other BA_ lines are skipped.
Physical value = raw * scale + offset, raw two's complement for '-' signals.
"""

import argparse
import json
import os
import re
import sys

DEFAULT_DBC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "throttle.dbc")


class DbcError(Exception):
    """The DBC uses something outside the supported subset, or is malformed."""


class Signal:
    def __init__(self, name, start, length, signed, scale, offset, vmin, vmax, unit):
        self.name = name
        self.start = start
        self.length = length
        self.signed = signed
        self.scale = scale
        self.offset = offset
        self.min = vmin
        self.max = vmax
        self.unit = unit
        self.comment = ""
        self.values = {}

    def decode_raw(self, data):
        """Raw integer of this signal from the payload bytes (Intel bit numbering)."""
        word = int.from_bytes(bytes(data).ljust(8, b"\0")[:8], "little")
        raw = (word >> self.start) & ((1 << self.length) - 1)
        if self.signed and raw & (1 << (self.length - 1)):
            raw -= 1 << self.length
        return raw

    def decode(self, data):
        return self.decode_raw(data) * self.scale + self.offset


class Message:
    def __init__(self, frame_id, extended, name, dlc, sender):
        self.id = frame_id
        self.extended = extended
        self.name = name
        self.dlc = dlc
        self.sender = sender
        self.signals = []
        self.comment = ""
        self.cycle_ms = None

    def signal(self, name):
        for s in self.signals:
            if s.name == name:
                return s
        raise KeyError(name)


_RE_BO = re.compile(r"^BO_\s+(\d+)\s+(\w+)\s*:\s*(\d+)\s+(\w+)\s*$")
_RE_SG = re.compile(
    r"^SG_\s+(\w+)\s*(\S*)\s*:\s*(\d+)\|(\d+)@([01])([+-])\s*"
    r"\(\s*([-+0-9.eE]+)\s*,\s*([-+0-9.eE]+)\s*\)\s*"
    r"\[\s*([-+0-9.eE]+)\s*\|\s*([-+0-9.eE]+)\s*\]\s*"
    r'"([^"]*)"\s*(.*)$'
)
_RE_CM_BO = re.compile(r'^CM_\s+BO_\s+(\d+)\s+"((?:[^"\\]|\\.)*)"\s*;\s*$', re.S)
_RE_CM_SG = re.compile(r'^CM_\s+SG_\s+(\d+)\s+(\w+)\s+"((?:[^"\\]|\\.)*)"\s*;\s*$', re.S)
_RE_VAL = re.compile(r"^VAL_\s+(\d+)\s+(\w+)\s+(.*);\s*$", re.S)
_RE_VAL_PAIR = re.compile(r'(-?\d+)\s+"((?:[^"\\]|\\.)*)"')
_RE_CYCLE = re.compile(r'^BA_\s+"GenMsgCycleTime"\s+BO_\s+(\d+)\s+(\d+)\s*;\s*$')


def _statements(text):
    """Split DBC text into statements: one per line, except CM_/VAL_/BA_ which end at ';'."""
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i].strip()
        i += 1
        if not line:
            continue
        if line.startswith("NS_"):
            # the new-symbols list: indented keywords up to the next unindented line
            while i < len(lines) and (not lines[i].strip() or lines[i][:1] in " \t"):
                i += 1
            continue
        if line.startswith(("CM_", "VAL_", "BA_")) and not line.startswith(("BA_DEF_",)):
            stmt = line
            # a statement ends with ';' outside a quoted string
            while not _ends_statement(stmt) and i < len(lines):
                stmt += "\n" + lines[i]
                i += 1
            yield stmt
        else:
            yield line


def _ends_statement(stmt):
    quoted = False
    escaped = False
    last = ""
    for ch in stmt:
        if escaped:
            escaped = False
        elif ch == "\\":
            escaped = True
        elif ch == '"':
            quoted = not quoted
        if not quoted and not ch.isspace():
            last = ch
    return not quoted and last == ";"


def load_dbc(path=DEFAULT_DBC):
    """Parse a DBC file; returns {frame_id: Message} (extended ids with bit 31 cleared)."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    messages = {}
    current = None
    for stmt in _statements(text):
        if stmt.startswith("BO_ ") or stmt == "BO_":
            m = _RE_BO.match(stmt)
            if not m:
                raise DbcError("cannot parse: " + stmt)
            raw_id = int(m.group(1))
            extended = bool(raw_id & 0x80000000)
            frame_id = raw_id & 0x1FFFFFFF
            current = Message(frame_id, extended, m.group(2), int(m.group(3)), m.group(4))
            if frame_id in messages:
                raise DbcError("message id %d defined twice" % frame_id)
            messages[frame_id] = current
        elif stmt.startswith("SG_"):
            m = _RE_SG.match(stmt)
            if not m or current is None:
                raise DbcError("cannot parse: " + stmt)
            if m.group(2):
                raise DbcError("multiplexed signal not supported: " + stmt)
            if m.group(5) != "1":
                raise DbcError("Motorola (@0) byte order not supported: " + stmt)
            sig = Signal(
                m.group(1), int(m.group(3)), int(m.group(4)), m.group(6) == "-",
                float(m.group(7)), float(m.group(8)), float(m.group(9)), float(m.group(10)), m.group(11),
            )
            if sig.length < 1 or sig.start + sig.length > 8 * current.dlc:
                raise DbcError("signal %s.%s outside the %d-byte payload" % (current.name, sig.name, current.dlc))
            current.signals.append(sig)
        elif stmt.startswith("CM_"):
            m = _RE_CM_SG.match(stmt)
            if m:
                msg = messages.get(int(m.group(1)) & 0x1FFFFFFF)
                if msg is None:
                    raise DbcError("comment for an unknown message: " + stmt)
                msg.signal(m.group(2)).comment = m.group(3)
                continue
            m = _RE_CM_BO.match(stmt)
            if m:
                msg = messages.get(int(m.group(1)) & 0x1FFFFFFF)
                if msg is None:
                    raise DbcError("comment for an unknown message: " + stmt)
                msg.comment = m.group(2)
        elif stmt.startswith("VAL_TABLE_"):
            continue
        elif stmt.startswith("VAL_"):
            m = _RE_VAL.match(stmt)
            if not m:
                raise DbcError("cannot parse: " + stmt)
            msg = messages.get(int(m.group(1)) & 0x1FFFFFFF)
            if msg is None:
                raise DbcError("value table for an unknown message: " + stmt)
            msg.signal(m.group(2)).values = {int(k): v for k, v in _RE_VAL_PAIR.findall(m.group(3))}
        elif stmt.startswith("BA_ "):
            m = _RE_CYCLE.match(stmt)
            if m and int(m.group(1)) & 0x1FFFFFFF in messages:
                messages[int(m.group(1)) & 0x1FFFFFFF].cycle_ms = int(m.group(2))
        # VERSION, NS_ (and its indented keyword list), BS_, BU_, BA_DEF_, BA_DEF_DEF_: skipped
    return messages


# ---- frames -------------------------------------------------------------------------------

class Frame:
    def __init__(self, timestamp, iface, frame_id, extended, data, dlc, remote=False, fd=False):
        self.timestamp = timestamp
        self.iface = iface
        self.id = frame_id
        self.extended = extended
        self.data = data
        self.dlc = dlc
        self.remote = remote
        self.fd = fd


_RE_LOG = re.compile(r"^\((\d+\.\d+)\)\s+(\S+)\s+([0-9A-Fa-f]{3}|[0-9A-Fa-f]{8})(##?)([0-9A-Fa-f]*|R\d?)\s*$")
_RE_DEFAULT = re.compile(
    r"^\s*(?:\((\d+\.\d+)\)\s+)?(\S+)\s+([0-9A-Fa-f]{3}|[0-9A-Fa-f]{8})\s+\[(\d+)\]\s*(.*)$"
)


def parse_candump_line(line):
    """One candump line (log or default format) -> Frame, or None when it is not a frame."""
    line = line.rstrip("\r\n")
    m = _RE_LOG.match(line)
    if m:
        ts, iface, id_hex, sep, payload = m.groups()
        extended = len(id_hex) == 8
        if payload.startswith("R"):
            dlc = int(payload[1:]) if len(payload) > 1 else 0
            return Frame(float(ts), iface, int(id_hex, 16), extended, b"", dlc, remote=True)
        if sep == "##":
            data = bytes.fromhex(payload[1:]) if len(payload) > 1 else b""
            return Frame(float(ts), iface, int(id_hex, 16), extended, data, len(data), fd=True)
        if len(payload) % 2:
            return None
        data = bytes.fromhex(payload)
        return Frame(float(ts), iface, int(id_hex, 16), extended, data, len(data))
    m = _RE_DEFAULT.match(line)
    if m:
        ts, iface, id_hex, dlc_s, rest = m.groups()
        dlc = int(dlc_s)
        extended = len(id_hex) == 8
        if rest.strip().startswith("remote request"):
            return Frame(float(ts) if ts else None, iface, int(id_hex, 16), extended, b"", dlc, remote=True)
        tokens = rest.split()
        if len(tokens) < dlc or any(not re.fullmatch(r"[0-9A-Fa-f]{2}", t) for t in tokens[:dlc]):
            return None
        data = bytes(int(t, 16) for t in tokens[:dlc])
        return Frame(float(ts) if ts else None, iface, int(id_hex, 16), extended, data, dlc)
    return None


def crc8_j1850(data):
    """CRC-8 SAE J1850: poly 0x1D, init 0xFF, xorout 0xFF, not reflected."""
    crc = 0xFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc ^ 0xFF


def frame_crc(frame_id, data):
    """The protocol's CRC of a frame: over id low, id high, data[1..7]."""
    payload = bytes(data).ljust(8, b"\0")
    return crc8_j1850(bytes([frame_id & 0xFF, (frame_id >> 8) & 0xFF]) + payload[1:8])


def decode_frame(messages, frame):
    """Decode a Frame with the DBC. Returns a dict (message, signals, crc_ok, counter) or None
    when the id is not in the DBC or the frame cannot be decoded (remote, FD, short)."""
    msg = messages.get(frame.id)
    if msg is None or msg.extended != frame.extended or frame.remote or frame.fd:
        return None
    if frame.dlc != msg.dlc:
        return {"message": msg.name, "id": frame.id, "error": "dlc %d, DBC says %d" % (frame.dlc, msg.dlc)}
    signals = {}
    for s in msg.signals:
        signals[s.name] = s.decode(frame.data)
    out = {"message": msg.name, "id": frame.id, "signals": signals}
    if msg.signals and msg.signals[0].name == "CRC":
        out["crc_ok"] = frame_crc(frame.id, frame.data) == frame.data[0]
    if "Counter" in signals:
        out["counter"] = int(signals["Counter"])
    return out


def format_value(sig, value):
    if sig.scale == int(sig.scale) and sig.offset == int(sig.offset):
        text = "%d" % round(value)
    else:
        decimals = max(0, -int(("%e" % sig.scale).split("e")[1]))
        text = "%.*f" % (decimals, value)
    if sig.values and round(value) in sig.values:
        text += "(%s)" % sig.values[round(value)]
    return text + sig.unit


def main(argv=None):
    ap = argparse.ArgumentParser(description="Decode candump output with a DBC file.")
    ap.add_argument("files", nargs="*", help="candump output files (default: standard input)")
    ap.add_argument("--dbc", default=DEFAULT_DBC, help="DBC file (default: %(default)s)")
    ap.add_argument("--format", choices=("text", "jsonl"), default="text")
    ap.add_argument("--all", action="store_true", help="also print frames whose id is not in the DBC")
    args = ap.parse_args(argv)
    try:
        messages = load_dbc(args.dbc)
    except (OSError, DbcError) as e:
        print("can_decode: %s: %s" % (args.dbc, e), file=sys.stderr)
        return 2
    last_counter = {}
    skipped = 0
    streams = [open(p, encoding="utf-8", errors="replace") for p in args.files] if args.files else [sys.stdin]
    try:
        for stream in streams:
            for line in stream:
                frame = parse_candump_line(line)
                if frame is None:
                    if line.strip():
                        skipped += 1
                    continue
                dec = decode_frame(messages, frame)
                if dec is None:
                    if args.all:
                        print("%s %s %X unknown %s" % (frame.timestamp, frame.iface, frame.id, frame.data.hex()))
                    continue
                jump = False
                if "counter" in dec:
                    prev = last_counter.get(frame.id)
                    jump = prev is not None and dec["counter"] != (prev + 1) % 16
                    last_counter[frame.id] = dec["counter"]
                if args.format == "jsonl":
                    dec["timestamp"] = frame.timestamp
                    dec["iface"] = frame.iface
                    dec["counter_jump"] = jump
                    print(json.dumps(dec, sort_keys=True))
                    continue
                msg = messages[frame.id]
                if "error" in dec:
                    print("%s %s %03X %s error: %s" % (frame.timestamp, frame.iface, frame.id, msg.name, dec["error"]))
                    continue
                parts = ["%s=%s" % (s.name, format_value(s, dec["signals"][s.name]))
                         for s in msg.signals if s.name not in ("CRC", "Counter")]
                head = "%s %s %03X %s" % ("%.6f" % frame.timestamp if frame.timestamp is not None else "-",
                                          frame.iface, frame.id, msg.name)
                tail = " crc=%s ctr=%d%s" % ("ok" if dec.get("crc_ok", True) else "BAD", dec.get("counter", 0),
                                             " jump" if jump else "")
                print(head + " " + " ".join(parts) + tail)
                sys.stdout.flush()
    except BrokenPipeError:
        return 0
    finally:
        for s in streams:
            if s is not sys.stdin:
                s.close()
    if skipped:
        print("can_decode: %d lines were not candump frames" % skipped, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
