"""The hand-made glTF test scenes (plain JSON with an embedded buffer; no Blender needed):
quads under the constant environment, a point light over a floor, vertex colours, alpha BLEND and
the material extensions clearcoat, specular, transmission and volume, and those extensions'
textures, the normal textures (the base's and the coat's) included."""

import base64
import json
import math
import os
import struct
import zlib

import numpy as np


class GltfBuilder:
    def __init__(self):
        self.doc = {
            "asset": {"version": "2.0", "generator": "chiaro scripts/cycles_crosscheck.py"},
            "scene": 0,
            "scenes": [{"nodes": []}],
            "nodes": [],
            "meshes": [],
            "materials": [],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }
        self.blob = bytearray()

    def _view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        offset = len(self.blob)
        self.blob += data
        self.doc["bufferViews"].append(
            {"buffer": 0, "byteOffset": offset, "byteLength": len(data), "target": target}
        )
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, array, kind, target=34962):
        array = np.ascontiguousarray(array)
        if array.dtype == np.uint32:
            comp = 5125
        else:
            array = array.astype(np.float32)
            comp = 5126
        view = self._view(array.tobytes(), target)
        acc = {"bufferView": view, "componentType": comp, "count": int(array.shape[0]),
               "type": kind}
        if kind == "VEC3" and comp == 5126:
            acc["min"] = array.min(axis=0).tolist()
            acc["max"] = array.max(axis=0).tolist()
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def material(self, **m):
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def texture(self, rgba):
        """A texture of the H x W x 4 uint8 array `rgba` (an embedded PNG, nearest texels,
        repeating); returns its index."""
        for k in ["images", "samplers", "textures"]:
            self.doc.setdefault(k, [])
        self.doc["images"].append({"uri": "data:image/png;base64,"
                                   + base64.b64encode(png(rgba)).decode()})
        self.doc["samplers"].append({"magFilter": 9728, "minFilter": 9728})
        self.doc["textures"].append({"source": len(self.doc["images"]) - 1,
                                     "sampler": len(self.doc["samplers"]) - 1})
        return len(self.doc["textures"]) - 1

    def quad(self, size, material, colors=None, z=0.0):
        """A size x size quad in the XY plane at height z, facing +Z (counter-clockwise), UVs
        over [0, 1]^2 (v down, as glTF's)."""
        h = 0.5 * size
        pos = np.array([[-h, -h, z], [h, -h, z], [h, h, z], [-h, h, z]], np.float32)
        nrm = np.tile(np.array([0, 0, 1], np.float32), (4, 1))
        idx = np.array([0, 1, 2, 0, 2, 3], np.uint32)
        uv = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
        attrs = {"POSITION": self.accessor(pos, "VEC3"), "NORMAL": self.accessor(nrm, "VEC3"),
                 "TEXCOORD_0": self.accessor(uv, "VEC2")}
        if colors is not None:
            attrs["COLOR_0"] = self.accessor(np.array(colors, np.float32), "VEC4")
        prim = {"attributes": attrs, "indices": self.accessor(idx, "SCALAR", 34963),
                "material": material}
        self.doc["meshes"].append({"primitives": [prim]})
        return len(self.doc["meshes"]) - 1

    def sphere(self, radius, material, rings=48, segments=96):
        """A UV sphere of this radius about the origin, outward normals, counter-clockwise from
        outside."""
        pos, nrm = [], []
        for i in range(rings + 1):
            theta = math.pi * i / rings
            for j in range(segments + 1):
                phi = 2.0 * math.pi * j / segments
                n = [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi),
                     math.cos(theta)]
                nrm.append(n)
                pos.append([radius * c for c in n])
        idx = []
        for i in range(rings):
            for j in range(segments):
                a = i * (segments + 1) + j
                b = a + segments + 1
                if i > 0:
                    idx += [a, b, a + 1]
                if i < rings - 1:
                    idx += [a + 1, b, b + 1]
        attrs = {"POSITION": self.accessor(np.array(pos, np.float32), "VEC3"),
                 "NORMAL": self.accessor(np.array(nrm, np.float32), "VEC3")}
        prim = {"attributes": attrs,
                "indices": self.accessor(np.array(idx, np.uint32), "SCALAR", 34963),
                "material": material}
        self.doc["meshes"].append({"primitives": [prim]})
        return len(self.doc["meshes"]) - 1

    def node(self, root=True, **n):
        self.doc["nodes"].append(n)
        i = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(i)
        return i

    def write(self, path, extras=None):
        if extras:
            self.doc["asset"]["extras"] = {"cycles_crosscheck": extras}
        self.doc["buffers"] = [{
            "byteLength": len(self.blob),
            "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.blob)).decode(),
        }]
        for k in ["materials", "meshes"]:
            if not self.doc[k]:
                del self.doc[k]
        with open(path, "w") as f:
            json.dump(self.doc, f, indent=1)


