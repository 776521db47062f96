#!/usr/bin/env python3
"""A campaign run as a Slurm job array, for real (issue 21, docs/campaigns.md).

Brings up a single-node Slurm on loopback with scripts/slurm-local, the
recipe docs/campaigns.md gives users ("Slurm on one machine"): munged,
slurmctld and slurmd of Debian's munge and slurm-wlm, each with its own key,
socket, configuration, state, spool and logs in a temporary folder, on free
ports. It submits a
small campaign with `strata campaign SPEC --slurm --submit`, waits (bounded)
for the merge job, and checks that the merged results and report equal a
local run of the same spec, apart from the wall-clock fields. The spec and
the folders have spaces and quotes in their names.

`scripts/slurm-local start --foreground` runs as this script's child and is
stopped by its process id, also when the test fails; it stops the daemons
by theirs (and they die with it if it is killed), and `slurm-local status`
must then find none running. When slurm-local refuses to start (packages
missing: 69; not root: 77) the test prints "skipped: <why>" and exits 77
(ctest's SKIP_RETURN_CODE); a daemon that exits or a node that never comes
up is a failure, with the daemons' logs.

With --deep, instead: the cluster's folder is too deep a path for a Unix
socket (slurmd's step sockets in its spool would pass 107 bytes, as in a
checkout's build folder), and one job must still run: slurm-local puts the
sockets and the spool in a short folder in /tmp, and stop removes it. The
folder has spaces in its name, which slurm.conf must quote; a folder with a
double quote, a # or a line break, which it cannot hold, is refused (64)
before anything starts.

usage: slurm_round_trip.py --strata PATH --source DIR [--deep]
"""

import argparse
import ctypes
import json
import os
import re
import shutil
import signal
import select
import shlex
import subprocess
import sys
import tempfile
import time

SKIP = 77
DAEMON_BOUND_S = 20  # munged, slurmctld and slurmd up and the node idle
JOBS_BOUND_S = 60  # the array and the merge done


class Skip(Exception):
    pass


class Failure(Exception):
    pass


def tail(path, lines=15):
    try:
        with open(path, errors="replace") as f:
            return "".join(f.readlines()[-lines:])
    except OSError as e:
        return f"({path}: {e.strerror})"


def die_with_parent():
    """In slurm-local before exec: SIGTERM when this script dies, however it dies."""
    ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG


def find(name):
    return shutil.which(name) or shutil.which(name, path="/usr/sbin:/sbin:/usr/bin")


