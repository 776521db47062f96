#!/usr/bin/env python3
"""Every fenced block of the README and docs/ is run or checked by a test.

A block counts as run or checked when:

  - its document is run by doc_run.py (--run) and it is a file block
    (```LANG file=PATH) or a ```sh block of `$ ` commands; a ```sh
    group=NAME block only when a test runs that group (--run-groups
    DOC:NAME, doc_run.py --group NAME);
  - its document's examples are checked by doc_examples.py (--examples) and
    it is a ```coral or ```prolog block that is not a fragment, or a ```toml
    block that sets `seed`;
  - it is a session of protocol.md §9 (protocol_session.py), the README's
    short tour (readme_tour.py), a ```json line of sonar.md
    (doc_sonar_lines.py), or a ```sh block of build lines of a document
    that doc_build_lines.py reads (--build-lines);
  - it is a piece of a repository file, marked ```LANG from=PATH: this
    test checks that its lines are in PATH, together and as written;

or it is in ALLOW below, by its document and first line, with the reason
it cannot run here (or is no example: a grammar, a diagram, a synopsis).
Any other block fails the test, with its line; so does an entry of ALLOW
that no block has any longer, or one whose block is now run anyway.
A document given with --skip is left out.

  doc_blocks.py --source REPO --run DOC... --examples DOC... --build-lines DOC... [--run-groups DOC:NAME...]
                [--skip DOC...]
"""
import argparse
import glob
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from doc_run import blocks  # noqa: E402
from protocol_session import session_blocks  # noqa: E402

# (document, how the block's first non-blank line starts) -> why no test runs it
ALLOW = {
    ("docs/imc.md", "$ ./dune -c lauv-simulator-1"):
        "LSTS DUNE is never part of Strata's build or CI (its licence): imc.on_dune runs it when STRATA_DUNE names it",
    ("docs/imc.md", "$ STRATA_DUNE="):
        "the optional DUNE test's own command line: it needs a DUNE build, which CI does not have",
    ("docs/imc.md", "strata vehicle --imc "):
        "vehicles that serve until Ctrl-C: the README tour runs `strata vehicle --imc --port 0 --speed 50`, "
        "imc_server_test speaks to the same server",
    ("docs/architecture.md", "core <- petri <- coral <- strategic -> tactical -> protocol <- vehicle"):
        "a diagram of the libraries' layers, not a command (scripts/check-layers checks the rule)",
    ("docs/architecture.md", "CoralEngine or PrologExecutor"):
        "a diagram of one run's objects, not a command",
    ("docs/campaigns.md", 'params = "heavy.toml"   # at the top level, relative to the spec\'s folder'):
        "one key shown out of a spec",
    ("docs/campaigns.md", "strata campaign SPEC --case I"):
        "a synopsis: SPEC, I, MISSION and DIR stand for what a failing case's results line gives",
    ("docs/campaigns.md", "$ strata campaign missions/tank/campaign.toml --slurm --shards 16 --out /scratch/tank "
                          "--partition short --time 30"):
        "submitting needs a Slurm cluster's sbatch (cli.campaign_slurm_array_merge_equals_a_local_run submits "
        "to a single-node Slurm of its own)",
    ("docs/campaigns.md", "campaign missions/tank/campaign.toml: 456 cases in 16 Slurm array tasks (1 CPU each)"):
        "what --submit prints, job ids from a real cluster",
    ("docs/campaigns.md", "$ strata campaign missions/tank/campaign.toml --slurm --submit --out tank-slurm"):
        "what --submit says without a cluster: it depends on the machine (one with a slurm.conf would take 456 "
        "cases' jobs); cli.campaign_slurm_submit_no_cluster_says_how_to_try_one checks the message with a "
        "stand-in sbatch that fails as Slurm's does",
    ("docs/campaigns.md", "mkdir -p /shared/run"):
        "GNU parallel over SSH to other hosts",
    ("docs/campaigns.md", "apiVersion: batch/v1"):
        "a Kubernetes Job: needs a cluster",
    ("docs/campaigns.md", "kubectl apply -f tank-campaign.yaml"):
        "kubectl against a Kubernetes cluster",
    ("docs/language.md", "file        = { import | net } ;"):
        "the grammar (EBNF), not an example",
    ("docs/language.md", "net NAME "):
        "the summary of the syntax, not a file",
    ("docs/open_water.md", "transition start_leg {"):
        "a CORAL fragment shown out of its net (marked fragment)",
    ("docs/prolog.md", "mission :- repeat, step, mission_over, !, finish."):
        "a PROLOG fragment shown out of its file (marked fragment)",
    ("docs/protocol.md", "field  = bare | quoted"):
        "the grammar of a message's fields, not a session",
    ("docs/sonar.md", "strata sonar --stream HOST:PORT --out DIR [--size N] [--connect-timeout S] [-q | -v]"):
        "the synopsis, and a line needing a vehicle's sonar stream on 7021 (docs.readme_tour runs strata sonar "
        "--stream against a vehicle it starts)",
    ("docs/sonar.md", "vehicle ──TCP──> Capture thread"):
        "a diagram of the manager's threads",
    ("docs/sonar.md", '#include "sonar/manager.h"'):
        "C++ using the library, with `...` for the caller's code (src/sonar/manager_test.cpp makes the same calls)",
    ("docs/studio.md", "strata studio missions                      # prints http://127.0.0.1:PORT; open it in a browser"):
        "the studio serves until Ctrl-C, for a browser: docs.readme_tour starts and stops `strata studio`, "
        "cli.run_studio_wait_serves_then_exits runs `run --studio`, StudioWebRoot.* serves a --web-root",
    ("docs/studio.md", '{ "path": P, "text": "...the .coral text...", "layout": {...} | null,'):
        "the mission model's JSON, annotated field by field (the studio's API tests read each field)",
    ("docs/studio.md", '{ "path": P, "kind": "prolog", "read_only": true, "text": "...", "etag": "\\"...\\"",'):
        "the PROLOG model's JSON, annotated (the studio's API tests read each field)",
    ("docs/tutorial-first-mission.md", "$ strata studio first"):
        "the studio serves until Ctrl-C and is used in a browser: web/e2e/tutorial.spec.mjs runs it as written",
    ("docs/tutorial-first-survey.md", "$ strata studio out_and_back"):
        "the studio serves until Ctrl-C and is used in a browser: web/e2e/tutorial.spec.mjs runs it as written",
    ("docs/verification.md", '{ "ok": false, "all_hold": false,'):
        "the --format json answer, shortened and annotated",
    ("docs/verification.md", "strata verify MISSION --witness-out FILE"):
        "a synopsis: MISSION and FILE are placeholders",
    ("docs/verification.md", '{ "strata_answers": 1,                       the format\'s version'):
        "the answers file's format, annotated field by field",
    ("docs/verification.md", "predicate := or"):
        "the grammar of a question, not an example",
}


