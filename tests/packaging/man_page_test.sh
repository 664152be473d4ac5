#!/usr/bin/env bash
# The man page builds whether or not this rayfarm has the viewer: cmake/make_man.cmake with
# VIEW=0 (a build without Qt 6, as the quickstart's on a fresh machine: `rayfarm view --help` is
# an error there, and the build of the page failed with it) and with VIEW=1 when it has one.
#   man_page_test.sh RAYFARM SOURCE_DIR OUT_DIR
set -uo pipefail
rayfarm=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake -DRAYFARM="$rayfarm" -DVERSION=0.1 -DOUT="$out/noview.1" -DVIEW=0 -P "$src/cmake/make_man.cmake" ||
    fail "make_man with VIEW=0 failed"
page=$out/noview.1
grep -q '^.SH "RAYFARM VIEW"' "$page" || fail "no view section without the viewer"
sed -n '/^.SH "RAYFARM VIEW"/,/^.SH "RAYFARM REPORT"/p' "$page" | grep -q 'Not in this build: rayfarm was built without Qt 6' ||
    fail "the view section does not say the viewer is not in this build"
for cmd in RENDER STILL REPORT INFO; do
    grep -q "^.SH \"RAYFARM $cmd\"" "$page" || fail "no $cmd section"
done
grep -q -- '--camera' "$page" || fail "render's --help text missing from the page"

if QT_QPA_PLATFORM=offscreen "$rayfarm" view --help >/dev/null 2>&1; then
    cmake -DRAYFARM="$rayfarm" -DVERSION=0.1 -DOUT="$out/view.1" -DVIEW=1 -P "$src/cmake/make_man.cmake" ||
        fail "make_man with VIEW=1 failed"
    sed -n '/^.SH "RAYFARM VIEW"/,/^.SH "RAYFARM REPORT"/p' "$out/view.1" | grep -q -- '--watch' ||
        fail "the view section lacks view's --help text"
else
    cmake -DRAYFARM="$rayfarm" -DVERSION=0.1 -DOUT="$out/view.1" -DVIEW=1 -P "$src/cmake/make_man.cmake" 2>/dev/null &&
        fail "make_man with VIEW=1 succeeded though view --help fails"
fi
echo "man page: ok without the viewer and with it"
