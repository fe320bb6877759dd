"""The metrics (relMSE as `chiaro compare` prints it, the centre-region probe) and the tables of
results.md."""

import os

import numpy as np

EPSILON = 0.01
LUMA = np.array([0.2126, 0.7152, 0.0722])


def rel_mse(x, y):
    return float(np.mean((x - y) ** 2 / (y * y + EPSILON)))


def centre_region(img, frac=0.1):
    h, w, _ = img.shape
    k = max(2, int(round(frac * min(w, h))))
    y0, x0 = (h - k) // 2, (w - k) // 2
    return img[y0 : y0 + k, x0 : x0 + k].reshape(-1, 3).mean(axis=0), k


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
