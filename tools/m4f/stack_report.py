#!/usr/bin/python3
"""Worst-case stack of a Cortex-M image, from the compiler's per-function frames and the call
graph of the linked code.

    stack_report.py ELF [--level "ISR ISR ..."]... [--objdump arm-none-eabi-objdump]

What it does:
  * call graph: the disassembly of the final ELF (every function that was linked, ours and the
    C library's): bl/blx to an address and b/b.w to another function's start (tail calls);
  * frame of each function: the compiler's -fstack-usage number (.su files of the objects the
    map file lists as linked) where there is one; otherwise (newlib, libm, libgcc, which were
    not compiled with -fstack-usage) the sum of every stack-pointer decrement in its code
    (push, vpush, stmdb sp!, sub sp) - an upper bound for straight-line prologues;
  * worst path from the thread entry (Reset_Handler) and from each handler, then the total:
    thread + for each --level (a group of handlers at one priority that do not preempt each
    other; list them from the lowest priority up) the deepest handler of the group plus one
    exception frame of 108 bytes (26 words with the FPU context, plus 4 bytes of alignment).

What it does not cover (reported when found): calls through function pointers (blx/bx to a
register), recursion (no bound exists), variable-size frames ("dynamic" in .su). The numbers
are for the code as linked; semihosting breakpoints and the debugger's own use are not counted.
"""
import argparse
import glob
import os
import re
import subprocess
import sys

EXC_FRAME = 108  # bytes: FPU extended frame (26 words) + 4 alignment


def parse_map(map_path):
    """Object files the map lists as linked -> their .su files."""
    base = os.path.dirname(os.path.abspath(map_path))
    text = open(map_path, encoding="utf-8", errors="replace").read()
    su = set()
    for obj in re.findall(r"^LOAD (\S+\.obj)$", text, re.M):
        p = os.path.normpath(os.path.join(base, obj))
        su.add(p[:-4] + ".su")
    for arch, member in set(re.findall(r"(\S+?\.a)\((\S+?\.obj)\)", text)):
        arch_p = os.path.normpath(os.path.join(base, arch))
        name = os.path.basename(arch_p)
        if not name.startswith("lib") or arch_p.startswith("/usr/"):
            continue
        tgt = name[3:-2]
        pat = os.path.join(os.path.dirname(arch_p), "CMakeFiles", tgt + ".dir", "**", member[:-4] + ".su")
        su.update(glob.glob(pat, recursive=True))
    return sorted(p for p in su if os.path.exists(p))


def parse_su(files):
    frames = {}
    for f in files:
        for line in open(f, encoding="utf-8"):
            parts = line.rstrip("\n").split("\t")
            if len(parts) != 3:
                continue
            name = parts[0].rsplit(":", 1)[-1]
            size = int(parts[1])
            qual = parts[2]
            old = frames.get(name)
            # static functions of the same name in two files: keep the larger (conservative)
            if old is None or size > old[0]:
                frames[name] = (size, qual)
    return frames


def reg_count(reglist):
    n = 0
    for item in reglist.split(","):
        item = item.strip()
        m = re.match(r"([rsd])(\d+)-[rsd](\d+)$", item)
        if m:
            n += (int(m.group(3)) - int(m.group(2)) + 1) * (8 if m.group(1) == "d" else 4)
        elif item:
            n += 8 if item.startswith("d") else 4
    return n


def disassemble(elf, objdump):
    out = subprocess.run([objdump, "-d", "--no-show-raw-insn", elf], check=True, capture_output=True,
                         text=True).stdout
    funcs = {}  # start address -> dict
    cur = None
    for line in out.splitlines():
        m = re.match(r"^([0-9a-f]+) <(.+)>:$", line)
        if m:
            cur = {"name": m.group(2), "start": int(m.group(1), 16), "insns": []}
            funcs[cur["start"]] = cur
            continue
        m = re.match(r"^\s*([0-9a-f]+):\s+(\S+)\s*(.*)$", line)
        if m and cur is not None:
            cur["insns"].append((int(m.group(1), 16), m.group(2), m.group(3)))
    return funcs


