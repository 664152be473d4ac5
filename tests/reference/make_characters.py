# Writes the skinned test assets of tests/reference/characters/ (CC0, made for rayfarm) with
# Blender 3.4, as an artist would make them, and exports each to glTF:
# - walker.gltf: a character of one connected mesh (a Skin modifier over a stick figure,
#   subdivided), an armature of 13 bones, automatic weights (bone heat), a one-second walk cycle
#   (legs, arms, a bobbing pelvis), a painted baseColor texture, a camera and two suns;
# - car.gltf: a car whose body and four wheels are rigid parts of one skinned mesh: the body on
#   one joint, the wheels on two (front and rear axle), which spin once a second while the
#   body bobs; a spoke texture on the wheels so that their turn shows; the same camera and suns.
# Run it in Blender (no test runs Blender):
#   blender --background --factory-startup --python tests/reference/make_characters.py -- OUTDIR
# then render the references with cycles_reference.sh --time T --transparent (README.md).
import math
import os
import sys

import bpy
import bmesh
from mathutils import Matrix, Vector

OUT = os.path.abspath(sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else os.path.dirname(__file__))
FPS = 24


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.frame_start, scene.frame_end = 0, FPS
    return scene


def save_png(name, w, h, pixel):
    """An RGBA image of pixel(x, y) -> (r, g, b) in [0, 1] (sRGB), saved as OUT/name and loaded."""
    img = bpy.data.images.new(name, w, h, alpha=False)
    px = []
    for y in range(h):
        for x in range(w):
            r, g, b = pixel(x, y)
            px += [r, g, b, 1.0]
    img.pixels = px
    img.filepath_raw = os.path.join(OUT, name)
    img.file_format = "PNG"
    img.save()
    return img


def textured_material(name, image, roughness=0.6):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    bsdf = nt.nodes["Principled BSDF"]
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular"].default_value = 0.5
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = image
    nt.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return m


