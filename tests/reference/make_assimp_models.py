# Blender 3.4 script: one model exported by Blender's own exporters as glTF (GLB), OBJ (+MTL),
# STL (binary: the test writes the ASCII twin), PLY and FBX (Y up, and Z up to exercise the FBX axis settings), for
# tests/engine/load/assimp/assimp_blender_test.cpp: each format must render alike to the GLB.
#
#   blender -b --factory-startup --python tests/reference/make_assimp_models.py -- OUT_DIR
#
# The model: Suzanne (flat shaded, so every format carries the same normals) on a bevelled
# box, both in one material that STL's and PLY's neutral default matches (base colour 0.8,
# roughness 0.5, metallic 0, specular 0.5: the F0 of 0.04 glTF assumes). Asymmetric on every
# axis, so a wrong up or front axis shows.
import os
import sys

import bpy

out = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else "."
os.makedirs(out, exist_ok=True)

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.mesh.primitive_monkey_add(size=1.0, location=(0.0, 0.0, 0.9), rotation=(0.0, 0.0, 0.5))
monkey = bpy.context.active_object
bpy.ops.object.shade_flat()
bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.25, -0.1, 0.2))
box = bpy.context.active_object
box.scale = (1.4, 0.8, 0.4)
bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
bpy.ops.object.shade_flat()

mat = bpy.data.materials.new("clay")
mat.use_nodes = True
bsdf = mat.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1.0)
bsdf.inputs["Roughness"].default_value = 0.5
bsdf.inputs["Metallic"].default_value = 0.0
bsdf.inputs["Specular"].default_value = 0.5
for o in (monkey, box):
    o.data.materials.append(mat)

# One mesh object: every exporter writes the same single node, with the transforms applied.
bpy.ops.object.select_all(action="SELECT")
bpy.context.view_layer.objects.active = monkey
bpy.ops.object.join()
bpy.ops.object.transform_apply(location=True, rotation=True, scale=True)

path = lambda name: os.path.join(out, name)
bpy.ops.export_scene.gltf(filepath=path("suzanne.glb"), export_format="GLB")
bpy.ops.export_scene.obj(filepath=path("suzanne.obj"), use_materials=True, use_normals=True, use_uvs=False)
bpy.ops.export_mesh.stl(filepath=path("suzanne.stl"), ascii=False)  # Z up, as STL is by convention
# PLY is Y up by the convention of scans (Stanford's); Blender's exporter writes Z up unless told.
# Without normals: its exporter writes one smooth normal per merged vertex, and a PLY without
# normals is drawn flat, as glTF draws a mesh without them.
bpy.ops.export_mesh.ply(filepath=path("suzanne.ply"), axis_forward="-Z", axis_up="Y", use_normals=False, use_colors=False,
                        use_uv_coords=False)
bpy.ops.export_scene.fbx(filepath=path("suzanne.fbx"))
bpy.ops.export_scene.fbx(filepath=path("suzanne_zup.fbx"), axis_forward="Y", axis_up="Z")

# An animated model for the node animations of FBX and COLLADA: a cone (its tip shows the turn)
# that moves up and right and turns about Z over 2 s, keyed linearly at frames 1, 25 and 49
# (24 fps), over a still box; exported as GLB, FBX and COLLADA (Blender's own exporters).
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.mesh.primitive_cube_add(size=0.5, location=(0.0, 0.0, 0.0))
bpy.ops.mesh.primitive_cone_add(vertices=6, radius1=0.3, depth=0.6, location=(0.0, 0.0, 0.6), rotation=(0.0, 1.2, 0.0))
cone = bpy.context.active_object
bpy.ops.object.shade_flat()
scene = bpy.context.scene
scene.frame_start, scene.frame_end, scene.render.fps = 1, 49, 24
for frame, loc, rot in ((1, (0.0, 0.0, 0.6), 0.0), (25, (0.8, 0.0, 1.2), 1.5), (49, (0.0, 0.0, 0.6), 3.0)):
    cone.location = loc
    cone.rotation_euler = (0.0, 1.2, rot)
    cone.keyframe_insert("location", frame=frame)
    cone.keyframe_insert("rotation_euler", frame=frame)
