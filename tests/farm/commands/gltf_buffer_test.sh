#!/usr/bin/env bash
# Issue 46 #7: a glTF buffer that is there but is no regular file (a FIFO, a folder) is named as
# what it is, by still and render: exit 2, one line "rayfarm: error: FILE: not a regular file but
# a FIFO (named by MODEL)", never blocking on the FIFO; one that is really missing is still
# "cannot find" it.
# Usage: gltf_buffer_test.sh RAYFARM WORK_DIR
set -euo pipefail
RAYFARM=$1 WORK=$2
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"
cp "$BOX"/* .
rm BoxTextured0.bin

. "$(dirname "$0")/../../lib/refusal.sh"  # fail, expect_refusal
export REFUSAL_TIMEOUT=20
still=("$RAYFARM" still BoxTextured.gltf --size 32x24 -o box.png)
render=("$RAYFARM" render BoxTextured.gltf --size 32x24 --frames 0:1 -o box.mp4)

mkfifo BoxTextured0.bin
expect_refusal --exact "BoxTextured0.bin: not a regular file but a FIFO (named by BoxTextured.gltf)" "${still[@]}"
expect_refusal --exact "BoxTextured0.bin: not a regular file but a FIFO (named by BoxTextured.gltf)" "${render[@]}"
rm BoxTextured0.bin
mkdir BoxTextured0.bin
expect_refusal --exact "BoxTextured0.bin: not a regular file but a directory (named by BoxTextured.gltf)" "${still[@]}"
rmdir BoxTextured0.bin
expect_refusal --exact "BoxTextured.gltf: cannot find \"BoxTextured0.bin\" in the model's folder" "${still[@]}"
[ ! -e box.png ] && [ ! -e box.mp4 ] || fail "an output was written"
echo "a FIFO or a folder as a glTF buffer is named as one, exit 2; a missing one is missing"
