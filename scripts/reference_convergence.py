#!/usr/bin/env python3
"""Speed against error of chiaro's CPU reference: renders a scene at increasing samples per pixel
and reports, for each, the render time (chiaro's own, render loop only) and the relMSE against a
converged render of the same scene made with a different seed (so the two share no samples).

    relMSE(x, y) = mean((x - y)^2 / (y^2 + 0.01)) over pixels and channels, linear HDR

The converged render's own noise is printed too (a quarter of the relMSE between its halves):
figures near it are limited by the reference, not by the test image.

Measures with `chiaro compare` (needs only a release build: cargo build --release).

With several `--light-sampling` methods or `--sampler`s, each is measured at each spp (the
converged render uses the first of each), so they can be compared at equal time.

Examples:
    python3 scripts/reference_convergence.py --scene builtin:cornell --size 128x128 \\
        --spp 4 16 64 256 --reference-spp 4096
    python3 scripts/reference_convergence.py --scene builtin:many-lights --size 96x96 \\
        --spp 4 16 64 --reference-spp 2048 --light-sampling tree power
"""

import argparse
import os
import subprocess

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def render(chiaro, scene, size, spp, seed, out, light_sampling, sampler):
    cmd = [chiaro, "reference", scene, "--spp", str(spp), "--size", size, "--seed", str(seed), "--out", out,
           "--light-sampling", light_sampling, "--sampler", sampler]
    text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    seconds = next(float(line.split(" in ")[1].split()[0]) for line in text.splitlines() if " spp in " in line)
    halves = next(float(line.split(":")[1].split()[0]) for line in text.splitlines() if line.startswith("relMSE"))
    return seconds, halves


def rel_mse(chiaro, test, reference):
    text = subprocess.run([chiaro, "compare", test, reference], check=True, capture_output=True, text=True).stdout
    return next(float(line.split()[1]) for line in text.splitlines() if line.startswith("relmse "))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="builtin:cornell")
    ap.add_argument("--size", default="128x128")
    ap.add_argument("--spp", type=int, nargs="+", default=[4, 16, 64, 256])
    ap.add_argument("--reference-spp", type=int, default=4096)
    ap.add_argument("--chiaro", default=os.path.join(REPO, "target", "release", "chiaro"))
    ap.add_argument("--out-dir", default="/tmp/chiaro_convergence")
    ap.add_argument("--light-sampling", nargs="+", default=["tree"], choices=["tree", "power"])
    ap.add_argument("--sampler", nargs="+", default=["sobol"], choices=["sobol", "independent"])
    args = ap.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    ref_path = os.path.join(args.out_dir, "converged.exr")
    methods = args.light_sampling
    seconds, halves = render(args.chiaro, args.scene, args.size, args.reference_spp, 1, ref_path, methods[0],
                             args.sampler[0])
    print(f"{args.scene} {args.size}: converged {args.reference_spp} spp (seed 1) in {seconds:.1f} s, "
          f"its own noise ~ {halves / 4:.2e}")
    print("| light sampling | sampler | spp | render time (s) | relMSE vs converged |")
    print("|---|---|---|---|---|")
    for method in methods:
        for sampler in args.sampler:
            for spp in args.spp:
                path = os.path.join(args.out_dir, f"{method}_{sampler}_spp{spp}.exr")
                seconds, _ = render(args.chiaro, args.scene, args.size, spp, 0, path, method, sampler)
                print(f"| {method} | {sampler} | {spp} | {seconds:.2f} | {rel_mse(args.chiaro, path, ref_path):.3e} |")


if __name__ == "__main__":
    main()