def first_line(body):
    return next((b.strip() for b in body if b.strip()), "")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True)
    ap.add_argument("--run", nargs="*", default=[])
    ap.add_argument("--examples", nargs="*", default=[])
    ap.add_argument("--build-lines", nargs="*", default=[])
    ap.add_argument("--run-groups", nargs="*", default=[], metavar="DOC:NAME")
    ap.add_argument("--skip", nargs="*", default=[])
    a = ap.parse_args()
    src = os.path.abspath(a.source)
    docs = ["README.md"] + sorted(os.path.relpath(p, src) for p in glob.glob(os.path.join(src, "docs", "*.md")))
    failures, counts, used = [], {"run": 0, "checked": 0, "allowed": 0}, set()
    for doc in docs:
        if doc in a.skip:
            continue
        with open(os.path.join(src, doc), encoding="utf-8") as f:
            lines = f.read().split("\n")
        protocol = set()
        if doc == "docs/protocol.md":
            protocol = {first for first, _body in session_blocks(lines)}
        tour = lines.index("## A short tour of the CLI") if "## A short tour of the CLI" in lines else None
        tour_done = False
        for start, lang, rest, body in blocks(lines):
            commands = lang == "sh" and any(b.startswith("$ ") for b in body)
            gm = re.search(r"(?:^|\s)group=(\S+)", rest)
            if commands and gm and f"{doc}:{gm.group(1)}" not in a.run_groups:
                commands = False  # a group no test runs
            how = None
            if doc in a.run and (re.match(r"file=\S+$", rest) or commands):
                how = "run"
            elif doc in a.examples and not re.match(r"file=", rest) and "fragment" not in rest.split() and (
                    lang in ("coral", "prolog") or (lang == "toml" and any(re.match(r"^seed\s*=", b) for b in body))):
                how = "checked"
            elif start in protocol:
                how = "checked"
            elif doc == "README.md" and tour is not None and start > tour and lang == "sh" and not tour_done:
                tour_done = True
                how = "checked"
            elif doc == "docs/sonar.md" and lang == "json":
                how = "checked"
            elif doc in a.build_lines and lang == "sh" and not rest and not commands:
                how = "checked"
            elif re.match(r"from=\S+$", rest):
                how = "checked"
                piece = rest[len("from="):]
                try:
                    with open(os.path.join(src, piece), encoding="utf-8") as f:
                        whole = f.read().split("\n")
                except OSError as e:
                    failures.append(f"{doc}:{start}: from={piece}: {e}")
                    continue
                n = len(body)
                if not any(whole[i:i + n] == body for i in range(len(whole) - n + 1)):
                    failures.append(f"{doc}:{start}: the block is not in {piece} as written")
            first = first_line(body)
            key = next((k for k in ALLOW if k[0] == doc and first.startswith(k[1])), (doc, first))
            if how:
                counts[how] += 1
                if key in ALLOW:
                    failures.append(f"{doc}:{start}: run or checked, yet in ALLOW: take it out")
                continue
            if key in ALLOW:
                used.add(key)
                counts["allowed"] += 1
                continue
            failures.append(f"{doc}:{start}: a ```{lang} block that no test runs or checks ({key[1][:60]!r}): "
                            "make it run (a `$ ` block of a document doc_run.py runs, a file= block, ...), "
                            "or add it to ALLOW in tests/doc_blocks.py with the reason it cannot")
    for key in sorted(set(ALLOW) - used):
        failures.append(f"{key[0]}: ALLOW names a block that is not there any longer: {key[1][:70]!r}")
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{len(docs) - len(a.skip)} documents: {counts['run']} blocks run, {counts['checked']} checked, "
          f"{counts['allowed']} shown and not run (ALLOW), {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
