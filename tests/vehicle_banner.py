#!/usr/bin/env python3
"""`strata vehicle` says which scenario it runs (issue 40: `--scenario leak`
printed `scenario ''`, the file's empty description, not its name).

Each case starts its own vehicle on a free loopback port, reads the line
that says what it listens with, and stops it by its pid.

  vehicle_banner.py STRATA TANK_MISSION
"""
import re
import signal
import subprocess
import sys
import threading


def banner(strata, args):
    v = subprocess.Popen([strata, "vehicle", "--listen", "0", *args], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    # A vehicle that never says it listens must not hang the test.
    timer = threading.Timer(60, v.kill)
    timer.start()
    try:
        v.stdout.readline()  # the address
        line = v.stderr.readline().strip()
    finally:
        timer.cancel()
        v.send_signal(signal.SIGTERM)
        try:
            v.wait(timeout=30)
        except subprocess.TimeoutExpired:
            v.kill()
            v.wait()
    return line


def main():
    strata, tank = sys.argv[1], sys.argv[2]
    cases = [
        (["--mission", tank, "--scenario", "leak_phase3"],
         r"scenario leak_phase3 \(leak at 14\.0 s, during the dive of phase 3\), seed 1\)$"),
        ([], r"scenario nominal, seed 1\)$"),
    ]
    failures = 0
    for args, want in cases:
        line = banner(strata, args)
        if not line.startswith("vehicle: listening on 127.0.0.1:") or not re.search(want, line):
            print(f"strata vehicle {' '.join(args)}: said {line!r}; wanted {want}", file=sys.stderr)
            failures += 1
    print(f"{len(cases)} vehicles: {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
