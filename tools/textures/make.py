#!/usr/bin/env python3
"""Writes the albedo maps under scenes/textures/ (PNG, sRGB, 8-bit RGB).

Every map here is made by this script from nothing but arithmetic, so the
project carries no third-party image and a change to a map is a change to
this file. Python's standard library only (zlib for the PNG stream).

- kitchen_floor.png (512 x 512): 4 x 4 stone tiles of 128 texels, each a
  slightly different warm grey, with 3-texel dark grout and a fine
  deterministic grain. The kitchen floor's cage maps 4 tiles to 12 units,
  so one tile lies on each 3-unit quad of the cage
  (tools/kitchen/make.py, kitchen_floor.obj/.mtl).
- uv_grid.png (512 x 512): a UV test grid of 8 x 8 cells whose hue runs
  with s and brightness with t, black cell borders, and a white mark in
  each cell's upper-left corner: where a map is stretched, mirrored or
  turned, the marks show it (scenes/textured.toml).

Usage: tools/textures/make.py [OUT_DIR]   (default: scenes/textures beside tools/)
"""
import colorsys
import os
import struct
import sys
import zlib


def write_png(path, width, height, pixel):
    """Writes `pixel(x, y) -> (r, g, b)` (bytes, y = 0 the top row) as PNG."""
    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter: none
        for x in range(width):
            rows.extend(pixel(x, y))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"sRGB", b"\x00")
    png += chunk(b"IDAT", zlib.compress(bytes(rows), 9))
    png += chunk(b"IEND", b"")
    tmp = path + ".tmp"
    with open(tmp, "wb") as out:
        out.write(png)
    os.replace(tmp, path)


def hash2(x, y, seed):
    """A deterministic value in [0, 1) for integer (x, y)."""
    h = (x * 374761393 + y * 668265263 + seed * 2246822519) & 0xFFFFFFFF
    h = ((h ^ (h >> 13)) * 1274126177) & 0xFFFFFFFF
    return ((h ^ (h >> 16)) & 0xFFFF) / 65536.0


def floor_pixel(x, y):
    tile = 128
    gx, gy = x % tile, y % tile
    grout = 3
    if gx < grout or gy < grout:
        base = (58, 54, 50)
        n = hash2(x, y, 7) * 10 - 5
        return bytes(int(max(0, min(255, c + n))) for c in base)
    tx, ty = x // tile, y // tile
    shade = hash2(tx, ty, 1) * 0.18 - 0.09
    warm = (196, 180, 158)
    grain = hash2(x // 2, y // 2, 3) * 16 - 8 + hash2(x, y, 5) * 8 - 4
    return bytes(int(max(0, min(255, c * (1 + shade) + grain))) for c in warm)


def grid_pixel(x, y):
    cell = 64
    i, j = x // cell, y // cell
    cx, cy = x % cell, y % cell
    if cx < 2 or cy < 2:
        return bytes((16, 16, 16))
    if 6 <= cx < 18 and 6 <= cy < 18 and cx - 6 <= 18 - cy:
        return bytes((245, 245, 245))
    # t runs upwards in OBJ's convention: the bottom row of cells is t = 0.
    t = (7 - j) / 7
    r, g, b = colorsys.hsv_to_rgb(i / 8, 0.65, 0.45 + 0.5 * t)
    return bytes((int(r * 255), int(g * 255), int(b * 255)))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "scenes", "textures")
    os.makedirs(out, exist_ok=True)
    for name, pixel in (("kitchen_floor.png", floor_pixel), ("uv_grid.png", grid_pixel)):
        path = os.path.join(out, name)
        write_png(path, 512, 512, pixel)
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
