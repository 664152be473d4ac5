#!/usr/bin/env python3
"""Writes scenes/iridescence_spheres.gltf: four spheres under a thin film
(KHR_materials_iridescence, factor 1, film index 2.0) of 100, 300, 400 and 600 nm over a dark
grey dielectric base (roughness 0.25), in a row before a camera. Blender 3.4 cannot export
KHR_materials_iridescence (its exporter writes none of it), so this script writes the file.
Every buffer is a data: URI, so the file travels alone.
    python3 tests/engine/materials/make_iridescence_spheres.py [OUT]
"""
import base64
import json
import math
import struct
import sys

out = sys.argv[1] if len(sys.argv) > 1 else "scenes/iridescence_spheres.gltf"
THICKNESSES = [100, 300, 400, 600]  # nm; at normal incidence gold, blue, magenta, green

# One unit UV sphere (smooth normals), shared by the four nodes' meshes.
RINGS, SEGS = 24, 48
pos, nrm, idx = [], [], []
for i in range(RINGS + 1):
    theta = math.pi * i / RINGS
    for j in range(SEGS + 1):
        phi = 2 * math.pi * j / SEGS
        n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
        pos += n
        nrm += n
for i in range(RINGS):
    for j in range(SEGS):
        a = i * (SEGS + 1) + j
        b = a + SEGS + 1
        if i > 0:  # the top ring's first triangle would be degenerate (two corners on the pole)
            idx += [a, b, a + 1]
        if i < RINGS - 1:  # the bottom ring's second likewise
            idx += [a + 1, b, b + 1]

blob = struct.pack("<%df" % len(pos), *pos) + struct.pack("<%df" % len(nrm), *nrm) + struct.pack("<%dH" % len(idx), *idx)
nv = len(pos) // 3
views = [
    {"buffer": 0, "byteOffset": 0, "byteLength": 12 * nv, "target": 34962},
    {"buffer": 0, "byteOffset": 12 * nv, "byteLength": 12 * nv, "target": 34962},
    {"buffer": 0, "byteOffset": 24 * nv, "byteLength": 2 * len(idx), "target": 34963},
]
accessors = [
    {"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3", "min": [-1, -1, -1], "max": [1, 1, 1]},
    {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
    {"bufferView": 2, "componentType": 5123, "count": len(idx), "type": "SCALAR"},
]
materials, meshes, nodes = [], [], []
for k, t in enumerate(THICKNESSES):
    materials.append({
        "name": "film_%dnm" % t,
        "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.05, 1], "metallicFactor": 0, "roughnessFactor": 0.25},
        "extensions": {"KHR_materials_iridescence": {
            "iridescenceFactor": 1, "iridescenceIor": 2.0,
            "iridescenceThicknessMinimum": 0, "iridescenceThicknessMaximum": t}},
    })
    meshes.append({"name": "sphere_%dnm" % t,
                   "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": k}]})
    nodes.append({"name": "sphere_%dnm" % t, "mesh": k, "translation": [2.25 * k - 3.375, 0, 0]})
nodes.append({"name": "camera", "camera": 0, "translation": [0, 0, 9]})
doc = {
    "asset": {"version": "2.0", "generator": "rayfarm tests/engine/materials/make_iridescence_spheres.py"},
    "extensionsUsed": ["KHR_materials_iridescence"],
    "scene": 0,
    "scenes": [{"nodes": list(range(len(nodes)))}],
    "nodes": nodes,
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.42, "aspectRatio": 8 / 3, "znear": 0.1}}],
    "materials": materials,
    "meshes": meshes,
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(blob),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}
with open(out, "w") as f:
    json.dump(doc, f, indent=1)
    f.write("\n")
