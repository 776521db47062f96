#!/usr/bin/env python3
"""`strata verify MISSION --bound ... --format json` against
docs/schema/bound.schema.json: a bounded, an unbounded and a failed `within`
answer, on the tank and the survey.

  bound_output_schema.py --source REPO --strata BIN

Exit 0 when all holds, 1 with each failure, 77 (skipped) when python3's
jsonschema module is missing (Debian: python3-jsonschema, in scripts/setup).
"""
import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from schema_check import errors, load_schema  # noqa: E402 (exits 77 without jsonschema)

CASES = [  # (mission, questions, exit, verdicts)
    ("missions/tank/tank.coral", ["fault system_problem -> exec surface", "fault system_problem -> exit closed"],
     65, ["bounded", "unbounded"]),
    ("missions/survey/survey.coral", ["trip leak -> surface within 1"], 65, ["bounded"]),
]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--source", required=True)
    ap.add_argument("--strata", required=True)
    a = ap.parse_args()
    import jsonschema
    validator = jsonschema.Draft202012Validator(load_schema(a.source, "bound.schema.json"))
    failures = []
    for mission, questions, code, verdicts in CASES:
        args = [a.strata, "verify", os.path.join(a.source, mission), "--format", "json"]
        for q in questions:
            args += ["--bound", q]
        r = subprocess.run(args, capture_output=True, text=True, timeout=600)
        if r.returncode != code:
            failures.append(f"{mission}: exit {r.returncode}, expected {code}: {r.stderr[-500:]}")
        try:
            doc = json.loads(r.stdout)
        except json.JSONDecodeError:
            failures.append(f"{mission}: no JSON: {r.stdout[-300:]}")
            continue
        failures += [f"{mission}: {e}" for e in errors(validator, doc)]
        got = [b.get("verdict") for b in doc.get("bounds", [])]
        if got != verdicts:
            failures.append(f"{mission}: verdicts {got}, expected {verdicts}")
    for f in failures:
        print(f"FAIL {f}")
    print(f"{len(CASES)} missions, {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
