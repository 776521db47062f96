#!/usr/bin/env python3
"""Runs a Markdown document as written: its files and its commands.

The document is read top to bottom, in a scratch folder holding a copy of the
repository's missions/ (as a clone has them; --copy DIR adds another of its
folders), with strata first on PATH and HOME a folder inside it (home/; the
XDG_* folders and STRATA_CONFIG, STRATA_LOG_DIR unset):

  ```coral file=first/first.coral      a file block: written to that path
  ...                                  (any language; the path is relative
  ```                                  to the scratch folder, never outside)

  ```sh                                a command block: each `$ ` line runs
  $ strata check first/first.coral     in bash; the lines after it, up to the
  first/first.coral: ok ...            next `$ `, are output it must print,
  ```                                  in order (other lines may come between;
                                       `...` in a line matches any text). A
                                       command that must fail ends with
                                       `# exit N`.

A command `export NAME=VALUE` (VALUE as bash expands it, in the scratch
folder) sets NAME for the commands after it, as in the reader's shell.

  ```sh group=NAME                     a command block that needs what not
  $ scripts/slurm-local start here     every machine has (root, daemons): run
  ```                                  only with --group NAME, and then only
                                       the blocks of that group (and the file
                                       blocks) are. With --requires CMD, CMD
                                       runs first in the scratch folder; when
                                       it fails, the document is skipped:
                                       "skipped: <its output>", exit 77.
                                       --finally CMD runs after the commands,
                                       also when they failed or the run was
                                       stopped by SIGTERM (a daemon stopped).

Blocks of any other kind (```console for what cannot run here, such as the
studio) are shown to the reader and not run. Exit 0 when every command gave
its exit code and its output; else each failure with its line in the
document, exit 1.

  doc_run.py DOC --strata BIN --source REPO --work DIR [--copy DIR ...]
             [--group NAME [--requires CMD] [--finally CMD]]
"""
import argparse
import os
import re
import shutil
import signal
import subprocess
import sys

FENCE = re.compile(r"^```(\S*)(.*)$")
EXIT = re.compile(r"#\s*exit\s+(\d+)\s*$")
EXPORT = re.compile(r"^export ([A-Za-z_][A-Za-z0-9_]*)=(.*)$")
GROUP = re.compile(r"(?:^|\s)group=(\S+)")


def blocks(lines):
    """(line number of the fence, info string, body lines) for each fenced block."""
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        start, lang, rest = i + 1, m.group(1), m.group(2).strip()
        body = []
        i += 1
        while i < len(lines) and not lines[i].startswith("```"):
            body.append(lines[i])
            i += 1
        if i >= len(lines):
            raise SystemExit(f"line {start}: the block is not closed")
        i += 1
        yield start, lang, rest, body


def expected_regex(line):
    parts = [re.escape(p) for p in line.strip().split("...")]
    return re.compile(".*".join(parts))


def check_output(out, expected):
    """The first expected line not found in order in out, or None."""
    got = out.splitlines()
    j = 0
    for e in expected:
        if not e.strip():
            continue
        rx = expected_regex(e)
        while j < len(got) and not rx.search(got[j]):
            j += 1
        if j == len(got):
            return e
        j += 1
    return None


