#!/usr/bin/env python3
"""No decision on message text in src/ (issue 36).

A message is words for people: an error's message, a reason, a note, what
a process printed. Code that decides what to do by looking inside one
(`error.message.starts_with("vehicle error")`, `reason == "..."`) breaks
when the words are improved, so it is refused here: the decision belongs
on a typed value (an error kind, an enum, a field).

Flagged, in src/ outside tests: find / rfind / starts_with / ends_with /
contains with a string literal, or == / != against a string literal, on an
expression whose last name is one of MESSAGE_NAMES (or on
`.error().message`). A line that must do it anyway says why on the line:
`// text-ok: <why>` (a third party's message, a Prolog term's text), on
the line or the one before.

Usage: no_text_decisions.py REPO_ROOT
"""
import os
import re
import sys

MESSAGE_NAMES = r"(?:message|reason|error|what|why|note|err|stderr|problems|vehicle_reason|shutdown_error)"
CALL = re.compile(r"\b" + MESSAGE_NAMES + r"\b(?:\(\))?\s*\.\s*(?:find|rfind|starts_with|ends_with|contains)\s*\(\s*\"")
COMPARE = re.compile(r"\b" + MESSAGE_NAMES + r"\b(?:\(\))?\s*[!=]=\s*\"|\"\s*[!=]=\s*\w+\.\s*" + MESSAGE_NAMES + r"\b")
OPT_OUT = re.compile(r"//\s*text-ok:\s*\S")


def is_test(name: str) -> bool:
    return name.endswith(("_test.cpp", "_test.h")) or "_test_" in name or name.startswith("test_")


def scan(root: str):
    found, excused = [], []
    for folder, _, files in os.walk(os.path.join(root, "src")):
        for name in sorted(files):
            if not name.endswith((".cpp", ".h")) or is_test(name):
                continue
            path = os.path.join(folder, name)
            with open(path, encoding="utf-8") as f:
                previous = ""
                for number, line in enumerate(f, 1):
                    if CALL.search(line) or COMPARE.search(line):
                        place = f"{os.path.relpath(path, root)}:{number}: {line.strip()}"
                        (excused if OPT_OUT.search(line) or OPT_OUT.search(previous) else found).append(place)
                    previous = line
    return found, excused


def self_test() -> int:
    """The rule catches a decision added on a message, and lets a reasoned one by."""
    import tempfile
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "src", "run"))
        with open(os.path.join(root, "src", "run", "x.cpp"), "w", encoding="utf-8") as f:
            f.write('if (r.error().message.starts_with("vehicle error")) stop();\n'
                    'if (report.reason == "mission stalled") stalled = true;\n'
                    'if (r.why.find("lost") != npos) {}  // text-ok: a test of the opt-out\n'
                    'if (token.text == "EXEC") kind = Exec;\n')
        with open(os.path.join(root, "src", "run", "x_test.cpp"), "w", encoding="utf-8") as f:
            f.write('EXPECT_TRUE(err.find("strata run:") != npos);\n')
        found, excused = scan(root)
    ok = [p.split(": ", 1)[0] for p in found] == ["src/run/x.cpp:1", "src/run/x.cpp:2"] and len(excused) == 1
    print("ok: the rule catches both decisions and excuses the reasoned one" if ok
          else f"error: the rule missed: found {found}, excused {excused}", file=sys.stdout if ok else sys.stderr)
    return 0 if ok else 1


def main() -> int:
    if len(sys.argv) == 2 and sys.argv[1] == "--self-test":
        return self_test()
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 64
    found, excused = scan(sys.argv[1])
    for place in excused:
        print(f"excused: {place}")
    for place in found:
        print(f"error: a decision on message text: {place}", file=sys.stderr)
    if found:
        print(f"{len(found)} decision(s) on message text; decide on a typed value, or say why with "
              "`// text-ok: <why>` on the line", file=sys.stderr)
        return 1
    print(f"ok: no decision on message text in src/ ({len(excused)} excused)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
