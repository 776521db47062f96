#!/usr/bin/env python3
"""The README's short tour of the CLI, run as written.

The tour is the ```sh block under "## A short tour of the CLI". Each of its
lines that starts with `strata` is run (its `# ...` comment dropped) in a
scratch folder holding copies of missions/, tests/run/ and tests/verify/,
in the order written (the plot reads the log an earlier line wrote), with
strata first on PATH. What each line must do is in TOUR below: its exit
code and a line of its output; or, for the commands that serve until
Ctrl-C (the studio, the vehicle, the Sonar Manager), the line they print
when they are up, after which they are sent SIGINT and must end cleanly.

`strata vehicle` without `--listen` listens on 127.0.0.1:7020, which
another program may hold on a shared machine: the test adds `--listen 0`
(a free port) and looks for that port instead.

A tour line that TOUR does not know fails, and so does an entry of TOUR
that the tour no longer has: the README and this test change together.

Two lines name an address that only exists while the test runs: the
vehicle of `--vehicle 127.0.0.1:7020` and the sonar socket of `strata
sonar --stream 127.0.0.1:PORT` are a `strata vehicle --listen 0` the test
starts, and their ports are put in place of 7020 and PORT.

  readme_tour.py README --strata BIN --source REPO --work DIR
"""
import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time

# command as written -> (exit code, a regex one line of its output must match)
#                    or ("serve", regex of the line that says it is up[, regex of
#                        a line to wait for before Ctrl-C])
TOUR = {
    "strata check missions/tank/*.coral": (0, r"missions/tank/tank\.coral: ok"),
    "strata check --format json tests/coral/fail_undefined_place.coral": (65, r'"kind": "UndefinedPlace"'),
    "strata dump missions/tank/tank.coral": (0, r"net dive_from_surface"),
    "strata dump missions/tank/tank.coral --net dive_from_surface": (0, r"dive_from_surface"),
    "strata run missions/tank/tank.coral": (0, r"^mission tank: completed"),
    "strata run missions/tank/tank.coral --scenario weak_thrusters --log run.jsonl": (1, r"log: run\.jsonl"),
    "strata run missions/tank/tank.coral --realtime --speed 10": (0, r"^mission tank: completed"),
    "strata run missions/tank/tank.coral --vehicle 127.0.0.1:7020": (0, r"^mission tank: completed"),
    "strata run tests/run/hold_at_depth.coral --max-sim-time 600": (1, r"limit"),
    "strata run missions/tank/tank.pl": (0, r"^mission tank: completed"),
    "strata compare missions/tank/tank.coral missions/tank/tank.pl --scenario leak_phase3": (0, r"identical"),
    "strata verify missions/tank/tank.coral": (0, r"^verified 5 nets"),
    "strata verify --format json tests/verify/stuck_phase.coral": (65, r'"no_deadlock"'),
    "strata run tests/verify/exits_together.coral --unverified": (0, r"^mission exits_together: completed"),
    "strata export --pnml missions/tank/tank.coral -o nets/": (0, r"nets/"),
    "strata plot run.jsonl -o run.svg": (0, r"run\.svg"),
    "strata run missions/sonar_search/sonar_search.coral --sonar scans": (0, r"scans in scans"),
    "strata compare missions/sonar_search/sonar_search.coral missions/sonar_search/sonar_search.pl "
    "--scenario leak_search": (0, r"identical"),
    "strata sonar --stream 127.0.0.1:PORT --out scans": ("serve", r"."),
    "strata verify missions/tank/tank.coral --net dive_from_surface --question 'EF filter_on >= 1' "
    "--witness-out w.json": (0, r"answer\s+yes"),
    "strata run missions/tank/tank.coral --answers w.json": (1, r"^mission tank: failed"),
    "strata verify --pnml tests/verify/mutex.pnml --format json": (0, r'"states": 3'),
    "strata verify --pnml tests/verify/mutex.pnml --question deadlock": (0, r"answer\s+no"),
    "strata-pnml tests/verify/mutex.pnml": (0, r"states\s+3"),
    "strata studio missions": ("serve", r"http://127\.0\.0\.1:\d+"),
    # Ctrl-C once the run has ended (the studio may serve on after it).
    "strata run missions/tank/tank.coral --studio --speed 10": ("serve", r"http://127\.0\.0\.1:\d+",
                                                                r"^mission tank: completed"),
    "strata primitives": (0, r"system_problem"),
    "strata library": (0, r"goto\(x, y, depth, speed\)  exits: arrived"),
    "strata vehicle --listen 0": ("serve", r"^127\.0\.0\.1:\d+$"),
    "strata vehicle --scenario weak_thrusters --mission missions/tank/tank.coral": ("serve", r"^127\.0\.0\.1:7020$"),
    "strata vehicle --realtime --speed 5": ("serve", r"^127\.0\.0\.1:7020$"),
    "strata vehicle --interface": (0, r"tlm"),
    "strata check --vehicle imc://127.0.0.1:6002 missions/survey/survey.coral": (0, r"survey\.coral: ok"),
    "strata vehicle --imc --port 0 --speed 50": ("serve", r"^imc vehicle phoenix-sim \(id 0x2C01\) on udp://127\.0\.0\.1:\d+$"),
    "strata --help": (0, r"run"),
}


