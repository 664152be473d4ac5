#!/usr/bin/env python3
"""Writes a large glTF mesh of positions and indices only: an N x N grid of vertices on a gentle
wave, 2 (N-1)^2 triangles (N = 1601: 5.12 M triangles in a 92 MB .bin, the size issue 44
measures large-model loading on). For timing `rayfarm still` and `rayfarm info` on big inputs.

    make_grid_mesh.py OUT.gltf [N]      (the buffer is OUT's name with .bin, beside it)
"""
import array
import json
import math
import os
import sys


def main():
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 1601
    pos = array.array('f')
    for j in range(n):
        for i in range(n):
            x, z = i / (n - 1) * 2 - 1, j / (n - 1) * 2 - 1
            pos.extend((x, 0.15 * math.sin(7 * x) * math.cos(5 * z), z))
    idx = array.array('I')
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            idx.extend((a, a + n, a + 1, a + 1, a + n, a + n + 1))
    pb, ib = pos.tobytes(), idx.tobytes()
    binname = os.path.splitext(os.path.basename(out))[0] + ".bin"
    with open(os.path.join(os.path.dirname(os.path.abspath(out)), binname), "wb") as f:
        f.write(pb)
        f.write(ib)
    lo = [min(pos[k::3]) for k in range(3)]
    hi = [max(pos[k::3]) for k in range(3)]
    doc = {"asset": {"version": "2.0", "generator": "rayfarm bench/make_grid_mesh.py"}, "scene": 0,
           "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
           "buffers": [{"byteLength": len(pb) + len(ib), "uri": binname}],
           "bufferViews": [{"buffer": 0, "byteLength": len(pb)}, {"buffer": 0, "byteOffset": len(pb), "byteLength": len(ib)}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3", "min": lo, "max": hi},
                         {"bufferView": 1, "componentType": 5125, "count": len(idx), "type": "SCALAR"}]}
    with open(out, "w") as f:
        json.dump(doc, f)
    print(len(idx) // 3, "triangles")


if __name__ == "__main__":
    main()
