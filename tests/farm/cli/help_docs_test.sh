#!/usr/bin/env bash
# `rayfarm COMMAND --help` and docs/cli.md stay in step, both ways: help_docs_test.py.
#   help_docs_test.sh RAYFARM SOURCE_DIR
set -u
exec python3 "$2/tests/farm/cli/help_docs_test.py" "$1" "$2/docs/cli.md"
