#!/usr/bin/env python3
"""`strata studio` makes its sonar folder with mkdtemp and removes it.

Regression: the folder was $TMPDIR/strata-studio-PID-sonar, a name another
user of the machine could make first (as a folder of links at the names the
sonar writes, sonar.jsonl among them, which is opened following links). Now
it is a fresh strata-studio-sonar-XXXXXX, mode 0700, gone after Ctrl-C; a
folder at the old name is left alone.

  studio_sonar_folder.py STRATA MISSIONS_DIR
"""
import os
import signal
import stat
import subprocess
import sys
import tempfile
import time


def main():
    strata, missions = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, TMPDIR=tmp)
        proc = subprocess.Popen([strata, "studio", missions, "--listen", "127.0.0.1:0", "-q"], env=env,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            # The old name, made first as another user would: must stay untouched.
            squat = os.path.join(tmp, f"strata-studio-{proc.pid}-sonar")
            os.mkdir(squat)
            url = proc.stdout.readline().strip()
            if not url.startswith("http://127.0.0.1:"):
                print(f"FAIL: no URL from strata studio: {url!r} {proc.stderr.read()}")
                return 1
            made = [n for n in os.listdir(tmp) if n.startswith("strata-studio-sonar-")]
            if len(made) != 1:
                print(f"FAIL: expected one strata-studio-sonar-XXXXXX folder in TMPDIR, found {os.listdir(tmp)}")
                return 1
            mode = stat.S_IMODE(os.stat(os.path.join(tmp, made[0])).st_mode)
            if mode != 0o700:
                print(f"FAIL: the sonar folder's mode is {oct(mode)}, not 0700")
                return 1
        finally:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                proc.kill()
                print("FAIL: strata studio did not stop within 20 s of Ctrl-C")
                return 1
        left = sorted(os.listdir(tmp))
        if left != [os.path.basename(squat)]:
            print(f"FAIL: after Ctrl-C TMPDIR holds {left}: the studio's folder must be gone, the other left alone")
            return 1
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
