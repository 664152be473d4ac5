#!/usr/bin/env bash
# Installs what is missing, builds, and renders the default demo.
set -euo pipefail
cd "$(dirname "$0")/.."

bash tests/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs" --target rayfarm

mkdir -p out
build/bin/rayfarm still scenes/whitted.json -o out/whitted.png --stats out/whitted-stats.json
echo "quickstart: wrote out/whitted.png"