class Cluster:
    """scripts/slurm-local start --foreground in `root`: munged, slurmctld and slurmd, stopped by its pid."""

    def __init__(self, source, root, folder="slurm"):
        self.script = os.path.join(source, "scripts", "slurm-local")
        self.root = root
        self.dir = os.path.join(root, folder)
        self.proc = None
        self.env = None
        self.output = ""

    def start(self):
        # The script itself refuses, saying why, with 69 (a program missing) or 77 (not root).
        self.proc = subprocess.Popen([sys.executable, self.script, "start", "--foreground", self.dir],
                                     stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     preexec_fn=die_with_parent)
        deadline = time.monotonic() + DAEMON_BOUND_S + 10  # the script's own bound is DAEMON_BOUND_S
        conf, buf, fd = None, b"", self.proc.stdout.fileno()
        while conf is None and time.monotonic() < deadline:
            if not select.select([fd], [], [], 0.2)[0]:
                continue
            chunk = os.read(fd, 65536)
            if not chunk:
                self.proc.wait(timeout=10)  # its output ended: it has exited
                break
            buf += chunk
            m = re.search(rb"^  export SLURM_CONF=(.+)$", buf, re.M)
            if m:
                conf = shlex.split(m.group(1).decode())[0]
        buf = buf.decode(errors="replace")
        self.output = buf
        if conf is None:
            code = self.proc.poll()
            if code in (69, 77):
                raise Skip(buf.strip())
            raise Failure(f"scripts/slurm-local start exited {code} without a cluster:\n{buf}")
        if conf != os.path.join(self.dir, "slurm.conf"):
            raise Failure(f"scripts/slurm-local start says SLURM_CONF={conf}, not in {self.dir}")
        self.env = dict(os.environ)
        for var in list(self.env):
            if var.startswith(("SLURM_", "SBATCH_")):
                del self.env[var]  # the test's own jobs, not an outer job's settings
        self.env["SLURM_CONF"] = conf

    def run(self, argv, **kw):
        return subprocess.run(argv, capture_output=True, text=True, env=self.env, timeout=30, **kw)

    def job(self, job_id):
        """scontrol's fields of a job (of an array: its tasks' records, joined)."""
        r = self.run([find("scontrol"), "-o", "show", "job", job_id])
        if r.returncode != 0:
            raise Failure(f"scontrol show job {job_id}: {r.stderr.strip()}")
        return r.stdout

    def logs(self):
        return "".join(f"--- {n}'s log ends:\n{tail(os.path.join(self.dir, 'log', n + '.log'))}"
                       for n in ("munged", "slurmctld", "slurmd"))

    def stop(self, job_ids):
        """The jobs cancelled, then slurm-local stopped by its pid (it stops the daemons by theirs); Failure when
        a daemon still runs after."""
        if self.proc is None:
            return
        if self.env is not None:
            for j in job_ids:
                try:
                    self.run([find("scancel"), j])
                except (OSError, subprocess.TimeoutExpired):
                    pass
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=40)
            except subprocess.TimeoutExpired:
                self.proc.kill()  # its daemons get SIGTERM as it dies (PR_SET_PDEATHSIG)
                self.proc.wait()
                raise Failure("scripts/slurm-local did not stop within 40 s of SIGTERM")
        self.proc.stdout.close()
        self.proc = None  # stopped: a second stop does nothing
        if self.env is not None:
            status = subprocess.run([sys.executable, self.script, "status", self.dir], capture_output=True, text=True,
                                    timeout=30)
            if status.returncode != 3:
                raise Failure(f"after scripts/slurm-local stopped, status exited {status.returncode} (3: nothing "
                              f"runs):\n{status.stdout}{status.stderr}")


def results_by_index(path):
    lines = []
    with open(path) as f:
        for line in f:
            j = json.loads(line)
            j.pop("timings", None)  # wall seconds and the worker's pid
            j.pop("repro_run", None)  # names the output folder
            lines.append(j)
    return sorted(lines, key=lambda j: j["index"])


def compare(local, merged):
    a = results_by_index(os.path.join(local, "results.jsonl"))
    b = results_by_index(os.path.join(merged, "results.jsonl"))
    if len(a) != len(b):
        raise Failure(f"{len(a)} cases run locally, {len(b)} merged from the array")
    for x, y in zip(a, b):
        if x != y:
            raise Failure(f"case {x['index']} differs:\n local: {json.dumps(x)}\nmerged: {json.dumps(y)}")
    ra = json.load(open(os.path.join(local, "report.json")))
    rb = json.load(open(os.path.join(merged, "report.json")))
    for key in ("cases", "outcomes", "families", "matrix", "time_to_surface", "coverage"):
        if ra.get(key) != rb.get(key):
            raise Failure(f"report.json's {key} differs:\n local: {json.dumps(ra.get(key))}\n"
                          f"merged: {json.dumps(rb.get(key))}")
    fa = [{k: v for k, v in f.items() if k != "repro_run"} for f in ra.get("failures", [])]
    fb = [{k: v for k, v in f.items() if k != "repro_run"} for f in rb.get("failures", [])]
    if fa != fb:
        raise Failure(f"the failing cases differ:\n local: {json.dumps(fa)}\nmerged: {json.dumps(fb)}")
    for line in b:
        for key in ("log", "scenario"):
            if key in line and not os.path.isfile(os.path.join(merged, line[key])):
                raise Failure(f"case {line['index']}'s {key} {line[key]} was not merged")
    return len(a), sum(1 for line in a if not line["pass"])


def field(record, name):
    m = re.search(rf"\b{name}=(\S+)", record)
    return m.group(1) if m else None


