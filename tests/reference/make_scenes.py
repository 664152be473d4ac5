#!/usr/bin/env python3
# Writes the small glTF test scenes of tests/reference/ (CC0, made for rayfarm): their geometry is
# generated here (spheres, boxes, a floor) so that each material is exactly what it says, and
# cycles_reference.sh renders their references. Plain Python 3, no packages:
#   python3 tests/reference/make_scenes.py [SCENE ...]   (writes beside this script; all by default)
# - metals_glass.gltf: a copper box, a chrome, a glass and a blue plastic sphere on a checker floor
#   (baseColor texture through KHR_texture_transform), a sun; rendered under courtyard.exr.
# - textured_spot.gltf: a box with a baseColor texture and a normal map, a sphere with a
#   metallicRoughness texture, an emissive-textured sphere, a grey floor; a spot and a point
#   light, black world.
# - coat_sheen_volume.gltf: a red sphere under a clear coat (KHR_materials_clearcoat), a blue
#   velvet sphere (KHR_materials_sheen) and an amber glass sphere (transmission with
#   KHR_materials_volume's attenuation) on a grey floor, a sun; rendered under courtyard.exr.
# Lights are in the photometric units Blender's exporter writes (lx = W/m²·683, cd = W·683/4π).
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def png(path, w, h, pixel):
    """An 8-bit RGB PNG of pixel(x, y) -> (r, g, b)."""
    rows = b"".join(b"\0" + bytes(c for x in range(w) for c in pixel(x, y)) for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def sphere(segments=32, rings=16):
    """Unit sphere: u = longitude from +X towards -Z (counter-clockwise seen from +Y), v = 0 at the top."""
    pos, nrm, uv, tan, idx = [], [], [], [], []
    for r in range(rings + 1):
        th = math.pi * r / rings
        for s in range(segments + 1):
            ph = 2 * math.pi * s / segments
            n = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            pos.append(n)
            nrm.append(n)
            uv.append((s / segments, r / rings))
            # dP/du, and w so that cross(N, T) * w points up the texture (towards smaller v).
            tan.append((-math.sin(ph), 0.0, -math.cos(ph), 1.0))
    for r in range(rings):
        for s in range(segments):
            a, b = r * (segments + 1) + s, (r + 1) * (segments + 1) + s
            # The pole rings are one point each: their half of the quad has no area.
            if r > 0:
                idx += [a, b, a + 1]
            if r < rings - 1:
                idx += [a + 1, b, b + 1]
    return pos, nrm, uv, tan, idx


def box():
    """Unit cube from -1 to 1, four vertices a face, uv (0,0) at each face's top left."""
    pos, nrm, uv, tan, idx = [], [], [], [], []
    faces = [((1, 0, 0), (0, 0, -1)), ((-1, 0, 0), (0, 0, 1)), ((0, 1, 0), (1, 0, 0)),
             ((0, -1, 0), (1, 0, 0)), ((0, 0, 1), (1, 0, 0)), ((0, 0, -1), (-1, 0, 0))]
    for n, t in faces:
        b = (n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0])  # up the texture
        base = len(pos)
        for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
            x, y = 2 * du - 1, 1 - 2 * dv
            pos.append(tuple(n[i] + x * t[i] + y * b[i] for i in range(3)))
            nrm.append(n)
            uv.append((du, dv))
            tan.append(t + (1.0,))
        idx += [base, base + 3, base + 1, base + 1, base + 3, base + 2]
    return pos, nrm, uv, tan, idx


def floor(half=12.0, tiles=1.0):
    pos = [(-half, 0, -half), (half, 0, -half), (half, 0, half), (-half, 0, half)]
    uv = [(0, 0), (tiles, 0), (tiles, tiles), (0, tiles)]
    return pos, [(0, 1, 0)] * 4, uv, [(1, 0, 0, 1)] * 4, [0, 3, 1, 1, 3, 2]


