#!/usr/bin/env bash
# Installs what is missing, builds, and renders the default demo.
set -euo pipefail
cd "$(dirname "$0")/.."

# Only what building and running need (tools/install-deps.sh); tests/run.sh installs the rest.
bash tools/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
# The tests and benchmarks are not built here (they need GoogleTest and Google Benchmark);
# tests/run.sh configures the same build folder with them. The viewer is built when Qt 6 is
# installed (qt6-base-dev; tests/install-deps.sh installs it).
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRAYFARM_BUILD_TESTS=OFF
cmake --build build -j"$jobs" --target rayfarm

mkdir -p out
build/bin/rayfarm still scenes/whitted.json -o out/whitted.png --stats out/whitted-stats.json
echo "quickstart: wrote out/whitted.png"

# The default turntable of a real glTF model, to an MP4 any player plays (120 frames, 640x360;
# one process on all cores; under mpirun the same command becomes a render farm).
build/bin/rayfarm render /usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb \
  -o out/engine_turntable.mp4 --size 640x360 --no-frames --stats out/engine_turntable-stats.json
echo "quickstart: wrote out/engine_turntable.mp4"
