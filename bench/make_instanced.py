#!/usr/bin/env python3
"""Writes a glTF file of N small meshes scattered on a square: as EXT_mesh_gpu_instancing
instances of one mesh (the default), or with --flatten the same triangles written out into one
mesh (what the instances amount to). For bench/bench_instancing.sh.

    make_instanced.py N OUT.gltf [--flatten] [--seed S]

The mesh is an octahedron-topped box (20 triangles); each instance a random place on a
sqrt(N) x sqrt(N) grid, a random turn about y and a scale 0.3-0.45; the buffer is a .bin beside
the file.
"""
import json
import math
import os
import random
import struct
import sys


def mesh():
    # A box 1 x 0.6 x 1 with a pyramid roof: 10 vertices... kept simple: unshared corners per
    # triangle so that flat normals come from the vertices alone.
    b = [(-0.5, 0, -0.5), (0.5, 0, -0.5), (0.5, 0, 0.5), (-0.5, 0, 0.5),
         (-0.5, 0.6, -0.5), (0.5, 0.6, -0.5), (0.5, 0.6, 0.5), (-0.5, 0.6, 0.5), (0, 1.1, 0)]
    tris = [(0, 1, 2), (0, 2, 3),  # bottom (facing down)
            (0, 4, 5), (0, 5, 1), (1, 5, 6), (1, 6, 2), (2, 6, 7), (2, 7, 3), (3, 7, 4), (3, 4, 0),
            (4, 8, 5), (5, 8, 6), (6, 8, 7), (7, 8, 4)]
    return b, tris


def main():
    args = sys.argv[1:]
    flatten = "--flatten" in args
    seed = 1
    if "--seed" in args:
        seed = int(args[args.index("--seed") + 1])
    pos_args = [a for i, a in enumerate(args) if not a.startswith("--") and (i == 0 or args[i - 1] != "--seed")]
    n, out = int(pos_args[0]), pos_args[1]
    rnd = random.Random(seed)
    side = max(1, int(math.ceil(math.sqrt(n))))
    inst = []
    for i in range(n):
        x, z = (i % side) - side / 2 + rnd.uniform(-0.2, 0.2), (i // side) - side / 2 + rnd.uniform(-0.2, 0.2)
        a = rnd.uniform(0, 2 * math.pi)
        s = rnd.uniform(0.3, 0.45)
        inst.append(((x, 0.0, z), (0.0, math.sin(a / 2), 0.0, math.cos(a / 2)), (s, s, s)))
    corners, tris = mesh()
    blob = bytearray()
    views, accessors = [], []

    def add(data, count, typ, comp, target=None, minmax=None):
        while len(blob) % 4:
            blob.append(0)
        v = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)}
        if target:
            v["target"] = target
        views.append(v)
        blob.extend(data)
        a = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": typ}
        if minmax:
            a["min"], a["max"] = minmax
        accessors.append(a)
        return len(accessors) - 1

    def place(p, t, r, s):
        # q v q* for a turn about y, then scale, then translate.
        x, y, z = p[0] * s[0], p[1] * s[1], p[2] * s[2]
        ang = 2 * math.atan2(r[1], r[3])
        c, sn = math.cos(ang), math.sin(ang)
        return (c * x + sn * z + t[0], y + t[1], -sn * x + c * z + t[2])

    pos = []
    copies = inst if flatten else [((0, 0, 0), (0, 0, 0, 1), (1, 1, 1))]
    for t, r, s in copies:
        for tri in tris:
            for k in tri:
                pos.append(place(corners[k], t, r, s))
    lo = [min(p[c] for p in pos) for c in range(3)]
    hi = [max(p[c] for p in pos) for c in range(3)]
    pa = add(b"".join(struct.pack("<3f", *p) for p in pos), len(pos), "VEC3", 5126, 34962, (lo, hi))
    node = {"mesh": 0, "name": "scatter"}
    doc = {"asset": {"version": "2.0", "generator": "rayfarm bench/make_instanced.py"}, "scene": 0,
           "scenes": [{"nodes": [0]}], "nodes": [node],
           "meshes": [{"name": "hut", "primitives": [{"attributes": {"POSITION": pa}, "material": 0}]}],
           "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.3, 1], "roughnessFactor": 0.6, "metallicFactor": 0}}]}
    if not flatten:
        ta = add(b"".join(struct.pack("<3f", *t) for t, _, _ in inst), n, "VEC3", 5126)
        ra = add(b"".join(struct.pack("<4f", *r) for _, r, _ in inst), n, "VEC4", 5126)
        sa = add(b"".join(struct.pack("<3f", *s) for _, _, s in inst), n, "VEC3", 5126)
        node["extensions"] = {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": ta, "ROTATION": ra, "SCALE": sa}}}
        doc["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]
    binname = os.path.splitext(os.path.basename(out))[0] + ".bin"
    with open(os.path.join(os.path.dirname(os.path.abspath(out)), binname), "wb") as f:
        f.write(blob)
    doc["buffers"] = [{"byteLength": len(blob), "uri": binname}]
    doc["bufferViews"], doc["accessors"] = views, accessors
    with open(out, "w") as f:
        json.dump(doc, f)


if __name__ == "__main__":
    main()
