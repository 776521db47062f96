#!/usr/bin/env python3
"""The examples of a document that are not commands, checked by strata.

In a scratch folder holding a copy of the repository's missions/:

  - every ```coral block (without file=, which doc_run.py writes) is one
    whole file and must pass `strata check` (exit 0) — unless its info
    string says `fragment` (```coral fragment), a piece shown out of its
    file;
  - every ```toml block that sets `seed` is a vehicle scenario and must be
    read by strata (`strata run` of the survey mission with it, stopped at
    once: any exit but 65 and the reader's FILE:LINE:COL);
  - every ```prolog block that is not a fragment must pass `strata check`;
  - with --diagnostics, the table of language.md §7: each row whose example
    is one code span and no more is a whole one-line file, which `strata
    check --format json` must answer with the row's kind, and with no other
    error or warning; a row marked `fragment` or described in words is
    counted, not run.

Exit 0 when every example holds, 1 with each failure (and its line).

  doc_examples.py DOC --strata BIN --source REPO --work DIR [--diagnostics]
"""
import argparse
import concurrent.futures
import json
import os
import re
import shutil
import subprocess
import sys
import threading

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from doc_run import blocks  # noqa: E402 (the fenced blocks, as doc_run.py reads them)

ROW = re.compile(r"^\| `([A-Za-z]+)` \| (error|warning) \|.*\| (.*) \|$")
ONE_SPAN = re.compile(r"^`([^`]+)`$")


class Checker:
    def __init__(self, a, name):
        self.a, self.name = a, name
        self.failures, self.checked, self.skipped = [], 0, 0
        self.n = 0
        self.lock = threading.Lock()

    def count(self, what):
        with self.lock:
            setattr(self, what, getattr(self, what) + 1)

    def write(self, ext, text):
        with self.lock:
            self.n += 1
            n = self.n
        path = os.path.join(self.a.work, f"example{n}.{ext}")
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        return os.path.basename(path)

    def strata(self, *args):
        return subprocess.run([self.a.strata, *args], cwd=self.a.work, env=self.env(), capture_output=True,
                              text=True, timeout=120)

    def env(self):
        """The environment with a home of its own inside the scratch folder (as doc_run.py gives): the runs'
        default logs stay there, and the user's configuration changes nothing."""
        env = dict(os.environ)
        env["HOME"] = os.path.join(self.a.work, "home")
        os.makedirs(env["HOME"], exist_ok=True)
        for var in ("XDG_CONFIG_HOME", "XDG_STATE_HOME", "XDG_DATA_HOME", "STRATA_CONFIG", "STRATA_LOG_DIR"):
            env.pop(var, None)
        return env

    def check_file(self, line, ext, body):
        path = self.write(ext, "\n".join(body) + "\n")
        r = self.strata("check", path)
        self.checked += 1
        if r.returncode != 0:
            self.failures.append(f"{self.name}:{line}: the {ext} example does not pass `strata check` "
                                 f"(exit {r.returncode}):\n{(r.stdout + r.stderr)[-1500:]}")

    def check_scenario(self, line, body):
        path = self.write("toml", "\n".join(body) + "\n")
        r = self.strata("run", "missions/survey/survey.coral", "--scenario", path, "--max-sim-time", "1")
        self.checked += 1
        if r.returncode == 65 or r.returncode not in (0, 1):
            self.failures.append(f"{self.name}:{line}: the scenario example is refused (exit {r.returncode}):\n"
                                 f"{r.stderr[-1500:]}")

    def check_diagnostic(self, line, kind, severity, cell):
        m = ONE_SPAN.match(cell.strip())
        if not m or "fragment" in cell:
            self.count("skipped")
            return
        text = m.group(1)
        if not re.match(r"^(net|mission|import)\b", text):
            self.count("skipped")  # a command or words, not a file
            return
        path = self.write("coral", text + "\n")
        r = self.strata("check", "--format", "json", path)
        self.count("checked")
        try:
            report = json.loads(r.stdout)
        except json.JSONDecodeError:
            self.failures.append(f"{self.name}:{line}: {kind}: `strata check --format json` printed no JSON "
                                 f"(exit {r.returncode}):\n{(r.stdout + r.stderr)[-1000:]}")
            return
        kinds = sorted({d["kind"] for d in report.get("diagnostics", [])})
        want_exit = 65 if severity == "error" else 0
        if kinds != [kind] or r.returncode != want_exit:
            self.failures.append(f"{self.name}:{line}: `{text}` gives {kinds or 'no diagnostic'} (exit "
                                 f"{r.returncode}), the table says {kind} alone (exit {want_exit})")


def main():
    ap = argparse.ArgumentParser(description="Check a document's CORAL, PROLOG and scenario examples")
    ap.add_argument("doc")
    ap.add_argument("--strata", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--diagnostics", action="store_true", help="also the table of diagnostic kinds")
    a = ap.parse_args()
    a.strata = os.path.abspath(a.strata)
    a.work = os.path.abspath(a.work)
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    shutil.copytree(os.path.join(a.source, "missions"), os.path.join(a.work, "missions"),
                    ignore=shutil.ignore_patterns("runs", "*.layout.json"))
    with open(a.doc, encoding="utf-8") as f:
        lines = f.read().split("\n")
    name = os.path.basename(a.doc)
    c = Checker(a, name)
    for start, lang, rest, body in blocks(lines):
        if rest.startswith("file="):
            continue  # doc_run.py's
        fragment = "fragment" in rest.split()
        if lang in ("coral", "prolog"):
            if fragment:
                c.skipped += 1
                continue
            c.check_file(start, "coral" if lang == "coral" else "pl", body)
        elif lang == "toml" and any(re.match(r"^seed\s*=", b) for b in body):
            c.check_scenario(start, body)
    if a.diagnostics:
        rows = 0
        jobs = []
        for i, line in enumerate(lines, 1):
            m = ROW.match(line)
            if m:
                rows += 1
                jobs.append((i, m.group(1), m.group(2), m.group(3)))
        # Two at a time: each is a strata process of its own.
        with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
            list(pool.map(lambda job: c.check_diagnostic(*job), jobs))
        c.failures.sort(key=lambda f: int(re.search(r":(\d+):", f).group(1)) if re.search(r":(\d+):", f) else 0)
        if rows == 0:
            c.failures.append(f"{name}: no table of diagnostic kinds")
    for f in c.failures:
        print(f, file=sys.stderr)
    print(f"{name}: {c.checked} examples checked, {c.skipped} fragments or descriptions not run, "
          f"{len(c.failures)} failed")
    if c.checked == 0:
        print(f"{name}: no examples to check", file=sys.stderr)
        return 1
    return 1 if c.failures else 0


if __name__ == "__main__":
    sys.exit(main())