class Gltf:
    def __init__(self):
        self.bin = bytearray()
        self.shared = {}  # id(geometry) -> its attribute and index accessors, written once
        self.doc = {"asset": {"version": "2.0", "generator": "rayfarm tests/reference/make_scenes.py",
                              "copyright": "CC0"},
                    "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
                    "accessors": [], "bufferViews": [], "extensionsUsed": []}

    def use(self, ext):
        if ext not in self.doc["extensionsUsed"]:
            self.doc["extensionsUsed"].append(ext)

    def accessor(self, values, kind, comp, target, minmax=False):
        fmt = {5126: "f", 5123: "H"}[comp]
        flat = [c for v in values for c in (v if isinstance(v, tuple) else (v,))]
        while len(self.bin) % 4:
            self.bin.append(0)
        data = struct.pack("<%d%s" % (len(flat), fmt), *flat)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data),
                                        "target": target})
        self.bin += data
        acc = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": comp, "count": len(values),
               "type": kind}
        if minmax:
            n = len(values[0])
            acc["min"] = [min(v[i] for v in values) for i in range(n)]
            acc["max"] = [max(v[i] for v in values) for i in range(n)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def mesh(self, name, geometry, material):
        if id(geometry) not in self.shared:
            pos, nrm, uv, tan, idx = geometry
            attrs = {"POSITION": self.accessor(pos, "VEC3", 5126, 34962, True),
                     "NORMAL": self.accessor(nrm, "VEC3", 5126, 34962),
                     "TEXCOORD_0": self.accessor(uv, "VEC2", 5126, 34962),
                     "TANGENT": self.accessor(tan, "VEC4", 5126, 34962)}
            # The geometry is kept too: while it lives, no other object can take its id.
            self.shared[id(geometry)] = (geometry, attrs, self.accessor(idx, "SCALAR", 5123, 34963))
        _, attrs, indices = self.shared[id(geometry)]
        prim = {"attributes": dict(attrs), "indices": indices, "material": material}
        self.doc["meshes"].append({"name": name, "primitives": [prim]})
        return len(self.doc["meshes"]) - 1

    def material(self, m):
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def texture(self, uri):
        d = self.doc
        d.setdefault("images", []).append({"uri": uri})
        d.setdefault("samplers", [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}])
        d.setdefault("textures", []).append({"source": len(d["images"]) - 1, "sampler": 0})
        return len(d["textures"]) - 1

    def node(self, n):
        self.doc["nodes"].append(n)
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)

    def light(self, light, node):
        self.use("KHR_lights_punctual")
        lights = self.doc.setdefault("extensions", {}).setdefault("KHR_lights_punctual", {"lights": []})["lights"]
        lights.append(light)
        node["extensions"] = {"KHR_lights_punctual": {"light": len(lights) - 1}}
        self.node(node)

    def camera(self, yfov_deg, aspect, node):
        self.doc.setdefault("cameras", []).append(
            {"type": "perspective", "perspective": {"yfov": math.radians(yfov_deg), "aspectRatio": aspect,
                                                    "znear": 0.05, "zfar": 200}})
        node["camera"] = len(self.doc["cameras"]) - 1
        self.node(node)

    def write(self, name):
        binary = name.replace(".gltf", ".bin")
        self.doc["buffers"] = [{"byteLength": len(self.bin), "uri": binary}]
        with open(os.path.join(HERE, binary), "wb") as f:
            f.write(self.bin)
        with open(os.path.join(HERE, name), "w") as f:
            json.dump(self.doc, f, indent=1)
            f.write("\n")


def look_at(eye, target):
    """Node rotation (quaternion x, y, z, w) turning -Z towards target from eye, +Y up."""
    f = [target[i] - eye[i] for i in range(3)]
    fl = math.sqrt(sum(c * c for c in f))
    f = [c / fl for c in f]
    yaw = math.atan2(-f[0], -f[2])
    pitch = math.asin(f[1])
    cy, sy, cp, sp = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(pitch / 2), math.sin(pitch / 2)
    # yaw about Y, then pitch about the turned X: q = qy * qx
    return [cy * sp, sy * cp, -sy * sp, cy * cp]


def pbr(name, color, metallic, roughness, **extra):
    m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": list(color) + [1.0], "metallicFactor": metallic,
                                                "roughnessFactor": roughness}}
    m.update(extra)
    return m