def tour_lines(readme):
    with open(readme, encoding="utf-8") as f:
        lines = f.read().split("\n")
    start = lines.index("## A short tour of the CLI")
    i = start + 1
    while not lines[i].startswith("```"):
        i += 1
    first = i + 1
    out = []
    i = first
    while not lines[i].startswith("```"):
        text = lines[i].split(" #")[0].strip()
        if text.startswith("strata"):
            out.append((i + 1, text))
        i += 1
    return out


class Serving:
    """A process whose output is read as it comes."""

    def __init__(self, args, cwd, env):
        self.p = subprocess.Popen(args, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                  text=True, start_new_session=True)
        self.lines = []
        self.cond = threading.Condition()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for line in self.p.stdout:
            with self.cond:
                self.lines.append(line.rstrip("\n"))
                self.cond.notify_all()
        with self.cond:
            self.lines.append(None)
            self.cond.notify_all()

    def wait_for(self, rx, timeout):
        """The first line matching rx, or None (timeout, or the process ended)."""
        deadline = time.monotonic() + timeout
        seen = 0
        with self.cond:
            while True:
                while seen < len(self.lines):
                    line = self.lines[seen]
                    seen += 1
                    if line is None:
                        return None
                    m = rx.search(line)
                    if m:
                        return m
                left = deadline - time.monotonic()
                if left <= 0:
                    return None
                self.cond.wait(left)

    def interrupt(self, timeout=30):
        if self.p.poll() is None:
            self.p.send_signal(signal.SIGINT)
        try:
            return self.p.wait(timeout)
        except subprocess.TimeoutExpired:
            os.killpg(self.p.pid, signal.SIGKILL)
            return self.p.wait()

    def output(self):
        self.reader.join(5)
        return "\n".join(line for line in self.lines if line is not None)


