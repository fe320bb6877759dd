#!/usr/bin/env python3
"""Cross-check of chiaro's CPU reference path tracer against Blender Cycles on glTF scenes.

Checks that chiaro shades glTF materials as glTF defines them. For each glTF scene:

1. Cycles: the scene imported with Blender's own glTF importer (default options, lighting mode
   "Standard"), rendered twice with two seeds at --spp samples each, WxH, into linear float EXRs.
   Settings: world = constant colour (--env, default 0.5 grey, strength 1) or the equirectangular
   --env-hdr image (nearest texel, as chiaro looks it up); film not transparent; view transform
   "Standard"; every Principled BSDF set to single-scatter "GGX"; no denoising, no adaptive
   sampling, no clamping, light threshold 0; box pixel filter 1 px wide (chiaro jitters each
   sample uniformly over its pixel); 64 bounces of every kind, Russian roulette as Cycles does it;
   caustics on, filter glossy 0. glTF's single-sided materials are emulated (a back face is a
   black absorber, as chiaro's reference treats it) unless --no-single-sided. Primitives with no
   material get glTF's default material (white, metallic 1, roughness 1), as chiaro does.
2. The camera is chiaro's: the scene's first glTF camera (depth-first node order, as chiaro's
   importer walks the default scene), else chiaro's automatic camera (crates/chiaro_scene/src/
   framing.rs: yfov 45 degrees, looking down -Z at the centre of the world bounds, at the
   distance where the bounds' sphere fits the vertical field of view). The bounds are parsed
   from `chiaro info` (printed at full f32 precision), the camera is then rebuilt here and its
   position and direction checked against the camera line `chiaro info` prints.
   A coverage pass checks that the silhouettes line up: chiaro `--max-depth 0` under a 1000
   environment (1 - image/1000 is the coverage) against Cycles' alpha with a transparent film;
   the mean absolute difference is printed next to the same with Cycles shifted by one pixel
   and flipped, which a misplaced camera would make smaller.
3. chiaro: `chiaro reference` at the same size, --chiaro-spp samples (default 2 x --spp, the
   sample count of the compared Cycles image), the same environment; its noise from the two
   independent halves it writes (FILE.half.exr and 2 x full - half).
4. Compares, over pixels and channels (the project's metric, as `chiaro compare` prints it):

       relMSE(x, y) = mean((x - y)^2 / (y^2 + 0.01)),   x = chiaro, y = Cycles (mean of 2 seeds)

   and the mean ratio (mean luminance of chiaro / of Cycles, and per channel). Noise convention:
   for two independent estimates a, b of the same image (Cycles' two seeds; chiaro's two halves)
   the compared image is (a + b) / 2 and its per-pixel variance is estimated by (a - b)^2 / 4.
   The "noise" columns are mean((a - b)^2 / 4 / (y^2 + 0.01)), y = the Cycles image: each
   compared image's expected relMSE against the truth. (relMSE(a, b) itself estimates twice the
   variance of one estimate, four times that of their mean.) If both renderers converge to the
   same image, relMSE(chiaro, Cycles) is about noise_chiaro + noise_Cycles. Verdict "ok" when
   relMSE <= max(1e-3, 2 x (noise_chiaro + noise_Cycles)) and the mean luminance ratio is within
   1% of 1.

Outputs, under --out: per scene NAME/cycles_seed0.exr, cycles_seed1.exr, cycles.exr (their mean),
chiaro.exr (+ chiaro.half.exr, chiaro.png), coverage EXRs, and NAME/side_by_side.png (chiaro |
Cycles | |difference| x 4, each clamped to [0, 1] and sRGB-encoded); results.md (the tables) and
results.json.

--make-test-scenes DIR writes small hand-made glTF scenes into DIR (plain JSON with an embedded
buffer; no Blender needed) and adds them to the list: quads under the constant environment (the
glTF BRDF's directional albedo read off the centre region), a point light of 100 cd over a floor
(light units), a vertex-colour quad, an alpha-blended quad over a coloured floor, and the material
extensions: a clear-coated quad (facing and at 60 degrees), a KHR_materials_specular quad and a
transmissive pane over a coloured backdrop. After import, the Principled BSDF inputs of
KHR_materials_clearcoat / _specular / _transmission are checked against the glTF definition
(EXTENSION_SOCKETS) and set where they differ. A scene can
ask for its own environment through asset.extras.cycles_crosscheck.env ("R,G,B"), and for the
centre-region probe through asset.extras.cycles_crosscheck.probe = "centre".

Needs Python 3.13 with bpy (pip install bpy: Blender as a module; 5.3.0 was used) and numpy,
and a release build of chiaro (cargo build --release).

Examples:
    ~/.pyenv/versions/3.13.0/bin/python scripts/cycles_crosscheck.py --size 64x64 --spp 256
    ~/.pyenv/versions/3.13.0/bin/python scripts/cycles_crosscheck.py --no-default-scenes \\
        --make-test-scenes /tmp/cc_scenes --size 64x64 --spp 256
"""

import argparse
import base64
import json
import math
import os
import re
import struct
import subprocess
import sys
import time
import zlib

import warnings

import numpy as np

