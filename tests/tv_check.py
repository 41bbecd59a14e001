"""The Python tests' check: print ok/FAIL for each condition and count the failures
(tv_check.failures), so a test runs every check and exits non-zero if any failed."""
failures = 0


def check(cond, what):
    global failures
    if not cond:
        failures += 1
        print("FAIL: " + what)
    else:
        print("ok: " + what)
