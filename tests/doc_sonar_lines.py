#!/usr/bin/env python3
"""docs/sonar.md's lines of sonar.jsonl against what the manager writes.

The document shows a frame line and the summary line (```json blocks) and,
in the text after the frame, a target (`"target":{...}`), all from the run
it shows (`strata run missions/sonar_search/sonar_search.coral --sonar
scans`, a lockstep run: the same lines every time). This test makes that
run in a scratch folder and requires:

  - each ```json block to be one JSON object;
  - a frame block to equal, key for key and in the same order, the line of
    the same frame number in the run's sonar.jsonl;
  - the summary block (`"event":"end"`) to equal the run's last line, but
    for `queue_peak`, which depends on how the threads ran (a number);
  - the target in the text to equal the target of the frame it names
    ("as in its frame N").

Exit 0 when all holds, 1 with each difference.

  doc_sonar_lines.py DOC --strata BIN --source REPO --work DIR
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from doc_run import blocks  # noqa: E402

VARIES = {"end": {"queue_peak"}}


def compare(where, doc, got, varies=()):
    """Differences between a line of the document and the line written."""
    out = []
    if list(doc) != list(got):
        out.append(f"{where}: keys {list(doc)}\n  but the manager writes {list(got)}")
    for k in doc:
        if k in got and k not in varies and doc[k] != got[k]:
            out.append(f"{where}: {k} is {json.dumps(doc[k])} in the document, {json.dumps(got[k])} in the run")
        if k in varies and not isinstance(got.get(k), type(doc[k])):
            out.append(f"{where}: {k} is {json.dumps(doc[k])}, the run's is {json.dumps(got.get(k))}")
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("doc")
    ap.add_argument("--strata", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()

    work = os.path.abspath(a.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    mission = os.path.join(os.path.abspath(a.source), "missions", "sonar_search", "sonar_search.coral")
    r = subprocess.run([a.strata, "run", "-q", "--no-log", mission, "--sonar", "scans"], cwd=work,
                       capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        print(f"strata run {mission} --sonar scans: exit {r.returncode}\n{r.stdout}{r.stderr}", file=sys.stderr)
        return 1
    with open(os.path.join(work, "scans", "sonar.jsonl"), encoding="utf-8") as f:
        lines = [json.loads(line) for line in f if line.strip()]
    frames = {rec["frame"]: rec for rec in lines if rec.get("event") == "frame"}

    name = os.path.basename(a.doc)
    with open(a.doc, encoding="utf-8") as f:
        text = f.read()
    failures, checked = [], 0
    for start, lang, _rest, body in blocks(text.split("\n")):
        if lang != "json":
            continue
        where = f"{name}:{start}"
        try:
            doc = json.loads("\n".join(body))
        except json.JSONDecodeError as e:
            failures.append(f"{where}: not one JSON object: {e}")
            continue
        checked += 1
        event = doc.get("event")
        if event == "frame":
            got = frames.get(doc.get("frame"))
            if got is None:
                failures.append(f"{where}: the run has no frame {doc.get('frame')} (it has {len(frames)})")
                continue
            failures += compare(where, doc, got)
        elif event == "end":
            failures += compare(where, doc, lines[-1], VARIES["end"])
        else:
            failures.append(f"{where}: a line of event {event!r}, which this test does not know")
    m = re.search(r'as in its\s+frame (\d+), `"target":(\{[^`]*\})`', text)
    if not m:
        failures.append(f"{name}: no target example (as in its frame N, `\"target\":{{...}}`)")
    else:
        checked += 1
        got = frames.get(int(m.group(1)), {}).get("target")
        doc = json.loads(m.group(2))
        if not isinstance(got, dict):
            failures.append(f"{name}: the run's frame {m.group(1)} has no target: {got}")
        else:
            failures += compare(f"{name}: the target of frame {m.group(1)}", doc, got)
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{name}: {checked} lines of sonar.jsonl checked against a run, {len(failures)} differences")
    return 1 if failures or checked < 3 else 0


if __name__ == "__main__":
    sys.exit(main())