for curve in cone.animation_data.action.fcurves:
    for key in curve.keyframe_points:
        key.interpolation = "LINEAR"
bpy.ops.export_scene.gltf(filepath=path("animated.glb"), export_format="GLB")
bpy.ops.export_scene.fbx(filepath=path("animated.fbx"), bake_anim_use_all_actions=False, bake_anim_use_nla_strips=False)
bpy.ops.wm.collada_export(filepath=path("animated.dae"))

# A skinned model for the skins of FBX and COLLADA: a cylinder 2 m tall (16 sides, 8 rings),
# bound to a chain of three bones along it by weights that blend linearly between neighbouring
# bones (up to 2 per vertex, made here, not by Blender's heat weighting, so every exporter writes
# the same). Over 2 s (frames 0, 24, 48 at 24 fps, linear) the middle and top bones bend it
# forward and back and the root bone turns it about its axis; exported as GLB, FBX (no leaf bones)
# and COLLADA. Its material is the clay of Suzanne, so the pictures compare by SSIM too.
import math

bpy.ops.wm.read_factory_settings(use_empty=True)
sides, rings, height, radius = 16, 8, 2.0, 0.25
verts = [(radius * math.cos(2 * math.pi * s / sides), radius * math.sin(2 * math.pi * s / sides), height * r / rings)
         for r in range(rings + 1) for s in range(sides)]
faces = [(r * sides + s, r * sides + (s + 1) % sides, (r + 1) * sides + (s + 1) % sides, (r + 1) * sides + s)
         for r in range(rings) for s in range(sides)]
faces.append(tuple(reversed(range(sides))))
faces.append(tuple(rings * sides + s for s in range(sides)))
mesh = bpy.data.meshes.new("tube")
mesh.from_pydata(verts, [], faces)
mesh.update()
tube = bpy.data.objects.new("tube", mesh)
bpy.context.scene.collection.objects.link(tube)

clay = bpy.data.materials.new("clay")
clay.use_nodes = True
b = clay.node_tree.nodes["Principled BSDF"]
b.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1.0)
b.inputs["Roughness"].default_value = 0.5
b.inputs["Metallic"].default_value = 0.0
b.inputs["Specular"].default_value = 0.5
tube.data.materials.clear()
tube.data.materials.append(clay)
for p in tube.data.polygons:
    p.use_smooth = True

arm_data = bpy.data.armatures.new("rig")
rig = bpy.data.objects.new("rig", arm_data)
bpy.context.scene.collection.objects.link(rig)
bpy.context.view_layer.objects.active = rig
bpy.ops.object.mode_set(mode="EDIT")
ends = (0.0, 0.7, 1.4, 2.0)
names = ("root", "middle", "top")
parent = None
for k, name in enumerate(names):
    bone = arm_data.edit_bones.new(name)
    bone.head, bone.tail = (0.0, 0.0, ends[k]), (0.0, 0.0, ends[k + 1])
    if parent:
        bone.parent, bone.use_connect = parent, True
    parent = bone
bpy.ops.object.mode_set(mode="OBJECT")

# Weights: each vertex between the centres of two neighbouring bones blends them linearly.
centres = [(ends[k] + ends[k + 1]) / 2 for k in range(3)]
groups = [tube.vertex_groups.new(name=n) for n in names]
for i, v in enumerate(tube.data.vertices):
    z = v.co.z
    if z <= centres[0]:
        groups[0].add([i], 1.0, "REPLACE")
    elif z >= centres[2]:
        groups[2].add([i], 1.0, "REPLACE")
    else:
        k = 0 if z < centres[1] else 1
        t = (z - centres[k]) / (centres[k + 1] - centres[k])
        groups[k].add([i], 1.0 - t, "REPLACE")
        groups[k + 1].add([i], t, "REPLACE")
