# Renders a glTF file with Blender Cycles, as a reference image for rayfarm's image tests and for
# `rayfarm report --reference`. Run it through cycles_reference.sh beside it (Blender in the
# background, factory settings); it is a developer tool, never a test dependency.
#
# What it sets up, so a rayfarm still with `--exposure 0 --tonemap clamp` is the fair match:
# - the file through Blender's own glTF importer, lights in its "Standard" lighting mode
#   (W = cd·4π/683, W/m² = lx/683: the photometric conversion rayfarm's --exposure 0 uses),
#   lights otherwise as imported (Blender's default point radius and sun angle);
# - the view through the file's camera N, counted as rayfarm's --camera N counts: perspective
#   cameras in the order of a depth-first walk of the scene's nodes;
# - a black world, or --environment FILE.exr|.hdr as the world at --environment-strength,
#   mapped as Blender maps an equirectangular image (the orientation rayfarm follows);
# - Standard view transform (sRGB, clamped, no look, exposure 0), Cycles on the CPU at a fixed
#   number of samples (no adaptive sampling, no denoising, fixed seed), --bounces total bounces;
# - an 8-bit RGB PNG at --size.
import argparse
import json
import os
import struct
import sys
import time

import bpy


def restore_numpy_aliases():
    """Blender 3.4's glTF importer uses np.bool, an alias NumPy 1.24 (Debian 12's python3-numpy)
    removed; give the aliases back to the builtins they always meant."""
    import numpy
    for name, kind in (("bool", bool), ("int", int), ("float", float), ("object", object)):
        if name not in numpy.__dict__:
            setattr(numpy, name, kind)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="cycles_reference", description="glTF to a Cycles reference PNG")
    p.add_argument("gltf", help=".gltf or .glb file")
    p.add_argument("-o", "--out", required=True, help="output PNG")
    p.add_argument("--size", default="640x360", help="WxH (default 640x360)")
    p.add_argument("--samples", type=int, default=256, help="samples per pixel (default 256)")
    p.add_argument("--camera", type=int, default=0, help="glTF camera index as rayfarm counts (default 0)")
    p.add_argument("--environment", help="equirectangular .exr/.hdr as the world (default: black world)")
    p.add_argument("--environment-strength", type=float, default=1.0)
    p.add_argument("--bounces", type=int, default=8, help="maximum total bounces (default 8)")
    p.add_argument("--threads", type=int, default=0, help="render threads (default: all)")
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args(argv)
    try:
        w, h = (int(v) for v in a.size.lower().split("x"))
    except ValueError:
        p.error("--size: expected WxH, got " + a.size)
    a.width, a.height = w, h
    # Blender reads relative paths against the .blend file, not the working directory.
    a.gltf, a.out = os.path.abspath(a.gltf), os.path.abspath(a.out)
    if a.environment:
        a.environment = os.path.abspath(a.environment)
    return a


def read_gltf_json(path):
    """The JSON of a .gltf, or the JSON chunk of a .glb."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        length, kind = struct.unpack_from("<I4s", data, 12)
        if kind != b"JSON":
            raise SystemExit(path + ": the first GLB chunk is not JSON")
        return json.loads(data[20:20 + length])
    return json.loads(data)


def camera_node_names(doc):
    """Names of the nodes with a perspective camera, depth first from the scene's roots."""
    nodes = doc.get("nodes", [])
    cameras = doc.get("cameras", [])
    scene = doc.get("scenes", [{}])[doc.get("scene", 0)]
    out = []

    def walk(i):
        n = nodes[i]
        c = n.get("camera")
        if c is not None and cameras[c].get("type") == "perspective":
            out.append(n.get("name"))
        for child in n.get("children", []):
            walk(child)

    for root in scene.get("nodes", []):
        walk(root)
    return out


def pick_camera(doc, index):
    names = camera_node_names(doc)
    cams = [o for o in bpy.context.scene.objects if o.type == "CAMERA"]
    if index >= len(names):
        raise SystemExit("no glTF camera %d (the file has %d)" % (index, len(names)))
    if len(cams) == 1 and len(names) == 1:
        return cams[0]
    for o in cams:
        if names[index] and o.name == names[index]:
            return o
    raise SystemExit("camera %d: no Blender object named %r (give the camera nodes unique names)"
                     % (index, names[index]))


def set_world(scene, env_path, strength):
    world = bpy.data.worlds.new("reference world")
    world.use_nodes = True
    nodes = world.node_tree.nodes
    bg = nodes["Background"]
    if env_path:
        tex = nodes.new("ShaderNodeTexEnvironment")
        tex.image = bpy.data.images.load(env_path, check_existing=True)
        tex.projection = "EQUIRECTANGULAR"
        world.node_tree.links.new(tex.outputs["Color"], bg.inputs["Color"])
        bg.inputs["Strength"].default_value = strength
    else:
        bg.inputs["Color"].default_value = (0, 0, 0, 1)
        bg.inputs["Strength"].default_value = 0.0
    scene.world = world


def set_render(scene, a):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = a.samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = a.seed
    c.max_bounces = a.bounces
    scene.render.resolution_x = a.width
    scene.render.resolution_y = a.height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    if a.threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = a.threads
    vs = scene.view_settings
    scene.display_settings.display_device = "sRGB"
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    img = scene.render.image_settings
    img.file_format = "PNG"
    img.color_mode = "RGB"
    img.color_depth = "8"
    scene.render.filepath = a.out


def main():
    a = parse_args()
    restore_numpy_aliases()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    doc = read_gltf_json(a.gltf)
    bpy.ops.import_scene.gltf(filepath=a.gltf, convert_lighting_mode="SPEC")
    scene = bpy.context.scene
    scene.camera = pick_camera(doc, a.camera)
    set_world(scene, a.environment, a.environment_strength)
    set_render(scene, a)
    t0 = time.monotonic()
    bpy.ops.render.render(write_still=True)
    print("cycles_reference: wrote %s (%dx%d, %d samples) in %.2f s render"
          % (a.out, a.width, a.height, a.samples, time.monotonic() - t0))


main()
