# Builds three small scenes in Blender and writes them with Blender's own glTF exporter (so the
# tests see what a Blender user's export looks like: double-sided materials, Blender's light units,
# its UV spheres and subdivided monkeys), for rayfarm's Cycles comparisons (cycles_scenes_test):
#   blender --background --factory-startup --python tests/reference/make_blender_scenes.py
# (Blender 3.4 with python3-numpy; a developer tool, no test runs it). Writes beside this script:
# - showcase.gltf: a clay monkey, a gold torus and a glass ball on a white floor, under a key
#   point light, a spot and a sun (the showcase; rendered with a black world);
# - backdrop.gltf: a grey double-sided backdrop plane seen from its back side, a floor and a red
#   ball, no lights (rendered under courtyard.exr);
# - dim_light.gltf: a clay monkey and a box on a floor lit by one point light of 10 cd
#   (0.184 W in Blender), black world (rendered with 10 EV of exposure).
# Each file has one camera; cycles_reference.sh renders its reference (commands in the README).
import math
import os

import bpy
from mathutils import Vector

HERE = os.path.dirname(os.path.abspath(__file__))


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def material(name, color, metallic=0.0, roughness=0.5, transmission=0.0, ior=1.45):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Transmission"].default_value = transmission
    bsdf.inputs["IOR"].default_value = ior
    return m


def assign(obj, mat, smooth=True):
    obj.data.materials.append(mat)
    if smooth:
        for p in obj.data.polygons:
            p.use_smooth = True


def aim(obj, target):
    """Turns obj's -Z towards target, +Y up (cameras, spots and suns look down their -Z)."""
    d = Vector(target) - obj.location
    obj.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()


def camera(location, target, lens=40.0):
    bpy.ops.object.camera_add(location=location)
    cam = bpy.context.object
    cam.data.lens = lens
    aim(cam, target)
    bpy.context.scene.camera = cam
    return cam


def light(kind, name, location, watts, target=None, **props):
    bpy.ops.object.light_add(type=kind, location=location)
    lamp = bpy.context.object
    lamp.name = name
    lamp.data.energy = watts
    for k, v in props.items():
        setattr(lamp.data, k, v)
    if target is not None:
        aim(lamp, target)
    return lamp


def floor(mat, size=20.0):
    bpy.ops.mesh.primitive_plane_add(size=size, location=(0, 0, 0))
    assign(bpy.context.object, mat, smooth=False)


def monkey(mat, location, rotation_z=0.0):
    bpy.ops.mesh.primitive_monkey_add(location=location, rotation=(math.radians(-10), 0, rotation_z))
    m = bpy.context.object
    mod = m.modifiers.new("subdivision", "SUBSURF")
    mod.levels = 2
    assign(m, mat)
    return m


def export(name):
    bpy.ops.export_scene.gltf(filepath=os.path.join(HERE, name), export_format="GLTF_SEPARATE",
                              export_lights=True, export_cameras=True, export_apply=True)


def showcase():
    reset()
    floor(material("white floor", (0.8, 0.8, 0.8), roughness=0.6))
    monkey(material("clay", (0.62, 0.42, 0.32), roughness=0.75), (-1.9, 0.3, 0.85), math.radians(20))
    bpy.ops.mesh.primitive_torus_add(location=(0.1, 0.8, 0.75), rotation=(math.radians(70), 0, math.radians(-15)),
                                     major_radius=0.6, minor_radius=0.22, major_segments=64, minor_segments=24)
    assign(bpy.context.object, material("gold", (1.0, 0.77, 0.34), metallic=1.0, roughness=0.25))
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=0.7, location=(1.9, -0.2, 0.7))
    assign(bpy.context.object, material("glass", (1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.45))
    light("POINT", "key", (3.0, -3.5, 4.5), 350.0)
    light("SPOT", "fill", (-5.0, -3.0, 3.0), 150.0, target=(0, 0, 0.6), spot_size=math.radians(70),
          spot_blend=0.15)
    light("SUN", "rim", (0, 6, 5), 1.0, target=(0, 0, 0))
    camera((0.0, -7.5, 3.2), (0.0, 0.2, 0.7), lens=38.0)
    export("showcase.gltf")


def backdrop():
    reset()
    floor(material("floor", (0.35, 0.35, 0.35), roughness=0.8), size=12.0)
    # The backdrop stands behind the ball, turned so the camera sees its back side: Blender's
    # default material is double-sided, so it renders the same either way round in Cycles.
    bpy.ops.mesh.primitive_plane_add(size=5.0, location=(0, 2.0, 2.5), rotation=(math.radians(-90), 0, 0))
    assign(bpy.context.object, material("grey backdrop", (0.5, 0.5, 0.5), roughness=0.6), smooth=False)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=0.6, location=(0, 0, 0.6))
    assign(bpy.context.object, material("red ball", (0.7, 0.08, 0.06), roughness=0.4))
    camera((0.0, -6.0, 2.2), (0.0, 0.5, 1.2), lens=40.0)
    export("backdrop.gltf")


def dim_light():
    reset()
    floor(material("grey floor", (0.5, 0.5, 0.5), roughness=0.8))
    monkey(material("clay", (0.62, 0.42, 0.32), roughness=0.75), (-0.6, 0.0, 0.8), math.radians(-15))
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(1.1, 0.4, 0.4), rotation=(0, 0, math.radians(25)))
    assign(bpy.context.object, material("blue box", (0.1, 0.2, 0.6), roughness=0.5), smooth=False)
    # 10 cd: Blender's exporter writes W / 4π × 683 cd for a point light.
    light("POINT", "lamp", (1.5, -2.0, 3.0), 10.0 * 4.0 * math.pi / 683.0)
    camera((0.0, -6.0, 2.6), (0.2, 0.0, 0.6), lens=40.0)
    export("dim_light.gltf")


if __name__ == "__main__":  # Blender runs --python scripts as __main__; make_blend_alpha.py imports the helpers
    showcase()
    backdrop()
    dim_light()