warnings.filterwarnings("ignore", category=DeprecationWarning)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SCENES = "/work/shared/scenes"
DEFAULT_HDR = "/work/shared/scenes/qwantani_afternoon_puresky_1k.hdr"
EPSILON = 0.01
LUMA = np.array([0.2126, 0.7152, 0.0722])
# glTF (+Y up) -> Blender (+Z up), as Blender's glTF importer converts: (x, y, z) -> (x, -z, y).
GLTF_TO_BLENDER = np.array(
    [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
)


def log(*a):
    print(*a, flush=True)


# ---------------------------------------------------------------------------------------------
# glTF reading (JSON part only) and chiaro's camera rule
# ---------------------------------------------------------------------------------------------


def read_gltf_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        length, kind = struct.unpack_from("<II", data, 12)
        if kind != 0x4E4F534A:
            raise ValueError(f"{path}: first GLB chunk is not JSON")
        return json.loads(data[20 : 20 + length].decode("utf-8"))
    return json.loads(data.decode("utf-8"))


def quat_to_matrix(q):
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def node_local_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
    m = np.eye(4)
    r = quat_to_matrix(node.get("rotation", [0, 0, 0, 1]))
    s = np.array(node.get("scale", [1, 1, 1]), dtype=np.float64)
    m[:3, :3] = r * s[None, :]
    m[:3, 3] = node.get("translation", [0, 0, 0])
    return m


def first_gltf_camera(doc):
    """The first camera node in chiaro's import order (depth-first pre-order over the default
    scene's roots, children in order; subtrees of singular transforms skipped): (world matrix,
    camera dict), or None."""
    nodes = doc.get("nodes", [])
    scenes = doc.get("scenes", [])
    scene = None
    if "scene" in doc and doc["scene"] < len(scenes):
        scene = scenes[doc["scene"]]
    elif scenes:
        scene = scenes[0]
    if scene is not None:
        roots = list(scene.get("nodes", []))
    else:
        children = {c for n in nodes for c in n.get("children", [])}
        roots = [i for i in range(len(nodes)) if i not in children]
    stack = [(r, np.eye(4)) for r in reversed(roots)]
    while stack:
        index, parent = stack.pop()
        if index >= len(nodes):
            continue
        node = nodes[index]
        local = node_local_matrix(node)
        if abs(np.linalg.det(local[:3, :3])) < 1e-30:
            continue
        world = parent @ local
        if "camera" in node:
            return world, doc["cameras"][node["camera"]]
        for c in reversed(node.get("children", [])):
            stack.append((c, world))
    return None


def chiaro_info(chiaro, scene):
    out = subprocess.run(
        [chiaro, "info", scene], capture_output=True, text=True, check=False
    )
    if out.returncode != 0:
        raise RuntimeError(f"chiaro info failed: {out.stderr.strip()[-400:]}")
    info = {"text": out.stdout}
    num = r"(-?[0-9.eE+-]+|inf|-inf|NaN)"
    m = re.search(
        rf"^bounds: \({num}, {num}, {num}\) to \({num}, {num}, {num}\)", out.stdout, re.M
    )
    info["bounds"] = (
        np.array([float(v) for v in m.groups()[:3]], dtype=np.float32),
        np.array([float(v) for v in m.groups()[3:]], dtype=np.float32),
    ) if m else None
    m = re.search(
        rf"^camera: (.*): at \({num}, {num}, {num}\) looking \({num}, {num}, {num}\), (\w+)(?:, yfov ([0-9.]+) deg)?",
        out.stdout,
        re.M,
    )
    if m:
        g = m.groups()
        info["camera_name"] = g[0]
        info["camera_automatic"] = "(automatic)" in g[0]
        info["camera_at"] = np.array([float(v) for v in g[1:4]])
        info["camera_look"] = np.array([float(v) for v in g[4:7]])
        info["camera_projection"] = g[7]
        info["camera_yfov_deg"] = float(g[8]) if g[8] else None
    return info


def chiaro_camera(doc, info):
    """chiaro's active camera in glTF world space: dict(kind, matrix (4x4 rigid), yfov | xmag,
    ymag, automatic, warnings)."""
    warnings = []
    found = first_gltf_camera(doc)
    if found is not None:
        world, cam = found
        lin = world[:3, :3]
        u, s, vt = np.linalg.svd(lin)
        rot = u @ vt
        if np.max(np.abs(s - s.mean())) > 1e-4 * max(s.mean(), 1e-30):
            warnings.append(
                f"camera node has non-uniform scale {s}: chiaro's rays follow it, Blender's do not"
            )
        m = np.eye(4)
        m[:3, :3] = rot
        m[:3, 3] = world[:3, 3]
        if cam.get("type") == "orthographic" or "orthographic" in cam:
            o = cam["orthographic"]
            return dict(kind="ortho", matrix=m, xmag=o["xmag"], ymag=o["ymag"],
                        automatic=False, warnings=warnings)
        return dict(kind="persp", matrix=m, yfov=cam["perspective"]["yfov"], automatic=False,
                    warnings=warnings)
    # chiaro_scene::framing::frame_bounds, in f32 as chiaro computes it.
    f32 = np.float32
    yfov = f32(math.pi / 4)
    bounds = info.get("bounds")
    if bounds is None or np.any(bounds[0] > bounds[1]):
        center, radius = np.zeros(3, f32), f32(1.0)
    else:
        lo, hi = bounds
        center = f32(0.5) * (lo + hi)
        size = hi - lo
        r = f32(0.5) * np.sqrt(np.sum(size * size, dtype=f32), dtype=f32)
        radius = r if r > 0 else f32(1.0)
    distance = f32(radius / f32(np.sin(f32(0.5) * yfov)))
    m = np.eye(4)
    m[:3, 3] = (center + np.array([0, 0, distance], f32)).astype(np.float64)
    return dict(kind="persp", matrix=m, yfov=float(yfov), automatic=True, warnings=warnings)


def check_camera_against_info(cam, info):
    """Position and view direction against `chiaro info`'s camera line (4 and 3 decimals)."""
    if "camera_at" not in info:
        return "chiaro info printed no camera"
    at = cam["matrix"][:3, 3]
    look = -cam["matrix"][:3, 2]
    look = look / np.linalg.norm(look)
    d_at = np.max(np.abs(at - info["camera_at"]))
    d_look = np.max(np.abs(look - info["camera_look"]))
    auto_ok = cam["automatic"] == info["camera_automatic"]
    ok = d_at <= 0.5e-4 * 1.01 + 1e-6 * np.max(np.abs(at)) and d_look <= 0.5e-3 * 1.01 and auto_ok
    return (
        f"{'agrees with' if ok else 'DIFFERS from'} chiaro info "
        f"(position {d_at:.0e}, direction {d_look:.0e})"
    )


# ---------------------------------------------------------------------------------------------
# Images: EXR through bpy, PNG by hand
# ---------------------------------------------------------------------------------------------


def read_exr(path):
    import bpy

    img = bpy.data.images.load(path, check_existing=False)
    w, h = img.size
    buf = np.empty(w * h * img.channels, dtype=np.float32)
    img.pixels.foreach_get(buf)
    ch = img.channels
    bpy.data.images.remove(img)
    arr = buf.reshape(h, w, ch)[::-1]  # Blender stores the bottom row first
    return np.ascontiguousarray(arr)


def write_png(path, rgb8):
    h, w, _ = rgb8.shape
    raw = b"".join(b"\x00" + rgb8[y].tobytes() for y in range(h))

    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def to_srgb8(x):
    x = np.clip(np.nan_to_num(x, nan=0.0), 0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (s * 255.0 + 0.5).astype(np.uint8)


def side_by_side(path, chiaro_img, cycles_img):
    h, w, _ = chiaro_img.shape
    gap = np.full((h, 2, 3), 255, np.uint8)
    diff = np.abs(chiaro_img - cycles_img) * 4.0
    panels = [to_srgb8(chiaro_img), gap, to_srgb8(cycles_img), gap, to_srgb8(diff)]
    write_png(path, np.concatenate(panels, axis=1))


def rel_mse(x, y):
    return float(np.mean((x - y) ** 2 / (y * y + EPSILON)))


# ---------------------------------------------------------------------------------------------
# Cycles
# ---------------------------------------------------------------------------------------------


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


def blender_setup(scene_path, args, cam, env, width, height):
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


# ---------------------------------------------------------------------------------------------
# chiaro
# ---------------------------------------------------------------------------------------------


def run_chiaro_reference(args, scene_path, out, spp, env, seed, extra=()):
    cmd = [
        args.chiaro, "reference", scene_path,
        "--size", f"{args.width}x{args.height}",
        "--spp", str(spp),
        "--seed", str(seed),
        "--threads", str(args.threads),
        "--out", out,
        "--env", env["chiaro"],
    ] + list(extra)
    t = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, check=False)
    dt = time.time() - t
    if p.returncode != 0:
        raise RuntimeError(f"chiaro reference failed: {' '.join(cmd)}\n{p.stderr.strip()[-600:]}")
    return dt, p.stdout


def chiaro_compare(args, test, ref):
    p = subprocess.run([args.chiaro, "compare", test, ref], capture_output=True, text=True)
    m = re.search(r"^relmse\s+(\S+)", p.stdout, re.M)
    return float(m.group(1)) if m else None


# ---------------------------------------------------------------------------------------------
# Hand-made test scenes
# ---------------------------------------------------------------------------------------------


class GltfBuilder:
    def __init__(self):
        self.doc = {
            "asset": {"version": "2.0", "generator": "chiaro scripts/cycles_crosscheck.py"},
            "scene": 0,
            "scenes": [{"nodes": []}],
            "nodes": [],
            "meshes": [],
            "materials": [],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }
        self.blob = bytearray()

    def _view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        offset = len(self.blob)
        self.blob += data
        self.doc["bufferViews"].append(
            {"buffer": 0, "byteOffset": offset, "byteLength": len(data), "target": target}
        )
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, array, kind, target=34962):
        array = np.ascontiguousarray(array)
        if array.dtype == np.uint32:
            comp = 5125
        else:
            array = array.astype(np.float32)
            comp = 5126
        view = self._view(array.tobytes(), target)
        acc = {"bufferView": view, "componentType": comp, "count": int(array.shape[0]),
               "type": kind}
        if kind == "VEC3" and comp == 5126:
            acc["min"] = array.min(axis=0).tolist()
            acc["max"] = array.max(axis=0).tolist()
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def material(self, **m):
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def quad(self, size, material, colors=None, z=0.0):
        """A size x size quad in the XY plane at height z, facing +Z (counter-clockwise)."""
        h = 0.5 * size
        pos = np.array([[-h, -h, z], [h, -h, z], [h, h, z], [-h, h, z]], np.float32)
        nrm = np.tile(np.array([0, 0, 1], np.float32), (4, 1))
        idx = np.array([0, 1, 2, 0, 2, 3], np.uint32)
        attrs = {"POSITION": self.accessor(pos, "VEC3"), "NORMAL": self.accessor(nrm, "VEC3")}
        if colors is not None:
            attrs["COLOR_0"] = self.accessor(np.array(colors, np.float32), "VEC4")
        prim = {"attributes": attrs, "indices": self.accessor(idx, "SCALAR", 34963),
                "material": material}
        self.doc["meshes"].append({"primitives": [prim]})
        return len(self.doc["meshes"]) - 1

    def node(self, root=True, **n):
        self.doc["nodes"].append(n)
        i = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(i)
        return i

    def write(self, path, extras=None):
        if extras:
            self.doc["asset"]["extras"] = {"cycles_crosscheck": extras}
        self.doc["buffers"] = [{
            "byteLength": len(self.blob),
            "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.blob)).decode(),
        }]
        for k in ["materials", "meshes"]:
            if not self.doc[k]:
                del self.doc[k]
        with open(path, "w") as f:
            json.dump(self.doc, f, indent=1)


