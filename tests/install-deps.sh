#!/usr/bin/env bash
# Installs the Debian packages rayfarm needs to build, test and run, if any are missing.
# Idempotent; uses apt-get as root, sudo otherwise. Extra package names may be passed.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev   # engine/
  libopenexr-dev                                              # engine/: .exr environments (DWAB)
  libpng-dev                                                  # engine/: glTF PNGs read row by row, downsampled on load (a huge declared size never costs its texels)
  libwebp-dev                                                 # engine/: EXT_texture_webp (and data:image/webp); tests encode WebP with it (no cwebp)
  libjpeg-dev                                                 # engine/: glTF JPEGs scaled in the DCT and read by scanline (a huge JPEG never costs its full texels)
  libdraco-dev                                                # engine/: KHR_draco_mesh_compression
  libmeshoptimizer-dev                                        # engine/: EXT_meshopt_compression decoders (and filters)
  gltfpack                                                    # tests: meshopt and quantized copies of the project's models
  libopenmpi-dev openmpi-bin                                  # farm/: MPI
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev # farm/: H.264 MP4 through FFmpeg
  libavfilter-dev                                             # farm/: GIF palette (palettegen/paletteuse)
  libopenexr-dev                                              # farm/: half-float EXR frames
  chromium                                                    # tests: the WebM-with-alpha page, headless
  libgtest-dev libbenchmark-dev                               # tests and benchmarks
  libembree-dev                                               # bench/embree_bench: equal-work traversal reference (never linked into rayfarm)
  assimp-testmodels                                           # real glTF files the tests render
  ffmpeg                                                      # ffprobe, to check videos independently
  python3 procps                                              # farm MPI tests: stats JSON, pgrep for ranks
  gnuplot-nox                                                 # plots in rayfarm report
  clang                                                       # libFuzzer + ASan/UBSan harnesses (tests/fuzz)
  qt6-base-dev                                                # rayfarm view: the Qt 6 Widgets window
  xvfb xdotool imagemagick                                    # view tests: X server, real mouse/keys, window grabs
  iproute2                                                    # tests/multihost: namespaces, bridge, veth cables (ip)
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "rayfarm: installing missing packages: ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
