#!/usr/bin/env python3
"""A campaign run as a Slurm job array, for real (issue 21, docs/campaigns.md).

Brings up a single-node Slurm on loopback -- munged, slurmctld and slurmd of
Debian's munge and slurm-wlm, each with its own key, socket, configuration,
state, spool and logs in a temporary folder, on free ports -- submits a
small campaign with `strata campaign SPEC --slurm --submit`, waits (bounded)
for the merge job, and checks that the merged results and report equal a
local run of the same spec, apart from the wall-clock fields. The spec and
the folders have spaces and quotes in their names.

Every daemon is started in the foreground by this script and stopped by its
process id, also when the test fails. When the daemons cannot be started
(packages missing, not root, a daemon that exits or a node that never comes
up) it prints "skipped: <why>" and exits 77 (ctest's SKIP_RETURN_CODE).

usage: slurm_round_trip.py --strata PATH --source DIR
"""

import argparse
import ctypes
import json
import os
import pwd
import re
import shutil
import signal
import socket
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


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def tail(path, lines=15):
    try:
        with open(path, errors="replace") as f:
            return "".join(f.readlines()[-lines:])
    except OSError as e:
        return f"({path}: {e.strerror})"


def die_with_parent():
    """In a daemon before exec: SIGTERM when this script dies, however it dies."""
    ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG


def find(name):
    return shutil.which(name) or shutil.which(name, path="/usr/sbin:/sbin:/usr/bin")


