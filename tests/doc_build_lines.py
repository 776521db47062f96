#!/usr/bin/env python3
"""The build, install, test, fuzz and benchmark lines of the documents.

docs/install.md, docs/testing.md and the README's "The two commands" and
"Building by hand" show command lines that build, install or run for
minutes (a release build, a 10-minute fuzz run, the whole test suite): too
long for a test, or needing what this machine may not have (clang's
libFuzzer build, root). Every such line (a ```sh block that is not a
`$ ` block of doc_run.py; a line ending in `\\` goes on on the next) must be
an entry of LINES below, and every entry must still be in its document:
the document and this test change together. Each entry says how the line
is checked, as far as it can be in seconds with the build under test:

  presets P...      each preset named exists in CMakePresets.json, of the
                    kinds the line uses (configure, build, test)
  script PATH       the script is there, executable, and `bash -n` passes
  ctest ARGS        `ctest -N ARGS` in the build lists at least one test
                    (the regex or label selects something)
  bench NAME ARGS   the benchmark of the build runs with ARGS and
                    --benchmark_list_tests (the flags parse, it has
                    benchmarks); where the benchmarks are not built
                    (STRATA_BUILD_BENCH off, as in asan), NAME is checked
                    against bench/CMakeLists.txt alone, saying so
  fuzz NAME         the fuzz preset cannot be built here (clang's libFuzzer
                    build takes long): NAME is an executable of
                    fuzz/CMakeLists.txt, the path build/fuzz is the preset's
                    binaryDir, the corpus and dictionary named exist
  install           `cmake --install BUILD` into a scratch prefix (the
                    line's own, under a scratch HOME, or DESTDIR for
                    `sudo`'s): every path of install.md's table is there
  run               the line itself, in bash, with strata on PATH and HOME
                    a scratch folder, plus a check of what it made
  same FILE TEXT... the line is a step another test runs: FILE (that test's
                    script) holds each TEXT (package.deb's cpack in the
                    build folder)
  shown REASON      not run, for the reason given

Exit 0 when every line is known and holds, 1 with each failure.

  doc_build_lines.py DOC... --source REPO --build BUILD --strata BIN --work DIR [--bench-built ON|OFF]
"""
import argparse
import glob
import json
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from doc_run import blocks  # noqa: E402

# The README's blocks that readme_tour.py runs are not these.
TOUR = "## A short tour of the CLI"

