"""The modules of scripts/cycles_crosscheck.py, the cross-check of chiaro against Blender Cycles.

gltf: the glTF JSON and chiaro's camera rule; chiaro: running the chiaro binary; cycles: Blender's
import, settings and renders; test_scenes: the hand-made glTF scenes; images: EXR and PNG files;
compare: the metrics and the tables; scene: one scene's cross-check from both renders to its row.
"""


def log(*a):
    print(*a, flush=True)
