#!/usr/bin/env python3
"""`rayfarm COMMAND --help` and docs/cli.md stay in step, both ways (issue 47 #8):
- every option a command's --help names is in that command's section of docs/cli.md (its
  "## COMMAND" heading to the next "## "), so help cannot offer what the page does not explain;
- every option in the first column of that section's option tables is in the command's --help,
  so the page cannot document what the help leaves out (or an option that is gone);
- `rayfarm --help` names every command that has a section, and --version.
Shown able to fail first: the same checks over a copy of the page with an option taken out of a
table and one added to it must report both.
    help_docs_test.py RAYFARM DOCS_CLI_MD"""
import os
import re
import subprocess
import sys

COMMANDS = ["render", "still", "view", "report", "info"]
OPTION = re.compile(r"(?<![A-Za-z0-9-])--[a-z][a-z0-9-]*")


def sections(text):
    """{command: (whole section text, options in the first column of its tables)}."""
    out, name, lines = {}, None, []
    for line in text.split("\n") + ["## end"]:
        if line.startswith("## "):
            if name in COMMANDS:
                body = "\n".join(lines)
                table = set()
                for l in lines:
                    if l.startswith("| `"):
                        table |= set(OPTION.findall(l.split(" | ")[0]))
                out[name] = (body, table)
            name, lines = line[3:].strip(), []
        else:
            lines.append(line)
    return out


def helps(rayfarm):
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    out = {}
    for c in COMMANDS:
        r = subprocess.run([rayfarm, c, "--help"], capture_output=True, text=True, env=env, timeout=60)
        if r.returncode != 0:
            sys.exit("FAIL: rayfarm %s --help exited %d: %s" % (c, r.returncode, r.stderr.strip()))
        out[c] = set(OPTION.findall(r.stdout + r.stderr))
        if not out[c]:
            sys.exit("FAIL: rayfarm %s --help names no options" % c)
    top = subprocess.run([rayfarm, "--help"], capture_output=True, text=True, timeout=60)
    out[""] = top.stdout
    return out


def problems(doc_text, help_opts):
    errors = []
    secs = sections(doc_text)
    for c in COMMANDS:
        if c not in secs:
            errors.append("docs/cli.md has no \"## %s\" section" % c)
            continue
        body, table = secs[c]
        for o in sorted(help_opts[c]):
            if not re.search(r"(?<![A-Za-z0-9-])%s(?![A-Za-z0-9-])" % re.escape(o), body):
                errors.append("rayfarm %s --help names %s, docs/cli.md's %s section does not" % (c, o, c))
        for o in sorted(table - help_opts[c]):
            errors.append("docs/cli.md's %s table names %s, rayfarm %s --help does not" % (c, o, c))
        if not re.search(r"^  %s " % c, help_opts[""], re.M):
            errors.append("rayfarm --help does not list the %s command" % c)
    if "--version" not in help_opts[""]:
        errors.append("rayfarm --help does not mention --version")
    return errors


def main():
    rayfarm, doc = sys.argv[1], sys.argv[2]
    text = open(doc, encoding="utf-8").read()
    h = helps(rayfarm)
    # Able to fail: take --spp out of render's table rows and add a --frobnicate row.
    broken = re.sub(r"^\| `--spp N` \|.*$", "| `--frobnicate` | not an option |", text, count=1, flags=re.M)
    broken = re.sub(r"--spp", "--s-p-p", broken.split("## still")[0]) + "## still" + broken.split("## still", 1)[1]
    found = problems(broken, h)
    want = ["rayfarm render --help names --spp, docs/cli.md's render section does not",
            "docs/cli.md's render table names --frobnicate, rayfarm render --help does not"]
    for w in want:
        if w not in found:
            sys.exit("FAIL: the check missed \"%s\" on a broken page (found: %s)" % (w, found))
    errors = problems(text, h)
    for e in errors:
        print("FAIL: " + e)
    if errors:
        sys.exit(1)
    n = sum(len(h[c]) for c in COMMANDS)
    print("help_docs: %d options in the --help of 5 commands, each in its docs/cli.md section, and every "
          "documented option in its command's --help" % n)


main()
