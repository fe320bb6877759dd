"""Running the chiaro binary: `chiaro info` (bounds and camera), `chiaro reference` and
`chiaro compare`."""

import re
import subprocess
import time

import numpy as np


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
