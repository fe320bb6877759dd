"""glTF's JSON (the JSON part only) and chiaro's camera rule: the scene's first glTF camera in
chiaro's import order, else chiaro's automatic camera from the bounds `chiaro info` prints."""

import json
import math
import struct

import numpy as np


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