def on_a_cluster(source, folder, body):
    """body(cluster, root, job_ids) on a cluster of scripts/slurm-local in `folder` of a new temporary folder
    `root`, returning its exit code: SKIP when slurm-local refuses to start here, 1 on a Failure (printed with the
    daemons' logs). The cluster is stopped by its pid, the jobs in job_ids cancelled and root removed, whatever
    happens."""
    root = tempfile.mkdtemp(prefix="strata-slurm-")
    cluster = Cluster(source, root, folder)
    job_ids = []
    rc = 1
    try:
        rc = body(cluster, root, job_ids)
    except Skip as e:
        print(f"skipped: {e}")
        rc = SKIP
    except (Failure, subprocess.TimeoutExpired) as e:
        print(f"FAILED: {e}", file=sys.stderr)
        print(cluster.logs(), file=sys.stderr)
        rc = 1
    finally:
        try:
            cluster.stop(job_ids)
        except Failure as e:
            print(f"FAILED: {e}", file=sys.stderr)
            rc = 1
        shutil.rmtree(root, ignore_errors=True)
    return rc



def one_job_in_a_deep_folder(cluster, root, job_ids):
    """--deep: a job runs on a cluster whose folder is too deep a path for slurmd's step sockets."""
    if len(os.path.join(cluster.dir, "spool", "strata-node_1.4294967291")) <= 108:
        raise Failure(f"{cluster.dir} is not deep enough for this test")
    for name, bad in (('a "quoted" folder', '\'"\''), ("a #hash folder", "'#'"), ("a\nline", "'\\n'")):
        refused = os.path.join(root, name)
        r = subprocess.run([sys.executable, cluster.script, "start", refused], capture_output=True, text=True,
                           timeout=30)
        if r.returncode in (69, 77):
            raise Skip(r.stderr.strip())
        if r.returncode != 64 or f"slurm.conf cannot name a path with {bad} in it" not in r.stderr \
                or os.path.exists(refused):
            raise Failure(f"slurm-local start in {refused!r} exited {r.returncode} (64 expected, before making "
                          f"it): {r.stderr}")
    cluster.start()
    m = re.search(r"Its sockets and spool are in (/tmp/strata-slurm-sockets-\S+):", cluster.output)
    if not m:
        raise Failure(f"slurm-local did not say where the sockets went:\n{cluster.output}")
    short = m.group(1)
    if not os.path.isdir(os.path.join(short, "spool")):
        raise Failure(f"{short}/spool is no folder while the cluster runs")
    said = os.path.join(root, "said")
    sub = cluster.run([find("sbatch"), "--parsable", "--output", os.devnull, "--wrap", f"echo ran > {said}"])
    if sub.returncode != 0:
        raise Failure(f"sbatch exited {sub.returncode}: {sub.stderr}")
    job_ids[:] = [sub.stdout.strip().split(";")[0]]
    deadline = time.monotonic() + JOBS_BOUND_S
    state = None
    while time.monotonic() < deadline:
        state = field(cluster.job(job_ids[0]), "JobState")
        if state in ("COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY"):
            break
        time.sleep(0.25)
    if state != "COMPLETED" or not os.path.isfile(said) or open(said).read() != "ran\n":
        raise Failure(f"the job was {state} after at most {JOBS_BOUND_S} s, and wrote "
                      f"{open(said).read() if os.path.isfile(said) else 'nothing'!r}\n{cluster.job(job_ids[0])}")
    cluster.stop(job_ids)
    if os.path.exists(short):
        raise Failure(f"{short} is still there after slurm-local stopped")
    print(f"slurm in a folder {len(cluster.dir)} bytes deep: job {job_ids[0]} ran, its sockets in {short}, "
          "removed when it stopped")
    return 0


