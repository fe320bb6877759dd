"""Image files: EXR read through bpy, linear float EXR and PNG written by hand, and the side by
side PNG (chiaro | Cycles | |difference| x 4)."""

import struct
import zlib

import numpy as np


def read_exr(path):
    import bpy

    img = bpy.data.images.load(path, check_existing=False)
    w, h = img.size
    buf = np.empty(w * h * img.channels, dtype=np.float32)
    img.pixels.foreach_get(buf)
    ch = img.channels
    bpy.data.images.remove(img)
    arr = buf.reshape(h, w, ch)[::-1]  # Blender stores the bottom row first
    return np.ascontiguousarray(arr)


def write_png(path, rgb8):
    h, w, _ = rgb8.shape
    raw = b"".join(b"\x00" + rgb8[y].tobytes() for y in range(h))

    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def to_srgb8(x):
    x = np.clip(np.nan_to_num(x, nan=0.0), 0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (s * 255.0 + 0.5).astype(np.uint8)


def side_by_side(path, chiaro_img, cycles_img):
    h, w, _ = chiaro_img.shape
    gap = np.full((h, 2, 3), 255, np.uint8)
    diff = np.abs(chiaro_img - cycles_img) * 4.0
    panels = [to_srgb8(chiaro_img), gap, to_srgb8(cycles_img), gap, to_srgb8(diff)]
    write_png(path, np.concatenate(panels, axis=1))


def write_exr(path, rgb):
    """A linear float32 RGB OpenEXR file, scanline, uncompressed (written by hand: bpy's
    Image.save colour-manages float buffers, which `chiaro compare` then reads differently)."""
    rgb = np.ascontiguousarray(rgb, dtype=np.float32)
    h, w, _ = rgb.shape

    def attr(name, kind, data):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data

    chlist = b"".join(c.encode() + b"\0" + struct.pack("<iBBBBii", 2, 0, 0, 0, 0, 1, 1)
                      for c in "BGR") + b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = (
        struct.pack("<ii", 20000630, 2)
        + attr("channels", "chlist", chlist)
        + attr("compression", "compression", b"\0")
        + attr("dataWindow", "box2i", box)
        + attr("displayWindow", "box2i", box)
        + attr("lineOrder", "lineOrder", b"\0")
        + attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
        + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
        + attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
        + b"\0"
    )
    line_bytes = w * 3 * 4
    table_start = len(header)
    first = table_start + 8 * h
    offsets = struct.pack(f"<{h}Q", *[first + y * (8 + line_bytes) for y in range(h)])
    lines = []
    for y in range(h):
        row = rgb[y]
        lines.append(struct.pack("<ii", y, line_bytes)
                     + row[:, 2].tobytes() + row[:, 1].tobytes() + row[:, 0].tobytes())
    with open(path, "wb") as f:
        f.write(header + offsets + b"".join(lines))
