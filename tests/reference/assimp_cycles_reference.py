# Renders a rayfarm scene file that names one OBJ, STL, PLY, FBX or COLLADA model with Blender
# Cycles, the model imported by Blender 3.4's own importer for its format, as a reference for
# tests/engine/load/assimp/assimp_cycles_test.cpp. Run it through assimp_cycles_reference.sh
# beside it (Blender in the background, factory settings); a developer tool, never a test
# dependency.
#
# The scene file is the one rayfarm renders (`rayfarm still SCENE.json`), so both see the same:
# - its "camera" (eye, target, up, vertical "fov" in degrees), turned from rayfarm's axes (+Y up,
#   glTF's) into Blender's (+Z up) as Blender's glTF importer turns them: (x, y, z) -> (x, -z, y);
# - its "environment" (file, "intensity") as the world, mapped as Blender maps an
#   equirectangular image (the orientation rayfarm follows);
# - its one "model", placed as rayfarm places it: rayfarm turns each format's up axis and unit
#   into +Y up metres, Blender's importers into +Z up metres, and the two agree where the
#   importer's options say so (place_model);
# - its "exposure" (default 0) as the view exposure, Standard view transform (sRGB, clamped),
#   a transparent film (the PNG's alpha is the model's coverage), Cycles on the CPU at a fixed
#   number of samples, 8 bounces, no denoising, seed 0.
# The file's own cameras and lights are deleted after the import: rayfarm does not read them.
import argparse
import json
import math
import os
import sys
import time
import xml.etree.ElementTree as ET

import bpy
from mathutils import Matrix, Vector


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="assimp_cycles_reference",
                                description="a rayfarm scene file naming one non-glTF model, to a Cycles reference PNG")
    p.add_argument("scene", help="rayfarm scene file (.json) with one model object")
    p.add_argument("-o", "--out", required=True, help="output PNG (RGBA)")
    p.add_argument("--samples", type=int, default=128, help="samples per pixel (default 128)")
    p.add_argument("--threads", type=int, default=0, help="render threads (default: all)")
    a = p.parse_args(argv)
    a.scene, a.out = os.path.abspath(a.scene), os.path.abspath(a.out)
    return a


def to_blender(v):
    """rayfarm's (glTF's) +Y-up axes to Blender's +Z-up: the turn Blender's glTF importer makes."""
    return Vector((v[0], -v[2], v[1]))


def scene_path(base, p):
    return p if os.path.isabs(p) else os.path.normpath(os.path.join(base, p))


def read_scene(path):
    with open(path) as f:
        doc = json.load(f)
    models = [o for o in doc.get("objects", []) if o.get("type") == "model"]
    if len(models) != 1 or len(doc["objects"]) != 1:
        raise SystemExit(path + ": expected exactly one object, a model")
    if "transform" in models[0] or "material" in models[0]:
        raise SystemExit(path + ": a model's transform or material is not reproduced here")
    if doc.get("lights"):
        raise SystemExit(path + ": scene lights are not reproduced here (light it with an environment)")
    return doc, scene_path(os.path.dirname(path), models[0]["path"])


