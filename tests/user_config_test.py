#!/usr/bin/env python3
"""The operator's defaults (issue 22 item 4): config.toml, STRATA_LOG_DIR,
dated logs, --no-log, against the real binary.

usage: user_config_test.py STRATA TANK_MISSION WORK_DIR
Each case is a function; a failure names the case and what it saw."""
import datetime
import os
import shutil
import subprocess
import sys

STRATA, TANK, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
failures = []


def env_with(**extra):
    env = {k: v for k, v in os.environ.items()
           if k not in ("STRATA_CONFIG", "STRATA_LOG_DIR", "XDG_CONFIG_HOME", "XDG_STATE_HOME")}
    env["HOME"] = os.path.join(WORK, "home")
    env.update(extra)
    return env


def strata(args, **env):
    return subprocess.run([STRATA] + args, env=env_with(**env), capture_output=True, text=True, timeout=60)


def folder(name):
    path = os.path.join(WORK, name)
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def expect(case, cond, what, r=None):
    if not cond:
        seen = f"\n  exit {r.returncode}\n  stdout: {r.stdout[-800:]}\n  stderr: {r.stderr[-800:]}" if r else ""
        failures.append(f"{case}: {what}{seen}")


def logs_in(path):
    return sorted(f for f in os.listdir(path) if f.endswith(".jsonl")) if os.path.isdir(path) else []


def without_a_file_the_built_in_values_are_shown():
    r = strata(["config", "show"])
    expect("no_file", r.returncode == 0, "exit 0", r)
    expect("no_file", "does not exist: built-in values" in r.stdout, "says the file is absent", r)
    expect("no_file", os.path.join(WORK, "home", ".local/state/strata/logs") in r.stdout,
           "the log folder is under ~/.local/state", r)
    r = strata(["config", "path"], XDG_CONFIG_HOME="/x/y")
    expect("path", r.stdout.strip() == "/x/y/strata/config.toml", "the path follows XDG_CONFIG_HOME", r)


def a_run_is_logged_to_a_dated_file_by_default():
    state = folder("state")
    before = datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%dT")
    r = strata(["run", "-q", TANK], XDG_STATE_HOME=state)
    logs = logs_in(os.path.join(state, "strata", "logs"))
    expect("dated", r.returncode == 0, "the run completes", r)
    expect("dated", len(logs) == 1 and logs[0].startswith(before) and logs[0].endswith("Z-tank.coral.jsonl"),
           f"one dated log YYYYMMDDTHHMMSSZ-tank.coral.jsonl, found {logs}", r)
    expect("dated", "  log: " in r.stdout, "the summary names the log", r)


def the_config_file_sets_the_defaults_and_says_where():
    d = folder("file")
    cfg = write(os.path.join(d, "config.toml"),
                '[run]\nlog_dir = "~/auv-logs"\ntelemetry_hz = 5\n\n[studio]\nlisten = "127.0.0.1:0"\n')
    r = strata(["config", "show"], STRATA_CONFIG=cfg)
    expect("file", r.returncode == 0, "exit 0", r)
    expect("file", f'"{os.path.join(WORK, "home", "auv-logs")}"' in r.stdout, "~ is the home folder", r)
    expect("file", f"# {cfg}:2" in r.stdout and f"# {cfg}:3" in r.stdout, "each value says its line", r)
    r = strata(["run", "-q", TANK], STRATA_CONFIG=cfg)
    expect("file", len(logs_in(os.path.join(WORK, "home", "auv-logs"))) >= 1, "the run logs into log_dir", r)


def strata_log_dir_beats_the_file_and_the_command_line_beats_both():
    d = folder("precedence")
    cfg = write(os.path.join(d, "config.toml"), f'[run]\nlog_dir = "{d}/from-file"\n')
    r = strata(["run", "-q", TANK], STRATA_CONFIG=cfg, STRATA_LOG_DIR=f"{d}/from-env")
    expect("env", len(logs_in(f"{d}/from-env")) == 1 and not logs_in(f"{d}/from-file"), "STRATA_LOG_DIR wins", r)
    r = strata(["run", "-q", TANK, "--log", f"{d}/mine.jsonl"], STRATA_LOG_DIR=f"{d}/from-env")
    expect("cli", os.path.exists(f"{d}/mine.jsonl") and len(logs_in(f"{d}/from-env")) == 1, "--log wins", r)