def main():
    ap = argparse.ArgumentParser(description="Run a Markdown document's files and commands")
    ap.add_argument("doc")
    ap.add_argument("--strata", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--timeout", type=float, default=120.0, help="seconds per command")
    ap.add_argument("--copy", action="append", default=[], metavar="DIR",
                    help="a folder of the repository to copy too (tests/verify, ...); repeatable")
    ap.add_argument("--group", help="run only the ```sh group=NAME blocks of this name (without it: none of them)")
    ap.add_argument("--requires", metavar="CMD", help="with --group: skip (exit 77) unless CMD succeeds")
    ap.add_argument("--finally", dest="finally_", metavar="CMD", help="with --group: run CMD at the end, always")
    a = ap.parse_args()
    # ctest's timeout (SIGTERM) or a Ctrl-C: through the finally below, which runs --finally.
    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, lambda n, _: sys.exit(128 + n))

    work = os.path.abspath(a.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    shutil.copytree(os.path.join(a.source, "missions"), os.path.join(work, "missions"),
                    ignore=shutil.ignore_patterns("runs", "*.layout.json"))
    for d in a.copy:
        shutil.copytree(os.path.join(a.source, d), os.path.join(work, d))
    env = dict(os.environ)
    env["PATH"] = os.path.dirname(os.path.abspath(a.strata)) + os.pathsep + env.get("PATH", "")
    # A home of its own: what the document writes under ~ (the default log
    # folder, a completion script) stays in the scratch folder, and the
    # user's configuration does not change what strata prints.
    env["HOME"] = os.path.join(work, "home")
    os.makedirs(env["HOME"])
    for var in ("XDG_CONFIG_HOME", "XDG_STATE_HOME", "XDG_DATA_HOME", "STRATA_CONFIG", "STRATA_LOG_DIR"):
        env.pop(var, None)

    with open(a.doc, encoding="utf-8") as f:
        lines = f.read().split("\n")
    name = os.path.basename(a.doc)
    if a.requires:
        r = subprocess.run(["bash", "-c", a.requires], cwd=work, env=env, capture_output=True, text=True,
                           timeout=a.timeout)
        if r.returncode != 0:
            print(f"skipped: {name}: `{a.requires}` exited {r.returncode}: {(r.stdout + r.stderr).strip()}")
            return 77
    try:
        return run_blocks(a, lines, name, work, env)
    finally:
        if a.finally_:
            r = subprocess.run(["bash", "-c", a.finally_], cwd=work, env=env, capture_output=True, text=True,
                               timeout=a.timeout)
            print(f"{name}: finally `{a.finally_}` exited {r.returncode}: {(r.stdout + r.stderr).strip()}")


def run_blocks(a, lines, name, work, env):
    failures, commands, files, held_back = [], 0, 0, 0
    for start, lang, rest, body in blocks(lines):
        fm = re.match(r"file=(\S+)$", rest)
        if fm:
            rel = os.path.normpath(fm.group(1))
            if rel.startswith("..") or os.path.isabs(rel):
                raise SystemExit(f"{name}:{start}: a file block's path must stay inside the folder: {rel}")
            path = os.path.join(work, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as out:
                out.write("\n".join(body) + "\n")
            files += 1
            continue
        if lang != "sh":
            continue
        gm = GROUP.search(rest)
        if (gm.group(1) if gm else None) != a.group:
            held_back += 1 if gm else 0
            continue
        k = 0
        while k < len(body):
            if not body[k].startswith("$ "):
                k += 1
                continue
            cmd, line_no = body[k][2:], start + 1 + k
            k += 1
            expected = []
            while k < len(body) and not body[k].startswith("$ "):
                expected.append(body[k])
                k += 1
            em = EXIT.search(cmd)
            want = int(em.group(1)) if em else 0
            commands += 1
            try:
                r = subprocess.run(["bash", "-c", cmd], cwd=work, env=env, capture_output=True, text=True,
                                   timeout=a.timeout)
            except subprocess.TimeoutExpired:
                failures.append(f"{name}:{line_no}: `{cmd}` did not end in {a.timeout:.0f} s")
                continue
            out = r.stdout + r.stderr
            xm = EXPORT.match(cmd)
            if xm and r.returncode == 0:
                value = subprocess.run(["bash", "-c", f"printf %s {xm.group(2)}"], cwd=work, env=env,
                                       capture_output=True, text=True, timeout=a.timeout).stdout
                env[xm.group(1)] = value
            if r.returncode != want:
                failures.append(f"{name}:{line_no}: `{cmd}` exited {r.returncode}, the document says {want}\n{out[-2000:]}")
                continue
            missing = check_output(out, expected)
            if missing is not None:
                failures.append(f"{name}:{line_no}: `{cmd}` did not print, in order: {missing.strip()}\n{out[-2000:]}")
    for f in failures:
        print(f, file=sys.stderr)
    group = f" (group {a.group})" if a.group else ""
    held = f", {held_back} blocks of a group not run here" if held_back else ""
    print(f"{name}{group}: {commands} commands, {files} files, {len(failures)} failed{held}")
    if commands == 0:
        print(f"{name}: no commands to run", file=sys.stderr)
        return 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
