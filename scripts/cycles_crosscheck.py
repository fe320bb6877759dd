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
extensions: a clear-coated quad (facing and at 60 degrees), a KHR_materials_specular quad, a
transmissive pane over a coloured backdrop, glass spheres (volume), and the coat, specular and
pane again with the extensions' textures in stripes (k_*). After import, the Principled BSDF
inputs of KHR_materials_clearcoat / _specular / _transmission are checked against the glTF definition
(EXTENSION_SOCKETS in cycles_crosscheck/cycles.py) and set where they differ. A scene can
ask for its own environment through asset.extras.cycles_crosscheck.env ("R,G,B"), and for the
centre-region probe through asset.extras.cycles_crosscheck.probe = "centre".

The code: this file (options, the loop over the scenes, results.md and results.json) and the
package cycles_crosscheck/ beside it (its __init__.py lists the modules).

Needs Python 3.13 with bpy (pip install bpy: Blender as a module; 5.3.0 was used) and numpy,
and a release build of chiaro (cargo build --release).

Examples:
    ~/.pyenv/versions/3.13.0/bin/python scripts/cycles_crosscheck.py --size 64x64 --spp 256
    ~/.pyenv/versions/3.13.0/bin/python scripts/cycles_crosscheck.py --no-default-scenes \\
        --make-test-scenes /tmp/cc_scenes --size 64x64 --spp 256
"""

import argparse
import json
import os
import sys
import warnings

warnings.filterwarnings("ignore", category=DeprecationWarning)

sys.dont_write_bytecode = True  # no __pycache__ beside the script in the working tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # the package beside this file

from cycles_crosscheck import log  # noqa: E402
from cycles_crosscheck.compare import table  # noqa: E402
from cycles_crosscheck.scene import process_scene  # noqa: E402
from cycles_crosscheck.test_scenes import make_test_scenes  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SCENES = "/work/shared/scenes"
DEFAULT_HDR = "/work/shared/scenes/qwantani_afternoon_puresky_1k.hdr"


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
    ap.add_argument("--chiaro-sampler", default="sobol", choices=["sobol", "independent"],
                    help="chiaro's sampler (default sobol)")
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
