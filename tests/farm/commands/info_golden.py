#!/usr/bin/env python3
"""Compares `rayfarm info --json` output with a golden file written by hand: every key of the
golden must be in the output with an equal value (numbers within 1e-6 relative); keys starting
with '_' are comments; a golden object {"_count": N, "K": {...}} stands for a list of N items
whose item K is checked. Keys the golden leaves out are not checked.
    info_golden.py GOLDEN.json ACTUAL.json"""
import json
import math
import sys


def check(want, got, where, errors):
    if isinstance(want, dict) and "_count" in want:
        if not isinstance(got, list):
            errors.append("%s: expected a list, got %r" % (where, got))
            return
        if len(got) != want["_count"]:
            errors.append("%s: %d items, expected %d" % (where, len(got), want["_count"]))
        for k, v in want.items():
            if k.startswith("_"):
                continue
            i = int(k)
            if i >= len(got):
                errors.append("%s[%d]: missing" % (where, i))
            else:
                check(v, got[i], "%s[%d]" % (where, i), errors)
    elif isinstance(want, dict):
        if not isinstance(got, dict):
            errors.append("%s: expected an object, got %r" % (where, got))
            return
        for k, v in want.items():
            if k.startswith("_"):
                continue
            if k not in got:
                errors.append("%s.%s: missing" % (where, k))
            else:
                check(v, got[k], where + "." + k, errors)
    elif isinstance(want, list):
        if not isinstance(got, list) or len(got) != len(want):
            errors.append("%s: expected %d items, got %r" % (where, len(want), got))
            return
        for i, (a, b) in enumerate(zip(want, got)):
            check(a, b, "%s[%d]" % (where, i), errors)
    elif isinstance(want, bool) or want is None or isinstance(want, str):
        if got != want or type(got) is not type(want):
            errors.append("%s: %r, expected %r" % (where, got, want))
    elif isinstance(want, (int, float)):
        if isinstance(got, bool) or not isinstance(got, (int, float)) or \
                not math.isclose(got, want, rel_tol=1e-6, abs_tol=1e-9):
            errors.append("%s: %r, expected %r" % (where, got, want))
    else:
        errors.append("%s: cannot compare %r" % (where, want))


def main():
    want = json.load(open(sys.argv[1]))
    got = json.load(open(sys.argv[2]))
    errors = []
    check(want, got, "$", errors)
    for e in errors:
        print("  " + e)
    sys.exit(1 if errors else 0)


main()
