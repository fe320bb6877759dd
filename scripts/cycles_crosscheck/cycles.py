"""Blender's side: the glTF import with its material adjustments (GGX, glTF's default material,
single-sided faces, the material extensions' Principled inputs), the Cycles settings, world and
camera that match chiaro's, and the renders."""

import math
import time

import numpy as np

from . import log

# glTF (+Y up) -> Blender (+Z up), as Blender's glTF importer converts: (x, y, z) -> (x, -z, y).
GLTF_TO_BLENDER = np.array(
    [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
)


def try_set(obj, name, value):
    if hasattr(obj, name):
        try:
            setattr(obj, name, value)
            return True
        except (TypeError, AttributeError, ValueError) as e:
            log(f"    (could not set {name} = {value!r}: {e})")
    return False


# The Principled BSDF inputs that glTF's material extensions map to, as the spec defines the
# material (Blender's importer, io_scene_gltf2/blender/imp/pbrMetallicRoughness.py, sets the same
# sockets; this checks them after import and sets any that differ). Each entry: extension,
# Principled input, value from the extension's dict (None: leave the socket alone).
EXTENSION_SOCKETS = [
    ("KHR_materials_clearcoat", "Coat Weight", lambda e: e.get("clearcoatFactor", 0.0)),
    # The spec's default clearcoatRoughnessFactor is 0; the importer puts 0.03 when it is absent.
    ("KHR_materials_clearcoat", "Coat Roughness", lambda e: e.get("clearcoatRoughnessFactor", 0.0)),
    # The clear coat is a dielectric of IOR 1.5 (F0 0.04), colourless.
    ("KHR_materials_clearcoat", "Coat IOR", lambda e: 1.5),
    ("KHR_materials_clearcoat", "Coat Tint", lambda e: [1.0, 1.0, 1.0]),
    # Principled scales F0 by 2 x "Specular IOR Level": 0.5 x specularFactor scales it by the factor.
    ("KHR_materials_specular", "Specular IOR Level", lambda e: 0.5 * e.get("specularFactor", 1.0)),
    ("KHR_materials_specular", "Specular Tint", lambda e: list(e.get("specularColorFactor", [1.0] * 3))),
    ("KHR_materials_transmission", "Transmission Weight", lambda e: e.get("transmissionFactor", 0.0)),
]


def check_extension_sockets(doc, notes):
    """After import: for each glTF material with KHR_materials_clearcoat / _specular /
    _transmission, check the Principled BSDF's inputs against EXTENSION_SOCKETS and set those
    that differ (a linked input, i.e. a texture, is left alone and reported)."""
    import bpy

    checked, fixed, linked = 0, [], []
    for i, gm in enumerate(doc.get("materials", [])):
        exts = gm.get("extensions", {}) or {}
        wanted = [(ext, sock, f(exts[ext])) for ext, sock, f in EXTENSION_SOCKETS if ext in exts]
        if not wanted:
            continue
        mat = bpy.data.materials.get(gm.get("name", f"Material_{i}"))
        if mat is None or not mat.node_tree:
            notes.append(f"material {i} ({gm.get('name')}) not found after import: extensions unchecked")
            continue
        pr = [n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED"]
        if len(pr) != 1:
            notes.append(f"material {mat.name}: {len(pr)} Principled BSDFs, extensions unchecked")
            continue
        node = pr[0]
        for ext, sock, value in wanted:
            inp = node.inputs[sock]
            checked += 1
            if inp.is_linked:
                linked.append(f"{mat.name}.{sock}")
                continue
            cur = inp.default_value
            if isinstance(value, list):
                ok = all(abs(cur[k] - value[k]) < 1e-6 for k in range(3))
                new = (value[0], value[1], value[2], 1.0)
            else:
                ok = abs(cur - value) < 1e-6
                new = value
            if not ok:
                was = [round(float(v), 4) for v in cur[:3]] if isinstance(value, list) else round(float(cur), 4)
                fixed.append(f"{mat.name}.{sock} {was} -> {value}")
                inp.default_value = new
    if checked:
        notes.append(f"{checked} extension inputs checked"
                     + (f", set here: {'; '.join(fixed)}" if fixed else ", all as the importer set them")
                     + (f", linked (textured, left alone): {', '.join(linked)}" if linked else ""))


def blender_import(scene_path, args, doc=None):
    """Fresh Blender state with the scene imported and its materials adjusted; returns notes."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    notes = []
    res = bpy.ops.import_scene.gltf(
        filepath=scene_path, export_import_convert_lighting_mode=args.lighting_mode
    )
    if "FINISHED" not in res:
        raise RuntimeError(f"Blender's glTF import returned {res}")

    # glTF's default material for primitives without one (chiaro does the same).
    default_mat = None
    for ob in bpy.data.objects:
        if ob.type != "MESH":
            continue
        slots = ob.material_slots
        if len(slots) == 0 or all(s.material is None for s in slots):
            if default_mat is None:
                default_mat = bpy.data.materials.new("gltf_default")
                default_mat.use_nodes = True
                p = default_mat.node_tree.nodes.get("Principled BSDF")
                p.inputs["Base Color"].default_value = (1, 1, 1, 1)
                p.inputs["Metallic"].default_value = 1.0
                p.inputs["Roughness"].default_value = 1.0
                default_mat.use_backface_culling = True
                notes.append("glTF default material added")
            if len(slots) == 0:
                ob.data.materials.append(default_mat)
            else:
                for s in slots:
                    s.material = default_mat

    n_principled = 0
    n_single = 0
    for mat in bpy.data.materials:
        if not mat.node_tree:
            continue
        trees = [mat.node_tree] + [
            n.node_tree for n in mat.node_tree.nodes if n.type == "GROUP" and n.node_tree
        ]
        for tree in trees:
            for node in tree.nodes:
                if node.type == "BSDF_PRINCIPLED":
                    node.distribution = "GGX"
                    n_principled += 1
        # glTF doubleSided false: the importer sets use_backface_culling (viewport only). chiaro's
        # reference shades a back face of a single-sided material as a black absorber that ends
        # the path; here the same through a Mix Shader on Backfacing with an empty (black) input
        # (for a blended material, black with probability alpha and transparent otherwise).
        if args.single_sided and mat.use_backface_culling:
            tree = mat.node_tree
            outs = [n for n in tree.nodes if n.type == "OUTPUT_MATERIAL"]
            for out in outs:
                surf = out.inputs["Surface"]
                if not surf.is_linked:
                    continue
                src = surf.links[0].from_socket
                geo = tree.nodes.new("ShaderNodeNewGeometry")
                mix = tree.nodes.new("ShaderNodeMixShader")
                tree.links.new(geo.outputs["Backfacing"], mix.inputs[0])
                tree.links.new(src, mix.inputs[1])
                tree.links.new(mix.outputs[0], surf)
                # A blended material's back face keeps its coverage: chiaro stops a ray there
                # with probability alpha (and absorbs it), and lets it through otherwise.
                principled = [n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"]
                if principled:
                    alpha = principled[0].inputs["Alpha"]
                    if alpha.is_linked or alpha.default_value < 1.0:
                        clear = tree.nodes.new("ShaderNodeBsdfTransparent")
                        cover = tree.nodes.new("ShaderNodeMixShader")
                        if alpha.is_linked:
                            tree.links.new(alpha.links[0].from_socket, cover.inputs[0])
                        else:
                            cover.inputs[0].default_value = alpha.default_value
                        tree.links.new(clear.outputs[0], cover.inputs[1])
                        tree.links.new(cover.outputs[0], mix.inputs[2])
                n_single += 1
    notes.append(f"{n_principled} Principled BSDF -> GGX")
    if doc is not None:
        check_extension_sockets(doc, notes)
    if args.single_sided:
        notes.append(f"{n_single} single-sided materials")

    for ob in bpy.data.objects:
        if ob.type == "LIGHT":
            light = ob.data
            try_set(light, "shadow_soft_size", 0.0)
            try_set(light, "use_soft_falloff", False)
            if light.type == "SUN":
                try_set(light, "angle", 0.0)
    return notes


def blender_setup(args, cam, env, width, height):
    import bpy

    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.max_bounces = args.max_bounces
    c.diffuse_bounces = args.max_bounces
    c.glossy_bounces = args.max_bounces
    c.transmission_bounces = args.max_bounces
    c.transparent_max_bounces = args.max_bounces
    c.volume_bounces = 0
    c.min_light_bounces = 0
    c.min_transparent_bounces = 0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    try_set(c, "use_pixel_jitter", False)
    try_set(c, "use_guiding", False)
    try_set(c, "use_fast_gi", False)
    try_set(c, "film_exposure", 1.0)
    try_set(c, "use_auto_tile", False)
    r = scene.render
    r.resolution_x = width
    r.resolution_y = height
    r.resolution_percentage = 100
    r.pixel_aspect_x = 1.0
    r.pixel_aspect_y = 1.0
    r.film_transparent = False
    r.threads_mode = "FIXED"
    r.threads = args.threads
    r.use_border = False
    try_set(r, "use_compositing", False)
    try_set(r, "use_sequencer", False)
    r.use_motion_blur = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    im = r.image_settings
    try_set(im, "media_type", "IMAGE")
    im.file_format = "OPEN_EXR"
    im.color_mode = "RGB"
    im.color_depth = "32"
    im.exr_codec = "ZIP"

    # World.
    world = bpy.data.worlds.new("crosscheck_world")
    scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    bg = nt.nodes.new("ShaderNodeBackground")
    out = nt.nodes.new("ShaderNodeOutputWorld")
    nt.links.new(bg.outputs["Background"], out.inputs["Surface"])
    bg.inputs["Strength"].default_value = 1.0
    if env["kind"] == "hdr":
        tex = nt.nodes.new("ShaderNodeTexEnvironment")
        tex.image = bpy.data.images.load(env["path"], check_existing=True)
        tex.interpolation = "Closest"  # chiaro reads the nearest texel
        tex.projection = "EQUIRECTANGULAR"
        nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
    else:
        rgb = env["rgb"]
        bg.inputs["Color"].default_value = (rgb[0], rgb[1], rgb[2], 1.0)
    try_set(world.cycles, "sampling_method", "AUTOMATIC")

    # Camera.
    cam_data = bpy.data.cameras.new("crosscheck_camera")
    cam_ob = bpy.data.objects.new("crosscheck_camera", cam_data)
    scene.collection.objects.link(cam_ob)
    scene.camera = cam_ob
    import mathutils

    m = GLTF_TO_BLENDER @ cam["matrix"]
    cam_ob.matrix_world = mathutils.Matrix(m.tolist())
    cam_data.shift_x = 0.0
    cam_data.shift_y = 0.0
    cam_data.sensor_fit = "VERTICAL"
    cam_data.clip_start = 1e-6
    cam_data.clip_end = 1e9
    if cam["kind"] == "ortho":
        cam_data.type = "ORTHO"
        cam_data.ortho_scale = 2.0 * cam["ymag"]
        if abs(cam["xmag"] / cam["ymag"] - width / height) > 1e-6:
            cam["warnings"].append(
                "orthographic xmag/ymag differs from the image's aspect: chiaro stretches, "
                "Blender does not"
            )
    else:
        cam_data.type = "PERSP"
        cam_data.sensor_height = 24.0
        cam_data.lens_unit = "MILLIMETERS"
        cam_data.lens = 0.5 * cam_data.sensor_height / math.tan(0.5 * cam["yfov"])
    return scene


def blender_render(scene, path, spp, seed):
    import bpy

    scene.cycles.samples = spp
    scene.cycles.seed = seed
    scene.render.filepath = path
    t = time.time()
    bpy.ops.render.render(write_still=True)
    return time.time() - t
