#!/usr/bin/env bash
# Issue 47 #3, installable: `cmake --install BUILD --prefix P` puts bin/rayfarm, the man page
# made from --help and the docs under P; `cpack -G DEB` makes rayfarm_VERSION_ARCH.deb whose
# Depends are Debian runtime packages; as root, `apt-get install ./rayfarm_*.deb` puts rayfarm on
# PATH (/usr/bin), which renders a small scene alone and under `mpirun -np 2`; the package is
# removed again at the end (never one installed before the test: then it stops).
# Opt-in (a package build and an install as root): RAYFARM_PACKAGE=1, else skipped (77).
#   deb_test.sh RAYFARM SOURCE_DIR BUILD_DIR OUT_DIR
set -euo pipefail
rayfarm=$1 src=$2 build=$3 out=$4
# shellcheck source=tests/lib/refusal.sh
source "$src/tests/lib/refusal.sh"
if [ "${RAYFARM_PACKAGE:-0}" != 1 ]; then
    echo "skipped: RAYFARM_PACKAGE=1 builds the .deb and installs it (as root)"
    exit 77
fi
rm -rf "$out" && mkdir -p "$out"
version=$("$rayfarm" --version | awk '{print $2}')
scene=$src/scenes/whitted.json

# 1. cmake --install to a prefix.
cmake --install "$build" --prefix "$out/prefix" > "$out/install.log" || { cat "$out/install.log"; fail "cmake --install"; }
p=$out/prefix
for f in bin/rayfarm share/man/man1/rayfarm.1 share/doc/rayfarm/README.md share/doc/rayfarm/cli.md share/doc/rayfarm/farm.md; do
    [ -s "$p/$f" ] || fail "cmake --install did not put $f under the prefix"
done
[ "$("$p/bin/rayfarm" --version)" = "rayfarm $version" ] || fail "the installed rayfarm's --version"
# The man page is --help's text: every option of every command's --help is in it.
for c in render still view report info; do
    for o in $(QT_QPA_PLATFORM=offscreen "$rayfarm" "$c" --help | grep -oE -- '--[a-z][a-z0-9-]*' | sort -u); do
        grep -qF -- "$o" "$p/share/man/man1/rayfarm.1" || fail "rayfarm.1 lacks $o of rayfarm $c --help"
    done
    grep -q "^.SH \"RAYFARM ${c^^}\"" "$p/share/man/man1/rayfarm.1" || fail "rayfarm.1 has no section for $c"
done
if command -v man >/dev/null; then
    man -l "$p/share/man/man1/rayfarm.1" 2>/dev/null | grep -q "RAYFARM RENDER" || fail "man -l cannot read rayfarm.1"
fi
echo "ok: cmake --install to a prefix, man page from --help"

# 2. cpack -G DEB: Debian runtime packages as dependencies.
(cd "$build" && cpack -G DEB -B "$out/pkg") > "$out/cpack.log" 2>&1 || { cat "$out/cpack.log"; fail "cpack -G DEB"; }
deb=$(ls "$out"/pkg/rayfarm_"$version"_*.deb)
depends=$(dpkg-deb -f "$deb" Depends)
for want in openmpi-bin libopenmpi libavcodec libavformat libavfilter libassimp libc6 libstdc++6; do
    grep -q "$want" <<<"$depends" || fail "$deb: Depends lacks $want: $depends"
done
dpkg-deb -c "$deb" > "$out/contents.txt"; grep -q ' ./usr/bin/rayfarm$' "$out/contents.txt" || fail "$deb holds no /usr/bin/rayfarm"
echo "ok: $(basename "$deb"): Depends: $depends"

# 3. apt install as root, rayfarm from PATH, alone and under mpirun; removed afterwards.
if [ "$(id -u)" != 0 ] || ! command -v apt-get >/dev/null; then
    echo "ok (install not tried: needs root and apt-get)"
    exit 0
fi
if dpkg -s rayfarm >/dev/null 2>&1; then fail "a rayfarm package is installed already; this test does not touch it"; fi
cleanup() { DEBIAN_FRONTEND=noninteractive apt-get remove -y -q rayfarm > "$out/remove.log" 2>&1 || true; }
trap cleanup EXIT
DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "$deb" > "$out/apt.log" 2>&1 ||
    { cat "$out/apt.log"; fail "apt-get install $deb"; }
[ "$(env -i PATH=/usr/local/bin:/usr/bin:/bin bash -c 'command -v rayfarm')" = /usr/bin/rayfarm ] || fail "rayfarm is not /usr/bin/rayfarm on PATH"
mkdir -p "$out/run" && cd "$out/run"
env -i PATH=/usr/bin:/bin HOME="$out/run" rayfarm render "$scene" -o solo.mp4 --size 64x36 --frames 0:5 2> solo.log ||
    { cat solo.log; fail "rayfarm render from PATH"; }
env -i PATH=/usr/bin:/bin HOME="$out/run" OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 HWLOC_COMPONENTS=-gl \
    mpirun --oversubscribe -np 2 rayfarm render "$scene" -o farm.mp4 --size 64x36 --frames 0:5 --mode frame 2> farm.log ||
    { cat farm.log; fail "mpirun -np 2 rayfarm render from PATH"; }
grep -q "2 ranks" farm.log || fail "mpirun -np 2 did not give 2 ranks: $(cat farm.log)"
for f in solo.mp4 farm.mp4; do [ -s "$f" ] || fail "$f was not written"; done
# The kept frames are in OUTPUT.frames (docs/cli.md, --frames-dir).
for f in solo.mp4.frames/frame_000003.png farm.mp4.frames/frame_000003.png; do [ -s "$f" ] || fail "$f was not written"; done
cmp -s solo.mp4.frames/frame_000003.png farm.mp4.frames/frame_000003.png || fail "frame 3 differs between one process and mpirun -np 2"
# A format read through libassimp (issue 48), from the installed package.
obj=/usr/share/assimp/models/OBJ/spider.obj
if [ -s "$obj" ]; then
    env -i PATH=/usr/bin:/bin HOME="$out/run" rayfarm still "$obj" -o obj.png --size 64x36 2> obj.log ||
        { cat obj.log; fail "rayfarm still $obj from PATH"; }
    [ -s obj.png ] || fail "obj.png was not written"
fi
man -w rayfarm >/dev/null 2>&1 || [ -s /usr/share/man/man1/rayfarm.1.gz ] || [ -s /usr/share/man/man1/rayfarm.1 ] || fail "no man page installed"
cleanup
trap - EXIT
dpkg -s rayfarm >/dev/null 2>&1 && fail "apt-get remove left rayfarm installed"
[ ! -e /usr/bin/rayfarm ] || fail "/usr/bin/rayfarm is still there after the package's removal"
echo "ok: apt-get install ./$(basename "$deb"), rayfarm render from PATH alone and under mpirun -np 2, removed again"
