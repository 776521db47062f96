#!/usr/bin/env python3
"""A mission over IMC against `strata vehicle --imc`, compared with the same
mission over the Phoenix protocol (issue 35's target).

For each case MISSION[@SCENARIO], a fresh `strata vehicle --imc --port 0`
(the scenario's file, faster than real time) is started on loopback, and
`strata compare MISSION MISSION --vehicle-b imc://127.0.0.1:PORT` runs A on
the embedded lockstep vehicle and B on the IMC one; the comparison must say
the two ran the same commands in the same order with the same outcome. The
vehicle is stopped by its process id whatever happens.

  imc_e2e.py --strata BIN --source REPO --speed K CASE...

With --dune, the same against LSTS DUNE's own simulator instead, when
STRATA_DUNE names its executable and STRATA_DUNE_CONFIG its configuration
(e.g. lauv-simulator-1): DUNE is started (`-c CONFIG -p Simulation`), each
CASE is run on it with `strata run --vehicle imc://127.0.0.1:6002` and must
complete, and DUNE is stopped by its process id. Without them the test is
skipped (exit 77) with one line saying why: DUNE is never part of Strata's
build (docs/imc.md says how to build it).
"""
import argparse
import json
import os
import re
import queue
import subprocess
import sys
import threading
import time

PORT = re.compile(r"udp://127\.0\.0\.1:(\d+)")


def start_vehicle(strata, scenario, speed):
    cmd = [strata, "vehicle", "--imc", "--port", "0", "--speed", str(speed)]
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
    ap.add_argument("--strata", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--speed", type=float, default=20.0)
    ap.add_argument("cases", nargs="+")
    a = ap.parse_args()
    if a.dune:
        return run_on_dune(a)
    failures = []
    for case in a.cases:
        # MISSION@SCENARIO:lost -- the vehicle falls silent: both runs must
        # fail for the lost link (the call it fails on depends on the level).
        case_spec, _, expect = case.partition(":")
        mission, _, scenario = case_spec.partition("@")
        mission_path = os.path.join(a.source, mission)
        scenario_path = ""
        if scenario:
            scenario_path = os.path.join(os.path.dirname(mission_path), "scenarios", scenario + ".toml")
        proc, port = start_vehicle(a.strata, scenario_path, a.speed)
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
            failures.append(f"{case}: compare printed no JSON (exit {r.returncode}):\n{r.stdout}{r.stderr}")
            continue
        if expect == "lost":
            lost = (j["a"]["outcome"] == "failed" and j["b"]["outcome"] == "failed"
                    and "no EstimatedState from the IMC vehicle" in j["b"]["reason"])
            if not lost:
                failures.append(f"{case}: not both failed for the lost link:\n{json.dumps(j, indent=1)}")
            else:
                print(f"{case}: both runs failed for the lost link")
            continue
        if (r.returncode != 0 or not j.get("identical") or j.get("compared") != "commands"
                or j["b"].get("execution_level") != "imc"):
            failures.append(f"{case}: not the same commands over IMC (exit {r.returncode}):\n"
                            f"{json.dumps(j, indent=1)}\n{r.stderr}")
            continue
        print(f"{case}: the same {j['a']['outcome']} run over IMC ({j['a']['calls']} calls on the Phoenix, "
              f"{j['b']['calls']} over IMC)")
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{len(a.cases) - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
