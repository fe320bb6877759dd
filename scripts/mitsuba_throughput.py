#!/usr/bin/env python3
"""Throughput of chiaro's CPU reference against Mitsuba 3 on the Cornell box, same machine, same
moment: the same image size, spp and depth (chiaro --max-depth D, Mitsuba path max_depth D + 1,
Russian roulette from the third vertex in both).

Mitsuba: the scene is loaded and rendered once (JIT compilation of the kernel, kept in Dr.Jit's
cache), then each timed render is one mi.render call with a fresh seed, timed with
time.perf_counter around the call and the wait for its result. chiaro: each timed render is one
`chiaro reference` process; its own paths/s figure (render loop only: no scene load, BVH build or
file writes) is used, and the process's wall time is printed beside it. The runs alternate
(chiaro, Mitsuba, chiaro, ...) so both see the same machine load; the median is reported.

chiaro renders builtin:cornell and, with --gltf-ior 1, the glTF export of the same box with
KHR_materials_ior 1 (pure Lambertian, the same light transport as the Mitsuba scene; see
mitsuba_cornell.py).

Example:
    python3 scripts/mitsuba_throughput.py --size 256x256 --spp 64 --runs 3 --gltf-ior 1
"""

import argparse
import os
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba_cornell as mc  # noqa: E402


def time_chiaro(chiaro, scene, width, height, spp, max_depth, seed, out):
    cmd = [chiaro, "reference", scene, "--spp", str(spp), "--size", f"{width}x{height}",
           "--out", out, "--seed", str(seed), "--max-depth", str(max_depth)]
    start = time.perf_counter()
    result = subprocess.run(cmd, check=True, capture_output=True, text=True)
    wall = time.perf_counter() - start
    rate = next(float(line.split()[1]) for line in result.stdout.splitlines() if line.startswith("paths/s:"))
    return rate, wall


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", default="256x256")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--max-depth", type=int, default=64, help="chiaro --max-depth; Mitsuba gets this + 1")
    ap.add_argument("--rr-depth", type=int, default=3)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--variant", default="auto", help="auto: llvm_ad_rgb, else scalar_rgb")
    ap.add_argument("--chiaro", default=os.path.join(mc.REPO, "target", "release", "chiaro"))
    ap.add_argument("--gltf-ior", type=float, nargs="*", default=[])
    ap.add_argument("--out-dir", default="/tmp/chiaro_mitsuba_throughput")
    args = ap.parse_args()
    width, height = map(int, args.size.split("x"))
    os.makedirs(args.out_dir, exist_ok=True)
    paths = width * height * args.spp

    mi = mc.setup_mitsuba(args.variant)
    import drjit as dr

    print(f"Mitsuba {mi.__version__} {mi.variant()}, {width}x{height}, {args.spp} spp, "
          f"chiaro max-depth {args.max_depth} / Mitsuba max_depth {args.max_depth + 1}, rr_depth {args.rr_depth}; "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}")
    scene = mc.mitsuba_scene(mi, os.path.join(args.out_dir, "meshes"), width, height,
                             args.max_depth + 1, args.rr_depth)
    start = time.perf_counter()
    mi.render(scene, spp=args.spp, seed=0).numpy()
    dr.sync_thread()
    print(f"Mitsuba warm-up render (includes JIT compilation): {time.perf_counter() - start:.2f} s")

    scenes = [("builtin:cornell", "builtin:cornell")]
    for ior in args.gltf_ior:
        path = os.path.join(args.out_dir, f"cornell_ior{ior:g}.gltf")
        mc.write_gltf(path, ior)
        scenes.append((f"glTF export, IOR {ior:g}", path))

    rates = {label: [] for label, _ in scenes}
    rates["Mitsuba"] = []
    for run in range(args.runs):
        for label, scene_arg in scenes:
            rate, wall = time_chiaro(args.chiaro, scene_arg, width, height, args.spp, args.max_depth, run + 1,
                                     os.path.join(args.out_dir, "chiaro.exr"))
            rates[label].append(rate)
            print(f"run {run + 1} chiaro ({label}): {rate / 1e6:.3f} M paths/s (process wall {wall:.2f} s)",
                  flush=True)
        start = time.perf_counter()
        mi.render(scene, spp=args.spp, seed=run + 1).numpy()
        dr.sync_thread()
        seconds = time.perf_counter() - start
        rates["Mitsuba"].append(paths / seconds)
        print(f"run {run + 1} Mitsuba {mi.variant()}: {paths / seconds / 1e6:.3f} M paths/s ({seconds:.2f} s)",
              flush=True)

    print(f"\nmedian of {args.runs} runs, {width}x{height} at {args.spp} spp ({paths} paths):")
    m = statistics.median(rates["Mitsuba"])
    print(f"  Mitsuba {mi.variant()}: {m / 1e6:.3f} M paths/s")
    for label, _ in scenes:
        c = statistics.median(rates[label])
        print(f"  chiaro ({label}): {c / 1e6:.3f} M paths/s; chiaro / Mitsuba = {c / m:.2f}")


if __name__ == "__main__":
    main()