class Cluster:
    """munged, slurmctld and slurmd in `root`, stopped by pid in stop()."""

    def __init__(self, root):
        self.root = root
        self.procs = []  # (name, Popen, log file)
        self.env = dict(os.environ)
        self.tools = {}

    def check_tools(self):
        missing = [n for n in ("munged", "mungekey", "slurmctld", "slurmd", "sbatch", "scontrol", "scancel")
                   if not find(n)]
        if missing:
            raise Skip(f"{', '.join(missing)} not found: install the Debian packages munge and slurm-wlm "
                       "(scripts/setup)")
        self.tools = {n: find(n) for n in ("munged", "mungekey", "slurmctld", "slurmd", "sbatch", "scontrol",
                                           "scancel")}
        if os.geteuid() != 0:
            raise Skip(f"not root (uid {os.geteuid()}): slurmd runs as root to start each job as its user "
                       "(Slurm's quick start guide); run the test as root")

    def start(self):
        r = self.root
        for d in ("munge", "state", "spool", "log"):
            os.makedirs(os.path.join(r, d), mode=0o700)
        key = os.path.join(r, "munge", "munge.key")
        made = subprocess.run([self.tools["mungekey"], "--create", "--keyfile", key], capture_output=True, text=True)
        if made.returncode != 0:
            raise Skip(f"mungekey could not make a key: {made.stderr.strip()}")
        self.munge_socket = os.path.join(r, "munge", "munge.socket")
        self.spawn("munged", [self.tools["munged"], "--foreground", "--force", f"--socket={self.munge_socket}",
                              f"--key-file={key}", f"--pid-file={r}/munge/munged.pid",
                              f"--seed-file={r}/munge/munged.seed", f"--log-file={r}/log/munged.log"],
                   f"{r}/log/munged.log")
        self.wait_for(lambda: os.path.exists(self.munge_socket), "munged", "its socket never appeared")

        user = pwd.getpwuid(os.geteuid()).pw_name
        host = socket.gethostname().split(".")[0]
        self.node = "strata-node"
        conf = os.path.join(r, "slurm.conf")
        with open(conf, "w") as f:
            f.write(f"""# A single-node Slurm for strata's round-trip test, all on loopback.
ClusterName=strata-test
SlurmctldHost={host}(127.0.0.1)
SlurmctldPort={free_port()}
SlurmdPort={free_port()}
SlurmUser={user}
SlurmdUser={user}
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={self.munge_socket}
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
StateSaveLocation={r}/state
SlurmdSpoolDir={r}/spool
SlurmctldPidFile={r}/slurmctld.pid
SlurmdPidFile={r}/slurmd.pid
SlurmctldLogFile={r}/log/slurmctld.log
SlurmdLogFile={r}/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
PlugStackConfig={r}/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SlurmdParameters=config_overrides
ReturnToService=2
MinJobAge=600
KillWait=2
NodeName={self.node} NodeAddr=127.0.0.1 NodeHostname={host} CPUs=2 State=UNKNOWN
PartitionName=strata-test Nodes={self.node} Default=YES MaxTime=INFINITE State=UP
""")
        open(os.path.join(r, "plugstack.conf"), "w").close()
        self.env["SLURM_CONF"] = conf
        for var in list(self.env):
            if var.startswith(("SLURM_", "SBATCH_")) and var != "SLURM_CONF":
                del self.env[var]  # the test's own jobs, not an outer job's settings
        self.spawn("slurmctld", [self.tools["slurmctld"], "-D", "-c", "-f", conf], f"{r}/log/slurmctld.log")
        self.spawn("slurmd", [self.tools["slurmd"], "-D", "-N", self.node, "-f", conf], f"{r}/log/slurmd.log")
        self.wait_for(self.node_idle, "slurmd", "the node never became idle")

    def spawn(self, name, argv, log):
        out = open(os.path.join(self.root, "log", f"{name}.stdout"), "w")
        try:
            p = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT, env=self.env,
                                 start_new_session=True, preexec_fn=die_with_parent)
        except OSError as e:
            raise Skip(f"cannot start {name}: {e}")
        finally:
            out.close()
        self.procs.append((name, p, log))

    def node_idle(self):
        r = subprocess.run([self.tools["scontrol"], "show", "node", self.node], capture_output=True, text=True,
                           env=self.env, timeout=10)
        return r.returncode == 0 and re.search(r"State=IDLE\b", r.stdout) is not None

    def wait_for(self, ready, name, what):
        deadline = time.monotonic() + DAEMON_BOUND_S
        while time.monotonic() < deadline:
            for n, p, log in self.procs:
                if p.poll() is not None:
                    raise Skip(f"{n} exited ({p.returncode}) while starting; its log ends:\n"
                               f"{tail(log)}{tail(os.path.join(self.root, 'log', n + '.stdout'))}")
            try:
                if ready():
                    return
            except subprocess.TimeoutExpired:
                pass
            time.sleep(0.2)
        logs = "".join(f"--- {n}:\n{tail(log)}" for n, _, log in self.procs)
        raise Skip(f"{name} did not come up within {DAEMON_BOUND_S} s: {what}\n{logs}")

    def run(self, argv, **kw):
        return subprocess.run(argv, capture_output=True, text=True, env=self.env, timeout=30, **kw)

    def job(self, job_id):
        """scontrol's fields of a job (of an array: its tasks' records, joined)."""
        r = self.run([self.tools["scontrol"], "-o", "show", "job", job_id])
        if r.returncode != 0:
            raise Failure(f"scontrol show job {job_id}: {r.stderr.strip()}")
        return r.stdout

    def stop(self, job_ids):
        for j in job_ids:
            try:
                self.run([self.tools["scancel"], j])
            except (OSError, subprocess.TimeoutExpired):
                pass
        for name, p, _ in reversed(self.procs):
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
                try:
                    p.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()


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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--strata", required=True)
    ap.add_argument("--source", required=True)
    args = ap.parse_args()
    # ctest's timeout or a Ctrl-C: through the finally below, which stops the daemons.
    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, lambda n, _: sys.exit(128 + n))
    started = time.monotonic()
    root = tempfile.mkdtemp(prefix="strata-slurm-")
    cluster = Cluster(root)
    job_ids = []
    try:
        cluster.check_tools()
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
                           "-j", "1", "--partition", "strata-test", "--time", "5"])
        print(sub.stdout, end="")
        if sub.returncode != 0:
            raise Failure(f"strata campaign --slurm --submit exited {sub.returncode}:\n{sub.stderr}")
        m = re.search(r"array job (\d+) \((\d+) tasks\), merge job (\d+)", sub.stdout)
        if not m:
            raise Failure(f"no job ids in strata's output:\n{sub.stdout}")
        array_id, merge_id = m.group(1), m.group(3)
        job_ids = [merge_id, array_id]
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
    except Skip as e:
        print(f"skipped: {e}")
        return SKIP
    except (Failure, subprocess.TimeoutExpired) as e:
        print(f"FAILED: {e}", file=sys.stderr)
        for name, _, log in cluster.procs:
            print(f"--- {name}'s log ends:\n{tail(log)}", file=sys.stderr)
        return 1
    finally:
        cluster.stop(job_ids)
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