def rot_x(deg):
    a = math.radians(deg) / 2
    return [math.sin(a), 0.0, 0.0, math.cos(a)]


def make_test_scenes(folder):
    os.makedirs(folder, exist_ok=True)
    paths = []

    def pbr(base, metallic, roughness, **extra):
        base = list(base) + [1.0] * (4 - len(base))
        return dict(pbrMetallicRoughness={"baseColorFactor": base, "metallicFactor": metallic,
                                          "roughnessFactor": roughness}, **extra)

    # (a) quad facing the camera: base 0.8, roughness 0.5, dielectric.
    b = GltfBuilder()
    m = b.material(name="dielectric_0.8_r0.5", **pbr([0.8, 0.8, 0.8], 0.0, 0.5))
    b.node(mesh=b.quad(2.0, m), name="quad")
    p = os.path.join(folder, "a_quad_facing.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (b) the same quad seen at 75 degrees (its normal turned 75 degrees up from the view axis).
    b = GltfBuilder()
    m = b.material(name="dielectric_0.8_r0.5", **pbr([0.8, 0.8, 0.8], 0.0, 0.5))
    b.node(mesh=b.quad(2.0, m), name="quad_75", rotation=rot_x(-75.0))
    p = os.path.join(folder, "b_quad_75deg.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (c) white, metallic 0.4, roughness 0.4, facing the camera.
    b = GltfBuilder()
    m = b.material(name="white_m0.4_r0.4", **pbr([1.0, 1.0, 1.0], 0.4, 0.4))
    b.node(mesh=b.quad(2.0, m), name="quad")
    p = os.path.join(folder, "c_quad_metal04.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (d) a 100 cd point light 2 m above a diffuse-ish floor, black environment, glTF camera.
    b = GltfBuilder()
    m = b.material(name="floor_0.8_r1", **pbr([0.8, 0.8, 0.8], 0.0, 1.0))
    b.node(mesh=b.quad(4.0, m), name="floor", rotation=rot_x(-90.0))  # facing +Y
    b.doc["extensionsUsed"] = ["KHR_lights_punctual"]
    b.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1.0, 1.0, 1.0], "intensity": 100.0, "name": "point_100cd"}]}}
    b.node(name="light", translation=[0.0, 2.0, 0.0],
           extensions={"KHR_lights_punctual": {"light": 0}})
    b.doc["cameras"] = [{"type": "perspective",
                         "perspective": {"yfov": 0.8, "znear": 0.01, "aspectRatio": 1.0}}]
    b.node(name="camera", camera=0, translation=[0.0, 3.0, 5.0],
           rotation=rot_x(-math.degrees(math.atan2(3.0, 5.0))))
    p = os.path.join(folder, "d_point_light_100cd.gltf")
    b.write(p, {"env": "0,0,0", "probe": "centre"})
    paths.append(p)

    # (e) vertex colours (COLOR_0, VEC4 float): red, green, blue, white corners.
    b = GltfBuilder()
    m = b.material(name="white_vertex_colour", **pbr([1.0, 1.0, 1.0], 0.0, 0.5))
    colors = [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 1, 1]]
    b.node(mesh=b.quad(2.0, m, colors=colors), name="quad")
    p = os.path.join(folder, "e_vertex_colour.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (f) alpha BLEND 0.5 white quad 0.5 above a blue floor quad, both facing the camera.
    b = GltfBuilder()
    floor = b.material(name="blue_floor", **pbr([0.1, 0.3, 0.8], 0.0, 0.5))
    glass = b.material(name="blend_0.5", alphaMode="BLEND",
                       **pbr([0.9, 0.9, 0.9, 0.5], 0.0, 0.5))
    b.node(mesh=b.quad(3.0, floor), name="floor")
    b.node(mesh=b.quad(2.0, glass, z=0.5), name="blend_quad")
    p = os.path.join(folder, "f_alpha_blend.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # Material extensions. Each scene lists its extension in extensionsUsed.
    def with_ext(builder, *names):
        builder.doc["extensionsUsed"] = sorted(set(builder.doc.get("extensionsUsed", [])) | set(names))

    # (g) KHR_materials_clearcoat (factor 1, roughness 0.3) over a red dielectric (roughness 0.6),
    # facing the camera and at 60 degrees (its normal 60 degrees up from the view axis).
    for name, tilt in [("g_clearcoat_facing", 0.0), ("g_clearcoat_60deg", -60.0)]:
        b = GltfBuilder()
        m = b.material(name="red_r0.6_clearcoat1_r0.3", **pbr(
            [0.8, 0.1, 0.1], 0.0, 0.6,
            extensions={"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                                    "clearcoatRoughnessFactor": 0.3}}))
        with_ext(b, "KHR_materials_clearcoat")
        node = dict(mesh=b.quad(2.0, m), name="quad")
        if tilt:
            node["rotation"] = rot_x(tilt)
        b.node(**node)
        p = os.path.join(folder, name + ".gltf")
        b.write(p, {"probe": "centre"})
        paths.append(p)

    # (h) KHR_materials_specular (factor 0.5, colour (1, 0.5, 0.25)) over a grey dielectric
    # (base 0.5, roughness 0.5), facing the camera.
    b = GltfBuilder()
    m = b.material(name="grey_r0.5_specular0.5", **pbr(
        [0.5, 0.5, 0.5], 0.0, 0.5,
        extensions={"KHR_materials_specular": {"specularFactor": 0.5,
                                               "specularColorFactor": [1.0, 0.5, 0.25]}}))
    with_ext(b, "KHR_materials_specular")
    b.node(mesh=b.quad(2.0, m), name="quad")
    p = os.path.join(folder, "h_specular.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (i) KHR_materials_transmission: a thin pane (one double-sided quad, white, roughness 0.2,
    # transmission 1) 0.5 m in front of an orange diffuse backdrop (3 x 3 m, roughness 1).
    # chiaro renders it thin-walled (no KHR_materials_volume); Cycles refracts at the quad.
    b = GltfBuilder()
    back = b.material(name="orange_backdrop_r1", **pbr([0.8, 0.4, 0.1], 0.0, 1.0))
    pane = b.material(name="pane_transmission1_r0.2", doubleSided=True, **pbr(
        [1.0, 1.0, 1.0], 0.0, 0.2,
        extensions={"KHR_materials_transmission": {"transmissionFactor": 1.0}}))
    with_ext(b, "KHR_materials_transmission")
    b.node(mesh=b.quad(3.0, back), name="backdrop")
    b.node(mesh=b.quad(2.0, pane, z=0.5), name="pane")
    p = os.path.join(folder, "i_transmission_pane.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)
    return paths


# ---------------------------------------------------------------------------------------------
# Per scene
# ---------------------------------------------------------------------------------------------


def scene_env(args, doc):
    hint = (doc.get("asset", {}).get("extras", {}) or {}).get("cycles_crosscheck", {}) or {}
    if "env" in hint and not args.ignore_scene_env:
        rgb = [float(v) for v in hint["env"].split(",")]
        return dict(kind="constant", rgb=rgb, chiaro=",".join(str(v) for v in rgb),
                    label=f"constant {hint['env']} (scene's hint)"), hint
    if args.env_hdr:
        return dict(kind="hdr", path=args.env_hdr, chiaro=args.env_hdr,
                    label=os.path.basename(args.env_hdr)), hint
    rgb = [float(v) for v in args.env.split(",")]
    if len(rgb) == 1:
        rgb = rgb * 3
    return dict(kind="constant", rgb=rgb, chiaro=",".join(str(v) for v in rgb),
                label=f"constant {args.env}"), hint


def coverage_check(args, scene_path, cam, env_unused, d, blender_scene):
    """Silhouettes: chiaro depth 0 under a 1000 environment against Cycles' alpha."""
    import bpy

    env_cov = dict(kind="constant", rgb=[1000.0] * 3, chiaro="1000,1000,1000")
    out = os.path.join(d, "coverage_chiaro.exr")
    run_chiaro_reference(args, scene_path, out, args.coverage_spp, env_cov, 7,
                         ["--max-depth", "0"])
    cov_ch = np.clip(1.0 - read_exr(out)[..., :3].mean(axis=2) / 1000.0, 0.0, 1.0)

    s = blender_scene
    saved = (s.render.film_transparent, s.cycles.max_bounces, s.render.image_settings.color_mode)
    s.render.film_transparent = True
    s.cycles.max_bounces = 0
    s.render.image_settings.color_mode = "RGBA"
    path = os.path.join(d, "coverage_cycles.exr")
    blender_render(s, path, args.coverage_spp, 7)
    s.render.film_transparent, s.cycles.max_bounces, s.render.image_settings.color_mode = saved
    cov_cy = read_exr(path)[..., 3]

    def mae(a, b):
        return float(np.mean(np.abs(a - b)))

    inner = (slice(1, -1), slice(1, -1))
    base = mae(cov_ch[inner], cov_cy[inner])
    shifts = {
        "x+1": mae(cov_ch[inner], np.roll(cov_cy, 1, axis=1)[inner]),
        "x-1": mae(cov_ch[inner], np.roll(cov_cy, -1, axis=1)[inner]),
        "y+1": mae(cov_ch[inner], np.roll(cov_cy, 1, axis=0)[inner]),
        "y-1": mae(cov_ch[inner], np.roll(cov_cy, -1, axis=0)[inner]),
        "vflip": mae(cov_ch, cov_cy[::-1]),
        "hflip": mae(cov_ch, cov_cy[:, ::-1]),
    }
    def centroid(c):
        ys, xs = np.mgrid[0 : c.shape[0], 0 : c.shape[1]] + 0.5
        t = max(float(c.sum()), 1e-30)
        return np.array([(c * xs).sum() / t, (c * ys).sum() / t])

    shift = centroid(cov_ch) - centroid(cov_cy)
    return dict(mae=base, shifted=shifts, centroid_shift_px=shift.tolist(),
                min_shifted=min(v for k, v in shifts.items() if "flip" not in k),
                min_flipped=min(shifts["vflip"], shifts["hflip"]),
                coverage_chiaro=float(cov_ch.mean()), coverage_cycles=float(cov_cy.mean()))


def centre_region(img, frac=0.1):
    h, w, _ = img.shape
    k = max(2, int(round(frac * min(w, h))))
    y0, x0 = (h - k) // 2, (w - k) // 2
    return img[y0 : y0 + k, x0 : x0 + k].reshape(-1, 3).mean(axis=0), k


def process_scene(args, scene_path):
    name = os.path.splitext(os.path.basename(scene_path))[0]
    d = os.path.join(args.out, name)
    os.makedirs(d, exist_ok=True)
    row = dict(scene=name, path=scene_path)
    t_scene = time.time()
    doc = read_gltf_json(scene_path)
    env, hint = scene_env(args, doc)
    row["env"] = env["label"]
    info = chiaro_info(args.chiaro, scene_path)
    cam = chiaro_camera(doc, info)
    row["camera"] = ("automatic" if cam["automatic"] else "glTF") + (
        f", yfov {math.degrees(cam['yfov']):.3f} deg" if cam["kind"] == "persp" else ", orthographic")
    row["camera_vs_info"] = check_camera_against_info(cam, info)
    log(f"  camera: {row['camera']}; {row['camera_vs_info']}")

    # Cycles.
    t = time.time()
    notes = blender_import(scene_path, args, doc)
    bscene = blender_setup(scene_path, args, cam, env, args.width, args.height)
    row["blender_notes"] = notes
    row["blender_import_s"] = time.time() - t
    cy = []
    t_cy = 0.0
    for k, seed in enumerate(args.seeds):
        p = os.path.join(d, f"cycles_seed{k}.exr")
        t_cy += blender_render(bscene, p, args.spp, seed)
        cy.append(read_exr(p)[..., :3].astype(np.float64))
    row["cycles_s"] = t_cy
    log(f"  Cycles: 2 x {args.spp} spp in {t_cy:.1f} s ({'; '.join(notes)})")

    # chiaro.
    out = os.path.join(d, "chiaro.exr")
    t_ch, stdout = run_chiaro_reference(args, scene_path, out, args.chiaro_spp, env, args.chiaro_seed)
    row["chiaro_s"] = t_ch
    x = read_exr(out)[..., :3].astype(np.float64)
    h0 = read_exr(os.path.join(d, "chiaro.half.exr"))[..., :3].astype(np.float64)
    h1 = 2.0 * x - h0
    m = re.search(r"relMSE between independent halves: (\S+)", stdout)
    row["chiaro_halves_printed"] = float(m.group(1)) if m else None
    log(f"  chiaro: {args.chiaro_spp} spp in {t_ch:.1f} s")

    # Camera / silhouette check.
    if args.coverage_spp > 0:
        cov = coverage_check(args, scene_path, cam, env, d, bscene)
        row["coverage"] = cov
        log(f"  silhouette: MAE {cov['mae']:.4f} (shifted 1 px: {cov['min_shifted']:.4f} or more, "
            f"flipped: {cov['min_flipped']:.4f} or more), centroid chiaro - Cycles "
            f"({cov['centroid_shift_px'][0]:+.3f}, {cov['centroid_shift_px'][1]:+.3f}) px, "
            f"coverage chiaro {cov['coverage_chiaro']:.4f} Cycles {cov['coverage_cycles']:.4f}")

    # Comparison.
    y = 0.5 * (cy[0] + cy[1])
    write_exr(os.path.join(d, "cycles.exr"), y)
    denom = y * y + EPSILON
    row["relmse"] = rel_mse(x, y)
    row["relmse_chiaro_compare"] = chiaro_compare(args, out, os.path.join(d, "cycles.exr"))
    row["noise_chiaro"] = float(np.mean((h0 - h1) ** 2 / 4.0 / denom))
    row["noise_cycles"] = float(np.mean((cy[0] - cy[1]) ** 2 / 4.0 / denom))
    row["relmse_cycles_seeds"] = rel_mse(cy[0], cy[1])
    row["relmse_chiaro_halves"] = rel_mse(h0, h1)
    expected = row["noise_chiaro"] + row["noise_cycles"]
    row["expected"] = expected
    mx, my = x.reshape(-1, 3).mean(axis=0), y.reshape(-1, 3).mean(axis=0)
    row["mean_chiaro"] = mx.tolist()
    row["mean_cycles"] = my.tolist()
    lx, ly = float(mx @ LUMA), float(my @ LUMA)
    row["mean_ratio"] = lx / ly if ly > 0 else float("nan")
    row["mean_ratio_rgb"] = [float(a / b) if b > 0 else float("nan") for a, b in zip(mx, my)]
    # Standard error of the luminance ratio from the per-pixel variances of both images.
    var_x = ((h0 - h1) ** 2 / 4.0) @ LUMA**2
    var_y = ((cy[0] - cy[1]) ** 2 / 4.0) @ LUMA**2
    n = var_x.size
    se = math.sqrt(var_x.sum() / n**2 / max(lx, 1e-30) ** 2 + var_y.sum() / n**2 / max(ly, 1e-30) ** 2)
    row["mean_ratio_se"] = row["mean_ratio"] * se
    tol = max(1e-3, 2.0 * expected)
    ok_mse = row["relmse"] <= tol
    ok_mean = abs(row["mean_ratio"] - 1.0) <= 0.01
    row["verdict"] = "ok" if ok_mse and ok_mean else "FAIL (" + ", ".join(
        ([f"relMSE > {tol:.1e}"] if not ok_mse else []) + (["mean off > 1%"] if not ok_mean else [])) + ")"
    if hint.get("probe") == "centre":
        cx, k = centre_region(x)
        cc, _ = centre_region(y)
        row["centre"] = dict(pixels=k, chiaro=cx.tolist(), cycles=cc.tolist(),
                             env=env.get("rgb"))
        log(f"  centre {k}x{k} px: chiaro {fmt3(cx)}, Cycles {fmt3(cc)}")
    side_by_side(os.path.join(d, "side_by_side.png"), x, y)
    row["total_s"] = time.time() - t_scene
    log(f"  relMSE {row['relmse']:.3e} (chiaro compare {row['relmse_chiaro_compare']}), "
        f"expected {expected:.3e}, mean ratio {row['mean_ratio']:.4f}: {row['verdict']}")
    return row


def write_exr(path, rgb):
    """A linear float32 RGB OpenEXR file, scanline, uncompressed (written by hand: bpy's
    Image.save colour-manages float buffers, which `chiaro compare` then reads differently)."""
    rgb = np.ascontiguousarray(rgb, dtype=np.float32)
    h, w, _ = rgb.shape

    def attr(name, kind, data):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data

    chlist = b"".join(c.encode() + b"\0" + struct.pack("<iBBBBii", 2, 0, 0, 0, 0, 1, 1)
                      for c in "BGR") + b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = (
        struct.pack("<ii", 20000630, 2)
        + attr("channels", "chlist", chlist)
        + attr("compression", "compression", b"\0")
        + attr("dataWindow", "box2i", box)
        + attr("displayWindow", "box2i", box)
        + attr("lineOrder", "lineOrder", b"\0")
        + attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
        + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
        + attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
        + b"\0"
    )
    line_bytes = w * 3 * 4
    table_start = len(header)
    first = table_start + 8 * h
    offsets = struct.pack(f"<{h}Q", *[first + y * (8 + line_bytes) for y in range(h)])
    lines = []
    for y in range(h):
        row = rgb[y]
        lines.append(struct.pack("<ii", y, line_bytes)
                     + row[:, 2].tobytes() + row[:, 1].tobytes() + row[:, 0].tobytes())
    with open(path, "wb") as f:
        f.write(header + offsets + b"".join(lines))


def fmt3(v):
    return "(" + ", ".join(f"{a:.4f}" for a in v) + ")"


def table(rows, args):
    lines = [
        f"{args.width}x{args.height}; Cycles 2 x {args.spp} spp (seeds {args.seeds[0]}, {args.seeds[1]}), "
        f"chiaro {args.chiaro_spp} spp (seed {args.chiaro_seed}); environment: "
        + (os.path.basename(args.env_hdr) if args.env_hdr else f"constant {args.env}")
        + " unless a scene asks for its own; noise = expected relMSE of each compared image "
          "(mean((a - b)^2 / 4 / (y^2 + 0.01)), a, b its two seeds or halves, y the Cycles image).",
        "",
        "| scene | relMSE chiaro vs Cycles | mean ratio (lum.) | chiaro noise | Cycles noise | verdict |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['scene']} | - | - | - | - | error: {r['error']} |")
            continue
        lines.append(
            f"| {r['scene']} | {r['relmse']:.3e} | {r['mean_ratio']:.4f} +- {r['mean_ratio_se']:.1e} | "
            f"{r['noise_chiaro']:.2e} | {r['noise_cycles']:.2e} | {r['verdict']} |"
        )
    lines += ["", "Camera check: the camera rebuilt here against the one `chiaro info` prints; "
              "silhouettes: mean |coverage chiaro - coverage Cycles| as rendered, and the smallest "
              "of the same with Cycles' coverage shifted 1 px (x or y) and flipped (h or v); the "
              "shift of the coverage centroid (chiaro - Cycles) in pixels.", "",
              "| scene | mean ratio R, G, B | camera | silhouette MAE (1 px shift; flip) | "
              "centroid shift px | coverage chiaro / Cycles | time: Cycles (2 renders), chiaro, whole scene |",
              "|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            continue
        cov = r.get("coverage")
        cov_s = (f"{cov['mae']:.4f} ({cov['min_shifted']:.4f}; {cov['min_flipped']:.4f})" if cov else "-")
        cov_f = (f"{cov['coverage_chiaro']:.3f} / {cov['coverage_cycles']:.3f}" if cov else "-")
        cov_c = ("({:+.3f}, {:+.3f})".format(*cov["centroid_shift_px"]) if cov else "-")
        lines.append(
            f"| {r['scene']} | {', '.join(f'{v:.3f}' for v in r['mean_ratio_rgb'])} | "
            f"{r['camera']}; {r['camera_vs_info']} | {cov_s} | {cov_c} | {cov_f} | "
            f"{r['cycles_s']:.1f} s, {r['chiaro_s']:.1f} s, {r['total_s']:.1f} s |"
        )
    probes = [r for r in rows if "centre" in r]
    if probes:
        lines += ["", "Centre region (mean pixel value; divided by the environment's radiance "
                  "where it is a constant: the directional albedo seen along the view):", "",
                  "| scene | pixels | chiaro RGB | Cycles RGB | chiaro / env | Cycles / env |",
                  "|---|---|---|---|---|---|"]
        for r in probes:
            c = r["centre"]
            env = c["env"]
            if env and all(e > 0 for e in env):
                a = fmt3([v / e for v, e in zip(c["chiaro"], env)])
                b = fmt3([v / e for v, e in zip(c["cycles"], env)])
            else:
                a = b = "-"
            lines.append(f"| {r['scene']} | {c['pixels']}x{c['pixels']} | {fmt3(c['chiaro'])} | "
                         f"{fmt3(c['cycles'])} | {a} | {b} |")
    return "\n".join(lines) + "\n"


def list_scenes(folder):
    if not os.path.isdir(folder):
        return []
    return sorted(
        os.path.join(folder, f) for f in os.listdir(folder)
        if f.lower().endswith((".glb", ".gltf")) and os.path.isfile(os.path.join(folder, f))
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*", help="extra .glb/.gltf files")
    ap.add_argument("--scenes-dir", default=DEFAULT_SCENES,
                    help=f"default scene folder, top level only (default {DEFAULT_SCENES})")
    ap.add_argument("--no-default-scenes", action="store_true",
                    help="skip the default scene folder")
    ap.add_argument("--extra", action="append", default=[], metavar="DIR",
                    help="a folder of more test scenes (repeatable)")
    ap.add_argument("--make-test-scenes", metavar="DIR",
                    help="write the hand-made test scenes into DIR and include them")
    ap.add_argument("--only", action="append", default=[],
                    help="keep only scenes whose file name contains this (repeatable)")
    ap.add_argument("--out", default="/tmp/chiaro_cycles", help="output folder")
    ap.add_argument("--size", default="128x128", help="WxH (default 128x128)")
    ap.add_argument("--spp", type=int, default=1024, help="Cycles samples per seed (default 1024)")
    ap.add_argument("--chiaro-spp", type=int, default=None,
                    help="chiaro's samples (default 2 x --spp, the compared Cycles image's count)")
    ap.add_argument("--seeds", default="0,1", help="Cycles' two seeds (default 0,1)")
    ap.add_argument("--chiaro-seed", type=int, default=0)
    ap.add_argument("--env", default="0.5,0.5,0.5",
                    help="constant environment, linear R,G,B or one value (default 0.5)")
    ap.add_argument("--env-hdr", nargs="?", const=DEFAULT_HDR, default=None,
                    help=f"equirectangular environment instead (default file {DEFAULT_HDR})")
    ap.add_argument("--ignore-scene-env", action="store_true",
                    help="ignore a scene's own environment hint (asset.extras)")
    ap.add_argument("--lighting-mode", default="SPEC", choices=["SPEC", "COMPAT", "RAW"],
                    help="Blender glTF importer's lighting mode: SPEC (\"Standard\", the default: "
                         "physical units, 683 lm/W), COMPAT (\"Unitless\"), RAW")
    ap.add_argument("--max-bounces", type=int, default=64)
    ap.add_argument("--threads", type=int, default=1, help="threads for both renderers")
    ap.add_argument("--coverage-spp", type=int, default=16,
                    help="samples of the silhouette check (0 skips it)")
    ap.add_argument("--no-single-sided", dest="single_sided", action="store_false",
                    help="leave Cycles' materials two-sided")
    ap.add_argument("--chiaro", default=os.path.join(REPO, "target", "release", "chiaro"))
    args = ap.parse_args()
    args.width, args.height = (int(v) for v in args.size.lower().split("x"))
    args.chiaro_spp = args.chiaro_spp or 2 * args.spp
    args.seeds = [int(v) for v in args.seeds.split(",")][:2]
    args.out = os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)

    scenes = []
    if not args.no_default_scenes:
        scenes += list_scenes(args.scenes_dir)
    if args.make_test_scenes:
        scenes += make_test_scenes(args.make_test_scenes)
        log(f"wrote the test scenes into {args.make_test_scenes}")
    for folder in args.extra:
        scenes += list_scenes(folder)
    scenes += [os.path.abspath(s) for s in args.scenes]
    if args.only:
        scenes = [s for s in scenes if any(o in os.path.basename(s) for o in args.only)]
    if not scenes:
        sys.exit("no scenes")

    import bpy  # noqa: F401  (fail early when bpy is missing)

    log(f"Blender {bpy.app.version_string}; chiaro {args.chiaro}")
    rows = []
    for s in scenes:
        log(f"{os.path.basename(s)}:")
        try:
            rows.append(process_scene(args, s))
        except Exception as e:  # keep going: one scene's failure is a row of the table
            log(f"  error: {e}")
            rows.append(dict(scene=os.path.splitext(os.path.basename(s))[0], path=s,
                             error=str(e).splitlines()[0][:200]))
    md = table(rows, args)
    with open(os.path.join(args.out, "results.md"), "w") as f:
        f.write(md)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(rows, f, indent=1, default=float)
    log("")
    log(md)


if __name__ == "__main__":
    main()