def no_log_writes_none_and_log_false_turns_it_off():
    d = folder("nolog")
    r = strata(["run", "-q", "--no-log", TANK], STRATA_LOG_DIR=d)
    expect("no_log", r.returncode == 0 and logs_in(d) == [] and "log:" not in r.stdout, "no log", r)
    r = strata(["run", "--no-log", "--log", f"{d}/x.jsonl", TANK], STRATA_LOG_DIR=d)
    expect("no_log", r.returncode == 64 and "give one" in r.stderr, "--log with --no-log is a usage error", r)
    cfg = write(os.path.join(WORK, "nolog.toml"), "[run]\nlog = false\n")
    r = strata(["run", "-q", TANK], STRATA_CONFIG=cfg, STRATA_LOG_DIR=d)
    expect("log_false", r.returncode == 0 and logs_in(d) == [], "log = false: no log", r)


def a_broken_file_stops_the_commands_that_use_it_with_each_problem_located():
    d = folder("broken")
    cfg = write(os.path.join(d, "config.toml"),
                '[run]\ntelemetry_hz = 500\nvehicel = "x"\nvehicle = "nohost:1"\nlog = "yes"\n[studo]\n')
    r = strata(["run", TANK], STRATA_CONFIG=cfg)
    expect("broken", r.returncode == 65, "run exits 65", r)
    for where in (":2:", ":3:1: unknown key 'vehicel' in [run]: did you mean 'vehicle'? (its keys: vehicle", ":4:", ":5:",
                  ":6:2: unknown table [studo]: did you mean 'studio'?"):
        expect("broken", f"{cfg}{where}" in r.stderr, f"names {where}", r)
    r = strata(["check", TANK], STRATA_CONFIG=cfg)
    expect("broken", r.returncode == 0, "check does not use it and runs", r)
    r = strata(["config", "show"], STRATA_CONFIG=cfg)
    expect("broken", r.returncode == 65, "config show exits 65", r)
    write(cfg, '[run]\nlog_dir = "logs"\n')
    r = strata(["run", TANK], STRATA_CONFIG=cfg)
    expect("relative", r.returncode == 65 and f"{cfg}:2:" in r.stderr and "absolute path" in r.stderr,
           "a relative log_dir is refused (it would follow the working folder)", r)
    write(cfg, "[run]\ntelemetry_hz = nan\n")
    r = strata(["run", TANK], STRATA_CONFIG=cfg)
    expect("nan", r.returncode == 65 and f"{cfg}:2:" in r.stderr, "telemetry_hz = nan is refused", r)
    write(cfg, "[run\n")
    r = strata(["vehicle", "--interface"], STRATA_CONFIG=cfg)
    expect("syntax", r.returncode == 65 and f"{cfg}:1:" in r.stderr, "a TOML syntax error is located", r)


def a_missing_fifo_or_huge_config_is_refused_without_hanging():
    r = strata(["config", "show"], STRATA_CONFIG=os.path.join(WORK, "no-such.toml"))
    expect("missing", r.returncode == 74 and "no such config file" in r.stderr, "a named file must exist", r)
    fifo = os.path.join(folder("fifo"), "config.toml")
    os.mkfifo(fifo)
    r = strata(["config", "show"], STRATA_CONFIG=fifo)
    expect("fifo", r.returncode in (65, 74) and "config.toml" in r.stderr, "a FIFO is refused, not waited on", r)
    big = os.path.join(WORK, "big.toml")
    with open(big, "w") as f:
        f.write("# " + "x" * (17 << 20) + "\n")
    r = strata(["config", "show"], STRATA_CONFIG=big)
    expect("big", r.returncode in (65, 74), "a file over the TOML limit is refused", r)
    os.remove(big)
    r = strata(["config", "show"], STRATA_CONFIG="/dev/zero")
    expect("device", r.returncode == 74 and "not a regular file" in r.stderr, "a device is refused, not read", r)


