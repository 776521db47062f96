#!/usr/bin/env python3
"""The JSON Schemas of docs/schema/ against the files Strata reads and writes.

  schema_check.py scenarios --source REPO --strata BIN --work DIR
      Every shipped scenario (missions/*/scenarios/*.toml, TOML read into
      JSON) is valid against scenario.schema.json; and a table of scenario
      files, valid and not, gets the same answer from the schema as from
      strata's own reader (`strata run ... --scenario FILE`: exit 65 and
      FILE:LINE:COL when the reader refuses it).

  schema_check.py logs --source REPO --strata BIN --work DIR MISSION
      MISSION run in every scenario of its folder; every line of every log
      is valid against mission-log.schema.json, the first is `run` and the
      last `mission_end`.

  schema_check.py log-agrees --source REPO --strata BIN --work DIR
      The log schema and the code agree: the record kinds the source writes
      are the schema's, no more and no fewer; runs that write the rarer
      records (--seed, a limit and its safe end, a mission that fails
      verification run with --unverified, scripted answers) are valid; and records the code
      does not write (an unknown kind, a field added, a required field
      removed, a field of the wrong type) are refused.

Exit 0 when all holds, 1 with each failure, 77 (skipped) when python3's
jsonschema module is missing (Debian: python3-jsonschema, in scripts/setup).
"""
import argparse
import concurrent.futures
import copy
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tomllib

try:
    import jsonschema
except ImportError:
    print(f"skipped: python3-jsonschema is not installed for {sys.executable} (scripts/setup installs it)")
    sys.exit(77)

SKIP = 77


def load_schema(source, name):
    with open(os.path.join(source, "docs", "schema", name), encoding="utf-8") as f:
        schema = json.load(f)
    jsonschema.Draft202012Validator.check_schema(schema)
    return schema


def toml_as_json(path):
    """A TOML file as the JSON value the schema sees. NaN and infinities,
    which JSON has not, become strings: no number in the schema accepts them,
    as the reader refuses them."""
    with open(path, "rb") as f:
        return tomllib.load(f, parse_float=lambda s: float(s) if s.lstrip("+-") not in ("nan", "inf") else s)


def errors(validator, instance):
    return [f"{'/'.join(str(p) for p in e.absolute_path) or '(top)'}: {e.message}"
            for e in sorted(validator.iter_errors(instance), key=lambda e: list(e.absolute_path))]


# --- scenarios -----------------------------------------------------------------

