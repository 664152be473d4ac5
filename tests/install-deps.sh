#!/usr/bin/env bash
# Installs the Debian packages rayfarm needs to build, test and run, if any are missing: what
# building and running need (tools/install-deps.sh, which the quickstart runs alone) and what
# the tests, benchmarks, the viewer and the packaging test need besides. Idempotent; uses
# apt-get as root, sudo otherwise. Extra package names may be passed.
set -euo pipefail
cd "$(dirname "$0")/.."

test_packages=(
  gltfpack                                                    # tests: meshopt and quantized copies of the project's models
  chromium                                                    # tests: the WebM-with-alpha page, headless
  libgtest-dev libbenchmark-dev                               # tests and benchmarks
  libembree-dev                                               # bench/embree_bench: equal-work traversal reference (never linked into rayfarm)
  ffmpeg                                                      # ffprobe, to check videos independently
  python3 procps                                              # farm MPI tests: stats JSON, pgrep for ranks
  gnuplot-nox                                                 # plots in rayfarm report
  clang                                                       # libFuzzer + ASan/UBSan harnesses (tests/fuzz); tests/build_configs.sh's clang build
  qt6-base-dev                                                # rayfarm view: the Qt 6 Widgets window
  xvfb xdotool imagemagick                                    # view tests: X server, real mouse/keys, window grabs
  iproute2                                                    # tests/multihost: namespaces, bridge, veth cables (ip)
  dpkg-dev                                                    # tests/packaging: dpkg-shlibdeps for cpack -G DEB
)
bash tools/install-deps.sh "${test_packages[@]}" "$@"
