# Builds a small animated scene in Blender and writes it with Blender's own glTF exporter, for
# issue 42's tests (a file's animated camera drives the film; several animations play together;
# a file of two scenes):
#   blender --background --factory-startup --python tests/reference/make_animated_camera.py
# (Blender 3.4 with python3-numpy; a developer tool, no test runs it). Writes beside this script
# animated_camera.gltf (+ .bin):
# - scene 0 "Stage": a grey floor, three cubes (red, green, blue), each with an action of its
#   own (so the exporter writes one animation per object: "RedSpin" 2 s, "GreenHop" 1 s,
#   "BlueSlide" 4/3 s), a sun, and a camera flown along a path of keyed positions over 2 s
#   (frames 1-49 at 24 fps), aimed at the middle cube at every key ("CameraFly");
# - scene 1 "Spare": a yellow ball and a still camera looking at it.
# and animated_camera_stage.gltf (+ .bin): the Stage scene alone, for the Cycles references
# (Blender's glTF importer draws every scene of a file at once, so a reference of the
# two-scene file would show the Spare ball and its sun in the Stage).
# The keys are LINEAR so the camera's path between keys is what both Blender and rayfarm
# interpolate the same way.
import math
import os

import bpy
from mathutils import Vector

HERE = os.path.dirname(os.path.abspath(__file__))


def material(name, color, roughness=0.6):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    return m


def aim_euler(location, target):
    d = Vector(target) - Vector(location)
    return d.to_track_quat("-Z", "Y").to_euler()


def linear(obj):
    for fc in obj.animation_data.action.fcurves:
        for k in fc.keyframe_points:
            k.interpolation = "LINEAR"


def cube(name, location, color, size=1.0):
    bpy.ops.mesh.primitive_cube_add(size=size, location=location)
    c = bpy.context.object
    c.name = name
    c.data.materials.append(material(name.lower(), color))
    return c


bpy.ops.wm.read_factory_settings(use_empty=True)
stage = bpy.context.scene
stage.name = "Stage"
stage.render.fps = 24
stage.frame_start = 1
stage.frame_end = 49

bpy.ops.mesh.primitive_plane_add(size=14.0, location=(0, 0, 0))
bpy.context.object.data.materials.append(material("floor", (0.5, 0.5, 0.5), 0.8))

red = cube("Red", (-2.2, 0, 0.5), (0.8, 0.05, 0.05))
red.animation_data_create()
red.animation_data.action = bpy.data.actions.new("RedSpin")
for f, a in ((1, 0.0), (49, 180.0)):
    red.rotation_euler = (0, 0, math.radians(a))
    red.keyframe_insert("rotation_euler", frame=f)
linear(red)

green = cube("Green", (0, 0, 0.5), (0.05, 0.7, 0.1))
green.animation_data_create()
green.animation_data.action = bpy.data.actions.new("GreenHop")
for f, z in ((1, 0.5), (13, 1.5), (25, 0.5)):
    green.location = (0, 0, z)
    green.keyframe_insert("location", frame=f)
linear(green)

blue = cube("Blue", (2.2, 0, 0.5), (0.05, 0.15, 0.8))
blue.animation_data_create()
blue.animation_data.action = bpy.data.actions.new("BlueSlide")
for f, y in ((1, 0.0), (17, 1.5), (33, 0.0)):
    blue.location = (2.2, y, 0.5)
    blue.keyframe_insert("location", frame=f)
linear(blue)

bpy.ops.object.light_add(type="SUN", location=(3, -4, 6))
sun = bpy.context.object
sun.data.energy = 3.0
sun.rotation_euler = aim_euler((3, -4, 6), (0, 0, 0))

bpy.ops.object.camera_add(location=(7, -7, 3))
cam = bpy.context.object
cam.name = "FlyCam"
cam.data.lens = 35.0
stage.camera = cam
cam.animation_data_create()
cam.animation_data.action = bpy.data.actions.new("CameraFly")
path = ((1, (7.0, -7.0, 3.0)), (17, (2.0, -9.0, 4.0)), (33, (-4.0, -8.0, 3.5)), (49, (-8.0, -4.0, 2.5)))
for f, p in path:
    cam.location = p
    cam.rotation_euler = aim_euler(p, (0, 0, 0.6))
    cam.keyframe_insert("location", frame=f)
    cam.keyframe_insert("rotation_euler", frame=f)
linear(cam)

spare = bpy.data.scenes.new("Spare")
bpy.context.window.scene = spare
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.8, location=(0, 0, 0.8))
bpy.context.object.name = "Ball"
bpy.context.object.data.materials.append(material("yellow", (0.8, 0.7, 0.05)))
bpy.ops.object.light_add(type="SUN", location=(2, -3, 5))
bpy.context.object.data.energy = 3.0
bpy.context.object.rotation_euler = aim_euler((2, -3, 5), (0, 0, 0))
bpy.ops.object.camera_add(location=(0, -5, 1.5))
spare_cam = bpy.context.object
spare_cam.name = "SpareCam"
spare_cam.rotation_euler = aim_euler((0, -5, 1.5), (0, 0, 0.8))
spare.camera = spare_cam
bpy.context.window.scene = stage

bpy.ops.export_scene.gltf(filepath=os.path.join(HERE, "animated_camera.gltf"), export_format="GLTF_SEPARATE",
                          export_lights=True, export_cameras=True, export_apply=True, use_active_scene=False)
bpy.ops.export_scene.gltf(filepath=os.path.join(HERE, "animated_camera_stage.gltf"), export_format="GLTF_SEPARATE",
                          export_lights=True, export_cameras=True, export_apply=True, use_active_scene=True)