tube.parent = rig
modifier = tube.modifiers.new("rig", "ARMATURE")
modifier.object = rig

scene = bpy.context.scene
scene.frame_start, scene.frame_end, scene.render.fps = 0, 48, 24
bpy.context.view_layer.objects.active = rig
bpy.ops.object.mode_set(mode="POSE")
for frame, bend, twist in ((0, 0.0, 0.0), (24, 0.7, 0.8), (48, -0.3, 1.6)):
    pose = rig.pose.bones
    for pb in pose:
        pb.rotation_mode = "XYZ"
    pose["root"].rotation_euler = (0.0, twist, 0.0)
    pose["middle"].rotation_euler = (bend, 0.0, 0.0)
    pose["top"].rotation_euler = (bend, 0.0, 0.0)
    for pb in pose:
        pb.keyframe_insert("rotation_euler", frame=frame)
bpy.ops.object.mode_set(mode="OBJECT")
for curve in rig.animation_data.action.fcurves:
    for key in curve.keyframe_points:
        key.interpolation = "LINEAR"
scene.frame_set(0)
bpy.ops.object.select_all(action="SELECT")
bpy.ops.export_scene.gltf(filepath=path("skinned.glb"), export_format="GLB")
bpy.ops.export_scene.fbx(filepath=path("skinned.fbx"), add_leaf_bones=False, bake_anim_use_all_actions=False,
                         bake_anim_use_nla_strips=False)
bpy.ops.wm.collada_export(filepath=path("skinned.dae"))

# Morph targets (shape keys) for FBX's blend shapes: a sphere with two shape keys, "tall"
# (twice as tall, its bottom at rest) and "wide" (1.8 times as wide in X), keyed over 2 s (frames
# 0, 24, 48 at 24 fps, linear): tall 0 → 1 → 0 while wide 0 → 0 → 1, so at some keys only one
# curve has a key of its own. Clay material, exported as GLB and FBX (Blender 3.4's COLLADA
# exporter writes no shape keys' animation).
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=0.5, location=(0.0, 0.0, 0.5))
ball = bpy.context.active_object
bpy.ops.object.shade_smooth()
putty = bpy.data.materials.new("clay")
putty.use_nodes = True
b = putty.node_tree.nodes["Principled BSDF"]
b.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1.0)
b.inputs["Roughness"].default_value = 0.5
b.inputs["Metallic"].default_value = 0.0
b.inputs["Specular"].default_value = 0.5
ball.data.materials.append(putty)
ball.shape_key_add(name="Basis")
tall = ball.shape_key_add(name="tall")
for v in tall.data:
    v.co.z = 2.0 * v.co.z + 0.5
wide = ball.shape_key_add(name="wide")
for v in wide.data:
    v.co.x *= 1.8
scene = bpy.context.scene
scene.frame_start, scene.frame_end, scene.render.fps = 0, 48, 24
for frame, a, b in ((0, 0.0, 0.0), (24, 1.0, 0.0), (48, 0.0, 1.0)):
    tall.value, wide.value = a, b
    tall.keyframe_insert("value", frame=frame)
    wide.keyframe_insert("value", frame=frame)
# No key of "wide" at frame 24: its curve runs from 0 at frame 0 to 1 at frame 48.
wide_curve = [c for c in ball.data.shape_keys.animation_data.action.fcurves if "wide" in c.data_path][0]
wide_curve.keyframe_points.remove(wide_curve.keyframe_points[1])
for curve in ball.data.shape_keys.animation_data.action.fcurves:
    for key in curve.keyframe_points:
        key.interpolation = "LINEAR"
scene.frame_set(0)
bpy.ops.export_scene.gltf(filepath=path("morph.glb"), export_format="GLB")
bpy.ops.export_scene.fbx(filepath=path("morph.fbx"), bake_anim_use_all_actions=False, bake_anim_use_nla_strips=False)
