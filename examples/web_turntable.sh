#!/usr/bin/env bash
# A turntable for a product page: a WebM with alpha (VP9, yuva420p) playing over the page's own
# colour, its poster image, and a contact sheet. Writes examples/turntable_page.html and its media
# in examples/turntable_page/ (OUT_DIR=... writes both there instead).
#   bash examples/web_turntable.sh [MODEL] [RANKS]
# SIZE (320x240), FRAMES (all: the default 120-frame turntable), SPP (4), PAGE_COLOUR (#2a9d8f).
set -euo pipefail
cd "$(dirname "$0")/.."
model=${1:-/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf}
ranks=${2:-0}
out=${OUT_DIR:-examples}
size=${SIZE:-320x240} spp=${SPP:-4} colour=${PAGE_COLOUR:-#2a9d8f}
source examples/common.sh
media="$out/turntable_page"
mkdir -p "$media"
args=(render "$model" -o "$media/turntable.webm" --size "$size" --spp "$spp" --background transparent
      --poster "$media/poster.png" --contact-sheet "$media/sheet.png" --frames-dir "$media/frames" --overwrite)
[ -n "${FRAMES:-}" ] && args+=(--frames "$FRAMES")
if [ "$ranks" -gt 0 ]; then
  mpirun --oversubscribe -np "$ranks" "$bin" "${args[@]}"
else
  "$bin" "${args[@]}"
fi
w=${size%x*} h=${size#*x}
# ?still: no autoplay and no poster, the first frame shown as decoded (what the page test checks).
cat > "$out/turntable_page.html" <<HTML
<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>rayfarm turntable over the page</title>
<style>
  html, body { margin: 0; background: $colour; }
  video { display: block; width: ${w}px; height: ${h}px; }
</style>
</head>
<body>
<video id="turntable" src="turntable_page/turntable.webm" poster="turntable_page/poster.png"
       width="$w" height="$h" autoplay loop muted playsinline></video>
<script>
  if (location.search.includes("still")) {
    const v = document.getElementById("turntable");
    v.removeAttribute("poster");
    v.removeAttribute("autoplay");
    v.preload = "auto";
  }
</script>
</body>
</html>
HTML
echo "web_turntable: wrote $out/turntable_page.html ($media/turntable.webm with alpha, poster.png, sheet.png)"