def a_log_folder_that_cannot_be_made_stops_the_run_before_it_starts():
    d = folder("notafolder")
    blocker = write(os.path.join(d, "logs"), "a file where the folder should be\n")
    r = strata(["run", TANK], STRATA_LOG_DIR=blocker)
    expect("blocked", r.returncode == 74 and "cannot make the log folder" in r.stderr and "--no-log" in r.stderr,
           "exit 74, saying how to go on", r)
    expect("blocked", "mission tank" not in r.stdout, "the mission did not run", r)


def a_planted_link_at_the_dated_name_is_never_written_through():
    d = folder("planted")
    victim = write(os.path.join(WORK, "victim.txt"), "untouched\n")
    now = datetime.datetime.now(datetime.timezone.utc)
    for s in range(0, 6):  # the names of this second and the next five
        stamp = (now + datetime.timedelta(seconds=s)).strftime("%Y%m%dT%H%M%SZ")
        os.symlink(victim, os.path.join(d, f"{stamp}-tank.coral.jsonl"))
    r = strata(["run", "-q", TANK], STRATA_LOG_DIR=d)
    expect("planted", r.returncode == 0, "the run completes", r)
    expect("planted", open(victim).read() == "untouched\n", "the link's target is untouched", r)
    real = [f for f in logs_in(d) if not os.path.islink(os.path.join(d, f))]
    expect("planted", len(real) == 1 and real[0].endswith("-tank.coral-2.jsonl"), f"logged beside the link: {real}", r)


def a_mission_that_never_starts_leaves_no_empty_log():
    d = folder("nostart")
    r = strata(["run", os.path.join(WORK, "no-such.coral")], STRATA_LOG_DIR=d)
    expect("nostart", r.returncode == 74 and logs_in(d) == [], "no log left", r)


def the_config_vehicle_is_the_default_and_embedded_overrides_it():
    cfg = write(os.path.join(WORK, "vehicle.toml"), '[run]\nvehicle = "127.0.0.1:1"\n')
    r = strata(["run", "--no-log", TANK], STRATA_CONFIG=cfg)
    expect("vehicle", r.returncode == 74 and "127.0.0.1:1" in r.stderr, "the run goes to the config's vehicle", r)
    write(cfg, '[run]\nvehicle = "127.0.0.1:0"\n')
    r = strata(["run", "--no-log", TANK], STRATA_CONFIG=cfg)
    expect("vehicle", r.returncode == 65 and "port 0 is not a vehicle's port" in r.stderr, "port 0 is refused", r)
    write(cfg, '[run]\nvehicle = "127.0.0.1:1"\n')
    r = strata(["run", "-q", "--no-log", "--vehicle", "embedded", TANK], STRATA_CONFIG=cfg)
    expect("vehicle", r.returncode == 0, "--vehicle embedded runs the simulated one", r)


os.makedirs(WORK, exist_ok=True)
for case in (without_a_file_the_built_in_values_are_shown, a_run_is_logged_to_a_dated_file_by_default,
             the_config_file_sets_the_defaults_and_says_where,
             strata_log_dir_beats_the_file_and_the_command_line_beats_both,
             no_log_writes_none_and_log_false_turns_it_off,
             a_broken_file_stops_the_commands_that_use_it_with_each_problem_located,
             a_missing_fifo_or_huge_config_is_refused_without_hanging,
             a_log_folder_that_cannot_be_made_stops_the_run_before_it_starts,
             a_planted_link_at_the_dated_name_is_never_written_through,
             a_mission_that_never_starts_leaves_no_empty_log,
             the_config_vehicle_is_the_default_and_embedded_overrides_it):
    case()
for f in failures:
    print("FAIL", f)
print(f"{len(failures)} checks failed" if failures else "every case passed")
sys.exit(1 if failures else 0)