def plain_material(name, rgb, roughness=0.5, metallic=0.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*rgb, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    return m


def camera_and_suns(location, target, lens=50.0):
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.data.lens = lens
    cam.data.sensor_fit = "VERTICAL"
    cam.data.sensor_height = 24.0
    cam.location = location
    cam.rotation_euler = (Vector(target) - Vector(location)).to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(cam)
    for name, strength, rot in (("key", 3.0, (math.radians(50), 0, math.radians(-35))),
                                ("fill", 1.0, (math.radians(70), 0, math.radians(150)))):
        sun = bpy.data.objects.new(name, bpy.data.lights.new(name, "SUN"))
        sun.data.energy = strength
        sun.rotation_euler = rot
        bpy.context.scene.collection.objects.link(sun)


def export(name):
    bpy.ops.export_scene.gltf(filepath=os.path.join(OUT, name + ".gltf"), export_format="GLTF_SEPARATE",
                              export_animations=True, export_skins=True, export_cameras=True, export_lights=True,
                              export_yup=True, export_apply=False, export_force_sampling=True,
                              export_frame_range=True)


def select_only(*objs, active):
    bpy.ops.object.select_all(action="DESELECT")
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = active


# ---------------------------------------------------------------- walker
def walker():
    scene = reset()
    # A stick figure (Blender Z up, the character faces -Y): joints and the radius of the body there.
    joints = {
        "pelvis": ((0, 0, 0.95), 0.13), "waist": ((0, 0, 1.12), 0.12), "chest": ((0, 0, 1.36), 0.15),
        "neck": ((0, 0, 1.56), 0.06), "head": ((0, 0, 1.70), 0.12), "crown": ((0, 0, 1.86), 0.07),
    }
    for s, x in (("L", 1), ("R", -1)):
        joints.update({
            "hip." + s: ((0.10 * x, 0, 0.92), 0.08), "knee." + s: ((0.11 * x, 0, 0.52), 0.06),
            "ankle." + s: ((0.12 * x, 0, 0.10), 0.05), "toe." + s: ((0.12 * x, -0.14, 0.04), 0.04),
            "shoulder." + s: ((0.21 * x, 0, 1.47), 0.06), "elbow." + s: ((0.27 * x, 0, 1.20), 0.045),
            "wrist." + s: ((0.30 * x, 0, 0.95), 0.04), "hand." + s: ((0.31 * x, 0, 0.86), 0.045),
        })
    edges = [("pelvis", "waist"), ("waist", "chest"), ("chest", "neck"), ("neck", "head"), ("head", "crown")]
    for s in "LR":
        edges += [("pelvis", "hip." + s), ("hip." + s, "knee." + s), ("knee." + s, "ankle." + s), ("ankle." + s, "toe." + s),
                  ("chest", "shoulder." + s), ("shoulder." + s, "elbow." + s), ("elbow." + s, "wrist." + s),
                  ("wrist." + s, "hand." + s)]
    names = list(joints)
    mesh = bpy.data.meshes.new("walker")
    mesh.from_pydata([joints[n][0] for n in names], [(names.index(a), names.index(b)) for a, b in edges], [])
    body = bpy.data.objects.new("walker", mesh)
    scene.collection.objects.link(body)
    skin = body.modifiers.new("skin", "SKIN")
    for i, n in enumerate(names):
        r = joints[n][1]
        body.data.skin_vertices[0].data[i].radius = (r, r)
    body.data.skin_vertices[0].data[names.index("pelvis")].use_root = True
    sub = body.modifiers.new("subdivide", "SUBSURF")
    sub.levels = 2
    select_only(body, active=body)
    bpy.ops.object.modifier_apply(modifier="skin")
    bpy.ops.object.modifier_apply(modifier="subdivide")
    bpy.ops.object.shade_smooth()
    # UVs by a cylinder around the body's axis (u: around, v: up), so the painted bands ring it.
    bpy.ops.object.mode_set(mode="EDIT")
    bm = bmesh.from_edit_mesh(body.data)
    uv = bm.loops.layers.uv.verify()
    for f in bm.faces:
        us = []
        for loop in f.loops:
            p = loop.vert.co
            us.append((math.atan2(p.x, -p.y) / (2 * math.pi) + 0.5, p.z / 1.9))
        # Faces that straddle the seam at the back take the near side of it.
        if max(u for u, _ in us) - min(u for u, _ in us) > 0.5:
            us = [(u + 1.0 if u < 0.5 else u, v) for u, v in us]
        for loop, (u, v) in zip(f.loops, us):
            loop[uv].uv = (u, v)
    bmesh.update_edit_mesh(body.data)
    bpy.ops.object.mode_set(mode="OBJECT")

    def paint(x, y):  # bands up the body, a checker around it: a pose moves them visibly
        u, v = x / 128.0, y / 128.0
        band = int(v * 12) % 3
        base = ((0.80, 0.35, 0.15), (0.20, 0.45, 0.75), (0.85, 0.80, 0.30))[band]
        return base if (int(u * 16) + int(v * 24)) % 2 else tuple(0.6 * c for c in base)

    body.data.materials.append(textured_material("walker_skin", save_png("walker_skin.png", 128, 128, paint)))

    arm_data = bpy.data.armatures.new("walker_rig")
    rig = bpy.data.objects.new("walker_rig", arm_data)
    scene.collection.objects.link(rig)
    select_only(rig, active=rig)
    bpy.ops.object.mode_set(mode="EDIT")
    bones = {}

    def bone(name, head, tail, parent=None):
        b = arm_data.edit_bones.new(name)
        b.head, b.tail = Vector(head), Vector(tail)
        b.roll = 0.0
        if parent:
            b.parent = bones[parent]
            b.use_connect = (bones[parent].tail - b.head).length < 1e-6
        bones[name] = b

    P = lambda n: joints[n][0]
    bone("hips", (0, 0, 0.85), P("pelvis"))
    bone("spine", P("pelvis"), P("waist"), "hips")
    bone("chest", P("waist"), P("neck"), "spine")
    bone("neck", P("neck"), P("head"), "chest")
    bone("head", P("head"), P("crown"), "neck")
    for s in "LR":
        bone("thigh." + s, P("hip." + s), P("knee." + s), "hips")
        bone("shin." + s, P("knee." + s), P("ankle." + s), "thigh." + s)
        bone("upper_arm." + s, P("shoulder." + s), P("elbow." + s), "chest")
        bone("forearm." + s, P("elbow." + s), P("hand." + s), "upper_arm." + s)
    bpy.ops.object.mode_set(mode="OBJECT")
    assert len(arm_data.bones) == 13, len(arm_data.bones)
    select_only(body, rig, active=rig)
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    unweighted = sum(1 for v in body.data.vertices if not v.groups)
    print("walker: %d vertices, %d faces, %d without weights" % (len(body.data.vertices), len(body.data.polygons), unweighted))
    assert unweighted == 0, "bone heat left vertices without weights"

    # The walk: one cycle a second (frames 0..24), legs and arms opposite, the pelvis bobbing.
    rig.animation_data_create()
    rig.animation_data.action = bpy.data.actions.new("walk")
    for pb in rig.pose.bones:
        pb.rotation_mode = "XYZ"
    swing = {0: 1.0, 6: 0.0, 12: -1.0, 18: 0.0, 24: 1.0}
    for f, k in swing.items():
        for s, sign in (("L", 1.0), ("R", -1.0)):
            t = rig.pose.bones["thigh." + s]
            t.rotation_euler = (math.radians(-28 * k * sign), 0, 0)
            t.keyframe_insert("rotation_euler", frame=f)
            sh = rig.pose.bones["shin." + s]
            # The knee bends as the leg swings forward (only backwards, as a knee does).
            sh.rotation_euler = (math.radians(35 * max(0.0, -k * sign) + 10), 0, 0)
            sh.keyframe_insert("rotation_euler", frame=f)
            ua = rig.pose.bones["upper_arm." + s]
            ua.rotation_euler = (math.radians(24 * k * sign), 0, 0)
            ua.keyframe_insert("rotation_euler", frame=f)
            fa = rig.pose.bones["forearm." + s]
            fa.rotation_euler = (math.radians(-20 - 15 * max(0.0, k * sign)), 0, 0)
            fa.keyframe_insert("rotation_euler", frame=f)
        hips = rig.pose.bones["hips"]
        hips.location = (0, 0.04 * abs(k), 0)  # bone space: +Y along the bone, i.e. up
        hips.keyframe_insert("location", frame=f)
        chest = rig.pose.bones["chest"]
        chest.rotation_euler = (0, math.radians(8 * k), 0)  # the shoulders turn against the hips
        chest.keyframe_insert("rotation_euler", frame=f)
        head = rig.pose.bones["head"]
        head.rotation_euler = (math.radians(-6 * abs(k)), 0, 0)
        head.keyframe_insert("rotation_euler", frame=f)
    camera_and_suns((1.9, -3.4, 1.45), (0, 0, 0.95))
    export("walker")


# ---------------------------------------------------------------- car
def car():
    scene = reset()
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=1.0, matrix=Matrix.Diagonal((1.0, 2.0, 0.45, 1.0)) @ Matrix.Translation((0, 0, 1.0)))
    bmesh.ops.create_cube(bm, size=1.0, matrix=Matrix.Translation((0, 0.15, 0.78)) @ Matrix.Diagonal((0.85, 1.0, 0.35, 1.0)))
    body_mesh = bpy.data.meshes.new("car")
    bm.to_mesh(body_mesh)
    bm.free()
    car = bpy.data.objects.new("car", body_mesh)
    scene.collection.objects.link(car)
    body_mesh.materials.append(plain_material("paint", (0.70, 0.08, 0.06), roughness=0.35))
    body_mesh.materials.append(textured_material("tyre", save_png("car_wheel.png", 64, 64, lambda x, y: (
        (0.9, 0.9, 0.85) if (int(math.atan2(y - 31.5, x - 31.5) / (2 * math.pi) * 6 + 6) % 2 and
                             math.hypot(x - 31.5, y - 31.5) < 24) else (0.06, 0.06, 0.07))), roughness=0.8))
    wheels = []
    for name, y in (("front", -0.62), ("rear", 0.62)):
        for x in (-0.55, 0.55):
            bm = bmesh.new()
            bmesh.ops.create_cone(bm, cap_ends=True, segments=24, radius1=0.3, radius2=0.3, depth=0.18,
                                  matrix=Matrix.Translation((x, y, 0.3)) @ Matrix.Rotation(math.pi / 2, 4, "Y"))
            # The hub texture on both caps (planar along the axle), the tread in the dark.
            uv = bm.loops.layers.uv.verify()
            for f in bm.faces:
                for loop in f.loops:
                    p = loop.vert.co
                    loop[uv].uv = ((p.y - y) / 0.62 + 0.5, (p.z - 0.3) / 0.62 + 0.5)
            m = bpy.data.meshes.new("wheel")
            bm.to_mesh(m)
            bm.free()
            w = bpy.data.objects.new("wheel", m)
            scene.collection.objects.link(w)
            w.data.materials.append(body_mesh.materials[1])
            wheels.append((w, name))
    # One mesh: the body's polygons use material 0, the wheels' material 1.
    groups = {}
    select_only(car, *[w for w, _ in wheels], active=car)
    body_count = len(body_mesh.vertices)
    bpy.ops.object.join()
    car = bpy.context.view_layer.objects.active
    for p in car.data.polygons:
        p.use_smooth = False
    arm_data = bpy.data.armatures.new("car_rig")
    rig = bpy.data.objects.new("car_rig", arm_data)
    scene.collection.objects.link(rig)
    select_only(rig, active=rig)
    bpy.ops.object.mode_set(mode="EDIT")
    root = arm_data.edit_bones.new("body")
    root.head, root.tail = Vector((0, 0, 0.3)), Vector((0, 0, 0.9))
    for name, y in (("front", -0.62), ("rear", 0.62)):
        b = arm_data.edit_bones.new("axle_" + name)
        b.head, b.tail = Vector((-0.55, y, 0.3)), Vector((0.55, y, 0.3))
        b.parent = root
    bpy.ops.object.mode_set(mode="OBJECT")
    # Rigid parts: every vertex wholly on one bone, by where it sits.
    for g in ("body", "axle_front", "axle_rear"):
        groups[g] = car.vertex_groups.new(name=g)
    for v in car.data.vertices:
        if v.index < body_count:
            groups["body"].add([v.index], 1.0, "REPLACE")
        else:
            groups["axle_front" if v.co.y < 0 else "axle_rear"].add([v.index], 1.0, "REPLACE")
    mod = car.modifiers.new("rig", "ARMATURE")
    mod.object = rig
    car.parent = rig
    rig.animation_data_create()
    rig.animation_data.action = bpy.data.actions.new("drive")
    for pb in rig.pose.bones:
        pb.rotation_mode = "XYZ"
    for f in range(0, FPS + 1, 3):
        turn = -2 * math.pi * f / FPS  # one turn a second, rolling towards -Y
        for name in ("axle_front", "axle_rear"):
            pb = rig.pose.bones[name]
            pb.rotation_euler = (0, turn, 0)  # about the bone's own axis, the axle
            pb.keyframe_insert("rotation_euler", frame=f)
        body = rig.pose.bones["body"]
        body.location = (0, 0.03 * math.sin(4 * math.pi * f / FPS), 0)
        body.rotation_euler = (math.radians(2.5 * math.sin(2 * math.pi * f / FPS)), 0, 0)
        body.keyframe_insert("location", frame=f)
        body.keyframe_insert("rotation_euler", frame=f)
    camera_and_suns((3.2, -4.2, 2.2), (0, 0, 0.55), lens=45.0)
    export("car")


os.makedirs(OUT, exist_ok=True)
walker()
car()
print("make_characters: wrote", OUT)
