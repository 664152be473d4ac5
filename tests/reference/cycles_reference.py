# Renders a glTF file with Blender Cycles, as a reference image for rayfarm's image tests and for
# `rayfarm report --reference`. Run it through cycles_reference.sh beside it (Blender in the
# background, factory settings); it is a developer tool, never a test dependency.
#
# What it sets up, so a rayfarm still with `--exposure 0 --tonemap clamp` is the fair match:
# - the file through Blender's own glTF importer, with the clearcoat, sheen and volume layers it
#   reads otherwise than their specifications rebuilt as they say (match_gltf_layers), lights in
#   its "Standard" lighting mode
#   (W = cd·4π/683, W/m² = lx/683: the photometric conversion rayfarm's --exposure 0 uses),
#   lights otherwise as imported (Blender's default point radius and sun angle);
# - the view through the file's camera N, counted as rayfarm's --camera N counts: perspective
#   cameras in the order of a depth-first walk of the scene's nodes;
# - a black world, or --environment FILE.exr|.hdr as the world at --environment-strength,
#   mapped as Blender maps an equirectangular image (the orientation rayfarm follows);
# - Standard view transform (sRGB, clamped, no look, exposure --exposure EV: rayfarm's --exposure EV), Cycles on the CPU at a fixed
#   number of samples (no adaptive sampling, no denoising, fixed seed), --bounces total bounces;
# - an 8-bit RGB PNG at --size (RGBA with --transparent: alpha is coverage);
# - --time T: the file's first animation posed at T seconds (skinned characters).
import argparse
import json
import math
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
    p.add_argument("--time", type=float, help="pose the file's first animation at T seconds (default: as imported)")
    p.add_argument("--all-animations", action="store_true",
                   help="play every animation of the file, not only the first: each object the importer left without an "
                        "action takes the one on its first (muted) NLA track")
    p.add_argument("--transparent", action="store_true",
                   help="transparent background: an RGBA PNG whose alpha is the model's coverage")
    p.add_argument("--exposure", type=float, default=0.0, help="view exposure in EV (default 0), as rayfarm's --exposure")
    p.add_argument("--multiscatter", action="store_true",
                   help="Principled BSDF's Multiscatter GGX (energy-conserving rough metals, as rayfarm's "
                        "compensation) instead of Blender 3.4's default single-scattering GGX")
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


def charlie_albedo(nv, roughness, theta_steps=96, phi_steps=48):
    """E(n·v) of KHR_materials_sheen's lobe (Charlie distribution, the extension's fitted
    visibility, sheen colour 1) by quadrature over the hemisphere, as rayfarm tabulates it
    (engine/materials/brdf_sheen.cpp: roughness from 0.07, alpha its square)."""
    alpha = max(0.07, min(1.0, roughness)) ** 2
    t = (1 - alpha) ** 2
    co = [a + (b - a) * t for a, b in ((21.5473, 25.3245), (3.82987, 3.32435), (0.19823, 0.16801),
                                        (-1.97760, -1.27393), (-4.32054, -4.85967))]

    def lam(c):
        fit = lambda x: co[0] / (1 + co[1] * x ** co[2]) + co[3] * x + co[4]
        return math.exp(fit(c)) if c < 0.5 else math.exp(2 * fit(0.5) - fit(1 - c))

    nv = max(1e-4, min(1.0, nv))
    v = (math.sqrt(1 - nv * nv), 0.0, nv)
    total = 0.0
    for i in range(theta_steps):
        c = (i + 0.5) / theta_steps
        s = math.sqrt(1 - c * c)
        for j in range(phi_steps):
            phi = math.pi * (j + 0.5) / phi_steps
            l = (s * math.cos(phi), s * math.sin(phi), c)
            h = [v[k] + l[k] for k in range(3)]
            hl = math.sqrt(sum(x * x for x in h))
            nh = h[2] / hl
            d = (2 + 1 / alpha) * max(0.0, 1 - nh * nh) ** (0.5 / alpha) / (2 * math.pi)
            vis = min(1.0, 1 / ((1 + lam(nv) + lam(c)) * 4 * nv * c))
            total += d * vis * c
    return total * 2 * math.pi / (theta_steps * phi_steps)


