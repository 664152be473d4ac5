#!/usr/bin/env bash
# Benchmark (not a test): texture bombs (issue 29). A 261 KB PNG that declares 16384x16384 and a
# 1.5 MB JPEG of 16000x16000 on BoxTextured, each as a whole `rayfarm still MODEL --size 64x48
# --spp 1` process at --exposure auto (the glTF default) and 0. Prints peak RSS (/usr/bin/time's
# maximum resident set), wall and CPU seconds per run; with two binaries, in turns.
#   bash bench/bench_textures.sh RAYFARM [OTHER_RAYFARM]      (ROUNDS=n, default 2)
# Target: under 2 GB and a few seconds per rank. Needs ffmpeg (to write the JPEG) and /usr/bin/time.
set -euo pipefail
bins=("$@")
[ ${#bins[@]} -ge 1 ] || { echo "usage: bench_textures.sh RAYFARM [OTHER_RAYFARM]" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
cp /usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured0.bin .
python3 - <<'PY'
import json, struct, zlib
side = 16384
def chunk(kind, data):
    return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
z = zlib.compressobj(9)
idat = b''.join(z.compress(bytes(1 + side)) for _ in range(side)) + z.flush()
open('bomb.png', 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', side, side, 8, 0, 0, 0, 0)) +
                            chunk(b'IDAT', idat) + chunk(b'IEND', b''))
g = json.load(open('/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf'))
for name, uri in (('png.gltf', 'bomb.png'), ('jpeg.gltf', 'bomb.jpg')):
    g['images'] = [{'uri': uri}]
    json.dump(g, open(name, 'w'))
PY
# FFmpeg's images stop short of 16384² (width·height under INT_MAX/8): 16000² it is.
ffmpeg -v error -f lavfi -i "color=c=0x808080:s=8000x8000" -frames:v 1 -vf scale=16000:16000 -q:v 5 -pix_fmt yuvj420p bomb.jpg
echo "load: $(uptime)"
for round in $(seq "${ROUNDS:-2}"); do
  for model in png.gltf jpeg.gltf; do
    for exposure in auto 0; do
      for bin in "${bins[@]}"; do
        /usr/bin/time -f '%M %e %U %S' -o t.txt "$bin" still "$model" -o out.png --size 64x48 --spp 1 --exposure "$exposure" \
            2>err.txt >/dev/null || { echo "FAILED: $bin $model: $(tail -1 err.txt)"; continue; }
        read -r kb wall user sys <t.txt
        printf '%s round %d %-9s exposure %-4s peak %5d MB  wall %6.2f s  cpu %6.2f s  %s\n' "$bin" "$round" "$model" "$exposure" \
            $((kb / 1024)) "$wall" "$(echo "$user + $sys" | bc)" "$(grep -o 'downsampled to [0-9x]*' err.txt | head -1)"
      done
    done
  done
done
echo "load: $(uptime)"
