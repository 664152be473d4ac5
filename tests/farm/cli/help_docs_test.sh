#!/usr/bin/env bash
# `rayfarm COMMAND --help` is the short form of docs/cli.md: every option a command's --help
# names must be in docs/cli.md, so the two cannot drift apart unnoticed.
#   help_docs_test.sh RAYFARM SOURCE_DIR
set -u
rayfarm=$1 src=$2
doc=$src/docs/cli.md
[ -s "$doc" ] || { echo "FAIL: $doc is missing"; exit 1; }
missing=0 total=0
for cmd in render still view report info; do
    help=$(QT_QPA_PLATFORM=offscreen "$rayfarm" "$cmd" --help 2>&1) || { echo "FAIL: rayfarm $cmd --help exited $?"; exit 1; }
    opts=$(grep -oE '(^|[^A-Za-z0-9-])--[a-z][a-z0-9-]*' <<<"$help" | grep -oE -- '--[a-z][a-z0-9-]*' | sort -u)
    [ -n "$opts" ] || { echo "FAIL: rayfarm $cmd --help names no options"; exit 1; }
    for o in $opts; do
        total=$((total + 1))
        # as a whole word: --frames must not pass because --frames-dir is there
        if ! grep -qE -- "(^|[^A-Za-z0-9-])$o([^A-Za-z0-9-]|$)" "$doc"; then
            echo "FAIL: rayfarm $cmd --help names $o, docs/cli.md does not"
            missing=$((missing + 1))
        fi
    done
done
[ "$missing" -eq 0 ] || exit 1
echo "help_docs: $total options of 5 commands, all in docs/cli.md"
