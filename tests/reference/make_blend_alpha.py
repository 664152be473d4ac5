# Builds blend_alpha.gltf in Blender and writes it with Blender's own glTF exporter:
#   blender --background --factory-startup --python tests/reference/make_blend_alpha.py
# (a developer tool, as make_blender_scenes.py, whose helpers it uses). A red ball and a grey box
# on a floor stand behind a vertical pane whose blue texture carries the alpha: 0.25 in its left
# third, 0.75 in the middle, 1 in the right third, and its material blends (Blender's Blend Mode
# "Alpha Blend", which the exporter writes as alphaMode BLEND with the alpha in the base-colour
# texture; its alpha factor stays 1). A sun behind the camera throws the pane's partial shadow
# on the floor. cycles_blend_alpha_test renders it against Cycles under the courtyard.
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_blender_scenes import HERE, assign, camera, floor, light, material, reset  # noqa: E402


def alpha_image(path, size=48):
    img = bpy.data.images.new("pane alpha", size, size, alpha=True)
    px = []
    for _ in range(size):
        for x in range(size):
            a = 0.25 if x < size // 3 else 0.75 if x < 2 * size // 3 else 1.0
            px += [0.15, 0.35, 0.9, a]
    img.pixels = px
    img.filepath_raw = path
    img.file_format = "PNG"
    img.save()
    return bpy.data.images.load(path)


def blend_alpha():
    reset()
    floor(material("floor", (0.45, 0.45, 0.45), roughness=0.8), size=12.0)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=0.6, location=(-0.5, 1.2, 0.6))
    assign(bpy.context.object, material("red ball", (0.7, 0.08, 0.06), roughness=0.4))
    bpy.ops.mesh.primitive_cube_add(size=0.9, location=(1.0, 1.4, 0.45), rotation=(0, 0, math.radians(20)))
    assign(bpy.context.object, material("grey box", (0.6, 0.6, 0.6), roughness=0.5), smooth=False)

    pane = material("blended pane", (1.0, 1.0, 1.0), roughness=0.5)
    pane.blend_method = "BLEND"
    pane.shadow_method = "HASHED"
    nodes, links = pane.node_tree.nodes, pane.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = alpha_image(os.path.join(HERE, "blend_alpha_pane.png"))
    bsdf = nodes["Principled BSDF"]
    links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    links.new(tex.outputs["Alpha"], bsdf.inputs["Alpha"])
    bpy.ops.mesh.primitive_plane_add(size=3.0, location=(0, 0.2, 1.2), rotation=(math.radians(90), 0, 0))
    assign(bpy.context.object, pane, smooth=False)

    light("SUN", "sun", (0, -6, 6), 2.0, target=(0, 1.0, 0))
    camera((0.4, -6.0, 2.0), (0.0, 0.6, 0.9), lens=40.0)
    bpy.ops.export_scene.gltf(filepath=os.path.join(HERE, "blend_alpha.gltf"), export_format="GLTF_SEPARATE",
                              export_lights=True, export_cameras=True, export_apply=True)


blend_alpha()