def metals_glass():
    g = Gltf()
    png(os.path.join(HERE, "tiles.png"), 64, 64,
        lambda x, y: (185, 185, 180) if ((x // 8) + (y // 8)) % 2 else (80, 82, 92))
    g.use("KHR_texture_transform")
    tiles = g.texture("tiles.png")
    floor_m = pbr("tiled floor", (1, 1, 1), 0.0, 0.6)
    floor_m["pbrMetallicRoughness"]["baseColorTexture"] = {
        "index": tiles, "extensions": {"KHR_texture_transform": {"scale": [3, 3]}}}
    g.node({"name": "floor", "mesh": g.mesh("floor", floor(), g.material(floor_m))})
    copper = g.material(pbr("copper r0.35", (0.95, 0.64, 0.54), 1.0, 0.35))
    g.node({"name": "copper box", "mesh": g.mesh("box", box(), copper), "translation": [-2.3, 0.8, 0.3],
            "rotation": [0, math.sin(math.radians(15)), 0, math.cos(math.radians(15))], "scale": [0.8, 0.8, 0.8]})
    sph = sphere()
    chrome = g.material(pbr("chrome r0.05", (0.9, 0.9, 0.9), 1.0, 0.05))
    g.node({"name": "chrome sphere", "mesh": g.mesh("chrome sphere", sph, chrome), "translation": [-0.2, 1.0, -0.6]})
    g.use("KHR_materials_transmission")
    g.use("KHR_materials_ior")
    glass = g.material(pbr("glass", (1, 1, 1), 0.0, 0.0, extensions={
        "KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5}}))
    g.node({"name": "glass sphere", "mesh": g.mesh("glass sphere", sph, glass), "translation": [1.6, 0.75, 0.9],
            "scale": [0.75, 0.75, 0.75]})
    blue = g.material(pbr("blue plastic r0.4", (0.08, 0.2, 0.75), 0.0, 0.4))
    g.node({"name": "blue sphere", "mesh": g.mesh("blue sphere", sph, blue), "translation": [2.9, 0.6, -1.2],
            "scale": [0.6, 0.6, 0.6]})
    g.light({"type": "directional", "name": "sun", "color": [1, 0.96, 0.9], "intensity": 3 * 683.0},
            {"name": "sun", "rotation": look_at((0, 0, 0), (-0.5, -1.0, -0.35))})
    eye = (0.6, 3.2, 8.5)
    g.camera(30, 16 / 9, {"name": "camera", "translation": list(eye), "rotation": look_at(eye, (0.4, 0.7, 0))})
    g.write("metals_glass.gltf")


def textured_spot():
    g = Gltf()
    png(os.path.join(HERE, "bricks.png"), 64, 64,
        lambda x, y: (40, 40, 40) if y % 16 < 2 or (x + (8 if (y // 16) % 2 else 0)) % 32 < 2
        else (170 + 3 * ((x * 7 + y * 3) % 9), 80, 50))

    def bumps(x, y):  # egg-crate normals: +X right, +Y up the image (OpenGL style, as glTF wants)
        a, b = 2 * math.pi * x / 16, 2 * math.pi * y / 16
        nx, ny = -0.5 * math.cos(a) * math.sin(b), 0.5 * math.sin(a) * math.cos(b)
        nz = math.sqrt(max(0.0, 1 - nx * nx - ny * ny))
        return tuple(int(round((c * 0.5 + 0.5) * 255)) for c in (nx, ny, nz))

    png(os.path.join(HERE, "bumps.png"), 64, 64, bumps)
    # G roughness (0.1 | 0.8 bands along v), B metallic (1 | 0 bands along u).
    png(os.path.join(HERE, "stripes_mr.png"), 64, 64,
        lambda x, y: (255, 25 if (y // 8) % 2 else 204, 255 if (x // 16) % 2 else 0))
    png(os.path.join(HERE, "glow.png"), 64, 32,
        lambda x, y: (40, 220, 255) if (x // 8) % 2 and 6 < y < 26 else (0, 0, 0))
    bricks, bumpsT, mr, glow = (g.texture(u) for u in ("bricks.png", "bumps.png", "stripes_mr.png", "glow.png"))
    g.node({"name": "floor", "mesh": g.mesh("floor", floor(), g.material(pbr("grey floor", (0.5, 0.5, 0.5), 0, 0.9)))})
    brick = pbr("brick box", (1, 1, 1), 0.0, 0.7)
    brick["pbrMetallicRoughness"]["baseColorTexture"] = {"index": bricks}
    brick["normalTexture"] = {"index": bumpsT, "scale": 1.0}
    g.node({"name": "brick box", "mesh": g.mesh("box", box(), g.material(brick)), "translation": [-1.6, 0.9, 0],
            "rotation": [0, math.sin(math.radians(-20)), 0, math.cos(math.radians(-20))], "scale": [0.9, 0.9, 0.9]})
    sph = sphere()
    striped = pbr("striped metal/plastic", (0.9, 0.75, 0.3), 1.0, 1.0)
    striped["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {"index": mr}
    g.node({"name": "striped sphere", "mesh": g.mesh("striped sphere", sph, g.material(striped)),
            "translation": [0.7, 0.85, 0.4], "scale": [0.85, 0.85, 0.85]})
    g.use("KHR_materials_emissive_strength")
    lamp = pbr("glowing stripes", (0.05, 0.05, 0.05), 0.0, 0.5, emissiveFactor=[1, 1, 1],
               emissiveTexture={"index": glow}, extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 3}})
    g.node({"name": "glowing sphere", "mesh": g.mesh("glowing sphere", sph, g.material(lamp)),
            "translation": [2.5, 0.55, -0.9], "scale": [0.55, 0.55, 0.55]})
    spot_at = (4.0, 6.0, 4.0)
    g.light({"type": "spot", "name": "spot", "color": [1, 0.95, 0.85], "intensity": 900 * 683 / (4 * math.pi),
             "spot": {"innerConeAngle": 0.65, "outerConeAngle": 0.75}},
            {"name": "spot", "translation": list(spot_at), "rotation": look_at(spot_at, (0.3, 0.5, 0))})
    g.light({"type": "point", "name": "fill", "color": [0.8, 0.85, 1], "intensity": 250 * 683 / (4 * math.pi)},
            {"name": "fill", "translation": [-5.0, 4.0, 3.0]})
    eye = (0.3, 2.6, 7.5)
    g.camera(32, 16 / 9, {"name": "camera", "translation": list(eye), "rotation": look_at(eye, (0.3, 0.7, 0))})
    g.write("textured_spot.gltf")


def coat_sheen_volume():
    g = Gltf()
    g.node({"name": "floor", "mesh": g.mesh("floor", floor(), g.material(pbr("grey floor", (0.45, 0.45, 0.45), 0, 0.8)))})
    sph = sphere(48, 24)
    g.use("KHR_materials_clearcoat")
    coat = pbr("red under clear coat", (0.55, 0.04, 0.03), 0.0, 0.7, extensions={
        "KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.05}})
    g.node({"name": "coated sphere", "mesh": g.mesh("coated sphere", sph, g.material(coat)), "translation": [-2.0, 0.8, 0.0],
            "scale": [0.8, 0.8, 0.8]})
    g.use("KHR_materials_sheen")
    cloth = pbr("blue velvet", (0.03, 0.04, 0.16), 0.0, 0.9, extensions={
        "KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.75, 0.5], "sheenRoughnessFactor": 0.45}})
    g.node({"name": "velvet sphere", "mesh": g.mesh("velvet sphere", sph, g.material(cloth)), "translation": [0.0, 0.8, -0.4],
            "scale": [0.8, 0.8, 0.8]})
    g.use("KHR_materials_transmission")
    g.use("KHR_materials_ior")
    g.use("KHR_materials_volume")
    amber = pbr("amber glass volume", (1, 1, 1), 0.0, 0.0, extensions={
        "KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5},
        "KHR_materials_volume": {"thicknessFactor": 1.0, "attenuationColor": [0.9, 0.45, 0.12], "attenuationDistance": 0.8}})
    g.node({"name": "amber sphere", "mesh": g.mesh("amber sphere", sph, g.material(amber)), "translation": [2.0, 0.75, 0.3],
            "scale": [0.75, 0.75, 0.75]})
    g.light({"type": "directional", "name": "sun", "color": [1, 0.97, 0.92], "intensity": 2.5 * 683.0},
            {"name": "sun", "rotation": look_at((0, 0, 0), (-0.6, -1.0, -0.5))})
    eye = (0.0, 2.4, 7.0)
    g.camera(30, 16 / 9, {"name": "camera", "translation": list(eye), "rotation": look_at(eye, (0.0, 0.7, 0))})
    g.write("coat_sheen_volume.gltf")


def rough_metals():
    g = Gltf()
    sph = sphere(64, 32)
    top = [g.material(pbr("white metal r%.2f" % r, (1, 1, 1), 1.0, r)) for r in (0.0, 0.25, 0.5, 0.75, 1.0)]
    g.use("KHR_materials_transmission")
    bottom = [g.material({"name": "default material", "pbrMetallicRoughness": {}}),
              g.material(pbr("gold r0.5", (1.0, 0.77, 0.34), 1.0, 0.5)),
              g.material(pbr("copper r0.8", (0.95, 0.64, 0.54), 1.0, 0.8)),
              g.material({"name": "metal with transmission", "pbrMetallicRoughness": {"roughnessFactor": 0.3},
                          "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}}),
              g.material(pbr("white plastic r1", (0.8, 0.8, 0.8), 0.0, 1.0))]
    for row, (y, mats) in enumerate(((0.55, top), (-0.55, bottom))):
        for i, m in enumerate(mats):
            name = g.doc["materials"][m]["name"]
            g.node({"name": name, "mesh": g.mesh(name, sph, m), "translation": [1.05 * (i - 2), y, 0.0],
                    "scale": [0.47, 0.47, 0.47]})
    eye = (0.0, 0.0, 6.5)
    g.camera(30, 16 / 9, {"name": "camera", "translation": list(eye), "rotation": look_at(eye, (0.0, 0.0, 0.0))})
    g.write("rough_metals.gltf")


SCENES = {"metals_glass": metals_glass, "textured_spot": textured_spot, "coat_sheen_volume": coat_sheen_volume,
          "rough_metals": rough_metals}
if __name__ == "__main__":
    import sys
    for name in sys.argv[1:] or SCENES:
        SCENES[name]()
