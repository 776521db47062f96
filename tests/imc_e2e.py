#!/usr/bin/env python3
"""A mission over IMC against `strata vehicle --imc`, compared with the same
mission over the Phoenix protocol (issue 35's target).

For each case MISSION[@SCENARIO], a fresh `strata vehicle --imc --port 0`
(the scenario's file; faster than real time at --speed, or with --lockstep
in lockstep with the run, the same whatever the machine's load) is started
on loopback, and
`strata compare MISSION MISSION --vehicle-b imc://127.0.0.1:PORT` runs A on
the embedded lockstep vehicle and B on the IMC one; the comparison must say
the two ran the same commands in the same order with the same outcome. The
vehicle is stopped by its process id whatever happens.

  imc_e2e.py --strata BIN --source REPO (--speed K | --lockstep) [--work DIR] CASE...

Two cases are not missions: `safe_end` (a run ended by --max-sim-time on the
vehicle's clock must be surfaced by a z = 0 Reference and say so in
mission_end) and `second_controller` (a second Strata run takes the vehicle
while the first one's link is flooded with garbage: the first ends safely,
naming the replaced plan, with what it did not use counted).

With --dune, the same against LSTS DUNE's own simulator instead, when
STRATA_DUNE names its executable and STRATA_DUNE_CONFIG its configuration
(e.g. lauv-simulator-1): DUNE is started (`-c CONFIG -p Simulation`), each
CASE is run on it with `strata run --vehicle imc://127.0.0.1:6002` and must
complete, and DUNE is stopped by its process id. Without them the test is
skipped (exit 77) with one line saying why: DUNE is never part of Strata's
build (docs/imc.md says how to build it).
"""
import argparse
import concurrent.futures
import json
import os
import re
import queue
import socket
import subprocess
import sys
import threading
import time

PORT = re.compile(r"udp://127\.0\.0\.1:(\d+)")


def start_vehicle(strata, scenario, speed, lockstep=False):
    cmd = [strata, "vehicle", "--imc", "--port", "0"] + (["--lockstep"] if lockstep else ["--speed", str(speed)])
    if scenario:
        cmd += ["--scenario", scenario]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines = queue.Queue()

    def read():  # every line the vehicle prints, so its pipe never fills
        for line in proc.stdout:
            lines.put(line)
        lines.put(None)

    threading.Thread(target=read, daemon=True).start()
    seen = []
    while True:
        try:
            # A bound so a broken vehicle fails the test; not a limit on its speed.
            line = lines.get(timeout=60)
        except queue.Empty:
            line = None
        if line is None:
            break
        seen.append(line)
        m = PORT.search(line)
        if m:
            return proc, int(m.group(1))
    proc.kill()
    proc.wait()
    raise SystemExit("the IMC vehicle did not print its port:\n" + "".join(seen))


def last_record(log, event):
    found = None
    with open(log, encoding="utf-8") as f:
        for line in f:
            r = json.loads(line)
            if r.get("event") == event:
                found = r
    return found


def wait_for(pred, what, bound_s=120):
    """Polls pred() until true; the bound only keeps a broken run from hanging the test."""
    deadline = time.monotonic() + bound_s
    while time.monotonic() < deadline:
        if pred():
            return
        time.sleep(0.05)
    raise SystemExit(f"gave up waiting for {what}")


def safe_end(a, work):
    """hold_at_depth over IMC, ended by the limit on the vehicle's clock: the
    run's safe end surfaces the vehicle with a z = 0 Reference and says so."""
    proc, port = start_vehicle(a.strata, "", a.speed)
    log = os.path.join(work, "safe_end.jsonl")
    try:
        r = subprocess.run([a.strata, "run", os.path.join(a.source, "tests/run/hold_at_depth.coral"), "--vehicle",
                            f"imc://127.0.0.1:{port}", "--speed", str(a.speed), "--max-sim-time", "40", "--log", log],
                           capture_output=True, text=True, timeout=600)
    finally:
        proc.kill()
        proc.wait()
    end = last_record(log, "mission_end") if os.path.exists(log) else None
    final = last_record(log, "vehicle_final") if os.path.exists(log) else None
    ok = (r.returncode == 1 and end and end.get("stopped_by") == "limit"
          and end.get("safe_end", {}).get("surface_by") == "reference" and end["safe_end"].get("surfaced")
          and end["safe_end"].get("done_answered") and final and final["depth_m"] <= 0.15)
    if not ok:
        return [f"safe end over IMC: exit {r.returncode}, mission_end {end}, vehicle_final {final}\n{r.stdout}{r.stderr}"]
    print(f"safe end over IMC: stopped by the limit, surfaced by a z = 0 Reference, done answered "
          f"(depth {final['depth_m']} m)")
    return []