def round_trip(args, started, cluster, root, job_ids):
    """The campaign on Slurm, against the same spec run locally."""
    cluster.start()
    up_s = time.monotonic() - started

    # The spec in a folder whose name a shell would take for code.
    work = os.path.join(root, "it's a \"campaign\" $(touch pwned)")
    os.makedirs(work)
    tank = os.path.join(args.source, "missions", "tank", "tank.coral")
    spec = os.path.join(work, "round trip.toml")
    with open(spec, "w") as f:
        # 26 cases; the weak-thrusters case at 10 % fails its
        # expectations, so a failing case's log and scenario travel.
        f.write(f"""name = "Slurm round trip"
missions = [{json.dumps(tank)}]
seeds = [1, 2]
[expect.leak]
outcomes = ["aborted", "completed"]
surface_within_s = 15.0
max_depth_m = 1.8
[expect.strong]
outcomes = ["completed"]
[[family]]
fault = "none"
[[family]]
fault = "leak"
at_s = {{ from = 0, to = 20, step = 2 }}
expect = "leak"
[[family]]
name = "weak"
fault = "weak_thrusters"
at_s = 6
health = [0.1]
expect = "strong"
""")
    out = os.path.join(work, "slurm run")
    shards = 4
    sub = cluster.run([args.strata, "campaign", spec, "--slurm", "--submit", "--shards", str(shards), "--out", out,
                       "-j", "1", "--partition", "strata-local", "--time", "5"])
    print(sub.stdout, end="")
    if sub.returncode != 0:
        raise Failure(f"strata campaign --slurm --submit exited {sub.returncode}:\n{sub.stderr}")
    m = re.search(r"array job (\d+) \((\d+) tasks\), merge job (\d+)", sub.stdout)
    if not m:
        raise Failure(f"no job ids in strata's output:\n{sub.stdout}")
    array_id, merge_id = m.group(1), m.group(3)
    job_ids[:] = [merge_id, array_id]
    if int(m.group(2)) != shards:
        raise Failure(f"{m.group(2)} tasks, asked for {shards}")

    # Local, meanwhile: the same spec in one run.
    local = os.path.join(root, "local")
    loc = subprocess.run([args.strata, "campaign", spec, "--out", local, "-j", "1"], capture_output=True,
                         text=True, timeout=JOBS_BOUND_S)

    deadline = started + JOBS_BOUND_S + up_s
    state = None
    while time.monotonic() < deadline:
        record = cluster.job(merge_id)
        state = field(record, "JobState")
        if state in ("COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY"):
            break
        if field(record, "Reason") == "DependencyNeverSatisfied":
            raise Failure("the merge job will never run: an array task failed\n" + cluster.job(array_id) +
                          "".join(f"--- {n}:\n{tail(os.path.join(out, n))}" for n in sorted(os.listdir(out))
                                  if n.startswith("slurm-")))
        time.sleep(0.25)
    else:
        raise Failure(f"the merge job {merge_id} was {state} after {JOBS_BOUND_S} s\n{cluster.job(array_id)}")
    merge_record = cluster.job(merge_id)
    merge_exit = field(merge_record, "ExitCode")
    # Every task of the array ran on Slurm and succeeded (exit 0: a
    # failing case is the merge's to report).
    tasks = cluster.job(array_id).strip().splitlines()
    if len(tasks) != shards or any(field(t, "JobState") != "COMPLETED" for t in tasks):
        raise Failure("the array's tasks:\n" + "\n".join(tasks))
    for i in range(shards):
        if not os.path.isfile(os.path.join(out, f"shard-{i}", "results.jsonl")):
            raise Failure(f"shard-{i} has no results.jsonl")
    if os.path.exists(os.path.join(work, "pwned")) or os.path.exists(os.path.join(out, "pwned")):
        raise Failure("a path in the scripts ran as shell code")

    cases, failing = compare(local, os.path.join(out, "merged"))
    # The merge job's exit code is the local run's: 1, a case failed.
    if merge_exit != f"{loc.returncode}:0" or loc.returncode != 1 or failing != 2:
        raise Failure(f"merge job ExitCode={merge_exit}, the local run exited {loc.returncode}, "
                      f"{failing} failing cases (expected 1:0, 1 and 2)\n{tail(os.path.join(out, 'slurm-merge-' + merge_id + '.out'))}")
    print(f"slurm round trip: {cases} cases in {shards} array tasks and a merge (job {array_id}, {merge_id}): "
          f"merged results and report equal the local run's; {failing} failing cases both ways; "
          f"Slurm up in {up_s:.1f} s, {time.monotonic() - started:.1f} s in all")
    return 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--strata", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--deep", action="store_true", help="one job on a cluster in a folder too deep for a socket")
    args = ap.parse_args()
    # ctest's timeout or a Ctrl-C: through the finally below, which stops the daemons.
    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, lambda n, _: sys.exit(128 + n))
    if args.deep:
        deep = os.path.join("a folder as deep as a checkout's build folder", "tests", "doc_run", "campaigns_slurm")
        return on_a_cluster(args.source, deep, one_job_in_a_deep_folder)
    started = time.monotonic()
    return on_a_cluster(args.source, "slurm", lambda c, r, j: round_trip(args, started, c, r, j))


if __name__ == "__main__":
    sys.exit(main())
