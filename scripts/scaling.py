#!/usr/bin/env python3
"""How the realtime frame's time scales: against the output size, against the triangles
(`builtin:walkthrough?size=N`, N bays of the street) and against the lights
(`builtin:many-lights?quads=N&lights=N`). Each point is one `chiaro render` of `--frames`
frames; the figures are what it prints: throughput (frames per second over the last half of
the run), latency (median submit-to-done time of one frame) and each pass's median time (GPU
timestamps where the adapter has them, else the wall clock per pass).

Prints three markdown tables. Needs a release build (cargo build --release).

Examples:
    python3 scripts/scaling.py                                   # lavapipe-sized defaults
    python3 scripts/scaling.py --sizes 1280x720 1920x1080 2560x1440 3840x2160 \\
        --fixed-size 1920x1080 --frames 64                       # a GPU
"""

import argparse
import os
import re
import subprocess
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def render(chiaro, scene, size, frames):
    """Runs one render; returns (frames/s, latency ms, {pass: ms})."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [chiaro, "render", scene, "--size", size, "--frames", str(frames), "--out",
               os.path.join(tmp, "frame.png")]
        out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    text = out.stdout + out.stderr
    throughput = re.search(r"throughput ([\d.]+) frames/s, latency ([\d.]+) ms", text)
    passes = {m.group(1): float(m.group(2)) for m in re.finditer(r"^\s+(\w+)\s+([\d.]+) ms \(median", text, re.M)}
    return float(throughput.group(1)), float(throughput.group(2)), passes


def scene_counts(chiaro, scene):
    """Triangles traced by `scene`, from `chiaro info`."""
    text = subprocess.run([chiaro, "info", scene], check=True, capture_output=True, text=True).stdout
    triangles = re.search(r"\((\d+) triangles traced\)", text)
    return int(triangles.group(1)) if triangles else 0


def table(title, rows, chiaro, frames):
    """Prints a table of renders: rows are (label, scene, size)."""
    print(f"\n### {title}\n")
    results = [(label, scene, size, *render(chiaro, scene, size, frames)) for label, scene, size in rows]
    names = []
    for *_, passes in results:
        names += [n for n in passes if n not in names]
    print("| " + " | ".join(["point", "scene", "size", "fps", "latency (ms)"] + names) + " |")
    print("|" + "---|" * (5 + len(names)))
    for label, scene, size, fps, latency, passes in results:
        cells = [label, f"`{scene}`", size, f"{fps:.2f}", f"{latency:.1f}"]
        cells += [f"{passes[n]:.2f}" if n in passes else "" for n in names]
        print("| " + " | ".join(cells) + " |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--chiaro", default=os.path.join(REPO, "target", "release", "chiaro"))
    ap.add_argument("--frames", type=int, default=16)
    ap.add_argument("--scene", default="builtin:cornell", help="scene of the size table")
    ap.add_argument("--sizes", nargs="+", default=["160x90", "320x180", "640x360", "1280x720"])
    ap.add_argument("--fixed-size", default="128x128", help="size of the triangle and light tables")
    ap.add_argument("--bays", type=int, nargs="+", default=[1, 2, 4, 8])
    ap.add_argument("--lights", type=int, nargs="+", default=[16, 64, 256, 1024])
    args = ap.parse_args()
    table("Frame time against the output size", [(s, args.scene, s) for s in args.sizes], args.chiaro,
          args.frames)
    rows = []
    for bays in args.bays:
        scene = f"builtin:walkthrough?size={bays}"
        rows.append((f"{scene_counts(args.chiaro, scene):,} triangles", scene, args.fixed_size))
    table("Frame time against the triangles", rows, args.chiaro, args.frames)
    rows = [(f"{n} quads + {n} punctual", f"builtin:many-lights?quads={n}&lights={n}", args.fixed_size)
            for n in args.lights]
    table("Frame time against the lights", rows, args.chiaro, args.frames)


if __name__ == "__main__":
    main()
