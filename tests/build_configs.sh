#!/usr/bin/env bash
# Builds the documented build configurations, each from a fresh clone of the committed tree, and
# counts the compiler's and linker's warnings (docs/building.md: every one must build warning-free).
#   bash tests/build_configs.sh                 every configuration below
#   bash tests/build_configs.sh debug clang     only those
# Configurations: default (Release, PGO + LTO), pgo-off, lto-off, native, debug (GCC) and clang
# (CXX=clang++, Release: LTO where clang's linker plugin is there, never PGO).
# Warnings are counted with RAYFARM_WERROR=OFF, so one configuration's warnings do not hide the
# next; the script fails (exit 1) when any configuration fails to build or warns. Environment:
#   RAYFARM_CONFIGS_DIR   where the clones and builds go (default: build-configs/ in the tree;
#                         each configuration's log: DIR/NAME.log)
#   RAYFARM_CONFIGS_JOBS  parallel jobs (default: nproc)
#   CMAKE_CXX_COMPILER_LAUNCHER  e.g. ccache, passed on (leave it unset for build times)
#   RAYFARM_CONFIGS_SCOPE all (default): everything the configuration builds by default, the
#                         test suites and benchmarks too; product: what a user's build installs
#                         (rayfarm, its viewer and libraries: -DRAYFARM_BUILD_TESTS=OFF
#                         -DRAYFARM_BUILD_BENCH=OFF), as CI builds the configurations besides the
#                         default one, whose full build tests/run.sh already makes
set -uo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
dir=${RAYFARM_CONFIGS_DIR:-$src/build-configs}
jobs=${RAYFARM_CONFIGS_JOBS:-$(nproc 2>/dev/null || echo 2)}
all=(default pgo-off lto-off native debug clang)
configs=("$@")
[ ${#configs[@]} -gt 0 ] || configs=("${all[@]}")

args_for() {
    case "$1" in
    default) echo "-DCMAKE_BUILD_TYPE=Release" ;;
    pgo-off) echo "-DCMAKE_BUILD_TYPE=Release -DRAYFARM_PGO=OFF" ;;
    lto-off) echo "-DCMAKE_BUILD_TYPE=Release -DRAYFARM_LTO=OFF" ;;
    native) echo "-DCMAKE_BUILD_TYPE=Release -DRAYFARM_NATIVE=ON" ;;
    debug) echo "-DCMAKE_BUILD_TYPE=Debug" ;;
    clang) echo "-DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++" ;;
    *) return 1 ;;
    esac
}

for c in "${configs[@]}"; do
    args_for "$c" >/dev/null || { echo "build_configs: unknown configuration $c (expected: ${all[*]})" >&2; exit 2; }
done
if [ "${configs[*]}" != "${configs[*]/clang/}" ] && ! command -v clang++ >/dev/null; then
    echo "build_configs: clang++ is not installed (tests/install-deps.sh installs it)" >&2
    exit 2
fi

mkdir -p "$dir"
clone=$dir/src
rm -rf "$clone"
git clone -q --no-hardlinks "$src" "$clone" || { echo "build_configs: cannot clone $src" >&2; exit 2; }
scope=()
case "${RAYFARM_CONFIGS_SCOPE:-all}" in
all) ;;
product) scope=(-DRAYFARM_BUILD_TESTS=OFF -DRAYFARM_BUILD_BENCH=OFF) ;;
*) echo "build_configs: RAYFARM_CONFIGS_SCOPE is all or product, not $RAYFARM_CONFIGS_SCOPE" >&2; exit 2 ;;
esac
launcher=()
[ -n "${CMAKE_CXX_COMPILER_LAUNCHER:-}" ] && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER="$CMAKE_CXX_COMPILER_LAUNCHER")

failed=0
printf '%-8s %8s %8s %s\n' config seconds warnings "result (scope: ${RAYFARM_CONFIGS_SCOPE:-all})"
for c in "${configs[@]}"; do
    b=$dir/build-$c log=$dir/$c.log
    rm -rf "$b"
    start=$(date +%s)
    # shellcheck disable=SC2046
    { cmake -S "$clone" -B "$b" $(args_for "$c") -DRAYFARM_WERROR=OFF "${scope[@]}" "${launcher[@]}" &&
      cmake --build "$b" -j"$jobs"; } >"$log" 2>&1
    status=$?
    secs=$(($(date +%s) - start))
    # GCC and clang both write "FILE:LINE:COL: warning: ..."; the linker (LTO) "lto-wrapper: warning:"
    # or "warning: ..." after a "In function" line. Every line that says warning counts.
    warnings=$(grep -cE '(^|[: ])warning: ' "$log")
    result=ok
    if [ "$status" -ne 0 ]; then result="FAILED (see $log)"; failed=1
    elif [ "$warnings" -ne 0 ]; then result="warnings (see $log)"; failed=1; fi
    printf '%-8s %8d %8d %s\n' "$c" "$secs" "$warnings" "$result"
done
exit "$failed"
