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
"""
import argparse
import json
import os
import re
import select
import subprocess
import sys
import time

PORT = re.compile(r"udp://127\.0\.0\.1:(\d+)")


def start_vehicle(strata, scenario, speed):
    cmd = [strata, "vehicle", "--imc", "--port", "0", "--speed", str(speed)]
    if scenario:
        cmd += ["--scenario", scenario]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    deadline = time.monotonic() + 60  # a bound so a broken vehicle fails the test, not a speed limit
    seen = []
    while time.monotonic() < deadline:
        ready, _, _ = select.select([proc.stdout], [], [], 1.0)
        if not ready:
            if proc.poll() is not None:
                break
            continue
        line = proc.stdout.readline()
        if not line:
            break
        seen.append(line)
        m = PORT.search(line)
        if m:
            return proc, int(m.group(1))
    proc.kill()
    proc.wait()
    raise SystemExit("the IMC vehicle did not print its port:\n" + "".join(seen))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--strata", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--speed", type=float, default=20.0)
    ap.add_argument("cases", nargs="+")
    a = ap.parse_args()
    failures = []
    for case in a.cases:
        mission, _, scenario = case.partition("@")
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