def main():
    ap = argparse.ArgumentParser(description="Run the README's tour of the CLI")
    ap.add_argument("readme")
    ap.add_argument("--strata", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    work = os.path.abspath(a.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    for d in ["missions", "tests/run", "tests/verify", "tests/coral"]:
        shutil.copytree(os.path.join(a.source, d), os.path.join(work, d),
                        ignore=shutil.ignore_patterns("runs", "*.layout.json"))
    env = dict(os.environ)
    env["PATH"] = os.path.dirname(os.path.abspath(a.strata)) + os.pathsep + env.get("PATH", "")
    # A home of its own, as doc_run.py gives: the runs' default logs stay in
    # the scratch folder and the user's configuration changes nothing.
    env["HOME"] = os.path.join(work, "home")
    os.makedirs(env["HOME"])
    for var in ("XDG_CONFIG_HOME", "XDG_STATE_HOME", "XDG_DATA_HOME", "STRATA_CONFIG", "STRATA_LOG_DIR"):
        env.pop(var, None)
    have_gnuplot = shutil.which("gnuplot") is not None

    tour = tour_lines(a.readme)
    name = os.path.basename(a.readme)
    failures = []
    for n, cmd in tour:
        if cmd not in TOUR:
            failures.append(f"{name}:{n}: `{cmd}`: a tour line this test does not know (add it to TOUR in "
                            f"tests/readme_tour.py, with what it must do)")
    for cmd in TOUR:
        if cmd not in [c for _, c in tour]:
            failures.append(f"tests/readme_tour.py: `{cmd}` is no longer in the README's tour: remove it from TOUR")

    # The vehicle that 127.0.0.1:7020 and PORT stand for.
    vehicle = Serving(["strata", "vehicle", "--listen", "0"], work, env)
    sonar_rx = re.compile(r"sonar socket on 127\.0\.0\.1:(\d+)")
    first = vehicle.wait_for(re.compile(r"^127\.0\.0\.1:(\d+)$"), 30)
    sonar = vehicle.wait_for(sonar_rx, 30)
    if not first or not sonar:
        print(f"the test's own vehicle did not start:\n{vehicle.output()}", file=sys.stderr)
        vehicle.interrupt()
        return 1
    ports = {"7020": first.group(1), "PORT": sonar.group(1)}

    run = 0
    for n, cmd in tour:
        if cmd not in TOUR:
            continue
        want, pattern, *then = TOUR[cmd]
        rx = re.compile(pattern, re.M)
        shell = cmd.replace("127.0.0.1:7020", "127.0.0.1:" + ports["7020"]).replace("127.0.0.1:PORT",
                                                                                  "127.0.0.1:" + ports["PORT"])
        if cmd.startswith("strata vehicle") and not any(f in cmd for f in ("--listen", "--interface", "--port")):
            shell += " --listen 0"  # 7020 may be taken on a shared machine
            pattern = r"^127\.0\.0\.1:\d+$"
        run += 1
        if want == "serve":
            s = Serving(["bash", "-c", "exec " + shell], work, env)
            up = s.wait_for(re.compile(pattern), 60)
            if up and then and not s.wait_for(re.compile(then[0], re.M), 120):
                failures.append(f"{name}:{n}: `{cmd}` did not print a line matching {then[0]}")
            time.sleep(0.3)
            code = s.interrupt()
            out = s.output()
            if not up:
                failures.append(f"{name}:{n}: `{cmd}` did not print a line matching {pattern}:\n{out[-1500:]}")
            elif code not in (0, 130):
                failures.append(f"{name}:{n}: `{cmd}` exited {code} after Ctrl-C:\n{out[-1500:]}")
            continue
        if cmd.startswith("strata plot") and not have_gnuplot:
            want, rx = 69, re.compile(r"gnuplot not found")
        try:
            r = subprocess.run(["bash", "-c", shell], cwd=work, env=env, capture_output=True, text=True,
                               timeout=300)
        except subprocess.TimeoutExpired:
            failures.append(f"{name}:{n}: `{cmd}` did not end in 300 s")
            continue
        out = r.stdout + r.stderr
        if r.returncode != want:
            failures.append(f"{name}:{n}: `{cmd}` exited {r.returncode}, not {want}:\n{out[-1500:]}")
        elif not rx.search(out):
            failures.append(f"{name}:{n}: `{cmd}` printed no line matching {pattern}:\n{out[-1500:]}")
    vehicle.interrupt()

    # What the tour says it leaves behind.
    for path, what in [("nets", "the PNML export"), ("scans", "the sonar scans")]:
        if not os.path.isdir(os.path.join(work, path)) or not os.listdir(os.path.join(work, path)):
            failures.append(f"{name}: the tour left no {path}/ ({what})")
    if have_gnuplot and not os.path.isfile(os.path.join(work, "run.svg")):
        failures.append(f"{name}: the tour left no run.svg")

    for f in failures:
        print(f, file=sys.stderr)
    print(f"{name}: the tour's {len(tour)} commands, {run} run, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