def analyse(funcs, su):
    starts = sorted(funcs)

    def owner(addr):
        lo, hi = 0, len(starts) - 1
        best = None
        while lo <= hi:
            mid = (lo + hi) // 2
            if starts[mid] <= addr:
                best = starts[mid]
                lo = mid + 1
            else:
                hi = mid - 1
        return best

    for f in funcs.values():
        calls = set()
        indirect = []
        sp_dec = 0
        dynamic = False
        for addr, op, args in f["insns"]:
            opb = op.split(".")[0]
            tm = re.match(r"([0-9a-f]+) <", args)
            if opb in ("bl", "blx") and tm:
                calls.add(owner(int(tm.group(1), 16)))
            elif opb in ("blx",) and re.match(r"r\d+|ip|lr", args):
                indirect.append(addr)
            elif re.match(r"b(eq|ne|cs|cc|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|hs|lo)?$", opb) and tm:
                tgt = owner(int(tm.group(1), 16))
                if tgt is not None and tgt != f["start"] and int(tm.group(1), 16) == tgt:
                    calls.add(tgt)  # tail call to another function's entry
            elif opb == "bx" and not args.startswith("lr"):
                indirect.append(addr)
            if opb == "push" or (opb == "stmdb" and args.startswith("sp!")):
                sp_dec += reg_count(args[args.index("{") + 1:args.index("}")])
            elif opb == "vpush" or (opb == "vstmdb" and args.startswith("sp!")):
                sp_dec += reg_count(args[args.index("{") + 1:args.index("}")])
            elif opb in ("sub", "subw") and re.match(r"sp, (sp, )?#\d+", args):
                sp_dec += int(re.search(r"#(\d+)", args).group(1))
            elif opb in ("sub", "subw") and re.match(r"sp, (sp, )?r\d+", args):
                dynamic = True
        calls.discard(None)
        f["calls"] = calls
        f["indirect"] = indirect
        base = f["name"]
        if base in su:
            f["frame"], qual = su[base]
            f["src"] = "su"
            f["dynamic"] = "dynamic" in qual and "bounded" not in qual
        else:
            f["frame"] = sp_dec
            f["src"] = "asm"
            f["dynamic"] = dynamic
    return owner


def worst(funcs, start, memo, stack, notes):
    if start in memo:
        return memo[start]
    f = funcs[start]
    if start in stack:
        notes.add("recursion through %s: no bound" % f["name"])
        return (0, [])
    stack.add(start)
    best = (0, [])
    for c in f["calls"]:
        if c in funcs:
            r = worst(funcs, c, memo, stack, notes)
            if r[0] > best[0]:
                best = r
    stack.discard(start)
    if f["indirect"]:
        notes.add("indirect call/branch in %s at %s: callee not followed" %
                  (f["name"], ", ".join("0x%x" % a for a in f["indirect"][:3])))
    if f["dynamic"]:
        notes.add("variable-size frame in %s" % f["name"])
    res = (f["frame"] + best[0], [f["name"]] + best[1])
    memo[start] = res
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("elf")
    ap.add_argument("--map", help="map file (default: ELF with .map)")
    ap.add_argument("--thread", default="Reset_Handler")
    ap.add_argument("--level", action="append", default=[],
                    help="handlers of one priority level, space separated, lowest priority first")
    ap.add_argument("--objdump", default="arm-none-eabi-objdump")
    ap.add_argument("--nm", default="arm-none-eabi-nm")
    ap.add_argument("--quiet-paths", action="store_true", help="print only the numbers")
    a = ap.parse_args()
    map_path = a.map or (os.path.splitext(a.elf)[0] + ".map")
    su_files = parse_map(map_path)
    su = parse_su(su_files)
    funcs = disassemble(a.elf, a.objdump)
    analyse(funcs, su)
    syms = {}
    for line in subprocess.run([a.nm, a.elf], check=True, capture_output=True, text=True).stdout.splitlines():
        p = line.split()
        if len(p) == 3:
            syms[p[2]] = int(p[0], 16) & ~1
    reserved = syms.get("_estack", 0) - syms.get("_sstack", 0)
    memo, notes = {}, set()

    def path_of(name):
        addr = syms.get(name)
        if addr is None or addr not in funcs:
            sys.exit("stack_report: no function %s in %s" % (name, a.elf))
        return worst(funcs, addr, memo, set(), notes)

    elf_name = os.path.basename(a.elf)
    thread = path_of(a.thread)
    total = thread[0]
    print("Worst-case stack of %s (static: call graph of the linked code, compiler frames)" % elf_name)
    print("  %-7s %6d B  %s" % ("thread", thread[0], " -> ".join(thread[1])))
    for lvl in a.level:
        best = (0, [])
        for h in lvl.split():
            r = path_of(h)
            if r[0] > best[0]:
                best = r
        total += best[0] + EXC_FRAME
        print("  %-7s %6d B  %s  (+%d B exception frame)" % ("handler", best[0], " -> ".join(best[1]), EXC_FRAME))
    reached = [funcs[k] for k in memo]
    n_su = sum(1 for f in reached if f["src"] == "su")
    print("  total   %6d B  of %d B reserved (%.0f %%)" % (total, reserved, 100.0 * total / reserved if reserved else 0))
    print("  coverage: %d functions on these paths, %d with compiler frames (-fstack-usage), "
          "%d library functions estimated from their push/sub sp instructions" % (len(reached), n_su, len(reached) - n_su))
    for n in sorted(notes):
        print("  not covered: " + n)
    if not notes:
        print("  no function pointers, no recursion, no variable-size frames on these paths")
    return 0


if __name__ == "__main__":
    sys.exit(main())
