#!/usr/bin/env python3
"""Writes scenes/animated_pointers.gltf: a light, camera and material timeline through
KHR_animation_pointer (issue 42), which Blender 3.4 cannot export (Blender 4 writes such files).

A floor, a box and a small marker cube; a spot light above them and a camera. One animation,
"Show", 2 s: the spot's intensity 40 -> 160 cd and colour white -> orange, its outer cone
0.5 -> 0.2 -> 0.9 rad (narrower than the 0.3 inner cone for a while, which the outer one then
follows); the camera's yfov 0.9 -> 0.6 rad; the box's base colour red -> blue and
its emissive strength 0 -> 3 (emissive factor 0.2); the marker hidden (KHR_node_visibility) from
1 s on. Every buffer is a data: URI, so the file travels alone.
    python3 tests/anim/make_animated_pointers.py [OUT]
"""
import base64
import json
import math
import struct
import sys

out = sys.argv[1] if len(sys.argv) > 1 else "scenes/animated_pointers.gltf"
blob = bytearray()
views, accessors = [], []


def add(fmt, values, type_, component=5126, count=None, minmax=False, target=None):
    """Appends packed values as a bufferView + accessor; returns the accessor index."""
    while len(blob) % 4:
        blob.append(0)
    start = len(blob)
    blob.extend(struct.pack("<" + fmt * len(values), *values))
    view = {"buffer": 0, "byteOffset": start, "byteLength": len(blob) - start}
    if target:
        view["target"] = target
    views.append(view)
    n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[type_]
    acc = {"bufferView": len(views) - 1, "componentType": component, "count": count or len(values) // n, "type": type_}
    if minmax:
        acc["min"] = [min(values[i::n]) for i in range(n)]
        acc["max"] = [max(values[i::n]) for i in range(n)]
    accessors.append(acc)
    return len(accessors) - 1


def box(hx, hy, hz):
    """Positions, normals, indices of an axis-aligned box centred on the origin (24 vertices)."""
    pos, nrm, idx = [], [], []
    for axis in range(3):
        for sign in (1, -1):
            n = [0, 0, 0]
            n[axis] = sign
            u, v = [(1, 2), (0, 2), (0, 1)][axis]
            base = len(pos) // 3
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0, 0, 0]
                p[axis] = sign
                p[u], p[v] = a, b
                pos += [p[0] * hx, p[1] * hy, p[2] * hz]
                nrm += n
            quad = [base, base + 1, base + 2, base, base + 2, base + 3]
            # Counter-clockwise seen from outside: flip where u x v points inwards.
            cross = [0, 0, 0]
            cross[3 - u - v] = 1 if (u, v) != (0, 2) else -1
            if cross[axis] * sign < 0:
                quad = [base, base + 2, base + 1, base, base + 3, base + 2]
            idx += quad
    return pos, nrm, idx


def mesh(pos, nrm, idx, material):
    p = add("f", pos, "VEC3", minmax=True, target=34962)
    n = add("f", nrm, "VEC3", target=34962)
    i = add("H", idx, "SCALAR", component=5123, target=34963)
    return {"primitives": [{"attributes": {"POSITION": p, "NORMAL": n}, "indices": i, "material": material}]}


floor = ([-3, 0, -3, 3, 0, -3, 3, 0, 3, -3, 0, 3], [0, 1, 0] * 4, [0, 2, 1, 0, 3, 2])
meshes = [mesh(*floor, 0), mesh(*box(0.5, 0.5, 0.5), 1), mesh(*box(0.25, 0.25, 0.25), 2)]

two = add("f", [0.0, 2.0], "SCALAR", minmax=True)
three = add("f", [0.0, 1.0, 2.0], "SCALAR", minmax=True)
steps = add("f", [0.0, 1.0], "SCALAR", minmax=True)
samplers = [
    {"input": two, "output": add("f", [40.0, 160.0], "SCALAR")},                         # 0 intensity
    {"input": two, "output": add("f", [1, 1, 1, 1, 0.5, 0.1], "VEC3")},                  # 1 colour
    {"input": three, "output": add("f", [0.5, 0.2, 0.9], "SCALAR")},                    # 2 outer cone
    {"input": two, "output": add("f", [0.9, 0.6], "SCALAR")},                            # 3 yfov
    {"input": two, "output": add("f", [0.8, 0.1, 0.1, 1, 0.1, 0.2, 0.8, 1], "VEC4")},    # 4 base colour
    {"input": two, "output": add("f", [0.0, 3.0], "SCALAR")},                            # 5 emissive strength
    {"input": steps, "output": add("B", [1, 0], "SCALAR", component=5121), "interpolation": "STEP"},  # 6 visible
]
pointers = [
    "/extensions/KHR_lights_punctual/lights/0/intensity",
    "/extensions/KHR_lights_punctual/lights/0/color",
    "/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle",
    "/cameras/0/perspective/yfov",
    "/materials/1/pbrMetallicRoughness/baseColorFactor",
    "/materials/1/extensions/KHR_materials_emissive_strength/emissiveStrength",
    "/nodes/4/extensions/KHR_node_visibility/visible",
]
channels = [{"sampler": i, "target": {"path": "pointer", "extensions": {"KHR_animation_pointer": {"pointer": p}}}}
            for i, p in enumerate(pointers)]


def x_rotation(degrees):
    h = math.radians(degrees) / 2
    return [math.sin(h), 0.0, 0.0, math.cos(h)]


gltf = {
    "asset": {"version": "2.0", "generator": "rayfarm tests/anim/make_animated_pointers.py"},
    "extensionsUsed": ["KHR_animation_pointer", "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_node_visibility"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"name": "Spot", "type": "spot", "color": [1, 1, 1], "intensity": 40.0,
         "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.5}}]}},
    "scene": 0,
    "scenes": [{"name": "Stage", "nodes": [0, 1, 2, 3, 4]}],
    "nodes": [
        {"name": "Floor", "mesh": 0},
        {"name": "Box", "mesh": 1, "translation": [0, 0.5, 0]},
        {"name": "Lamp", "translation": [0, 3, 0], "rotation": x_rotation(-90),
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "Eye", "camera": 0, "translation": [0, 2, 6], "rotation": x_rotation(-math.degrees(math.atan2(2, 6)))},
        {"name": "Marker", "mesh": 2, "translation": [1.3, 0.25, 1.0],
         "extensions": {"KHR_node_visibility": {"visible": True}}},
    ],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05, "aspectRatio": 16 / 9}}],
    "materials": [
        {"name": "Floor", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 0.9}},
        {"name": "Box", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1], "metallicFactor": 0, "roughnessFactor": 0.5},
         "emissiveFactor": [0.2, 0.2, 0.2], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 0.0}}},
        {"name": "Marker", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.7, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 0.6}},
    ],
    "meshes": meshes,
    "animations": [{"name": "Show", "samplers": samplers, "channels": channels}],
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
}
with open(out, "w") as f:
    json.dump(gltf, f, indent=1)
    f.write("\n")
print(out)
