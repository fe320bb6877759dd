#!/usr/bin/env python3
"""Cross-check of chiaro's CPU reference path tracer against Mitsuba 3 on the Cornell box.

Builds in Mitsuba the scene that chiaro's `builtin:cornell` builds
(crates/chiaro_scene/src/builtin/cornell.rs and shapes.rs), renders it converged with Mitsuba's
`path` integrator, renders chiaro's reference at the same size, and compares the two images:

    relMSE(x, y) = mean((x - y)^2 / (y^2 + 0.01)) over pixels and channels

both ways, against each image's own noise (chiaro: relMSE between its two halves; Mitsuba:
relMSE between two independent estimates with different seeds), and the mean radiance per channel.

Depth: chiaro's --max-depth D follows at most D surface vertices (emission at each, next-event
estimation at each); Mitsuba's max_depth counts path segments (1 = directly visible emitters
only), so chiaro D is run against Mitsuba max_depth D + 1. Russian roulette starts after the
third vertex in both (chiaro's default; Mitsuba rr_depth = 3).

Optionally (--gltf-ior) the same box is also written as a glTF file with a given
KHR_materials_ior on the diffuse materials and rendered by chiaro from that file, to separate
scene-construction differences from material differences.

Needs: pip install mitsuba numpy; a release build of chiaro (cargo build --release).
llvm_ad_rgb needs libLLVM (e.g. Debian's libllvm19); DRJIT_LIBLLVM_PATH is set from
/usr/lib/*/libLLVM*.so when it is not set already.

Example:
    python3 scripts/mitsuba_cornell.py --size 256x256 --spp 4096 --chiaro-spp 4096
"""

import argparse
import base64
import glob
import json
import os
import struct
import subprocess
import sys
import time

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# ---------------------------------------------------------------------------------------------
# The scene, as chiaro's builtin:cornell defines it (millimetres, scaled to metres).
# ---------------------------------------------------------------------------------------------

MM = 0.001
WHITE = (0.725, 0.71, 0.68)
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)
LIGHT_RADIANCE = (17.0, 12.0, 4.0)
EYE = np.array([278.0, 273.0, -800.0]) * MM
YFOV_DEG = float(np.degrees(2.0 * np.arctan(12.5 / 35.0)))


def p(x, y, z):
    return np.array([x, y, z], dtype=np.float64) * MM


WALLS = [
    ("floor", "white", [p(552.8, 0.0, 0.0), p(0.0, 0.0, 0.0), p(0.0, 0.0, 559.2), p(549.6, 0.0, 559.2)]),
    ("ceiling", "white", [p(556.0, 548.8, 0.0), p(556.0, 548.8, 559.2), p(0.0, 548.8, 559.2), p(0.0, 548.8, 0.0)]),
    ("back wall", "white", [p(549.6, 0.0, 559.2), p(0.0, 0.0, 559.2), p(0.0, 548.8, 559.2), p(556.0, 548.8, 559.2)]),
    ("right wall", "green", [p(0.0, 0.0, 559.2), p(0.0, 0.0, 0.0), p(0.0, 548.8, 0.0), p(0.0, 548.8, 559.2)]),
    ("left wall", "red", [p(552.8, 0.0, 0.0), p(549.6, 0.0, 559.2), p(556.0, 548.8, 559.2), p(556.0, 548.8, 0.0)]),
    ("light", "light", [p(343.0, 548.3, 227.0), p(343.0, 548.3, 332.0), p(213.0, 548.3, 332.0), p(213.0, 548.3, 227.0)]),
]

SHORT_BLOCK = [
    [p(130.0, 165.0, 65.0), p(82.0, 165.0, 225.0), p(240.0, 165.0, 272.0), p(290.0, 165.0, 114.0)],
    [p(290.0, 0.0, 114.0), p(290.0, 165.0, 114.0), p(240.0, 165.0, 272.0), p(240.0, 0.0, 272.0)],
    [p(130.0, 0.0, 65.0), p(130.0, 165.0, 65.0), p(290.0, 165.0, 114.0), p(290.0, 0.0, 114.0)],
    [p(82.0, 0.0, 225.0), p(82.0, 165.0, 225.0), p(130.0, 165.0, 65.0), p(130.0, 0.0, 65.0)],
    [p(240.0, 0.0, 272.0), p(240.0, 165.0, 272.0), p(82.0, 165.0, 225.0), p(82.0, 0.0, 225.0)],
]
TALL_BLOCK = [
    [p(423.0, 330.0, 247.0), p(265.0, 330.0, 296.0), p(314.0, 330.0, 456.0), p(472.0, 330.0, 406.0)],
    [p(423.0, 0.0, 247.0), p(423.0, 330.0, 247.0), p(472.0, 330.0, 406.0), p(472.0, 0.0, 406.0)],
    [p(472.0, 0.0, 406.0), p(472.0, 330.0, 406.0), p(314.0, 330.0, 456.0), p(314.0, 0.0, 456.0)],
    [p(314.0, 0.0, 456.0), p(314.0, 330.0, 456.0), p(265.0, 330.0, 296.0), p(265.0, 0.0, 296.0)],
    [p(265.0, 0.0, 296.0), p(265.0, 330.0, 296.0), p(423.0, 330.0, 247.0), p(423.0, 0.0, 247.0)],
]