# (name, TOML text, accepted?). Each is given to strata's reader and to the
# schema: both must give the answer in the third column.
SCENARIO_CASES = [
    ("minimal", "seed = 0\n", True),
    ("every_fault", """seed = 5
description = "every kind"
[[fault]]
kind = "weak_thrusters"
at_s = 0
health = 0.5
[[fault]]
kind = "leak"
at_s = 12.5
[[fault]]
kind = "sensor_dropout"
at_s = 5.0
duration_s = 2.0
[[fault]]
kind = "link_loss"
at_s = 3.0
duration_s = 4.0
[[fault]]
kind = "link_loss"
at_s = 30.0
forever = true
[[fault]]
kind = "compass_bias"
at_s = 0.0
bias_deg = -180
[[fault]]
kind = "altimeter_dead"
at_s = 30.0
[[fault]]
kind = "no_gps"
at_s = 0.0
""", True),
    ("tank_vehicle_and_target", "seed = 1\n[vehicle]\nx_m = 6\ny_m = 4.0\nheading_deg = 359.5\n"
     "[target]\nx_m = 4.0\ny_m = 1.0\nradius_m = 0.3\n", True),
    ("open_water_grid", """seed = 2
[world]
kind = "open_water"
current_x_mps = -3.0
current_y_mps = 3.0
[seabed]
kind = "grid"
x0_m = -100.0
y0_m = 0
spacing_m = 50.0
nx = 3
ny = 2
depths_m = [[30.0, 31.0, 32.0], [29, 28, 27]]
[vehicle]
x_m = -50.0
y_m = -100000.0
""", True),
    ("open_water_slope", "seed = 3\n[world]\nkind = \"open_water\"\n[seabed]\nkind = \"slope\"\n"
     "depth_m = 11000\nslope_x = -10\nslope_y = 10\n", True),
    ("world_tank_explicit", "seed = 3\n[world]\nkind = \"tank\"\n", True),
    ("no_seed", "description = \"x\"\n", False),
    ("negative_seed", "seed = -1\n", False),
    ("float_seed", "seed = 1.5\n", False),
    ("unknown_top_key", "seed = 1\nspeed = 2\n", False),
    ("unknown_fault_kind", "seed = 1\n[[fault]]\nkind = \"fire\"\nat_s = 1\n", False),
    ("fault_without_at_s", "seed = 1\n[[fault]]\nkind = \"leak\"\n", False),
    ("fault_negative_at_s", "seed = 1\n[[fault]]\nkind = \"leak\"\nat_s = -1\n", False),
    ("fault_nan_at_s", "seed = 1\n[[fault]]\nkind = \"leak\"\nat_s = nan\n", False),
    ("leak_with_health", "seed = 1\n[[fault]]\nkind = \"leak\"\nat_s = 1\nhealth = 0.5\n", False),
    ("health_above_one", "seed = 1\n[[fault]]\nkind = \"weak_thrusters\"\nat_s = 0\nhealth = 1.1\n", False),
    ("weak_without_health", "seed = 1\n[[fault]]\nkind = \"weak_thrusters\"\nat_s = 0\n", False),
    ("dropout_forever", "seed = 1\n[[fault]]\nkind = \"sensor_dropout\"\nat_s = 0\nforever = true\n", False),
    ("dropout_zero_duration", "seed = 1\n[[fault]]\nkind = \"sensor_dropout\"\nat_s = 0\nduration_s = 0\n", False),
    ("link_loss_both", "seed = 1\n[[fault]]\nkind = \"link_loss\"\nat_s = 0\nduration_s = 1\nforever = true\n", False),
    ("link_loss_neither", "seed = 1\n[[fault]]\nkind = \"link_loss\"\nat_s = 0\n", False),
    ("link_loss_forever_false", "seed = 1\n[[fault]]\nkind = \"link_loss\"\nat_s = 0\nforever = false\n", False),
    ("bias_too_big", "seed = 1\n[[fault]]\nkind = \"compass_bias\"\nat_s = 0\nbias_deg = 181\n", False),
    ("fault_not_a_table_array", "seed = 1\nfault = 3\n", False),
    ("tank_negative_x", "seed = 1\n[vehicle]\nx_m = -1.0\n", False),
    ("heading_360", "seed = 1\n[vehicle]\nheading_deg = 360\n", False),
    ("vehicle_unknown_key", "seed = 1\n[vehicle]\nz_m = 1\n", False),
    ("target_without_radius", "seed = 1\n[target]\nx_m = 1\ny_m = 1\n", False),
    ("target_zero_radius", "seed = 1\n[target]\nx_m = 1\ny_m = 1\nradius_m = 0\n", False),
    ("tank_with_seabed", "seed = 1\n[seabed]\nkind = \"flat\"\ndepth_m = 30\n", False),
    ("tank_with_current", "seed = 1\n[world]\ncurrent_y_mps = 0.1\n", False),
    ("unknown_world_kind", "seed = 1\n[world]\nkind = \"lake\"\n", False),
    ("current_above_5", "seed = 1\n[world]\nkind = \"open_water\"\ncurrent_x_mps = 5.5\n", False),
    ("open_water_far_start", "seed = 1\n[world]\nkind = \"open_water\"\n[vehicle]\nx_m = 100001\n", False),
    ("seabed_without_kind", "seed = 1\n[world]\nkind = \"open_water\"\n[seabed]\ndepth_m = 30\n", False),
    ("flat_with_slope", "seed = 1\n[world]\nkind = \"open_water\"\n[seabed]\nkind = \"flat\"\ndepth_m = 30\nslope_x = 0.1\n",
     False),
    ("seabed_too_deep", "seed = 1\n[world]\nkind = \"open_water\"\n[seabed]\nkind = \"flat\"\ndepth_m = 11001\n", False),
    ("grid_without_depths", "seed = 1\n[world]\nkind = \"open_water\"\n[seabed]\nkind = \"grid\"\nx0_m = 0\n"
     "y0_m = 0\nspacing_m = 1\nnx = 2\nny = 2\n", False),
    ("grid_nx_1", "seed = 1\n[world]\nkind = \"open_water\"\n[seabed]\nkind = \"grid\"\nx0_m = 0\n"
     "y0_m = 0\nspacing_m = 1\nnx = 1\nny = 2\ndepths_m = [[1.0], [1.0]]\n", False),
]


