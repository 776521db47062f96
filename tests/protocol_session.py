#!/usr/bin/env python3
"""The sessions of docs/protocol.md §9, replayed against a real vehicle.

Each ``` block of the section "## 9. A session" is a conversation: `> `
lines are the client's, `< ` lines the vehicle's. For each block a fresh
`strata vehicle --listen 0` is started (lockstep, its nominal scenario);
the client's lines that come together are sent together, then the
vehicle's lines that follow them in the block are read and must be exactly
those, in that order, except the sonar port (`sonar=N`: any port).
Heartbeats (`hb ...`), which the block does not show, are passed over.

  protocol_session.py DOC --strata BIN
"""
import argparse
import re
import socket
import subprocess
import sys

FENCE = re.compile(r"^```")


def session_blocks(lines):
    start = lines.index("## 9. A session")
    out, i = [], start + 1
    while i < len(lines) and not lines[i].startswith("## "):
        if FENCE.match(lines[i]):
            first = i + 1
            i += 1
            body = []
            while not FENCE.match(lines[i]):
                body.append(lines[i])
                i += 1
            out.append((first, body))
        i += 1
    return out


def same(expected, got):
    rx = re.sub(r"sonar=\d+", r"sonar=\\d+", re.escape(expected))
    return re.fullmatch(rx, got) is not None


def replay(strata, first_line, body, name):
    failures = []
    v = subprocess.Popen([strata, "vehicle", "--listen", "0"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                         text=True)
    try:
        addr = v.stdout.readline().strip()
        host, port = addr.rsplit(":", 1)
        with socket.create_connection((host, int(port)), timeout=30) as s:
            f = s.makefile("rw", encoding="utf-8", newline="\n")
            k = 0
            while k < len(body):
                sent = []
                while k < len(body) and body[k].startswith("> "):
                    sent.append(body[k][2:])
                    k += 1
                want = []
                while k < len(body) and body[k].startswith("< "):
                    want.append((first_line + k, body[k][2:]))
                    k += 1
                while k < len(body) and not body[k].strip():
                    k += 1
                if k < len(body) and not body[k].startswith(("> ", "< ")):
                    failures.append(f"{name}:{first_line + k}: neither `> ` nor `< `: {body[k]}")
                    k += 1
                for line in sent:
                    f.write(line + "\n")
                f.flush()
                for n, expected in want:
                    got = f.readline()
                    while got.startswith("hb "):
                        got = f.readline()
                    got = got.rstrip("\n")
                    if not same(expected, got):
                        failures.append(f"{name}:{n}: the vehicle said\n    {got!r}\n  the document says\n    "
                                        f"{expected!r}")
                        return failures
    except (OSError, ValueError) as e:
        failures.append(f"{name}:{first_line}: the session broke off: {e}")
    finally:
        v.terminate()
        try:
            v.wait(30)
        except subprocess.TimeoutExpired:
            v.kill()
    return failures


def main():
    ap = argparse.ArgumentParser(description="Replay docs/protocol.md's sessions against strata vehicle")
    ap.add_argument("doc")
    ap.add_argument("--strata", required=True)
    a = ap.parse_args()
    with open(a.doc, encoding="utf-8") as f:
        lines = f.read().split("\n")
    name = a.doc.rsplit("/", 1)[-1]
    sessions = session_blocks(lines)
    failures = []
    for first, body in sessions:
        failures += replay(a.strata, first, body, name)
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{name}: {len(sessions)} sessions, {sum(len(b) for _, b in sessions)} lines, {len(failures)} failed")
    return 1 if failures or not sessions else 0


if __name__ == "__main__":
    sys.exit(main())
