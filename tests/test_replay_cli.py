#!/usr/bin/env python3
"""End-to-end tests of the raw-log executables (issue 4): host_sim --raw-log / --params,
replay, replay_f32, log_convert. Exit codes and messages for every kind of bad input, stdin,
the skip mode's counts, format conversion both ways, and the exact round trip through the
executables (replay's estimate columns equal host_sim's, text for text: both print %.9g).

usage: test_replay_cli.py BIN_DIR WORK_DIR   (BIN_DIR holds host_sim, replay, ... of one build)
Standard library only.
"""
import csv
import json
import os
import shutil
import struct
import subprocess
import sys
import zlib

BIN = sys.argv[1]
WORK = sys.argv[2]
FAILED = []
CHECKS = [0]


def exe(name):
    return os.path.join(BIN, name)


def run(args, stdin_bytes=None):
    p = subprocess.run(args, input=stdin_bytes, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=120)
    return p.returncode, p.stdout, p.stderr.decode("utf-8", "replace")


def check(cond, what):
    CHECKS[0] += 1
    if not cond:
        FAILED.append(what)
        print("FAIL:", what)


def path(name):
    return os.path.join(WORK, name)


def write(name, data):
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(path(name), mode) as f:
        f.write(data)
    return path(name)


def body(out):
    """Output lines without the comment lines (which name the input)."""
    return [l for l in out.decode().splitlines() if not l.startswith("#")]


def expect(args, code, *needles, stdin_bytes=None):
    rc, out, err = run(args, stdin_bytes)
    check(rc == code, "%s: exit %d, expected %d\n%s" % (" ".join(args), rc, code, err[-800:]))
    for n in needles:
        check(n in err, "%s: stderr lacks %r:\n%s" % (" ".join(args), n, err[-800:]))
    return out, err


def csv_log(rows, meta="# sample_rate_Hz: 1000\n"):
    head = "t_us,duty,current_counts,tps1_counts,tps2_counts,supply_counts,driver_fault,bridge_enable\n"
    return head + meta + "".join(r + "\n" for r in rows)


