"""One scene's cross-check: its environment, the Cycles and chiaro renders, the silhouette check
and the comparison, returned as a row of the tables."""

import math
import os
import re
import time

import numpy as np

from . import log
from .chiaro import chiaro_compare, chiaro_info, run_chiaro_reference
from .compare import EPSILON, LUMA, centre_region, fmt3, rel_mse
from .cycles import blender_import, blender_render, blender_setup
from .gltf import check_camera_against_info, chiaro_camera, read_gltf_json
from .images import read_exr, side_by_side, write_exr


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


def coverage_check(args, scene_path, d, blender_scene):
    """Silhouettes: chiaro depth 0 under a 1000 environment against Cycles' alpha."""
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
    bscene = blender_setup(args, cam, env, args.width, args.height)
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
    t_ch, stdout = run_chiaro_reference(args, scene_path, out, args.chiaro_spp, env, args.chiaro_seed,
                                       ["--sampler", args.chiaro_sampler])
    row["chiaro_s"] = t_ch
    x = read_exr(out)[..., :3].astype(np.float64)
    h0 = read_exr(os.path.join(d, "chiaro.half.exr"))[..., :3].astype(np.float64)
    h1 = 2.0 * x - h0
    m = re.search(r"relMSE between independent halves: (\S+)", stdout)
    row["chiaro_halves_printed"] = float(m.group(1)) if m else None
    log(f"  chiaro: {args.chiaro_spp} spp in {t_ch:.1f} s")

    # Camera / silhouette check.
    if args.coverage_spp > 0:
        cov = coverage_check(args, scene_path, d, bscene)
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
