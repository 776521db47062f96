#!/usr/bin/env python3
"""The README and docs/ cite only what the repository holds.

Fails, with the file and line of each, on:
  - in the README, docs/, and the shipped source and configuration (src/,
    config/, web/src/, scripts/, cmake/): a citation of design.md in any
    spelling (below);
  - in the README and docs/, also: a citation of design.md (a design
    document that is not in the repository): `design.md`, `design §2.6`;
  - a path into the folder beside the repository (`../shared/...`);
  - a Markdown link whose target is not a file or folder of the repository;
  - a repository path in backquotes (`docs/x.md`, `src/run/session.h`,
    `tests/...`, `missions/...`, ...) that does not exist, so a renamed or
    removed file is not cited on.

  doc_references.py REPO
"""
import glob
import os
import re
import sys

OUTSIDE = [
    (re.compile(r"\bdesign\.md\b"), "cites design.md, which is not in the repository"),
    (re.compile(r"\bdesign\s+§"), "cites the design document (design §...), which is not in the repository"),
    (re.compile(r"(?<![\w/])\.\./shared\b"), "cites ../shared, a folder outside the repository"),
]
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
# A path in backquotes that starts at one of the repository's top folders.
TOP = ("docs", "src", "tests", "missions", "config", "scripts", "web", "bench", "fuzz", "cmake")
SCRATCH = {"fuzz/work"}
CODE_PATH = re.compile(r"`((?:%s)/[A-Za-z0-9_./-]+)`" % "|".join(TOP))


def main():
    repo = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
    docs = [os.path.join(repo, "README.md")] + sorted(glob.glob(os.path.join(repo, "docs", "**", "*.md"),
                                                                recursive=True))
    failures, checked = [], 0
    for doc in docs:
        rel = os.path.relpath(doc, repo)
        in_code = False
        with open(doc, encoding="utf-8") as f:
            for n, line in enumerate(f, 1):
                if line.startswith("```"):
                    in_code = not in_code
                for rx, why in OUTSIDE:
                    if rx.search(line):
                        failures.append(f"{rel}:{n}: {why}: {line.strip()}")
                if in_code:
                    continue
                for m in LINK.finditer(line):
                    target = m.group(1).split("#")[0]
                    if not target or re.match(r"^[a-z]+:", target):
                        continue  # a web address or an anchor
                    checked += 1
                    path = os.path.normpath(os.path.join(os.path.dirname(doc), target))
                    if not path.startswith(repo + os.sep) or not os.path.exists(path):
                        failures.append(f"{rel}:{n}: the link's target {target} is not in the repository")
                for m in CODE_PATH.finditer(line):
                    target = m.group(1).rstrip(".")
                    checked += 1
                    # A benchmark named by its program (bench/x_bench: bench/x_bench.cpp), a
                    # placeholder (tests/coral/ok/NAME.coral) or a scratch folder git ignores.
                    if re.search(r"[A-Z]{3,}", target) or target.rstrip("/") in SCRATCH:
                        continue
                    if not any(os.path.exists(os.path.join(repo, target + ext)) for ext in ("", ".cpp")):
                        failures.append(f"{rel}:{n}: `{target}` is not in the repository")
    # The code and configuration a user's clone carries cite no design
    # document either (its comments point to docs/).
    shipped = 0
    for top in ("src", "config", "web/src", "scripts", "cmake"):
        for path in sorted(glob.glob(os.path.join(repo, top, "**", "*"), recursive=True)):
            if not os.path.isfile(path) or os.path.islink(path):
                continue
            shipped += 1
            rel = os.path.relpath(path, repo)
            try:
                with open(path, encoding="utf-8") as f:
                    lines = list(f)
            except UnicodeDecodeError:
                continue  # an image or other binary
            for n, line in enumerate(lines, 1):
                for rx, why in OUTSIDE[:2]:
                    if rx.search(line):
                        failures.append(f"{rel}:{n}: {why}: {line.strip()}")
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{len(docs)} documents, {checked} paths and links, {shipped} source and configuration files, "
          f"{len(failures)} citations of what is not in the repository")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
