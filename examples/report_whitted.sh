#!/usr/bin/env bash
# Error against run time for scenes/whitted.json, as committed in examples/report-whitted/.
#   bash examples/report_whitted.sh [OUT_DIR]      (default: examples/report-whitted)
# At 320x180 the whole run (a 256-sample reference, 14 quality renders, 21 encodes, and the
# stability table) takes a few minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-examples/report-whitted}
bin=${RAYFARM_BIN:-build/bin/rayfarm}

if [ ! -x "$bin" ]; then
  bash tests/install-deps.sh
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
  cmake --build build -j"$(nproc 2>/dev/null || echo 2)" --target rayfarm
fi

"$bin" report scenes/whitted.json --out "$out" --size 320x180 --target-psnr 30
"$bin" report --stability --out "$out"
# The gnuplot scripts name the PNG by the path they were run with; keep them relocatable.
sed -i "s|set output \".*/\([^/]*\.png\)\"|set output \"\1\"|" "$out"/*.gp
echo "report_whitted: wrote $out/summary.md, report.csv, error_vs_time.png, video.csv, stability.md"