def png(rgba):
    """The H x W x 4 uint8 array as PNG bytes (8-bit RGBA, no filtering)."""
    h, w, _ = rgba.shape
    raw = b"".join(b"\x00" + rgba[y].astype(np.uint8).tobytes() for y in range(h))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def stripes(channel, period=2, size=8):
    """An 8 x 8 RGBA texture, white, whose `channel` is 255 and 0 in vertical stripes `period`
    texels wide (the other channels 255)."""
    t = np.full((size, size, 4), 255, np.uint8)
    for x in range(size):
        if (x // period) % 2:
            t[:, x, channel] = 0
    return t


def rot_x(deg):
    a = math.radians(deg) / 2
    return [math.sin(a), 0.0, 0.0, math.cos(a)]


def make_test_scenes(folder):
    os.makedirs(folder, exist_ok=True)
    paths = []

    def pbr(base, metallic, roughness, **extra):
        base = list(base) + [1.0] * (4 - len(base))
        return dict(pbrMetallicRoughness={"baseColorFactor": base, "metallicFactor": metallic,
                                          "roughnessFactor": roughness}, **extra)

    # (a) quad facing the camera: base 0.8, roughness 0.5, dielectric.
    b = GltfBuilder()
    m = b.material(name="dielectric_0.8_r0.5", **pbr([0.8, 0.8, 0.8], 0.0, 0.5))
    b.node(mesh=b.quad(2.0, m), name="quad")
    p = os.path.join(folder, "a_quad_facing.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (b) the same quad seen at 75 degrees (its normal turned 75 degrees up from the view axis).
    b = GltfBuilder()
    m = b.material(name="dielectric_0.8_r0.5", **pbr([0.8, 0.8, 0.8], 0.0, 0.5))
    b.node(mesh=b.quad(2.0, m), name="quad_75", rotation=rot_x(-75.0))
    p = os.path.join(folder, "b_quad_75deg.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (c) white, metallic 0.4, roughness 0.4, facing the camera.
    b = GltfBuilder()
    m = b.material(name="white_m0.4_r0.4", **pbr([1.0, 1.0, 1.0], 0.4, 0.4))
    b.node(mesh=b.quad(2.0, m), name="quad")
    p = os.path.join(folder, "c_quad_metal04.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (d) a 100 cd point light 2 m above a diffuse-ish floor, black environment, glTF camera.
    b = GltfBuilder()
    m = b.material(name="floor_0.8_r1", **pbr([0.8, 0.8, 0.8], 0.0, 1.0))
    b.node(mesh=b.quad(4.0, m), name="floor", rotation=rot_x(-90.0))  # facing +Y
    b.doc["extensionsUsed"] = ["KHR_lights_punctual"]
    b.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1.0, 1.0, 1.0], "intensity": 100.0, "name": "point_100cd"}]}}
    b.node(name="light", translation=[0.0, 2.0, 0.0],
           extensions={"KHR_lights_punctual": {"light": 0}})
    b.doc["cameras"] = [{"type": "perspective",
                         "perspective": {"yfov": 0.8, "znear": 0.01, "aspectRatio": 1.0}}]
    b.node(name="camera", camera=0, translation=[0.0, 3.0, 5.0],
           rotation=rot_x(-math.degrees(math.atan2(3.0, 5.0))))
    p = os.path.join(folder, "d_point_light_100cd.gltf")
    b.write(p, {"env": "0,0,0", "probe": "centre"})
    paths.append(p)

    # (e) vertex colours (COLOR_0, VEC4 float): red, green, blue, white corners.
    b = GltfBuilder()
    m = b.material(name="white_vertex_colour", **pbr([1.0, 1.0, 1.0], 0.0, 0.5))
    colors = [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 1, 1]]
    b.node(mesh=b.quad(2.0, m, colors=colors), name="quad")
    p = os.path.join(folder, "e_vertex_colour.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (f) alpha BLEND 0.5 white quad 0.5 above a blue floor quad, both facing the camera.
    b = GltfBuilder()
    floor = b.material(name="blue_floor", **pbr([0.1, 0.3, 0.8], 0.0, 0.5))
    glass = b.material(name="blend_0.5", alphaMode="BLEND",
                       **pbr([0.9, 0.9, 0.9, 0.5], 0.0, 0.5))
    b.node(mesh=b.quad(3.0, floor), name="floor")
    b.node(mesh=b.quad(2.0, glass, z=0.5), name="blend_quad")
    p = os.path.join(folder, "f_alpha_blend.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # Material extensions. Each scene lists its extension in extensionsUsed.
    def with_ext(builder, *names):
        builder.doc["extensionsUsed"] = sorted(set(builder.doc.get("extensionsUsed", [])) | set(names))

    # (g) KHR_materials_clearcoat (factor 1, roughness 0.3) over a red dielectric (roughness 0.6),
    # facing the camera and at 60 degrees (its normal 60 degrees up from the view axis).
    for name, tilt in [("g_clearcoat_facing", 0.0), ("g_clearcoat_60deg", -60.0)]:
        b = GltfBuilder()
        m = b.material(name="red_r0.6_clearcoat1_r0.3", **pbr(
            [0.8, 0.1, 0.1], 0.0, 0.6,
            extensions={"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                                    "clearcoatRoughnessFactor": 0.3}}))
        with_ext(b, "KHR_materials_clearcoat")
        node = dict(mesh=b.quad(2.0, m), name="quad")
        if tilt:
            node["rotation"] = rot_x(tilt)
        b.node(**node)
        p = os.path.join(folder, name + ".gltf")
        b.write(p, {"probe": "centre"})
        paths.append(p)

    # (h) KHR_materials_specular (factor 0.5, colour (1, 0.5, 0.25)) over a grey dielectric
    # (base 0.5, roughness 0.5), facing the camera.
    b = GltfBuilder()
    m = b.material(name="grey_r0.5_specular0.5", **pbr(
        [0.5, 0.5, 0.5], 0.0, 0.5,
        extensions={"KHR_materials_specular": {"specularFactor": 0.5,
                                               "specularColorFactor": [1.0, 0.5, 0.25]}}))
    with_ext(b, "KHR_materials_specular")
    b.node(mesh=b.quad(2.0, m), name="quad")
    p = os.path.join(folder, "h_specular.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (i) KHR_materials_transmission: a thin pane (one double-sided quad, white, roughness 0.2,
    # transmission 1) 0.5 m in front of an orange diffuse backdrop (3 x 3 m, roughness 1).
    # chiaro renders it thin-walled (no KHR_materials_volume); Cycles refracts at the quad.
    b = GltfBuilder()
    back = b.material(name="orange_backdrop_r1", **pbr([0.8, 0.4, 0.1], 0.0, 1.0))
    pane = b.material(name="pane_transmission1_r0.2", doubleSided=True, **pbr(
        [1.0, 1.0, 1.0], 0.0, 0.2,
        extensions={"KHR_materials_transmission": {"transmissionFactor": 1.0}}))
    with_ext(b, "KHR_materials_transmission")
    b.node(mesh=b.quad(3.0, back), name="backdrop")
    b.node(mesh=b.quad(2.0, pane, z=0.5), name="pane")
    p = os.path.join(folder, "i_transmission_pane.gltf")
    b.write(p, {"probe": "centre"})
    paths.append(p)

    # (j) KHR_materials_volume: two clear glass spheres of IOR 1.5 (radius 0.45, transmission 1,
    # thickness 1, no attenuation), smooth on the left and roughness 0.3 on the right, 0.6 m in
    # front of a backdrop whose vertex colours (red, green, blue, white corners) show where the
    # refracted rays land. Double-sided: chiaro shades both faces of a transmissive material.
    b = GltfBuilder()
    back = b.material(name="gradient_backdrop_r1", **pbr([1.0, 1.0, 1.0], 0.0, 1.0))
    colors = [[0.9, 0.1, 0.1, 1.0], [0.1, 0.9, 0.1, 1.0], [0.1, 0.1, 0.9, 1.0],
              [0.9, 0.9, 0.9, 1.0]]
    b.node(mesh=b.quad(3.0, back, colors=colors), name="backdrop")
    for name, x, roughness in [("smooth", -0.55, 0.0), ("rough", 0.55, 0.3)]:
        glass = b.material(name=f"glass_{name}_r{roughness}", doubleSided=True, **pbr(
            [1.0, 1.0, 1.0], 0.0, roughness,
            extensions={"KHR_materials_transmission": {"transmissionFactor": 1.0},
                        "KHR_materials_volume": {"thicknessFactor": 1.0}}))
        b.node(mesh=b.sphere(0.45, glass), name=f"{name} sphere", translation=[x, 0.0, 0.6])
    with_ext(b, "KHR_materials_transmission", "KHR_materials_volume")
    p = os.path.join(folder, "j_volume_spheres.gltf")
    b.write(p)
    paths.append(p)

    # (k) The extensions' textures, in stripes: (g)'s coat at 60 degrees with a clearcoatTexture
    # (R) and a clearcoatRoughnessTexture (G, stripes twice as wide, roughness factor 1);
    # (h)'s specular quad at 60 degrees with a specularTexture (A) and a specularColorTexture
    # (RGB, sRGB: a blue stripe); (i)'s pane with a transmissionTexture (R).
    b = GltfBuilder()
    coat = stripes(0)
    coat[:, :, 1] = stripes(1, period=4)[:, :, 1]
    t = b.texture(coat)
    m = b.material(name="red_r0.6_clearcoat_textured", **pbr(
        [0.8, 0.1, 0.1], 0.0, 0.6,
        extensions={"KHR_materials_clearcoat": {
            "clearcoatFactor": 1.0, "clearcoatTexture": {"index": t},
            "clearcoatRoughnessFactor": 1.0, "clearcoatRoughnessTexture": {"index": t}}}))
    with_ext(b, "KHR_materials_clearcoat")
    b.node(mesh=b.quad(2.0, m), name="quad", rotation=rot_x(-60.0))
    p = os.path.join(folder, "k_clearcoat_textured.gltf")
    b.write(p)
    paths.append(p)

    # (k) Normal textures tilting the normal 20 degrees along V (up and down the image: toward
    # and away from the view on a quad at 60 degrees) in vertical stripes two texels wide: the
    # base's normalTexture on a glossy red dielectric, and the coat's own clearcoatNormalTexture
    # over (g)'s coat (roughness factor 0.2) with the base keeping the quad's normal. A renderer
    # that reads the green channel upside down swaps the stripes.
    tilted = np.full((8, 8, 4), 255, np.uint8)
    tilted[:, :, 0] = 128
    tilted[:, :, 2] = round((math.cos(math.radians(20.0)) + 1.0) * 127.5)
    for x in range(8):
        sign = 1.0 if (x // 2) % 2 else -1.0
        tilted[:, x, 1] = round((sign * math.sin(math.radians(20.0)) + 1.0) * 127.5)
    b = GltfBuilder()
    t = b.texture(tilted)
    m = b.material(name="red_r0.3_normal_textured", normalTexture={"index": t},
                   **pbr([0.8, 0.1, 0.1], 0.0, 0.3))
    b.node(mesh=b.quad(2.0, m), name="quad", rotation=rot_x(-60.0))
    p = os.path.join(folder, "k_normal_textured.gltf")
    b.write(p)
    paths.append(p)

    b = GltfBuilder()
    t = b.texture(tilted)
    m = b.material(name="red_r0.6_clearcoat_normal_textured", **pbr(
        [0.8, 0.1, 0.1], 0.0, 0.6,
        extensions={"KHR_materials_clearcoat": {
            "clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.2,
            "clearcoatNormalTexture": {"index": t}}}))
    with_ext(b, "KHR_materials_clearcoat")
    b.node(mesh=b.quad(2.0, m), name="quad", rotation=rot_x(-60.0))
    p = os.path.join(folder, "k_clearcoat_normal_textured.gltf")
    b.write(p)
    paths.append(p)

    b = GltfBuilder()
    spec = stripes(3)
    spec[:, :4, 0:2] = 64
    t = b.texture(spec)
    m = b.material(name="grey_r0.3_specular_textured", **pbr(
        [0.5, 0.5, 0.5], 0.0, 0.3,
        extensions={"KHR_materials_specular": {
            "specularTexture": {"index": t}, "specularColorTexture": {"index": t}}}))
    with_ext(b, "KHR_materials_specular")
    b.node(mesh=b.quad(2.0, m), name="quad", rotation=rot_x(-60.0))
    p = os.path.join(folder, "k_specular_textured.gltf")
    b.write(p)
    paths.append(p)

    b = GltfBuilder()
    back = b.material(name="orange_backdrop_r1", **pbr([0.8, 0.4, 0.1], 0.0, 1.0))
    t = b.texture(stripes(0))
    pane = b.material(name="pane_transmission_textured_r0.2", doubleSided=True, **pbr(
        [1.0, 1.0, 1.0], 0.0, 0.2,
        extensions={"KHR_materials_transmission": {
            "transmissionFactor": 1.0, "transmissionTexture": {"index": t}}}))
    with_ext(b, "KHR_materials_transmission")
    b.node(mesh=b.quad(3.0, back), name="backdrop")
    b.node(mesh=b.quad(2.0, pane, z=0.5), name="pane")
    p = os.path.join(folder, "k_transmission_textured.gltf")
    b.write(p)
    paths.append(p)
    return paths