def match_gltf_layers(doc):
    """Blender 3.4's importer reads three material extensions otherwise than their specifications
    say; rebuild those layers so that Cycles renders what the file says:
    - KHR_materials_clearcoat becomes Principled's Clearcoat, a quarter-weight GTR lobe in
      Cycles 3.4: replaced by the glTF layering, a GGX Glossy BSDF of the coat's roughness mixed
      over the rest by clearcoat x Fresnel(ior 1.5);
    - KHR_materials_volume's attenuation becomes a Volume Absorption of colour c and density 1/d,
      which absorbs (1 - c)/d per unit length: set to sigma = -ln(c)/d, the Beer-Lambert law the
      extension gives (density max(sigma), colour 1 - sigma/density);
    - KHR_materials_sheen becomes a Velvet BSDF added over the base, with no albedo scaling: the
      base is now dimmed by 1 - max(sheenColor) x E(n.v), E the Charlie lobe's albedo (a Float
      Curve over Layer Weight's Facing). The Velvet lobe itself (Ashikhmin) stays: Cycles 3.4
      has no Charlie sheen, so the sheen's own shape is the one difference left (README).
    Factors only: a material with these extensions' textures keeps what the importer made."""
    for gm in doc.get("materials", []):
        ext = gm.get("extensions", {})
        bm = bpy.data.materials.get(gm.get("name", ""))
        if bm is None or not bm.use_nodes:
            continue
        nodes, links = bm.node_tree.nodes, bm.node_tree.links
        out = next(n for n in nodes if n.bl_idname == "ShaderNodeOutputMaterial")
        pr = next((n for n in nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"), None)
        vol = ext.get("KHR_materials_volume")
        if vol:
            absorb = next((n for n in nodes if n.bl_idname == "ShaderNodeVolumeAbsorption"), None)
            dist = vol.get("attenuationDistance")
            colour = vol.get("attenuationColor", [1, 1, 1])
            if absorb and dist:
                sigma = [-math.log(max(c, 1e-30)) / dist for c in colour]
                density = max(sigma)
                absorb.inputs["Density"].default_value = density
                absorb.inputs["Color"].default_value = [1 - sg / density if density > 0 else 1 for sg in sigma] + [1]
        sheen = ext.get("KHR_materials_sheen")
        if sheen and pr and "sheenColorTexture" not in sheen:
            m = max(sheen.get("sheenColorFactor", [0, 0, 0]))
            r = sheen.get("sheenRoughnessFactor", 0.0)
            add = next((n for n in nodes if n.bl_idname == "ShaderNodeAddShader"), None)
            if add and m > 0:
                to = next(l.to_socket for l in pr.outputs["BSDF"].links if l.to_node == add)
                weight = nodes.new("ShaderNodeLayerWeight")
                weight.inputs["Blend"].default_value = 0.5  # Facing = 1 - |n.v|
                curve = nodes.new("ShaderNodeFloatCurve")
                pts = curve.mapping.curves[0].points
                xs = [i / 16 for i in range(17)]
                ys = [min(1.0, m * charlie_albedo(1 - x, r)) for x in xs]
                pts[0].location, pts[1].location = (xs[0], ys[0]), (xs[-1], ys[-1])
                for x, y in zip(xs[1:-1], ys[1:-1]):
                    pts.new(x, y)
                curve.mapping.clip_max_y = 1.0
                curve.mapping.update()
                links.new(weight.outputs["Facing"], curve.inputs["Value"])
                black = nodes.new("ShaderNodeEmission")
                black.inputs["Strength"].default_value = 0.0
                mix = nodes.new("ShaderNodeMixShader")
                links.new(curve.outputs["Value"], mix.inputs["Fac"])
                links.new(pr.outputs["BSDF"], mix.inputs[1])
                links.new(black.outputs["Emission"], mix.inputs[2])
                links.new(mix.outputs["Shader"], to)
        coat = ext.get("KHR_materials_clearcoat")
        if coat and pr and "clearcoatTexture" not in coat and "clearcoatRoughnessTexture" not in coat:
            factor = coat.get("clearcoatFactor", 0.0)
            pr.inputs["Clearcoat"].default_value = 0.0
            if factor > 0:
                surface = out.inputs["Surface"].links[0].from_socket
                fresnel = nodes.new("ShaderNodeFresnel")
                fresnel.inputs["IOR"].default_value = 1.5
                scale = nodes.new("ShaderNodeMath")
                scale.operation = "MULTIPLY"
                scale.inputs[1].default_value = factor
                links.new(fresnel.outputs["Fac"], scale.inputs[0])
                glossy = nodes.new("ShaderNodeBsdfGlossy")
                glossy.distribution = "GGX"
                glossy.inputs["Color"].default_value = (1, 1, 1, 1)
                glossy.inputs["Roughness"].default_value = coat.get("clearcoatRoughnessFactor", 0.0)
                if pr.inputs["Clearcoat Normal"].is_linked:
                    nsrc = pr.inputs["Clearcoat Normal"].links[0].from_socket
                    links.new(nsrc, fresnel.inputs["Normal"])
                    links.new(nsrc, glossy.inputs["Normal"])
                mix = nodes.new("ShaderNodeMixShader")
                links.new(scale.outputs["Value"], mix.inputs["Fac"])
                links.new(surface, mix.inputs[1])
                links.new(glossy.outputs["BSDF"], mix.inputs[2])
                links.new(mix.outputs["Shader"], out.inputs["Surface"])


def use_multiscatter_ggx():
    """Every Principled BSDF to Multiscatter GGX. Blender 3.4's default GGX scatters once: a white
    metal of roughness 1 reflects 31% of a white world at normal incidence (rayfarm's split-sum
    table without its compensation says 30.7%), Multiscatter GGX all of it."""
    for bm in bpy.data.materials:
        if bm.use_nodes:
            for n in bm.node_tree.nodes:
                if n.bl_idname == "ShaderNodeBsdfPrincipled":
                    n.distribution = "MULTI_GGX"


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
    scene.render.film_transparent = a.transparent
    if a.threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = a.threads
    vs = scene.view_settings
    scene.display_settings.display_device = "sRGB"
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = a.exposure
    vs.gamma = 1.0
    img = scene.render.image_settings
    img.file_format = "PNG"
    img.color_mode = "RGBA" if a.transparent else "RGB"
    img.color_depth = "8"
    scene.render.filepath = a.out


def gltf_times(doc):
    """The first and last key time of the file's first animation (its samplers' inputs)."""
    anim = doc["animations"][0]
    acc = doc["accessors"]
    lo = min(acc[s["input"]]["min"][0] for s in anim["samplers"])
    hi = max(acc[s["input"]]["max"][0] for s in anim["samplers"])
    return lo, hi


def play_all_animations(scene):
    """Blender 3.4's glTF importer makes the file's first animation the objects' actions and
    stashes the others on muted NLA tracks: an object animated only by another animation (a
    Blender export's second object, its camera) stands still. Give each such object the action
    of its first track."""
    for o in scene.objects:
        ad = o.animation_data
        if not ad or ad.action:
            continue
        for track in ad.nla_tracks:
            if track.strips:
                ad.action = track.strips[0].action
                print("cycles_reference: %s plays %s" % (o.name, ad.action.name))
                break


def pose_at(scene, doc, t):
    """Sets the scene to glTF time t: the importer puts the first animation's keys on frames, so
    the frame is read back from where it put the first and last key (no assumption about its
    frame rate or offset), and set with its fraction as a subframe."""
    if not doc.get("animations"):
        raise SystemExit("--time: the file has no animations")
    actions = [o.animation_data.action for o in scene.objects if o.animation_data and o.animation_data.action]
    if not actions:
        raise SystemExit("--time: the importer made no action")
    f0 = min(a.frame_range[0] for a in actions)
    f1 = max(a.frame_range[1] for a in actions)
    t0, t1 = gltf_times(doc)
    f = f0 + (t - t0) * (f1 - f0) / (t1 - t0) if t1 > t0 else f0
    scene.frame_set(int(f // 1), subframe=f % 1)
    print("cycles_reference: glTF time %.4f s is frame %.4f (keys %.3f..%.3f s on frames %.3f..%.3f)" % (t, f, t0, t1, f0, f1))


def main():
    a = parse_args()
    restore_numpy_aliases()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    doc = read_gltf_json(a.gltf)
    bpy.ops.import_scene.gltf(filepath=a.gltf, convert_lighting_mode="SPEC")
    scene = bpy.context.scene
    match_gltf_layers(doc)
    if a.multiscatter:
        use_multiscatter_ggx()
    scene.camera = pick_camera(doc, a.camera)
    set_world(scene, a.environment, a.environment_strength)
    if a.all_animations:
        play_all_animations(scene)
    if a.time is not None:
        pose_at(scene, doc, a.time)
    set_render(scene, a)
    t0 = time.monotonic()
    bpy.ops.render.render(write_still=True)
    print("cycles_reference: wrote %s (%dx%d, %d samples) in %.2f s render"
          % (a.out, a.width, a.height, a.samples, time.monotonic() - t0))


main()