def append_quad(positions, faces, c, facing):
    """shapes.rs append_quad: two triangles (0,1,2), (0,2,3) over the corners, reordered to
    (0,3,2,1) when (c1 - c0) x (c2 - c0) points away from `facing`. Counter-clockwise winding
    gives the front face, as in Mitsuba."""
    normal = np.cross(c[1] - c[0], c[2] - c[0])
    order = [0, 1, 2, 3] if np.dot(normal, facing) >= 0.0 else [0, 3, 2, 1]
    base = len(positions)
    positions.extend(c[k] for k in order)
    faces.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]])


def cornell_meshes():
    """(name, material, positions (n, 3) float32, faces (m, 3) uint32) for the 8 meshes."""
    meshes = []
    room_center = p(278.0, 274.4, 279.6)
    for name, material, corners in WALLS:
        positions, faces = [], []
        center = sum(corners) / 4.0
        append_quad(positions, faces, corners, room_center - center)
        meshes.append((name, material, positions, faces))
    for name, block in [("short block", SHORT_BLOCK), ("tall block", TALL_BLOCK)]:
        # shapes.rs closed_quads: every face wound away from the centroid of all corners.
        center = sum(c for face in block for c in face) / (4.0 * len(block))
        positions, faces = [], []
        for face in block:
            append_quad(positions, faces, face, sum(face) / 4.0 - center)
        meshes.append((name, "white", positions, faces))
    return [
        (n, m, np.asarray(ps, dtype=np.float32), np.asarray(fs, dtype=np.uint32))
        for n, m, ps, fs in meshes
    ]


def write_ply(path, positions, faces):
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(positions)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(positions.astype("<f4").tobytes())
        for tri in faces:
            f.write(struct.pack("<Biii", 3, *map(int, tri)))


# ---------------------------------------------------------------------------------------------
# Mitsuba
# ---------------------------------------------------------------------------------------------


def setup_mitsuba(variant):
    if "llvm" in variant and "DRJIT_LIBLLVM_PATH" not in os.environ:
        found = sorted(glob.glob("/usr/lib/*/libLLVM*.so*") + glob.glob("/usr/lib/llvm-*/lib/libLLVM*.so*"))
        if found:
            os.environ["DRJIT_LIBLLVM_PATH"] = found[-1]
    import mitsuba as mi

    if variant == "auto":
        try:
            mi.set_variant("llvm_ad_rgb")
        except Exception as e:  # no libLLVM
            print(f"llvm_ad_rgb unavailable ({e}); using scalar_rgb", file=sys.stderr)
            mi.set_variant("scalar_rgb")
    else:
        mi.set_variant(variant)
    return mi


def mitsuba_scene(mi, workdir, width, height, max_depth, rr_depth):
    os.makedirs(workdir, exist_ok=True)
    bsdfs = {
        name: {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(rgb)}}
        for name, rgb in [("white", WHITE), ("red", RED), ("green", GREEN)]
    }
    # The light is black (chiaro's emitter material has base colour 0) and emits on its front
    # side only (Mitsuba's area emitter is one-sided, like chiaro's non-double-sided emitters).
    bsdfs["light"] = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}}
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth, "rr_depth": rr_depth},
        "sensor": {
            "type": "perspective",
            "fov": YFOV_DEG,
            "fov_axis": "y",
            "near_clip": 0.01,
            "far_clip": 100.0,
            "to_world": mi.ScalarTransform4f().look_at(
                origin=EYE.tolist(), target=(EYE + [0.0, 0.0, 1.0]).tolist(), up=[0.0, 1.0, 0.0]
            ),
            "sampler": {"type": "independent", "sample_count": 1},
            "film": {
                "type": "hdrfilm",
                "width": width,
                "height": height,
                "pixel_format": "rgb",
                "component_format": "float32",
                "rfilter": {"type": "box"},
            },
        },
    }
    for name, material, positions, faces in cornell_meshes():
        path = os.path.join(workdir, name.replace(" ", "_") + ".ply")
        write_ply(path, positions, faces)
        shape = {"type": "ply", "filename": path, "face_normals": True, "bsdf": bsdfs[material]}
        if material == "light":
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": list(LIGHT_RADIANCE)}}
        scene[name.replace(" ", "_")] = shape
    return mi.load_dict(scene)


