#!/usr/bin/env bash
# Error against run time for scenes/pbr_grid/ scored against Blender Cycles (512 samples, the
# lights plus the studio environment), as committed in examples/report-pbr_grid/.
#   bash examples/report_pbr_grid.sh [OUT_DIR]      (default: examples/report-pbr_grid)
# At 640x360 the sweep (14 renders, the slowest 64 spp) takes a minute or two on two cores.
# default.png is left out of the committed folder to keep it small: it is
#   rayfarm still scenes/pbr_grid/pbr_grid.gltf --camera 0 --exposure 0 --tonemap clamp \
#       --environment scenes/environments/studio.exr
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-examples/report-pbr_grid}
bin=${RAYFARM_BIN:-build/bin/rayfarm}

if [ ! -x "$bin" ]; then
  bash tests/install-deps.sh
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
  cmake --build build -j"$(nproc 2>/dev/null || echo 2)" --target rayfarm
fi

"$bin" report scenes/pbr_grid/pbr_grid.gltf --reference scenes/pbr_grid/reference/cycles_lights_studio.png \
  --camera 0 --exposure 0 --tonemap clamp --environment scenes/environments/studio.exr \
  --no-video --out "$out"
rm -f "$out/default.png"
# The gnuplot script names the PNG by the path it was run with; keep it relocatable.
sed -i "s|set output \".*/\([^/]*\.png\)\"|set output \"\1\"|" "$out"/*.gp
echo "report_pbr_grid: wrote $out/summary.md, report.csv, error_vs_time.png, error_default.png"