def good_rows(n, t0=0):
    return ["%d,0.1,2048,633,3463,2794,0,1" % (t0 + 1000 * k) for k in range(n)]


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)

    # --- help and usage -------------------------------------------------------------------
    out, _ = expect([exe("replay"), "--help"], 0)
    check(b"Exit codes" in out and b"19 finished with --on-error skip" in out, "replay --help lists the exit codes")
    expect([exe("log_convert"), "--help"], 0)
    expect([exe("replay"), "--setup", "4"], 2, "'4' is not 2 or 3")
    expect([exe("replay"), "--bogus"], 2, "unknown option '--bogus'")
    expect([exe("replay"), "--qu", "nan"], 2, "not a finite number")
    expect([exe("log_convert"), "--to", "xml"], 2, "is not csv or bin")
    expect([exe("host_sim"), "--mc", "2", "--raw-log", path("x.csv"), "--out", path("o")], 2, "--mc")

    # --- host_sim writes both formats; replay reproduces its estimates exactly ------------
    for fmt in ("csv", "bin"):
        expect([exe("host_sim"), "--duration", "1", "--out", path("sim_" + fmt), "--raw-log",
                path("raw." + fmt), "--raw-format", fmt], 0)
    with open(path("raw.bin"), "rb") as f:
        check(f.read(8) == b"TVRAWLOG", "binary raw log starts with the magic")
    with open(path("raw.csv")) as f:
        check(f.readline().startswith("t_us,duty,current_counts"), "CSV raw log starts with the column header")
    sim_rows = list(csv.DictReader(open(path("sim_csv/paper_sine.csv"))))
    outs = {}
    for fmt in ("csv", "bin"):
        out, err = expect([exe("replay"), path("raw." + fmt)], 0, "1000 samples replayed", "input errors: none")
        check("\r" not in err, "no progress line when stderr is not a terminal")
        outs[fmt] = body(out)
    check(outs["csv"] == outs["bin"], "replay of the CSV and the binary log agree")
    rep_rows = list(csv.DictReader(outs["bin"]))
    check(len(rep_rows) == len(sim_rows) == 1000, "one output line per sample")
    cols = ["i_est_A", "w_est_rad_s", "phi_est_rad", "i_sigma_A", "w_sigma_rad_s", "phi_sigma_rad"]
    same = all(a[c] == b[c] for a, b in zip(sim_rows, rep_rows) for c in cols)
    same = same and all(a["innov_i_A"] == b["innov_i_A"] and a["innov_phi_rad"] == b["innov_phi_rad"]
                        for a, b in zip(sim_rows, rep_rows))
    check(same, "replay's estimates, sigmas and innovations equal host_sim's (text, %.9g)")

    # float build
    expect([exe("host_sim_f32"), "--duration", "0.5", "--out", path("sim_f32"), "--raw-log", path("raw32.bin"),
            "--raw-format", "bin"], 0)
    out, _ = expect([exe("replay_f32"), path("raw32.bin")], 0)
    s32 = list(csv.DictReader(open(path("sim_f32/paper_sine.csv"))))
    r32 = list(csv.DictReader(body(out)))
    check(len(s32) == len(r32) and all(a[c] == b[c] for a, b in zip(s32, r32) for c in cols),
          "replay_f32 reproduces host_sim_f32 exactly")

    # stdin, start / stop
    with open(path("raw.bin"), "rb") as f:
        out, _ = expect([exe("replay"), "-"], 0, "<stdin>", stdin_bytes=f.read())
    check(body(out) == outs["bin"], "stdin gives the same output as the file")
    out, err = expect([exe("replay"), "--start", "0.2", "--stop", "0.2995", path("raw.csv")], 0,
                      "200 samples before the start time", "100 samples replayed")
    check(len(body(out)) == 1 + 100, "--start 0.2 --stop 0.2995 replays samples 200..299")

    # --- log_convert both ways, byte-identical on the second pass --------------------------
    expect([exe("log_convert"), path("raw.csv"), "-o", path("c1.bin")], 0, "1000 records written")
    expect([exe("log_convert"), path("c1.bin"), "-o", path("c1.csv")], 0)
    expect([exe("log_convert"), "--to", "bin", "--block-records", "7", path("c1.csv"), "-o", path("c2.bin")], 0)
    rc, out, _ = run([exe("log_convert"), "--to", "csv", "-"], open(path("c2.bin"), "rb").read())
    check(rc == 0 and out.decode().replace("<stdin>", "") != "", "log_convert streams stdin to stdout")
    expect([exe("log_convert"), path("c2.bin"), "-o", path("c2.csv")], 0)
    check(open(path("c1.csv")).read() == open(path("c2.csv")).read(), "CSV -> bin -> CSV is byte-identical")
    expect([exe("log_convert"), "--block-records", "64", path("c2.csv"), "-o", path("c3.bin")], 0)
    check(open(path("c1.bin"), "rb").read() == open(path("c3.bin"), "rb").read(), "bin -> CSV -> bin is byte-identical")
    out, _ = expect([exe("replay"), path("c2.bin")], 0)
    check(body(out) == outs["csv"], "a converted log replays identically")

    # --- parameter files ---------------------------------------------------------------------
    out, _ = expect([exe("replay"), "--print-params"], 0)
    write("defaults.txt", out)
    out, _ = expect([exe("replay"), "--params", path("defaults.txt"), path("raw.csv")], 0)
    check(body(out) == outs["csv"], "the printed defaults as a parameter file change nothing")
    write("bad_key.txt", "model.R_ohm = 4.3\nmodel.L = 0.002\n")
    expect([exe("replay"), "--params", path("bad_key.txt"), path("raw.csv")], 3, "bad_key.txt:2: unknown key 'model.L'")
    write("bad_range.txt", "\n\nekf.r_angle_rad2 = 2\n")
    expect([exe("replay"), "--params", path("bad_range.txt"), path("raw.csv")], 3,
           "bad_range.txt:3: ekf.r_angle_rad2 = 2 is out of range")
    write("dup.txt", "model.J_kg_m2 = 0.0016\nmodel.J_kg_m2 = 0.0017\n")
    expect([exe("host_sim"), "--params", path("dup.txt"), "--out", path("o")], 3, "dup.txt:2: duplicate key 'model.J_kg_m2'")
    write("noval.txt", "model.J_kg_m2 =\n")
    expect([exe("host_sim"), "--params", path("noval.txt"), "--out", path("o")], 3, "noval.txt:1: key 'model.J_kg_m2' has no value")
    expect([exe("replay"), "--params", path("missing.txt"), path("raw.csv")], 1, "cannot open")
    # host_sim --params and replay --params: still exact
    write("p.txt", "model.L_H = 0.0025\nekf.qT_Nm2_s = 1e-5\ncalib.tps1_counts_at_zero = 640\n")
    expect([exe("host_sim"), "--duration", "0.5", "--params", path("p.txt"), "--out", path("sim_p"),
            "--raw-log", path("rawp.bin"), "--raw-format", "bin"], 0)
    out, _ = expect([exe("replay"), "--params", path("p.txt"), path("rawp.bin")], 0)
    sp = list(csv.DictReader(open(path("sim_p/paper_sine.csv"))))
    rp = list(csv.DictReader(body(out)))
    check(len(sp) == len(rp) and all(a[c] == b[c] for a, b in zip(sp, rp) for c in cols),
          "host_sim --params and replay --params agree exactly")
    # R / Q overrides on the command line change the estimates
    out, _ = expect([exe("replay"), "--r-angle", "1e-6", "--qu", "1e-4", path("raw.csv")], 0)
    check(body(out) != outs["csv"], "--r-angle / --qu change the estimates")
    out, _ = expect([exe("replay"), "--setup", "3", "--wide", path("raw.csv")], 0)
    check(body(out)[0].endswith("innov_phi_sigma_rad,R_est_ohm,R_sigma_ohm,friction_rel,friction_rel_sigma,preload_rel,preload_rel_sigma,R_fit_ohm,R_fit_sigma_ohm,nKe_fit_V_s_rad,nKe_fit_sigma_V_s_rad,i_off_fit_A,i_off_fit_sigma_A,i_true_A,w_true_rad_s,phi_true_rad"),
          "--wide columns")
    check(body(out)[2].split(",")[10] != "", "set-up 3 uses the velocity channel")
    # the winding-resistance estimate: the nominal plant's R (4.3 ohm, plant.h) within 3 sigma at the
    # end, its sigma below the 0.5 ohm it starts from (the paper sine drives current: it learned)
    last = list(csv.DictReader(body(out)))[-1]
    r_est, r_sig = float(last["R_est_ohm"]), float(last["R_sigma_ohm"])
    check(0.0 < r_sig < 0.5 and abs(r_est - 4.3) <= 3.0 * r_sig,
          f"R estimate {r_est:.4f} +- {r_sig:.4f} ohm against the plant's 4.3")
    # the voltage equation's fit (volt_fit.h, a window of 1000 driven periods): empty before its
    # first window, then, on a 2 s paper sine, the nominal plant's R and n Ke (40 x 0.017 V s/rad)
    # within 3 %, with a sigma
    expect([exe("host_sim"), "--duration", "2", "--out", path("sim_fit"), "--raw-log", path("fit.csv")], 0)
    out, _ = expect([exe("replay"), "--wide", path("fit.csv")], 0)
    rows = list(csv.DictReader(body(out)))
    last = rows[-1]
    check(rows[0]["R_fit_ohm"] == "" and rows[0]["nKe_fit_V_s_rad"] == "", "no fit before its first window")
    r_fit, k_fit = float(last["R_fit_ohm"]), float(last["nKe_fit_V_s_rad"])
    check(abs(r_fit / 4.3 - 1.0) <= 0.03 and abs(k_fit / 0.68 - 1.0) <= 0.03 and float(last["R_fit_sigma_ohm"]) > 0.0,
          f"the fit's R {r_fit:.4f} ohm and n Ke {k_fit:.4f} V s/rad against the plant's 4.3 and 0.68")
    # ... and the current's offset from its fit with an intercept: about 0 on the healthy plant,
    # the injected +50 mA within 10 mA when the sensor reads it from the start
    b0 = float(last["i_off_fit_A"])
    check(rows[0]["i_off_fit_A"] == "" and abs(b0) <= 0.01 and float(last["i_off_fit_sigma_A"]) > 0.0,
          f"the fit's current offset {b0 * 1000:.1f} mA on the healthy plant")
    expect([exe("host_sim"), "--duration", "2", "--fault", "current_offset:0.05@0", "--out", path("sim_off"),
            "--raw-log", path("off.csv")], 0)
    out, _ = expect([exe("replay"), "--wide", path("off.csv")], 0)
    b1 = float(list(csv.DictReader(body(out)))[-1]["i_off_fit_A"])
    check(abs(b1 - 0.05) <= 0.01, f"the fit's current offset {b1 * 1000:.1f} mA with +50 mA injected")

    # --- bad input: each kind, its exit code, its location --------------------------------
    expect([exe("replay"), path("nonexistent.csv")], 1, "cannot open")
    expect([exe("replay"), write("empty.csv", "")], 5, "empty.csv: empty input (0 bytes)")
    expect([exe("replay"), write("hdr.csv", "time,duty\n0,0\n")], 6, "hdr.csv: line 1: the column header has no 't_us' column")
    expect([exe("replay"), write("rnd.bin", bytes(range(256)) * 4)], 7, "rnd.bin: byte offset 0: binary data with a bad magic")
    raw = bytearray(open(path("raw.bin"), "rb").read())
    v2 = bytearray(raw)
    v2[8] = 2
    v2[124:128] = struct.pack("<I", zlib.crc32(bytes(v2[:124])))
    expect([exe("replay"), write("v2.bin", bytes(v2))], 8, "v2.bin: byte offset 8: format version 2 is not supported")
    expect([exe("replay"), write("long.csv", csv_log(good_rows(2)) + "1" * 5000000 + "\n")], 9,
           "long.csv: line 5: 5000000 bytes, longer than the 4096-byte line limit")
    expect([exe("replay"), write("cols.csv", csv_log(good_rows(3) + ["3000,0,1,1,1"]))], 10,
           "cols.csv: line 6: 5 fields, the column header has 8")
    expect([exe("replay"), write("num.csv", csv_log(good_rows(1) + ["1000,0.1,20x48,633,3463,2794,0,1"]))], 11,
           "num.csv: line 4: column 3 (current_counts): '20x48' is not an unsigned integer")
    expect([exe("replay"), write("nan.csv", csv_log(["0,nan,2048,633,3463,2794,0,1"]))], 12,
           "nan.csv: line 3: column 2 (duty): 'nan' is not finite")
    expect([exe("replay"), write("range.csv", csv_log(["0,0,2048,633,4096,2794,0,1"]))], 13,
           "range.csv: line 3: column 5 (tps2_counts): '4096' is outside the ADC range 0..4095")
    expect([exe("replay"), write("back.csv", csv_log(good_rows(3) + ["1500,0,2048,633,3463,2794,0,1"]))], 14,
           "back.csv: line 6: t_us 1500 is 500 us earlier")
    expect([exe("replay"), write("rep.csv", csv_log(good_rows(3) + ["2000,0,2048,633,3463,2794,0,1"]))], 15,
           "rep.csv: line 6: t_us 2000 repeats")
    crc = bytearray(raw)
    crc[128 + 3100] ^= 0x01  # a bit in block 1
    expect([exe("replay"), write("crc.bin", bytes(crc))], 16, "crc.bin: byte offset 3212: block 1 CRC mismatch")
    bs = 8 + 64 * 48 + 4
    blk = bytearray(raw)
    blk[128 + 4:128 + 6] = struct.pack("<H", 0)
    blk[128 + bs - 4:128 + bs] = struct.pack("<I", zlib.crc32(bytes(blk[128:128 + bs - 4])))
    expect([exe("replay"), write("blk.bin", bytes(blk))], 17, "blk.bin: byte offset 132: block 0 claims 0 valid records")
    expect([exe("replay"), write("trunc.bin", bytes(raw[:128 + bs + 100]))], 18,
           "trunc.bin: byte offset 3212: block 1 truncated: 100 of 3084 bytes")
    expect([exe("replay"), write("trunc_hdr.bin", bytes(raw[:60]))], 18, "truncated header: 60 of 128 bytes")
    expect([exe("replay"), "--format", "bin", path("raw.csv")], 7, "bad magic")
    expect([exe("replay"), write("rate.csv", csv_log(good_rows(2), "# sample_rate_Hz: 500\n"))], 4,
           "the log's sample rate is 500 Hz; the application runs at 1000 Hz")
    expect([exe("replay"), "--parse-only", path("rate.csv")], 0, "2 samples validated")
    if os.path.exists("/dev/full"):
        expect([exe("replay"), path("raw.csv"), "-o", "/dev/full"], 1, "writing the output failed")
        expect([exe("log_convert"), path("raw.csv"), "-o", "/dev/full"], 1, "failed")
    # skip mode: every bad line skipped and counted, the good ones replayed, exit 19
    mixed = csv_log(good_rows(3) + ["3000,x,1,1,1,1,0,1", "3000,0,1,1", "3000,inf,2048,633,3463,2794,0,1",
                                    "3000,0,2048,633,3463,99999,0,1", "1000,0,2048,633,3463,2794,0,1"]
                    + good_rows(2, 3000) + ["4000,0,2048,633,3463,2794,0,1"] + good_rows(2, 9000))
    out, err = expect([exe("replay"), "--on-error", "skip", write("mixed.csv", mixed)], 19,
                      "[skipped]", "not a number 1;", "wrong column count 1;", "non-finite value 1;",
                      "value out of range 1;", "timestamp going backwards 1;", "repeated timestamp 1;",
                      "7 samples replayed", "missing samples: 4", "mixed.csv: line 14: 4 samples missing before t_us 9000")
    check(len(body(out)) == 1 + 7, "skip mode writes the 7 good samples")
    expect([exe("replay"), "--on-error", "skip", path("crc.bin")], 19, "CRC mismatch 1;", "936 samples replayed",
           "missing samples: 64")
    expect([exe("log_convert"), "--on-error", "skip", path("mixed.csv"), "-o", path("mixed.bin")], 19,
           "7 records written", "bad inputs skipped")
    expect([exe("log_convert"), path("nan.csv"), "-o", path("nan.bin")], 12, "nan.csv: line 3")
    # a gap is not an error: predicted across and reported
    expect([exe("replay"), write("gap.csv", csv_log(good_rows(3) + good_rows(2, 6000)))], 0,
           "gap.csv: line 6: 3 samples missing before t_us 6000 (predicted across)", "missing samples: 3")

    # --- issue 9 regressions ----------------------------------------------------------------
    # an output that is the input is refused before anything is written (it used to cut a
    # 3,000-record log to 631 records, or empty it), whatever the spelling of the path
    write("same.csv", csv_log(good_rows(3000)))
    before = open(path("same.csv"), "rb").read()
    expect([exe("log_convert"), "--to", "csv", "-o", path("same.csv"), path("same.csv")], 2,
           "is the input log", "refusing to overwrite it")
    expect([exe("replay"), "-o", path("same.csv"), path("same.csv")], 2, "is the input log")
    os.symlink(path("same.csv"), path("same_link.csv"))
    expect([exe("replay"), "-o", path("same_link.csv"), path("same.csv")], 2, "is the input log")
    expect([exe("log_convert"), "-o", os.path.join(WORK, ".", "same.csv"), path("same.csv")], 2, "is the input log")
    check(open(path("same.csv"), "rb").read() == before, "a refused output leaves the input byte for byte")
    # a usage error is one line and a hint, not the whole help
    for prog in ("host_sim", "replay", "log_convert"):
        _, err = expect([exe(prog), "--bogus"], 2, "unknown option '--bogus'", "try '%s --help'" % prog)
        check(len(err.strip().splitlines()) == 2, "%s: a usage error prints two lines, got:\n%s" % (prog, err))
    expect([exe("host_sim"), "--qu", "1", "--qu", "2"], 2, "option --qu given twice")
    expect([exe("replay"), "--r-angle", "0"], 2, "is not > 0 (a variance)")
    expect([exe("log_convert"), "--block-records", "0x10"], 2, "is not an integer in 1..")
    # host_sim --out naming a file: the real reason, not "Success"
    write("afile", "x")
    _, err = expect([exe("host_sim"), "--duration", "0.1", "--out", path("afile")], 1,
                    "cannot create output directory", "Not a directory")
    check("Success" not in err, "host_sim --out FILE does not say Success")
    # the same invalid parameter file gives the same exit code (3) in host_sim and replay
    write("mcms.txt", "model.Mc_Nm = 0.4\nmodel.Ms_Nm = 0.3\n")
    expect([exe("host_sim"), "--params", path("mcms.txt"), "--duration", "0.1", "--out", path("o")], 3,
           "mcms.txt:1", "must be <=")
    expect([exe("replay"), "--params", path("mcms.txt"), path("same.csv")], 3, "mcms.txt:1", "must be <=")
    # --print-params: shortest round-trip numbers
    out, _ = expect([exe("host_sim"), "--print-params"], 0)
    check(b"model.R_ohm = 4.3 " in out and b"4.2999" not in out, "--print-params prints 4.3, not 4.2999999999999998")

    # endless input without a newline ends at once with an error (it used to never end)
    expect([exe("replay"), "--format", "csv", "/dev/zero"], 11, "a NUL byte")
    expect([exe("log_convert"), "--from", "csv", "/dev/zero", "-o", path("z.bin")], 11, "a NUL byte")
    expect([exe("replay"), "--params", "/dev/zero", path("same.csv")], 3, "NUL byte in the line")
    # a log cut in its last line ("...,27" for "...,2793", no final newline) is not replayed as valid
    cut = csv_log(good_rows(3))[:-3]
    expect([exe("replay"), write("cut.csv", cut)], 18, "cut.csv: line 5: the last line has no final newline")
    # a header CRC mismatch exits 6 (bad header), as LOG_FORMATS.md says
    raw = bytearray(open(path("raw.bin"), "rb").read())
    raw[20] ^= 1
    expect([exe("replay"), write("hcrc.bin", bytes(raw))], 6, "header CRC mismatch")

    # a calibration the application refuses is named by file, line and key
    cal = csv_log(good_rows(3), "# sample_rate_Hz: 1000\n# tps1_rad_per_count: 0\n")
    expect([exe("replay"), write("cal0.csv", cal)], 4, "cal0.csv:3: metadata tps1_rad_per_count = 0 must be > 0")

    # the plant's own parameters (issue 10): print, read back, refuse bad keys, change the run
    out, _ = expect([exe("host_sim"), "--print-plant-params"], 0)
    check(b"plant.R_ohm = 4.3\n" in out and b"plant.phi_open_rad = " in out, "--print-plant-params lists the keys")
    write("plant_defaults.txt", out.decode())
    out2, _ = expect([exe("host_sim"), "--plant-params", path("plant_defaults.txt"), "--print-plant-params"], 0)
    check(out2 == out, "a printed plant parameter file reads back to the same values")
    write("plant_bad.txt", "# comment\nplant.R_ohm = 4.5\nplant.bogus = 1\n")
    expect([exe("host_sim"), "--plant-params", path("plant_bad.txt")], 3, "plant_bad.txt:3: unknown key 'plant.bogus'")
    write("plant_dup.txt", "plant.R_ohm = 4.5\nplant.R_ohm = 4.6\n")
    expect([exe("host_sim"), "--plant-params", path("plant_dup.txt")], 3, "plant_dup.txt:2: duplicate key")
    write("plant_hex.txt", "plant.J_kg_m2 = 0x1p-9\n")
    expect([exe("host_sim"), "--plant-params", path("plant_hex.txt")], 3, "is not a decimal number")
    write("plant_ms.txt", "plant.Mc_Nm = 0.5\n")
    expect([exe("host_sim"), "--plant-params", path("plant_ms.txt")], 3, "plant.Ms_Nm", "refuses")
    expect([exe("host_sim"), "--plant-params", "/dev/zero"], 3, "NUL byte")
    expect([exe("host_sim"), "--duration", "0.5", "--out", path("pl_def")], 0)
    expect([exe("host_sim"), "--duration", "0.5", "--out", path("pl_same"), "--plant-params",
            path("plant_defaults.txt")], 0)
    check(open(path("pl_def/paper_sine.csv")).read() == open(path("pl_same/paper_sine.csv")).read(),
          "the defaults as a plant file give the default run exactly")
    write("plant_stops.txt", "plant.phi_open_rad = 1.40\nplant.phi_closed_rad = -0.12\n")
    expect([exe("host_sim"), "--duration", "0.5", "--out", path("pl_st"), "--plant-params", path("plant_stops.txt")], 0)
    check(open(path("pl_def/paper_sine.csv")).read() != open(path("pl_st/paper_sine.csv")).read(),
          "a plant with other stops runs differently")

    # --- host_sim --params-out: what a run learned, as a parameter file read back by --params (the
    # host's persistence of the learned stops, issue 11); the stops against the unit's own plant file
    expect([exe("host_sim"), "--mc", "2", "--params-out", path("x.params"), "--out", path("o")], 2, "--params-out")
    expect([exe("host_sim"), "--scenario", "stop_learn", "--unit", "1005", "--spread", "stops", "--out", path("sl"),
            "--params-out", path("learned.params")], 0)
    plant_out, _ = expect([exe("host_sim"), "--unit", "1005", "--spread", "stops", "--print-plant-params"], 0)
    plant = plant_out.decode()
    learned = open(path("learned.params")).read()
    def value(text, key):
        for line in text.splitlines():
            if line.startswith(key + " ="):
                return float(line.split("=")[1].split("#")[0])
        return float("nan")
    for stop in ("phi_closed_rad", "phi_open_rad"):
        err_mrad = 1e3 * abs(value(learned, "model." + stop) - value(plant, "plant." + stop))
        check(err_mrad <= 5.0, "host_sim --params-out: the learned %s within 5 mrad of the unit's (%.2f mrad)" % (stop, err_mrad))
    check(value(learned, "model.stop_exponent") >= 1.0, "host_sim --params-out: the learned contact law (Hunt-Crossley)")
    expect([exe("host_sim"), "--scenario", "open_steps", "--duration", "0.5", "--unit", "1005", "--spread", "stops",
            "--params", path("learned.params"), "--out", path("sl2")], 0)
    # the fit's per-unit baseline: learned in 30 s of driving with the temperature told, written with
    # the stops, within 1 % (R at 20 degC) and 1.5 % (n Ke) of the unit's; not without the temperature
    write("learn_base.params", "diag.fit_base_windows = 16\n")
    expect([exe("host_sim"), "--scenario", "drive", "--duration", "30", "--unit", "1005", "--spread", "all",
            "--temp-reading", "plant", "--params", path("learn_base.params"), "--out", path("fb"),
            "--params-out", path("base.params")], 0, "the fit's baseline")
    plant_all = expect([exe("host_sim"), "--unit", "1005", "--spread", "all", "--print-plant-params"], 0)[0].decode()
    base = open(path("base.params")).read()
    r_rel = value(base, "diag.fit_base_r_ohm") / value(plant_all, "plant.R_ohm")
    k_rel = value(base, "diag.fit_base_nke_V_s") / (value(plant_all, "plant.n_gear") * value(plant_all, "plant.Ke_V_s_rad"))
    check(abs(r_rel - 1.0) < 0.01 and abs(k_rel - 1.0) < 0.015,
          "host_sim --params-out: the learned baseline's R %.4f and n Ke %.4f of the unit's" % (r_rel, k_rel))
    expect([exe("host_sim"), "--scenario", "drive", "--duration", "30", "--unit", "1005", "--spread", "all",
            "--params", path("learn_base.params"), "--out", path("fb0"), "--params-out", path("base0.params")], 0)
    check(value(open(path("base0.params")).read(), "diag.fit_base_r_ohm") == 0.0,
          "host_sim --params-out: no baseline learned with the winding's temperature unknown")

    # --- fault injection and diagnostic events (issue 12): host_sim --fault / --events, replay --events
    expect([exe("host_sim"), "--fault", "tps1_offset:1"], 2, "option --fault", "no '@'")
    expect([exe("host_sim"), "--fault", "jam:5@1:0.2"], 2, "option --fault", "jam cannot drift")
    expect([exe("host_sim"), "--fault", "supply_sag:20@0.1", "--duration", "0.2", "--out", path("o")], 1, "run failed")
    _, err = expect([exe("host_sim"), "--scenario", "closed_steps", "--duration", "1.5", "--out", path("dtc"),
                     "--fault", "tps1_offset:1@1.0", "--raw-log", path("dtc_raw.csv"), "--events", path("dtc_sim.csv")], 0)
    sim_ev = open(path("dtc_sim.csv")).read().splitlines()
    check(sim_ev[0] == "t_us,status,fault_class,dtc", "host_sim --events: header")
    check("1000000,pending,tps1_fault,P0121" in sim_ev and "1019000,confirmed,tps1_fault,P0121" in sim_ev,
          "host_sim --events: P0121 pending at the onset, confirmed at its 20th failing sample:\n%s" % "\n".join(sim_ev))
    _, err = expect([exe("replay"), path("dtc_raw.csv"), "-o", path("dtc_rep.csv"), "--events", path("dtc_rep_ev.csv")], 0,
                    "diagnostic codes confirmed: P0121 (tps1_fault) at t = 1.019000 s")
    rep_ev = open(path("dtc_rep_ev.csv")).read().splitlines()
    # replay observes in APP_MODE_EXTERNAL: no closed loop, so no jam check; the track codes are the same
    check([l for l in sim_ev if ",jam," not in l] == rep_ev,
          "replay --events reproduces host_sim's track events:\n%s\n--\n%s" % ("\n".join(sim_ev), "\n".join(rep_ev)))
    expect([exe("replay"), path("dtc_raw.csv"), "-o", path("dtc_rep.csv"), "--events", path("dtc_raw.csv")], 2,
           "is the input log")

    # --- the winding's temperature: a healthy winding at 110 degC (1.35 x its 20 degC resistance)
    # reads as P2101 to an application that is not told the temperature, and as healthy to one
    # that is (host_sim --winding-temp / --temp-reading, replay --winding-temp)
    expect([exe("host_sim"), "--scenario", "closed_steps", "--duration", "6", "--winding-temp", "110", "--out",
            path("warm"), "--raw-log", path("warm_raw.csv"), "--events", path("warm_sim.csv")], 0)
    check(any(",confirmed,winding_resistance_high,P2101" in l for l in open(path("warm_sim.csv"))),
          "host_sim: 110 degC untold confirms P2101")
    expect([exe("replay"), path("warm_raw.csv"), "-o", path("warm_rep.csv")], 0,
           "diagnostic codes confirmed: P2101 (winding_resistance_high)")
    expect([exe("replay"), path("warm_raw.csv"), "-o", path("warm_rep.csv"), "--winding-temp", "110"], 0,
           "diagnostic codes confirmed: none")
    expect([exe("host_sim"), "--scenario", "closed_steps", "--duration", "6", "--winding-temp", "110",
            "--temp-reading", "plant", "--out", path("warm2"), "--events", path("warm_sim2.csv")], 0)
    check(not any("P2101" in l for l in open(path("warm_sim2.csv"))), "host_sim: 110 degC told: no P2101")
    with open(os.path.join(path("warm2"), "closed_steps_metrics.json")) as f:
        wr = json.load(f)["winding_resistance"]
    check(abs(wr["plant_20C_ohm"] - 4.3) < 1e-9 and abs(wr["estimate_20C_ohm"] / 4.3 - 1.0) < 0.02,
          "host_sim: R referred to 20 degC: %s" % wr)
    expect([exe("replay"), path("warm_raw.csv"), "--winding-temp", "181"], 2, "--winding-temp")
    expect([exe("host_sim"), "--winding-temp", "-41"], 2, "--winding-temp")
    expect([exe("host_sim"), "--temp-reading", "hot"], 2, "--temp-reading", "plant or none")
    expect([exe("host_sim"), "--winding-temp", "20", "--winding-temp", "30"], 2, "given twice")

    print("%d checks, %d failed" % (CHECKS[0], len(FAILED)))
    return 1 if FAILED else 0


if __name__ == "__main__":
    sys.exit(main())
