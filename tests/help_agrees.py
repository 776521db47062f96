#!/usr/bin/env python3
"""strata --help, each command's --help and the man pages say the same (issue 40).

The man pages are written from the CLI's own definition (`strata manpages`,
src/cli/cli_docs.h); this checks the result, not the intent:

  - the commands `strata --help` lists are the man pages strata-NAME.1 there
    are, and strata.1 gives each the same description;
  - each command's options (every spelling) and arguments, with their help
    text and default, are in its man page, and the man page has no option
    the command does not take;
  - the exit codes `--help` ends with are in the man page;
  - the same for the programs of their own beside strata (strata-pnml),
    each with its page PROGRAM.1.

  help_agrees.py STRATA MAN_DIR
"""
import gzip
import os
import re
import subprocess
import sys


def run(strata, *args):
    r = subprocess.run([strata, *args], capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        raise SystemExit(f"`strata {' '.join(args)}` exited {r.returncode}: {r.stderr}")
    return r.stdout


def man_text(man_dir, name):
    """The page as words: roff escapes and font changes undone, lines joined."""
    path = os.path.join(man_dir, name)
    if os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            roff = f.read()
    else:
        with gzip.open(path + ".gz", "rt", encoding="utf-8") as f:
            roff = f.read()
    lines = []
    for line in roff.split("\n"):
        if line.startswith('.\\"'):
            continue
        line = re.sub(r"^\.(TH|SH|SS|TP|PP|B|I|IP|RS|RE|nf|fi|br)\b ?", "", line)
        line = re.sub(r"\\f[BIRP]", "", line)
        line = line.replace("\\-", "-").replace("\\(aq", "'").replace("\\(dq", '"').replace("\\e", "\\")
        line = line.replace("\\&", "").replace("\\ ", " ")
        lines.append(line)
    return words(" ".join(lines))


def words(text):
    return re.sub(r"\s+", " ", text).strip()


def sections(help_text):
    """{'Options': [(spellings, text)], ...} from CLI11's help."""
    out, current, items = {}, None, []
    for line in help_text.split("\n"):
        m = re.match(r"^(Options|Positionals|Subcommands):$", line)
        if m:
            current = m.group(1)
            items = out.setdefault(current, [])
            continue
        if current is None:
            continue
        if not line.strip():
            continue
        if not line.startswith(" "):
            current = None  # the footer
            continue
        head = re.match(r"^  (\S.*?)(?:\s{2,}(.*))?$", line)
        if line.startswith("   ") and items:  # a wrapped description
            items[-1][1] += " " + line.strip()
        elif head:
            items.append([head.group(1), head.group(2) or ""])
    return out


def footer(help_text):
    """The text after the last section: the exit codes."""
    parts = re.split(r"\n\n+", help_text.strip())
    return words(parts[-1])


# Programs of their own installed beside strata, each with a page
# PROGRAM.1 written by `strata manpages` (cli/pnml_verify.h).
PROGRAMS = ["strata-pnml"]


def check_page(text, page, page_name, command, failures):
    """What `COMMAND --help` (text) says, the page says, and no more options."""
    secs = sections(text)
    for spellings, description in secs.get("Options", []) + secs.get("Positionals", []):
        opt = re.sub(r"\s+(TEXT|FLOAT|UINT|INT|ENUM|\[.*\]).*$", "", spellings)
        opt = re.sub(r"\s+Excludes:.*$", "", opt)
        for s in re.findall(r"--?[\w-]+|^\w+$", opt):
            if s not in page:
                failures.append(f"{page_name} lacks {s} (`{command} --help` has it)")
        d = words(re.sub(r"\s*Excludes: \S+", "", description))
        d = re.sub(r"^(TEXT|FLOAT|UINT|INT)(:.*?)?(=\S+)?\s+", "", d)
        if d and d not in page:
            failures.append(f"{page_name} does not say what `{command} --help` says of {opt}: {d}")
    taken = set(re.findall(r"(?<![\w-])--[\w][\w-]*", text))
    for s in sorted(set(re.findall(r"(?<![\w-])--[\w][\w-]*", page)) - taken):
        # Options named in prose of another command ("`strata run --vehicle`") are fine.
        if not re.search(rf"strata \w+ [^`]*{re.escape(s)}", page) and s not in text:
            failures.append(f"{page_name} names {s}, which `{command} --help` does not")
    if footer(text) not in page:
        failures.append(f"{page_name} lacks the exit codes of `{command} --help`: {footer(text)}")


def main():
    strata, man_dir = sys.argv[1], sys.argv[2]
    failures = []
    top = run(strata, "--help")
    commands = [(c.split()[0], words(d)) for c, d in sections(top)["Subcommands"]]
    pages = sorted(f[len("strata-"):].split(".")[0] for f in os.listdir(man_dir)
                   if f.startswith("strata-") and (f.endswith(".1") or f.endswith(".1.gz"))
                   and f.split(".")[0] not in PROGRAMS)
    if sorted(set(pages)) != sorted(c for c, _ in commands):
        failures.append(f"man pages {sorted(set(pages))} but `strata --help` lists {sorted(c for c, _ in commands)}")
    main_page = man_text(man_dir, "strata.1")
    for name, description in commands:
        if description not in main_page:
            failures.append(f"strata.1 does not give {name} the description `strata --help` does: {description}")
    if footer(top) not in main_page:
        failures.append(f"strata.1 lacks the exit codes of `strata --help`: {footer(top)}")
    for name, _ in commands:
        if name in pages:  # else said above
            check_page(run(strata, name, "--help"), man_text(man_dir, f"strata-{name}.1"), f"strata-{name}.1",
                       f"strata {name}", failures)
    # The programs of their own, beside strata, each with its page.
    for program in PROGRAMS:
        path = os.path.join(os.path.dirname(strata), program)
        if not any(f.startswith(program + ".1") for f in os.listdir(man_dir)):
            failures.append(f"no man page {program}.1")
            continue
        check_page(run(path, "--help"), man_text(man_dir, f"{program}.1"), f"{program}.1", program, failures)
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{len(commands)} commands: {len(failures)} disagreements")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