def cmd_scenarios(a):
    schema = load_schema(a.source, "scenario.schema.json")
    v = jsonschema.Draft202012Validator(schema)
    failures = []
    shipped = sorted(glob.glob(os.path.join(a.source, "missions", "*", "scenarios", "*.toml")))
    if not shipped:
        failures.append("no shipped scenarios found under missions/*/scenarios/")
    for path in shipped:
        for e in errors(v, toml_as_json(path)):
            failures.append(f"{os.path.relpath(path, a.source)}: {e}")
    tank = os.path.join(a.source, "missions", "tank", "tank.coral")
    os.makedirs(a.work, exist_ok=True)
    def read(case):
        path = os.path.join(a.work, case[0] + ".toml")
        with open(path, "w", encoding="utf-8") as f:
            f.write(case[1])
        return path, subprocess.run([a.strata, "run", tank, "--scenario", path, "--max-sim-time", "1"],
                                    capture_output=True, text=True, timeout=120)

    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        answers = list(pool.map(read, SCENARIO_CASES))
    for (name, text, accepted), (path, r) in zip(SCENARIO_CASES, answers):
        errs = errors(v, toml_as_json(path))
        refused_by_reader = r.returncode == 65 and re.search(re.escape(path) + r"(:\d+:\d+)?: ", r.stderr)
        if r.returncode not in (0, 1, 65) or (r.returncode == 65 and not refused_by_reader):
            failures.append(f"case {name}: strata run exited {r.returncode}:\n{r.stderr[-1000:]}")
            continue
        reader_ok = not refused_by_reader
        if reader_ok != accepted:
            failures.append(f"case {name}: strata's reader {'accepts' if reader_ok else 'refuses'} it, the table says "
                            f"{'valid' if accepted else 'invalid'}: {r.stderr.strip()[-300:]}")
        if (not errs) != accepted:
            failures.append(f"case {name}: the schema {'accepts' if not errs else 'refuses'} it, strata's reader "
                            f"{'accepts' if reader_ok else 'refuses'} it" + (f": {errs[0]}" if errs else ""))
    for f in failures:
        print(f, file=sys.stderr)
    print(f"scenarios: {len(shipped)} shipped files, {len(SCENARIO_CASES)} cases, {len(failures)} failed")
    return 1 if failures else 0


# --- mission logs --------------------------------------------------------------

class LogChecker:
    """Every line of a log against the schema. A record is checked against
    the definition its `event` selects (what the schema's top-level if/then
    chain does, about ten times faster); the first record of each kind also
    against the whole schema."""

    def __init__(self, schema):
        self.schema = schema
        self.whole = jsonschema.Draft202012Validator(schema)
        self.kinds = schema["properties"]["event"]["enum"]
        self.by_kind = {}
        for k in self.kinds:
            sub = dict(schema["$defs"][k])
            sub["$defs"] = schema["$defs"]
            self.by_kind[k] = jsonschema.Draft202012Validator(sub)
        self.seen = set()

    def check(self, record):
        kind = record.get("event") if isinstance(record, dict) else None
        if kind not in self.by_kind or kind not in self.seen:
            if kind in self.by_kind:
                self.seen.add(kind)
            return errors(self.whole, record)
        v = self.by_kind[kind]
        return [] if v.is_valid(record) else errors(self.whole, record)

    def check_log(self, path, label):
        failures = []
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
        if not lines:
            return [f"{label}: the log is empty"]
        records = []
        for i, line in enumerate(lines, 1):
            try:
                rec = json.loads(line)
            except json.JSONDecodeError as e:
                failures.append(f"{label}:{i}: not JSON: {e}")
                continue
            records.append(rec)
            for e in self.check(rec)[:3]:
                failures.append(f"{label}:{i}: {e}\n    {line[:300]}")
        if records and records[0].get("event") != "run":
            failures.append(f"{label}:1: the first record is not `run`")
        if records and records[-1].get("event") != "mission_end":
            failures.append(f"{label}:{len(lines)}: the last record is not `mission_end`")
        return failures