def neutral_material(name, colour_attribute=None):
    """rayfarm's material for STL and PLY, which have none (docs/pictures.md): Principled BSDF,
    base colour 0.8 grey, roughness 0.5, metallic 0, specular 0.5 (glTF's F0 of 0.04); under
    vertex colours the base colour is the colour attribute (white times the colours)."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.5
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Specular"].default_value = 0.5
    if colour_attribute:
        attr = m.node_tree.nodes.new("ShaderNodeAttribute")
        attr.attribute_name = colour_attribute
        m.node_tree.links.new(attr.outputs["Color"], bsdf.inputs["Base Color"])
    return m


def give_material(objs, material):
    for o in objs:
        if o.type == "MESH" and not o.data.materials:
            o.data.materials.append(material)


def mtl_kd_times_map_kd():
    """An MTL's map_Kd is "multiplied by the Kd value" (the MTL specification; glTF's factor times
    texture, as rayfarm maps it); Blender 3.4's OBJ importer links the texture to Base Color and
    leaves Kd unused (it sets the socket's value, which a link hides). The reference multiplies
    the texture by that value, as the file means."""
    for bm in bpy.data.materials:
        pr = bm.node_tree.nodes.get("Principled BSDF") if bm.use_nodes else None
        if not pr or not pr.inputs["Base Color"].is_linked:
            continue
        base = pr.inputs["Base Color"]
        kd = tuple(base.default_value)
        if all(abs(v - 1.0) < 1e-6 for v in kd[:3]):
            continue
        src = base.links[0].from_socket
        mul = bm.node_tree.nodes.new("ShaderNodeMixRGB")
        mul.blend_type = "MULTIPLY"
        mul.inputs["Fac"].default_value = 1.0
        mul.inputs["Color2"].default_value = kd
        bm.node_tree.links.new(src, mul.inputs["Color1"])
        bm.node_tree.links.new(mul.outputs["Color"], base)
        print("assimp_cycles_reference: %s: map_Kd times Kd (%.3g, %.3g, %.3g)" % (bm.name, kd[0], kd[1], kd[2]))


def collada_reflectivity_as_meant(path):
    """COLLADA's common profile draws a mirror term of colour <reflective> x <reflectivity>;
    Blender 3.4's importer makes <reflectivity> Principled's Metallic whatever that colour is, so
    a material with a black <reflective> (no mirror term: COLLADA.dae's 0.5 over black) comes out
    half metal, its diffuse colour halved. The reference sets Metallic back to 0 where the
    reflective colour is black, as the file means (rayfarm reads no metalness from COLLADA). What
    the importer does not read (<shininess>, the <specular> colour: Roughness and Specular stay
    at 0.5) is left as imported; tests/reference/README.md says what it changes."""
    local = lambda tag: tag.rsplit("}", 1)[-1]
    root = ET.parse(path).getroot()
    effects = {e.get("id"): e for e in root.iter() if local(e.tag) == "effect"}
    for m in (e for e in root.iter() if local(e.tag) == "material"):
        inst = next((c for c in m if local(c.tag) == "instance_effect"), None)
        fx = effects.get(inst.get("url", "").lstrip("#")) if inst is not None else None
        if fx is None:
            continue
        refl = next((e for e in fx.iter() if local(e.tag) == "reflective"), None)
        colour = next((c.text for c in refl.iter() if local(c.tag) == "color"), None) if refl is not None else None
        black = colour is None or all(float(v) == 0.0 for v in colour.split()[:3])
        bm = bpy.data.materials.get(m.get("name") or m.get("id"))
        pr = bm.node_tree.nodes.get("Principled BSDF") if bm and bm.use_nodes else None
        if black and pr and pr.inputs["Metallic"].default_value != 0.0:
            print("assimp_cycles_reference: %s: Metallic %.3g -> 0 (<reflectivity> over a black <reflective>)"
                  % (bm.name, pr.inputs["Metallic"].default_value))
            pr.inputs["Metallic"].default_value = 0.0


def place_model(path):
    """Imports the model with Blender 3.4's importer for its format, so it lands where rayfarm
    puts it (rayfarm's +Y-up metres are Blender's +Z-up metres):
    - OBJ: wm.obj_import (Blender 3.4's File > Import > Wavefront), forward -Z, up +Y, its
      defaults: OBJ is +Y up, as rayfarm reads it; MTL and textures as that importer maps them,
      then mtl_kd_times_map_kd.
    - STL: import_mesh.stl, up +Z (its default) at global_scale 0.001: STL's convention is +Z up
      in millimetres, as rayfarm reads it. STL has no material: rayfarm's neutral one.
    - PLY: import_mesh.ply (no axis options in 3.4: it keeps the file's coordinates as Blender's,
      +Z up), then turned +90 degrees about X, the turn from +Y up that Blender's OBJ importer
      makes: rayfarm reads PLY as +Y up (the scans' convention). Its neutral material, the base
      colour from the importer's colour layer when the file has vertex colours.
    - FBX: import_scene.fbx at its defaults, which read the file's UpAxis/FrontAxis/CoordAxis and
      scale by UnitScaleFactor / 100 (centimetres to metres), as rayfarm does.
    - COLLADA: wm.collada_import at its defaults (import_units off: the <unit> is applied to the
      geometry in Blender's metres; <up_axis> turned to +Z), as assimp applies both for rayfarm;
      then collada_reflectivity_as_meant."""
    ext = os.path.splitext(path)[1].lower()
    before = set(bpy.data.objects)
    if ext == ".obj":
        bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
        mtl_kd_times_map_kd()
    elif ext == ".stl":
        bpy.ops.import_mesh.stl(filepath=path, global_scale=0.001, axis_forward="Y", axis_up="Z")
    elif ext == ".ply":
        bpy.ops.import_mesh.ply(filepath=path)
    elif ext == ".fbx":
        bpy.ops.import_scene.fbx(filepath=path)
    elif ext == ".dae":
        bpy.ops.wm.collada_import(filepath=path, import_units=False)
        collada_reflectivity_as_meant(path)
    else:
        raise SystemExit(path + ": expected .obj, .stl, .ply, .fbx or .dae")
    new = [o for o in bpy.data.objects if o not in before]
    # The file's cameras and lights: rayfarm notes them and does not use them.
    for o in [o for o in new if o.type in {"CAMERA", "LIGHT"}]:
        print("assimp_cycles_reference: deleted the file's %s %r (rayfarm does not read it)" % (o.type.lower(), o.name))
        bpy.data.objects.remove(o, do_unlink=True)
    new = [o for o in bpy.data.objects if o not in before]
    if ext == ".ply":
        for o in new:
            o.matrix_world = Matrix.Rotation(math.radians(90.0), 4, "X") @ o.matrix_world
    if ext in {".stl", ".ply"}:
        colours = next((o.data.vertex_colors[0].name for o in new if o.type == "MESH" and o.data.vertex_colors), None)
        give_material(new, neutral_material("rayfarm neutral", colours))
    meshes = [o for o in new if o.type == "MESH"]
    if not meshes:
        raise SystemExit(path + ": the importer made no mesh")
    bpy.context.view_layer.update()
    corners = [o.matrix_world @ Vector(c) for o in meshes for c in o.bound_box]
    lo = [min(c[i] for c in corners) for i in range(3)]
    hi = [max(c[i] for c in corners) for i in range(3)]
    # In rayfarm's axes, to set beside `rayfarm info`'s bounds.
    print("assimp_cycles_reference: %d meshes, bounds in rayfarm's axes (%.4g, %.4g, %.4g) to (%.4g, %.4g, %.4g)"
          % (len(meshes), lo[0], lo[2], -hi[1], hi[0], hi[2], -lo[1]))


def set_camera(scene, cam_doc, width, height):
    eye, target = to_blender(cam_doc["eye"]), to_blender(cam_doc["target"])
    up = to_blender(cam_doc.get("up", [0, 1, 0]))
    if cam_doc.get("type", "perspective") != "perspective" or cam_doc.get("fov_axis", "vertical") != "vertical" \
            or cam_doc.get("handedness", "right") != "right":
        raise SystemExit("only a right-handed perspective camera with a vertical fov is reproduced here")
    fwd = (target - eye).normalized()
    right = fwd.cross(up).normalized()
    cam_up = right.cross(fwd)
    data = bpy.data.cameras.new("rayfarm camera")
    data.sensor_fit = "VERTICAL"
    data.sensor_height = 24.0
    data.lens = 12.0 / math.tan(math.radians(cam_doc.get("fov", 45.0)) / 2)
    data.clip_start, data.clip_end = 1e-5, 1e5
    cam = bpy.data.objects.new("rayfarm camera", data)
    rot = Matrix((right, cam_up, -fwd)).transposed()  # columns: camera +X, +Y, +Z (it looks down -Z)
    cam.matrix_world = Matrix.Translation(eye) @ rot.to_4x4()
    scene.collection.objects.link(cam)
    scene.camera = cam


def set_world(scene, env, base):
    world = bpy.data.worlds.new("reference world")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    if env:
        spec = env if isinstance(env, dict) else {"file": env}
        if spec.get("rotation", 0):
            raise SystemExit("an environment rotation is not reproduced here")
        tex = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
        tex.image = bpy.data.images.load(scene_path(base, spec["file"]), check_existing=True)
        tex.projection = "EQUIRECTANGULAR"
        world.node_tree.links.new(tex.outputs["Color"], bg.inputs["Color"])
        bg.inputs["Strength"].default_value = spec.get("intensity", 1.0)
    else:
        bg.inputs["Strength"].default_value = 0.0
    scene.world = world


def set_render(scene, a, width, height, exposure):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = a.samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = 0
    c.max_bounces = 8
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    if a.threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = a.threads
    scene.display_settings.display_device = "sRGB"
    vs = scene.view_settings
    vs.view_transform, vs.look, vs.exposure, vs.gamma = "Standard", "None", exposure, 1.0
    img = scene.render.image_settings
    img.file_format, img.color_mode, img.color_depth = "PNG", "RGBA", "8"
    scene.render.filepath = a.out


def main():
    a = parse_args()
    doc, model = read_scene(a.scene)
    render = doc.get("render", {})
    width, height = render.get("width", 640), render.get("height", 360)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    place_model(model)
    set_camera(scene, doc["camera"], width, height)
    set_world(scene, doc.get("environment"), os.path.dirname(a.scene))
    exposure = doc.get("exposure", 0.0)
    if not isinstance(exposure, (int, float)):
        raise SystemExit("expected a numeric exposure")
    set_render(scene, a, width, height, exposure)
    t0 = time.monotonic()
    bpy.ops.render.render(write_still=True)
    print("assimp_cycles_reference: wrote %s (%dx%d, %d samples) in %.2f s render"
          % (a.out, width, height, a.samples, time.monotonic() - t0))


main()
