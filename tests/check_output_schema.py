#!/usr/bin/env python3
"""`strata check --format json` against docs/schema/check.schema.json.

  check_output_schema.py --source REPO --strata BIN --work DIR

In a scratch folder: CORAL and PROLOG files with errors, warnings and notes
(a syntax error with its column, a warning without one, an unreadable file
of each language) are checked, one file at a time and all in one document;
every output must be valid against the schema, with the places the files
hold (the column under one name, `col`, for both languages). And the
schema's kinds are those of src/core/diagnostic_kind.def, no more and no
fewer.

Exit 0 when all holds, 1 with each failure, 77 (skipped) when python3's
jsonschema module is missing (Debian: python3-jsonschema, in scripts/setup).
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from schema_check import errors, load_schema  # noqa: E402 (exits 77 without jsonschema)

# name: (text, what `strata check` must report for that file alone: exit,
# and (kind, line, col) of each diagnostic, None where the place has none).
FILES = {
    "mixed.coral": ("net quiet { place a = 1, spare; exit done; transition t { wait { a } signal { done } } }\n"
                    "net loud { place a; place a; transition t { wait { b } } }\n",
                    65, [("UnusedPlace", 1, 26), ("DuplicatePlace", 2, 27), ("UndefinedPlace", 2, 52)]),
    "warns.coral": ("net n { place a = 1, unused; exit done; transition t { wait { a } signal { done } } }\n",
                    0, [("UnusedPlace", 1, 22)]),
    "warns_and_fails.pl": ("p(X) :- true.\nmission :- exec_warp_drive(1, _).\n",
                           65, [("PrologLoadWarning", 1, None), ("PrologCheckError", 2, None)]),
    "syntax.pl": ("mission :- exec_submerge(X.\n", 65, [("PrologLoadError", 1, "any")]),
    "no_such.pl": (None, 74, [("FileUnreadable", None, None)]),
}


def same(got, want):
    """A diagnostic's (kind, line, col) as FILES wants it; "any" is a column, whichever."""
    return got[:2] == want[:2] and (got[2] is not None if want[2] == "any" else got[2] == want[2])


def check(a, validator, args):
    r = subprocess.run([a.strata, "check", "--format", "json", *args], cwd=a.work, capture_output=True, text=True,
                       timeout=300)
    try:
        doc = json.loads(r.stdout)
    except json.JSONDecodeError:
        return r.returncode, None, [f"check {' '.join(args)}: no JSON (exit {r.returncode}):\n{r.stderr[-1500:]}"]
    return r.returncode, doc, [f"check {' '.join(args)}: {e}" for e in errors(validator, doc)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--source", required=True)
    ap.add_argument("--strata", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    a.strata = os.path.abspath(a.strata)
    a.work = os.path.abspath(a.work)
    schema = load_schema(a.source, "check.schema.json")
    import jsonschema
    validator = jsonschema.Draft202012Validator(schema)
    failures = []

    with open(os.path.join(a.source, "src", "core", "diagnostic_kind.def"), encoding="utf-8") as f:
        kinds = re.findall(r"^X\((\w+),", f.read(), re.M)
    schema_kinds = schema["$defs"]["diagnostic"]["properties"]["kind"]["enum"]
    if sorted(kinds) != sorted(schema_kinds):
        failures.append(f"the schema's kinds are not diagnostic_kind.def's: missing "
                        f"{sorted(set(kinds) - set(schema_kinds))}, extra {sorted(set(schema_kinds) - set(kinds))}")

    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    for name, (text, _, _) in FILES.items():
        if text is not None:
            with open(os.path.join(a.work, name), "w", encoding="utf-8") as f:
                f.write(text)

    for name, (_, want_exit, want) in FILES.items():
        code, doc, bad = check(a, validator, [name])
        failures += bad
        if code != want_exit:
            failures.append(f"check {name}: exit {code}, not {want_exit}")
        if doc is None:
            continue
        got = [(d["kind"], d.get("line"), d.get("col")) for d in doc["diagnostics"]]
        if len(got) != len(want) or not all(same(g, w) for g, w in zip(got, want)):
            failures.append(f"check {name}: diagnostics (kind, line, col) {got}, not {want}")
        for d in doc["diagnostics"]:
            if "column" in d:
                failures.append(f"check {name}: a diagnostic spells its column `column`: {d}")
            if d["kind"] != "FileUnreadable" and d.get("file") != name:
                failures.append(f"check {name}: a diagnostic names file {d.get('file')!r}: {d}")
        if name == "mixed.coral" and not any(d["notes"] for d in doc["diagnostics"]):
            failures.append(f"check {name}: DuplicatePlace has no note at the first declaration")

    # All in one document: both languages, errors and warnings together.
    code, doc, bad = check(a, validator, list(FILES))
    failures += bad
    if code != 74:
        failures.append(f"check of every file: exit {code}, not 74 (a file cannot be read)")
    if doc is not None:
        if [f["language"] for f in doc["files"]] != ["coral", "coral", "prolog", "prolog", "prolog"]:
            failures.append(f"check of every file: files {doc['files']}")
        severities = [d["severity"] for d in doc["diagnostics"]]
        if doc["errors"] != severities.count("error") or doc["warnings"] != severities.count("warning"):
            failures.append(f"check of every file: totals {doc['errors']}, {doc['warnings']} do not count "
                            f"the diagnostics {severities}")
        if doc["warnings"] == 0 or doc["errors"] == 0:
            failures.append("check of every file: wants errors and warnings both")

    for f in failures:
        print(f, file=sys.stderr)
    print(f"check.schema.json: {len(FILES) + 1} outputs checked, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