def run_logged(a, args, log, label):
    """strata run ARGS --log LOG; the failures (an exit other than 0 or 1)."""
    r = subprocess.run([a.strata, "run", *args, "--log", log], capture_output=True, text=True, timeout=600,
                       cwd=a.work)
    if r.returncode not in (0, 1):
        return [f"{label}: strata run exited {r.returncode}:\n{(r.stdout + r.stderr)[-1500:]}"]
    return []


def cmd_logs(a):
    checker = LogChecker(load_schema(a.source, "mission-log.schema.json"))
    mission = os.path.join(a.source, a.mission)
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    scenarios = sorted(glob.glob(os.path.join(os.path.dirname(mission), "scenarios", "*.toml")))
    failures, lines = [], 0

    def run(sc):
        name = os.path.splitext(os.path.basename(sc))[0]
        log = os.path.join(a.work, name + ".jsonl")
        label = f"{a.mission} --scenario {name}"
        return log, label, run_logged(a, [mission, "--scenario", name], log, label)

    # Two runs at a time; each log is checked while the next runs.
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        done = [pool.submit(run, sc) for sc in scenarios]
        for future in done:
            log, label, run_failures = future.result()
            failures += run_failures
            if run_failures:
                continue
            failures += checker.check_log(log, label)
            with open(log, encoding="utf-8") as f:
                lines += sum(1 for _ in f)
    if not scenarios:
        failures.append(f"{a.mission}: no scenarios beside it")
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{a.mission}: {len(scenarios)} scenarios, {lines} log lines, kinds {sorted(checker.seen)}, "
          f"{len(failures)} failed")
    return 1 if failures else 0


# Where the source writes a record: {"event", "KIND"} (an initialiser),
# ["event"] = "KIND" (by key), ->event("KIND", ...) / .event("KIND", ...),
# or LogLine NAME("KIND") (a line written field by field).
KIND_IN_SOURCE = [re.compile(r'\{\s*"event"\s*,\s*"([a-z_]+)"\s*\}'),
                  re.compile(r'\[\s*"event"\s*\]\s*=\s*"([a-z_]+)"'),
                  re.compile(r'(?:->|\.)event\(\s*"([a-z_]+)"'),
                  re.compile(r'\bLogLine\s+\w+\(\s*"([a-z_]+)"\s*\)')]
# The folders whose code writes the mission log (the Sonar Manager and the
# campaign write files of their own).
LOG_WRITERS = ["tactical", "strategic", "run"]


def kinds_in_source(source):
    kinds = {}
    for folder in LOG_WRITERS:
        for path in sorted(glob.glob(os.path.join(source, "src", folder, "*.cpp"))):
            if path.endswith("_test.cpp"):
                continue
            with open(path, encoding="utf-8") as f:
                text = f.read()
            for rx in KIND_IN_SOURCE:
                for m in rx.finditer(text):
                    kinds.setdefault(m.group(1), os.path.relpath(path, source))
    return kinds


def mutations(record, schema):
    """(what, record) pairs the schema must refuse, made from a valid record."""
    kind = record["event"]
    d = schema["$defs"][kind]
    out = [(f"{kind} with a field the code does not write", dict(record, not_a_field=1))]
    for key in d.get("required", []):
        if key == "event":
            continue
        r = dict(record)
        del r[key]
        out.append((f"{kind} without '{key}'", r))
    for key, value in record.items():
        if key == "event":
            continue
        r = dict(record)
        r[key] = [value]  # no field of any record is an array of its own value
        out.append((f"{kind} with '{key}' of the wrong type", r))
    return out


