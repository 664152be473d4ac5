# Builds points_lines.glb in Blender and writes it with Blender's own glTF exporter, loose points
# and edges included (the exporter's "Loose Points" and "Loose Edges"):
#   blender --background --factory-startup --python tests/reference/make_points_lines.py
# (a developer tool, as make_blender_scenes.py). One mesh object: a cube's faces, a ring of 24
# loose vertices around it coloured from red to blue through a colour attribute, and a loose
# helix of edges above it. The exporter writes the faces as TRIANGLES, the vertices as POINTS
# and the edges as LINES, all three with COLOR_0.
import math
import os

import bmesh
import bpy

HERE = os.path.dirname(os.path.abspath(__file__))

bpy.ops.wm.read_factory_settings(use_empty=True)
mesh = bpy.data.meshes.new("cube points lines")
bm = bmesh.new()
bmesh.ops.create_cube(bm, size=1.0)
for k in range(24):
    t = 2.0 * math.pi * k / 24
    bm.verts.new((1.6 * math.cos(t), 1.6 * math.sin(t), 0.0))
prev = None
for k in range(61):
    t = 4.0 * math.pi * k / 60
    v = bm.verts.new((0.6 * math.cos(t), 0.6 * math.sin(t), 0.8 + 0.8 * k / 60))
    if prev is not None:
        bm.edges.new((prev, v))
    prev = v
bm.to_mesh(mesh)
bm.free()
colors = mesh.color_attributes.new("Col", "FLOAT_COLOR", "POINT")
for i, v in enumerate(mesh.vertices):
    s = max(0.0, min(1.0, (v.co.x + 1.6) / 3.2))
    colors.data[i].color = (1.0 - s, 0.2, s, 1.0)
obj = bpy.data.objects.new("cube points lines", mesh)
bpy.context.scene.collection.objects.link(obj)
bpy.ops.export_scene.gltf(filepath=os.path.join(HERE, "points_lines.glb"), export_format="GLB",
                          use_mesh_edges=True, use_mesh_vertices=True, export_colors=True)