LINES = {
    "README.md": {
        "scripts/run-mission": ("script", "scripts/run-mission"),
        "scripts/test": ("script", "scripts/test"),
        "cmake --preset dev && cmake --build --preset dev && ctest --preset dev": ("presets", "configure:dev",
                                                                                   "build:dev", "test:dev"),
    },
    "testing.md": {
        "scripts/test": ("script", "scripts/test"),
        "STRATA_TEST_PRESETS=dev scripts/test": ("script", "scripts/test", "STRATA_TEST_PRESETS"),
        "ctest --preset dev -R Coral/FailFile": ("ctest", "-R", "Coral/FailFile"),
        "ctest --preset tsan": ("presets", "test:tsan", "configure:tsan"),
        "ctest --preset dev -L threads": ("ctest", "-L", "threads"),
        "cmake --preset fuzz && cmake --build --preset fuzz": ("presets", "configure:fuzz", "build:fuzz"),
        "scripts/fuzz-seeds coral fuzz/work": ("script", "scripts/fuzz-seeds"),
        "build/fuzz/fuzz/coral_fuzz -dict=fuzz/coral.dict -max_len=4096 -max_total_time=600 -rss_limit_mb=2048 "
        "fuzz/work": ("fuzz", "coral_fuzz", "fuzz/coral.dict"),
        "cmake --preset fuzz && cmake --build build/fuzz --target prolog_fuzz": ("fuzz", "prolog_fuzz"),
        "scripts/fuzz-seeds prolog fuzz/work/prolog": ("script", "scripts/fuzz-seeds"),
        "cd fuzz/work && ASAN_OPTIONS=detect_leaks=0:handle_segv=0:allow_user_segv_handler=1 "
        "../../build/fuzz/fuzz/prolog_fuzz -handle_usr2=0 -max_len=4096 -max_total_time=600 -timeout=20 "
        "-rss_limit_mb=3072 -artifact_prefix=$PWD/ $PWD/prolog": ("fuzz", "prolog_fuzz"),
        "build/release/bench/petri_bench --benchmark_counters_tabular=true": ("bench",),
        "build/release/bench/coral_bench": ("bench",),
        "build/release/bench/run_bench --benchmark_counters_tabular=true": ("bench",),
        "build/release/bench/campaign_bench --benchmark_counters_tabular=true": ("bench",),
        "build/release/bench/prolog_bench --benchmark_counters_tabular=true": ("bench",),
        "build/release/bench/explorer_bench --benchmark_counters_tabular=true": ("bench",),
        "build/release/bench/studio_bench": ("bench",),
        "build/release/bench/sonar_bench": ("bench",),
        "build/release/bench/sonar_link_bench": ("bench",),
        "build/release/bench/link_bench": ("bench",),
        "build/release/bench/question_bench": ("bench",),
        "build/release/bench/open_water_bench": ("bench",),
        "build/release/bench/startup_bench --benchmark_counters_tabular=true": ("bench",),
    },
    "install.md": {
        "cmake --preset package && cmake --build --preset package": ("presets", "configure:package", "build:package"),
        "sudo cmake --install build/package": ("install", "sudo"),
        "cmake --install build/package --prefix ~/.local": ("install", "~/.local"),
        "cd build/package && cpack -G DEB": ("same", "tests/package_cpack.cmake", "COMMAND cpack -G DEB",
                                             "WORKING_DIRECTORY ${BUILD_DIR}"),
        "lintian --fail-on error,warning strata_*_amd64.deb": ("same", "tests/package_lintian.cmake",
                                                              "COMMAND ${LINTIAN} --fail-on error,warning"),
        "sudo apt install ./strata_*_amd64.deb": ("shown", "it installs into this machine's system; package.deb "
                                                  "unpacks the same package into a scratch root instead"),
        "source <(strata completion bash)": ("run", "complete -p strata", r"-F _strata strata"),
        "strata completion zsh > ~/.zfunc/_strata": ("run", "head -n 1 ~/.zfunc/_strata", r"^#compdef strata"),
    },
}