def mitsuba_render(mi, scene, spp, seed0, pass_spp):
    """Mean of ceil(spp / pass_spp) independent passes (seeds seed0, seed0 + 1, ...): a wavefront
    variant traces a pass's samples all at once, so large spp is split to bound memory."""
    import drjit as dr

    total = None
    done = 0
    k = 0
    while done < spp:
        n = min(pass_spp, spp - done)
        img = np.array(mi.render(scene, spp=n, seed=seed0 + k), dtype=np.float64)[..., :3]
        dr.sync_thread()
        total = img * n if total is None else total + img * n
        done += n
        k += 1
    return total / spp


def read_exr(mi, path):
    return np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]


def write_exr(mi, path, img):
    mi.Bitmap(np.ascontiguousarray(img, dtype=np.float32), mi.Bitmap.PixelFormat.RGB).write(path)


# ---------------------------------------------------------------------------------------------
# chiaro, and a glTF export of the same box
# ---------------------------------------------------------------------------------------------


def run_chiaro(chiaro, scene, width, height, spp, seed, max_depth, out, extra=()):
    cmd = [chiaro, "reference", scene, "--spp", str(spp), "--size", f"{width}x{height}",
           "--out", out, "--seed", str(seed), "--max-depth", str(max_depth), *extra]
    print("$ " + " ".join(cmd), flush=True)
    result = subprocess.run(cmd, check=True, capture_output=True, text=True)
    print(result.stdout.rstrip(), flush=True)
    paths_per_s = None
    for line in result.stdout.splitlines():
        if line.startswith("paths/s:"):
            paths_per_s = float(line.split()[1])
    return paths_per_s


def write_gltf(path, ior):
    """The same 8 meshes, materials and camera as a glTF 2.0 file, every material with
    KHR_materials_ior = `ior`, metallic 0, roughness 1 (what builtin:cornell passes)."""
    meshes = cornell_meshes()
    blob = bytearray()
    buffer_views, accessors, gltf_meshes, nodes = [], [], [], []
    mat_index = {"white": 0, "red": 1, "green": 2, "light": 3}

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        buffer_views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(buffer_views) - 1

    for name, material, positions, faces in meshes:
        v = add_view(positions.astype("<f4").tobytes(), 34962)
        accessors.append({"bufferView": v, "componentType": 5126, "count": len(positions), "type": "VEC3",
                          "min": positions.min(0).tolist(), "max": positions.max(0).tolist()})
        pos_acc = len(accessors) - 1
        i = add_view(faces.astype("<u4").tobytes(), 34963)
        accessors.append({"bufferView": i, "componentType": 5125, "count": int(faces.size), "type": "SCALAR"})
        gltf_meshes.append({"name": name, "primitives": [
            {"attributes": {"POSITION": pos_acc}, "indices": len(accessors) - 1, "material": mat_index[material]}]})
        nodes.append({"name": name, "mesh": len(gltf_meshes) - 1})

    def diffuse(name, rgb):
        return {"name": name, "pbrMetallicRoughness": {"baseColorFactor": [*rgb, 1.0], "metallicFactor": 0.0,
                                                       "roughnessFactor": 1.0},
                "extensions": {"KHR_materials_ior": {"ior": ior}}}

    strength = max(LIGHT_RADIANCE)
    # The light: black base colour as in Material::emitter, and the same IOR, since a dielectric
    # of IOR above 1 keeps a specular lobe (F0 = 0.04 at IOR 1.5) even with a black base colour.
    materials = [diffuse("white", WHITE), diffuse("red", RED), diffuse("green", GREEN), {
        "name": "light",
        "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                                 "roughnessFactor": 1.0},
        "emissiveFactor": [c / strength for c in LIGHT_RADIANCE],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": strength},
                       "KHR_materials_ior": {"ior": ior}},
    }]
    # A glTF camera looks down its local -Z with +Y up; a half turn about Y makes it look +Z.
    nodes.append({"name": "camera", "camera": 0, "translation": EYE.tolist(), "rotation": [0.0, 1.0, 0.0, 0.0]})
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_ior", "KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": gltf_meshes,
        "materials": materials,
        "cameras": [{"type": "perspective", "perspective": {
            "yfov": float(np.radians(YFOV_DEG)), "aspectRatio": 1.0, "znear": 0.01}}],
        "accessors": accessors,
        "bufferViews": buffer_views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
    }
    with open(path, "w") as f:
        json.dump(doc, f)


