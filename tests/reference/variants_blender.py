# A glTF file with KHR_materials_variants written by Blender 3.4's own exporter, for rayfarm's
# variants test (tests/engine/load/gltf/gltf_variants_test.cpp): a cube in a grey "paint" material and a
# metal sphere; variants "Ruby" and "Jade" give the cube's slot a red and a green material, the
# sphere has none. Made through the exporter's Material Variants UI, as a user would:
#   blender --background --factory-startup --python tests/reference/variants_blender.py
# writes tests/reference/variants_blender.gltf (+ .bin) beside this script.
import os

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))


def material(name, rgb, metallic=0.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = rgb + (1.0,)
    p.inputs["Metallic"].default_value = metallic
    p.inputs["Roughness"].default_value = 0.4
    return m


def main():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    prefs = bpy.context.preferences.addons["io_scene_gltf2"].preferences
    prefs.KHR_materials_variants_ui = True  # registers the variant properties and operators
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(-0.8, 0.5, 0.0))
    cube = bpy.context.object
    cube.name = "cube"
    cube.data.materials.append(material("paint", (0.5, 0.5, 0.5)))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(0.8, 0.5, 0.0))
    bpy.context.object.name = "sphere"
    bpy.context.object.data.materials.append(material("metal", (0.9, 0.9, 0.9), 1.0))
    scene = bpy.data.scenes[0]
    view = bpy.context.view_layer
    for name, rgb in (("Ruby", (0.8, 0.05, 0.05)), ("Jade", (0.05, 0.7, 0.2))):
        bpy.ops.scene.gltf2_variant_add()
        scene.gltf2_KHR_materials_variants_variants[scene.gltf2_active_variant].name = name
        cube.material_slots[0].material = material(name.lower(), rgb)
        view.objects.active = cube
        bpy.ops.scene.gltf2_assign_to_variant()
    # The slot's own (default) material again, as the file's default.
    cube.material_slots[0].material = bpy.data.materials["paint"]
    bpy.ops.export_scene.gltf(filepath=os.path.join(HERE, "variants_blender.gltf"), export_format="GLTF_SEPARATE",
                              export_yup=True)


main()