def command_lines(path):
    """(line number, command) of each line of the document's sh blocks that
    doc_run.py and readme_tour.py do not run: comments dropped, `\\` lines joined."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    tour = lines.index(TOUR) if TOUR in lines else None
    out = []
    for start, lang, rest, body in blocks(lines):
        if lang != "sh" or rest or any(b.startswith("$ ") for b in body):
            continue
        if tour is not None and start > tour and not any(lines[k].startswith("## ") for k in range(tour + 1, start)):
            continue  # the tour's block: readme_tour.py runs it
        cur, first = "", None
        for k, b in enumerate(body):
            text = b.rstrip()
            if not cur:
                first = start + 1 + k
            cont = text.endswith("\\")
            cur += (" " if cur else "") + text.rstrip("\\").strip()
            if cont:
                continue
            cmd = re.sub(r"\s+#\s.*$", "", cur).strip()
            cur = ""
            if cmd and not cmd.startswith("#"):
                out.append((first, re.sub(r"\s+", " ", cmd)))
    return out


class Checks:
    def __init__(self, a):
        self.a = a
        with open(os.path.join(a.source, "CMakePresets.json"), encoding="utf-8") as f:
            self.presets = json.load(f)
        self.notes = []

    def read(self, rel):
        with open(os.path.join(self.a.source, rel), encoding="utf-8") as f:
            return f.read()

    def presets_(self, *wanted):
        kinds = {"configure": "configurePresets", "build": "buildPresets", "test": "testPresets"}
        for w in wanted:
            kind, name = w.split(":")
            if name not in [p["name"] for p in self.presets.get(kinds[kind], [])]:
                return f"CMakePresets.json has no {kind} preset {name!r}"
        return None

    def script(self, rel, mentions=None):
        path = os.path.join(self.a.source, rel)
        if not os.access(path, os.X_OK):
            return f"{rel} is not an executable file"
        r = subprocess.run(["bash", "-n", path], capture_output=True, text=True)
        if r.returncode != 0:
            return f"bash -n {rel}: {r.stderr}"
        if mentions and mentions not in self.read(rel):
            return f"{rel} does not read {mentions}"
        return None

    def ctest(self, *args):
        r = subprocess.run(["ctest", "--test-dir", self.a.build, "-N", *args], capture_output=True, text=True,
                           timeout=120)
        m = re.search(r"Total Tests: (\d+)", r.stdout)
        if r.returncode != 0 or not m or int(m.group(1)) == 0:
            return f"ctest -N {' '.join(args)} in the build selects no test:\n{r.stdout[-800:]}{r.stderr[-800:]}"
        return None

    def bench(self, cmd):
        words = cmd.split()
        name, args = os.path.basename(words[0]), words[1:]
        if not words[0].startswith("build/release/bench/"):
            return "a benchmark is run from build/release/bench/"
        if not re.search(rf"add_executable\({re.escape(name)}\s", self.read("bench/CMakeLists.txt")):
            return f"bench/CMakeLists.txt has no benchmark {name}"
        binary = os.path.join(self.a.build, "bench", name)
        if self.a.bench_built != "ON":
            self.notes.append(f"note: the benchmarks are not built here (STRATA_BUILD_BENCH off): {name} "
                              "checked against bench/CMakeLists.txt only")
            return None
        r = subprocess.run([binary, *args, "--benchmark_list_tests=true"], capture_output=True, text=True,
                           timeout=60)
        if r.returncode != 0 or not r.stdout.strip():
            return f"{name} {' '.join(args)} --benchmark_list_tests=true: exit {r.returncode}\n{r.stderr[-800:]}"
        return None

    def fuzz(self, target, *paths):
        fuzz_cmake = self.read("fuzz/CMakeLists.txt")
        if target and not re.search(rf"add_executable\({re.escape(target)}\s", fuzz_cmake):
            return f"fuzz/CMakeLists.txt has no target {target}"
        if not re.search(r"add_subdirectory\(fuzz\)", self.read("CMakeLists.txt")):
            return "the top CMakeLists.txt does not add fuzz/"
        base = next((p for p in self.presets["configurePresets"] if p["name"] == "base"), {})
        fuzz = next((p for p in self.presets["configurePresets"] if p["name"] == "fuzz"), {})
        binary_dir = fuzz.get("binaryDir", base.get("binaryDir", ""))
        if binary_dir.replace("${presetName}", "fuzz") != "${sourceDir}/build/fuzz":
            return f"the fuzz preset builds into {binary_dir}, not build/fuzz"
        for p in paths:
            full = os.path.join(self.a.source, p)
            if not os.path.exists(full) or (os.path.isdir(full) and not os.listdir(full)):
                return f"{p} is missing or empty"
        self.notes.append(f"note: {target or paths[0]}: checked by name (the fuzz preset is not built here)")
        return None

    def home(self):
        home = os.path.join(self.a.work, "home")
        os.makedirs(home, exist_ok=True)
        env = dict(os.environ)
        env["HOME"] = home
        env["PATH"] = os.path.dirname(os.path.abspath(self.a.strata)) + os.pathsep + env.get("PATH", "")
        return home, env

    def install(self, how, table):
        home, env = self.home()
        if how == "sudo":
            # Without a prefix: the build's own, /usr/local unless the preset sets another.
            cache = open(os.path.join(self.a.build, "CMakeCache.txt"), encoding="utf-8").read()
            m = re.search(r"^CMAKE_INSTALL_PREFIX:PATH=(.*)$", cache, re.M)
            if not m or m.group(1) != "/usr/local":
                return f"the build installs under {m.group(1) if m else '?'}, not /usr/local as the line says"
            root = os.path.join(self.a.work, "destdir")
            env["DESTDIR"] = root
            cmd = ["cmake", "--install", self.a.build]
            prefix = root + "/usr/local"
        else:
            prefix = how.replace("~", home)
            cmd = ["cmake", "--install", self.a.build, "--prefix", prefix]
        r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=180)
        if r.returncode != 0:
            return f"{' '.join(cmd)}: exit {r.returncode}\n{r.stderr[-1500:]}"
        missing = [t for t in table if not glob.glob(os.path.join(prefix, t.replace("COMMAND", "*")))]
        if missing or not table:
            return f"not installed under the prefix: {', '.join(missing) or 'the table of paths is not found'}"
        return None

    def run(self, cmd, then, expect):
        _home, env = self.home()
        os.makedirs(os.path.join(env["HOME"], ".zfunc"), exist_ok=True)
        r = subprocess.run(["bash", "-c", f"{cmd} && {then}"], cwd=self.a.work, env=env, capture_output=True,
                           text=True, timeout=60)
        if r.returncode != 0 or not re.search(expect, r.stdout, re.M):
            return f"`{cmd}` then `{then}`: exit {r.returncode}, no line matching {expect}:\n{r.stdout}{r.stderr}"
        return None


def install_table(path):
    """The paths of install.md's table (`bin/strata`, ...), as globs under a prefix."""
    out = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            m = re.match(r"^\| `([^`]+)`(?:, `([^`]+)`)? \|", line)
            if m:
                first = m.group(1)
                out.append(first)
                if m.group(2):
                    out.append(os.path.join(os.path.dirname(first), m.group(2)))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("docs", nargs="+")
    ap.add_argument("--source", required=True)
    ap.add_argument("--build", required=True)
    ap.add_argument("--strata", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--bench-built", default="ON")
    a = ap.parse_args()
    a.work = os.path.abspath(a.work)
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    c = Checks(a)
    failures, checked, shown = [], 0, 0
    for doc in a.docs:
        name = os.path.basename(doc)
        known = LINES.get(name)
        if known is None:
            failures.append(f"{name}: no entry in LINES")
            continue
        seen = set()
        for line_no, cmd in command_lines(doc):
            where = f"{name}:{line_no}: `{cmd}`"
            entry = known.get(cmd)
            if entry is None:
                failures.append(f"{where}: a line this test does not know (add it to LINES with its check)")
                continue
            seen.add(cmd)
            kind, args = entry[0], entry[1:]
            if kind == "shown":
                shown += 1
                print(f"{where}: shown, not run: {args[0]}")
                continue
            if kind == "presets":
                err = c.presets_(*args)
            elif kind == "script":
                err = c.script(*args)
            elif kind == "ctest":
                err = c.ctest(*args)
            elif kind == "bench":
                err = c.bench(cmd)
            elif kind == "fuzz":
                err = c.fuzz(*args)
            elif kind == "same":
                text = c.read(args[0])
                err = next((f"{args[0]} no longer holds {t!r}" for t in args[1:] if t not in text), None)
            elif kind == "install":
                err = c.install(args[0], install_table(doc))
            else:
                err = c.run(cmd, *args)
            checked += 1
            if err:
                failures.append(f"{where}: {err}")
        for cmd in sorted(set(known) - seen):
            failures.append(f"{name}: `{cmd}` is in LINES but no longer in the document")
    for n in sorted(set(c.notes)):
        print(n)
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{checked} lines checked, {shown} shown and not run, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