def second_controller(a, work):
    """A run (A) holds at depth while its link is flooded with garbage; a
    second Strata run (B) starts its own plan on the same vehicle, which
    replaces A's (DUNE has no ownership). A must end safely, naming the
    fault, with what it dropped counted; B must complete."""
    proc, port = start_vehicle(a.strata, "", a.speed)
    log = os.path.join(work, "replaced.jsonl")
    try:
        run_a = subprocess.Popen([a.strata, "run", os.path.join(a.source, "tests/run/hold_at_depth.coral"),
                                  "--vehicle", f"imc://127.0.0.1:{port}", "--speed", str(a.speed), "--log", log],
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        lines = queue.Queue()
        threading.Thread(target=lambda: [lines.put(l) for l in run_a.stdout] + [lines.put(None)],
                         daemon=True).start()
        seen, link_port = [], None
        while link_port is None:
            line = lines.get(timeout=120)
            if line is None:
                break
            seen.append(line)
            m = re.search(r"started from udp://127\.0\.0\.1:(\d+)", line)
            if m:
                link_port = int(m.group(1))
        if link_port is None:
            run_a.kill()
            return ["second controller: run A never connected:\n" + "".join(seen)]

        def at_depth():
            rec = last_record(log, "telemetry") if os.path.exists(log) else None
            return rec is not None and rec.get("depth_m", 0) > 0.5
        wait_for(at_depth, "run A at depth")
        # The flood: garbage of every kind to A's link, as fast as one
        # thread sends, bounded in count.
        flood = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        garbage = [b"\x01", b"\x54\xfe" + b"\x00" * 30, b"\xfe\x54" + b"\xff" * 40, os.urandom(200)]
        sent, t0 = 0, time.monotonic()
        while sent < 100_000:
            for g in garbage:
                flood.sendto(g, ("127.0.0.1", link_port))
            sent += len(garbage)
        rate = sent / (time.monotonic() - t0)
        b = subprocess.run([a.strata, "run", os.path.join(a.source, "missions/tank/tank.coral"), "--vehicle",
                            f"imc://127.0.0.1:{port}", "--speed", str(a.speed), "--no-log"],
                           capture_output=True, text=True, timeout=600)
        # Run A must end by itself (its plan was replaced); a bound, not a speed limit.
        deadline = time.monotonic() + 300
        while True:
            pid, status, usage = os.wait4(run_a.pid, os.WNOHANG)
            if pid == run_a.pid:
                break
            if time.monotonic() > deadline:
                run_a.kill()
                run_a.wait()
                return ["second controller: run A did not end after its plan was replaced"]
            time.sleep(0.1)
        out_a = "".join(seen)
        while True:
            line = lines.get(timeout=60)
            if line is None:
                break
            out_a += line
    finally:
        proc.kill()
        proc.wait()
    end = last_record(log, "mission_end")
    code_a = os.waitstatus_to_exitcode(status)
    failures = []
    if not (code_a == 1 and end and "replaced this run's plan" in end.get("vehicle_fault", "")
            and "failed: the vehicle stopped taking this run's commands" in out_a
            and end.get("imc", {}).get("other_sources", 0) > 0 and "surface_by" not in end.get("safe_end", {})
            and usage.ru_maxrss < 1024 * 1024):  # KiB: bounded, flood or not (ASan included)
        failures.append(f"second controller: run A did not end safely for the replaced plan (exit {code_a}): "
                        f"{end}\n{out_a}")
    if b.returncode != 0:
        failures.append(f"second controller: run B did not complete (exit {b.returncode}):\n{b.stdout}{b.stderr}")
    if not failures:
        print(f"second controller: A ended for its replaced plan, {sent} garbage datagrams sent at "
              f"{rate:,.0f}/s, {end['imc']['other_sources']} counted from others and "
              f"{sum(end['imc']['dropped'].values())} dropped, A's peak RSS "
              f"{usage.ru_maxrss / 1024:.0f} MiB; B completed")
    return failures


def run_on_dune(a):
    dune, config = os.environ.get("STRATA_DUNE"), os.environ.get("STRATA_DUNE_CONFIG")
    if not dune or not config:
        print("skipped: STRATA_DUNE and STRATA_DUNE_CONFIG do not name a DUNE simulator (docs/imc.md, "
              "\"Running on LSTS DUNE\")")
        return 77
    proc = subprocess.Popen([dune, "-c", config, "-p", "Simulation"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    failures = []
    try:
        time.sleep(10)  # DUNE's tasks start; not a limit on anything Strata does
        for case in a.cases:
            mission = os.path.join(a.source, case.partition("@")[0])
            r = subprocess.run([a.strata, "run", mission, "--vehicle", "imc://127.0.0.1:6002", "--no-log"],
                               capture_output=True, text=True, timeout=3600)
            if r.returncode != 0:
                failures.append(f"{case} on DUNE: exit {r.returncode}\n{r.stdout}{r.stderr}")
            else:
                print(f"{case}: completed on DUNE")
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{len(a.cases) - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dune", action="store_true", help="run the cases on LSTS DUNE (STRATA_DUNE)")
    ap.add_argument("--work", default=None, help="a folder for the runs' logs (the safe-end cases)")
    ap.add_argument("--strata", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--speed", type=float, default=20.0)
    ap.add_argument("--lockstep", action="store_true",
                    help="the compared cases' vehicles in lockstep with their runs (strata vehicle --imc --lockstep), "
                         "not on the wall clock at --speed")
    ap.add_argument("--jobs", type=int, default=3, help="compared cases run at once (default 3)")
    ap.add_argument("cases", nargs="+")
    a = ap.parse_args()
    if a.jobs < 1:
        ap.error(f"--jobs must be 1 or more, not {a.jobs}")
    if a.dune:
        return run_on_dune(a)
    failures = []
    work = a.work or os.getcwd()
    os.makedirs(work, exist_ok=True)
    compared = []
    for case in a.cases:
        if case == "safe_end":
            failures += safe_end(a, work)
        elif case == "second_controller":
            failures += second_controller(a, work)
        else:
            compared.append(case)
    # The compared cases mostly wait on their vehicles' wall clocks: a few
    # at once (each its own vehicle on its own port), reported in order.
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        for lines, failed in pool.map(lambda c: compare_case(a, c), compared):
            for line in lines:
                print(line)
            failures += failed
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{len(a.cases) - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


def compare_case(a, case):
    """One mission compared over the Phoenix protocol and over IMC: (lines
    to print, failures)."""
    # MISSION@SCENARIO:lost -- the vehicle falls silent: both runs must
    # fail for the lost link (the call it fails on depends on the level).
    case_spec, _, expect = case.partition(":")
    mission, _, scenario = case_spec.partition("@")
    mission_path = os.path.join(a.source, mission)
    scenario_path = ""
    if scenario:
        scenario_path = os.path.join(os.path.dirname(mission_path), "scenarios", scenario + ".toml")
    proc, port = start_vehicle(a.strata, scenario_path, a.speed, a.lockstep)
    try:
        cmd = [a.strata, "compare", mission_path, mission_path, "--format", "json",
               "--vehicle-b", f"imc://127.0.0.1:{port}", "--speed", str(a.speed)]
        if scenario:
            cmd += ["--scenario", scenario]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    finally:
        proc.kill()  # by its pid: the vehicle never ends by itself
        proc.wait()
    try:
        j = json.loads(r.stdout)
    except json.JSONDecodeError:
        return [], [f"{case}: compare printed no JSON (exit {r.returncode}):\n{r.stdout}{r.stderr}"]
    if expect == "lost":
        lost = (j["a"]["outcome"] == "failed" and j["b"]["outcome"] == "failed"
                and "no EstimatedState from the IMC vehicle" in j["b"]["reason"])
        if not lost:
            return [], [f"{case}: not both failed for the lost link:\n{json.dumps(j, indent=1)}"]
        return [f"{case}: both runs failed for the lost link"], []
    if (r.returncode != 0 or not j.get("identical") or j.get("compared") != "commands"
            or j["b"].get("execution_level") != "imc"):
        return [], [f"{case}: not the same commands over IMC (exit {r.returncode}):\n"
                    f"{json.dumps(j, indent=1)}\n{r.stderr}"]
    return [f"{case}: the same {j['a']['outcome']} run over IMC ({j['a']['calls']} calls on the Phoenix, "
            f"{j['b']['calls']} over IMC)"], []


if __name__ == "__main__":
    sys.exit(main())