# ---------------------------------------------------------------------------------------------
# Comparison
# ---------------------------------------------------------------------------------------------


def rel_mse(x, y):
    return float(np.mean((x - y) ** 2 / (y * y + 0.01)))


def fmt3(v):
    return "(" + ", ".join(f"{c:.5f}" for c in v) + ")"


def mean_and_se(img, pixel_var):
    """Per-channel image mean and its standard error (pixels are independent)."""
    n = img.shape[0] * img.shape[1]
    return img.reshape(-1, 3).mean(0), np.sqrt(pixel_var.reshape(-1, 3).sum(0)) / n


def compare(label, chiaro_img, chiaro_half, chiaro_spp, mitsuba_img, mitsuba_seeds, mitsuba_var):
    # The other half: the full image is the sample-count-weighted mean of the two halves.
    n0 = (chiaro_spp + 1) // 2
    n1 = chiaro_spp // 2
    other = (chiaro_img * chiaro_spp - chiaro_half * n0) / n1
    halves = rel_mse(chiaro_half, other)
    # Per-pixel variance of the full image: E[(h0 - h1)^2] = Var(full) (N/n0 + N/n1), i.e. a
    # quarter of (h0 - h1)^2 for equal halves; the same for Mitsuba's two seeds.
    chiaro_var = (chiaro_half - other) ** 2 / (chiaro_spp / n0 + chiaro_spp / n1)
    # Each image's own noise as relMSE, over the same denominator as relMSE(chiaro vs Mitsuba)
    # (the Mitsuba image): if both are unbiased, that relMSE is about their sum. (Normalizing by
    # one noisy half instead, as relMSE(half, half) does, reads somewhat high on dark pixels.)
    denominator = mitsuba_img ** 2 + 0.01
    chiaro_noise = float(np.mean(chiaro_var / denominator))
    mitsuba_noise = float(np.mean(mitsuba_var / denominator))
    cm = rel_mse(chiaro_img, mitsuba_img)
    mc = rel_mse(mitsuba_img, chiaro_img)
    expected = chiaro_noise + mitsuba_noise
    mean_c, se_c = mean_and_se(chiaro_img, chiaro_var)
    mean_m, se_m = mean_and_se(mitsuba_img, mitsuba_var)
    ratio = mean_c / mean_m
    ratio_se = ratio * np.sqrt((se_c / mean_c) ** 2 + (se_m / mean_m) ** 2)
    print(f"\n== {label} ==")
    print(f"relMSE(chiaro vs Mitsuba)  = {cm:.4e}   (y = Mitsuba)")
    print(f"relMSE(Mitsuba vs chiaro)  = {mc:.4e}   (y = chiaro)")
    print(f"chiaro: relMSE between its halves = {halves:.4e}; full image's own noise ~ {chiaro_noise:.4e}")
    print(f"Mitsuba: relMSE between its seeds = {mitsuba_seeds:.4e}; full image's own noise ~ {mitsuba_noise:.4e}")
    print(f"expected relMSE if unbiased     ~ {expected:.4e}; measured / expected = {cm / expected:.3f}")
    print(f"mean radiance chiaro  {fmt3(mean_c)} +- {fmt3(se_c)}")
    print(f"mean radiance Mitsuba {fmt3(mean_m)} +- {fmt3(se_m)}")
    print(f"ratio chiaro / Mitsuba {fmt3(ratio)} +- {fmt3(ratio_se)}; "
          f"(ratio - 1) / se = {fmt3((ratio - 1) / ratio_se)}")
    print(f"orientation: relMSE vs Mitsuba mirrored left-right {rel_mse(chiaro_img, mitsuba_img[:, ::-1]):.3e}, "
          f"upside down {rel_mse(chiaro_img, mitsuba_img[::-1]):.3e}")
    return {"relmse_chiaro_vs_mitsuba": cm, "relmse_mitsuba_vs_chiaro": mc, "chiaro_halves": halves,
            "chiaro_noise": chiaro_noise, "mitsuba_noise": mitsuba_noise, "mean_chiaro": mean_c.tolist(),
            "mean_mitsuba": mean_m.tolist(), "se_chiaro": se_c.tolist(), "se_mitsuba": se_m.tolist(),
            "ratio": ratio.tolist(), "ratio_se": ratio_se.tolist()}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", default="256x256", help="WxH")
    ap.add_argument("--spp", type=int, default=4096, help="Mitsuba samples per pixel, per each of two seeds")
    ap.add_argument("--chiaro-spp", type=int, default=4096)
    ap.add_argument("--max-depth", type=int, default=64, help="chiaro --max-depth; Mitsuba gets this + 1")
    ap.add_argument("--direct-only", action="store_true",
                    help="chiaro --direct-only against Mitsuba max_depth 2")
    ap.add_argument("--rr-depth", type=int, default=3, help="Mitsuba rr_depth (chiaro: RR from depth 3)")
    ap.add_argument("--seed", type=int, default=0, help="chiaro --seed")
    ap.add_argument("--variant", default="auto", help="Mitsuba variant (auto: llvm_ad_rgb, else scalar_rgb)")
    ap.add_argument("--pass-spp", type=int, default=64, help="Mitsuba spp per render call")
    ap.add_argument("--chiaro", default=os.path.join(REPO, "target", "release", "chiaro"))
    ap.add_argument("--scene", default="builtin:cornell", help="chiaro scene")
    ap.add_argument("--gltf-ior", type=float, nargs="*", default=[],
                    help="also render chiaro on a glTF export of the box with this KHR_materials_ior")
    ap.add_argument("--out-dir", default="/tmp/chiaro_mitsuba")
    ap.add_argument("--json", help="write the figures here")
    args = ap.parse_args()
    width, height = map(int, args.size.split("x"))
    os.makedirs(args.out_dir, exist_ok=True)

    mi = setup_mitsuba(args.variant)
    mitsuba_depth = 2 if args.direct_only else args.max_depth + 1
    print(f"Mitsuba {mi.__version__}, variant {mi.variant()}, {width}x{height}, "
          f"2 x {args.spp} spp, path max_depth {mitsuba_depth}, rr_depth {args.rr_depth}")
    scene = mitsuba_scene(mi, os.path.join(args.out_dir, "meshes"), width, height, mitsuba_depth, args.rr_depth)

    # Two independent Mitsuba estimates: their relMSE measures Mitsuba's noise; their mean is the
    # Mitsuba image compared against (its noise a quarter of the relMSE between the two).
    start = time.perf_counter()
    seeds_per = (args.spp + args.pass_spp - 1) // args.pass_spp
    m_a = mitsuba_render(mi, scene, args.spp, 1_000_000, args.pass_spp)
    m_b = mitsuba_render(mi, scene, args.spp, 1_000_000 + seeds_per, args.pass_spp)
    print(f"Mitsuba: 2 x {args.spp} spp in {time.perf_counter() - start:.1f} s")
    m_seeds = rel_mse(m_a, m_b)
    mitsuba_img = 0.5 * (m_a + m_b)
    mitsuba_var = (m_a - m_b) ** 2 / 4.0  # per-pixel variance of their mean
    print(f"Mitsuba relMSE between the two seeds' images: {m_seeds:.4e}")
    tag = f"{width}x{height}_d{args.max_depth}{'_direct' if args.direct_only else ''}"
    write_exr(mi, os.path.join(args.out_dir, f"mitsuba_{tag}.exr"), mitsuba_img)

    extra = ["--direct-only"] if args.direct_only else []
    results = {"mitsuba_seeds_relmse": m_seeds, "mitsuba_variant": mi.variant(), "comparisons": {}}
    runs = [(args.scene, args.scene)]
    for ior in args.gltf_ior:
        path = os.path.join(args.out_dir, f"cornell_ior{ior:g}.gltf")
        write_gltf(path, ior)
        runs.append((f"glTF export, KHR_materials_ior {ior:g}", path))
    for label, scene_arg in runs:
        out = os.path.join(args.out_dir, f"chiaro_{len(results['comparisons'])}_{tag}.exr")
        run_chiaro(args.chiaro, scene_arg, width, height, args.chiaro_spp, args.seed, args.max_depth, out, extra)
        img = read_exr(mi, out)
        half = read_exr(mi, out[:-4] + ".half.exr")
        results["comparisons"][label] = compare(
            f"chiaro ({label}) vs Mitsuba", img, half, args.chiaro_spp, mitsuba_img, m_seeds,
            mitsuba_var)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
