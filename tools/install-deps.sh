#!/usr/bin/env bash
# Installs the Debian packages rayfarm needs to build and run (and the quickstart's demo model),
# if any are missing; nothing the tests alone need (tests/install-deps.sh adds those). Idempotent;
# uses apt-get as root, sudo otherwise. Extra package names may be passed.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev   # engine/
  libopenexr-dev                                              # engine/: .exr environments (DWAB); farm/: half-float EXR frames
  libpng-dev                                                  # engine/: glTF PNGs read row by row, downsampled on load (a huge declared size never costs its texels)
  libwebp-dev                                                 # engine/: EXT_texture_webp (and data:image/webp)
  libjpeg-dev                                                 # engine/: glTF JPEGs scaled in the DCT and read by scanline (a huge JPEG never costs its full texels)
  libdraco-dev                                                # engine/: KHR_draco_mesh_compression
  libmeshoptimizer-dev                                        # engine/: EXT_meshopt_compression decoders (and filters)
  libassimp-dev                                               # engine/: OBJ, STL, PLY, FBX, COLLADA and 3MF models through assimp (one library for six formats, already in Debian)
  libopenmpi-dev openmpi-bin                                  # farm/: MPI
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev # farm/: H.264 MP4 through FFmpeg
  libavfilter-dev                                             # farm/: GIF palette (palettegen/paletteuse)
  file                                                        # cpack -G DEB: CMake's Debian packager runs it before dpkg-shlibdeps (a fresh Debian lacks it)
  assimp-testmodels                                           # the quickstart's demo model (2CylinderEngine.glb); the tests' real glTF files
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