def cmd_log_agrees(a):
    schema = load_schema(a.source, "mission-log.schema.json")
    checker = LogChecker(schema)
    failures = []
    in_source = kinds_in_source(a.source)
    in_schema = set(schema["properties"]["event"]["enum"])
    for k in sorted(set(in_source) - in_schema):
        failures.append(f"{in_source[k]} writes records of kind '{k}', which the schema does not have")
    for k in sorted(in_schema - set(in_source)):
        failures.append(f"the schema has records of kind '{k}', which no code under src/{{{','.join(LOG_WRITERS)}}} writes")
    for k in sorted(in_schema):
        if k not in schema["$defs"] or k not in schema["$defs"]["is"]:
            failures.append(f"the schema's kind '{k}' has no definition in $defs (and $defs/is)")

    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    src = a.source
    runs = [
        ("tank, --seed", [f"{src}/missions/tank/tank.coral", "--seed", "7"]),
        ("a limit and the safe end", [f"{src}/tests/run/hold_at_depth.coral", "--max-sim-time", "30"]),
        ("failed verification, run anyway", [f"{src}/tests/verify/exits_together.coral", "--unverified"]),
        ("PROLOG, the link lost, a parameter file",
         [f"{src}/missions/tank/tank.pl", "--scenario", "link_loss", "--params", f"{src}/config/phoenix.toml"]),
        ("a witness's answers scripted",
         [f"{src}/missions/tank/tank.coral", "--answers", f"{src}/missions/tank/witnesses/filter_on.json"]),
        ("a phase exit scripted",
         [f"{src}/missions/tank/tank.coral", "--answers", f"{src}/missions/tank/witnesses/dive_abort.json"]),
    ]
    records = {}
    for i, (label, args) in enumerate(runs):
        log = os.path.join(a.work, f"run{i}.jsonl")
        run_failures = run_logged(a, args, log, label)
        failures += run_failures
        if run_failures:
            continue
        failures += checker.check_log(log, label)
        with open(log, encoding="utf-8") as f:
            for line in f:
                rec = json.loads(line)
                # Of each kind, the record with the most fields.
                if len(rec) > len(records.get(rec["event"], {})):
                    records[rec["event"]] = rec
    for k in ["choice", "verification", "emergency", "vehicle_final", "mission_end", "fire", "phase_start", "answers",
              "scripted_answer", "answers_end"]:
        if k not in records:
            failures.append(f"no run above wrote a '{k}' record")
    if "params" not in records.get("run", {}):
        failures.append("no run above wrote a 'run' record with 'params'")
    if "safe_end" not in records.get("mission_end", {}):
        failures.append("no run above wrote a 'mission_end' record with 'safe_end'")

    # Records the code does not write are refused.
    refused = 0
    unknown = {"event": "no_such_kind", "sim_time": 1.0}
    if not errors(checker.whole, unknown):
        failures.append("a record of an unknown kind is accepted")
    no_kind = {"sim_time": 1.0}
    if not errors(checker.whole, no_kind):
        failures.append("a record without 'event' is accepted")
    for kind, rec in sorted(records.items()):
        for what, bad in mutations(rec, schema):
            if errors(checker.whole, copy.deepcopy(bad)):
                refused += 1
            else:
                failures.append(f"accepted: {what}: {json.dumps(bad)[:300]}")
    for f in failures:
        print(f, file=sys.stderr)
    print(f"log-agrees: {len(in_source)} kinds in the source, {len(in_schema)} in the schema; {len(runs)} runs; "
          f"{refused} altered records refused; {len(failures)} failed")
    return 1 if failures else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=["scenarios", "logs", "log-agrees"])
    ap.add_argument("mission", nargs="?", help="logs: the mission file, relative to --source")
    ap.add_argument("--source", required=True)
    ap.add_argument("--strata", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    a.strata = os.path.abspath(a.strata)
    a.work = os.path.abspath(a.work)
    a.source = os.path.abspath(a.source)
    if a.what == "scenarios":
        return cmd_scenarios(a)
    if a.what == "logs":
        if not a.mission:
            ap.error("logs needs a mission")
        return cmd_logs(a)
    return cmd_log_agrees(a)


if __name__ == "__main__":
    sys.exit(main())
