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

- kitchen_floor_height.png (256 x 256, 16-bit grey): the floor's height
  map at half the albedo's resolution, the same 4 x 4 tiles: grout at 0,
  each tile a bevelled slab at 0.6-0.8 with a slight tilt and a fine grain
  (displaced in scenes/displaced.toml and the kitchen's displaced frame).
- bumps_height.png (128 x 128, 16-bit grey): smooth round bumps, 8 x 8 to
  a repeat, for curved models (the teapot, the torus).
- panels_height.png (512 x 512, 16-bit grey): sparse detail, riveted
  plating: a flat plate crossed by a few bevelled seams (rows at uneven
  heights, each row's joints staggered) with domed rivets along the rows'
  seams; most of the map is flat, so a surface's detail is local
  (scenes/panels.toml).

Usage: tools/textures/make.py [OUT_DIR]   (default: scenes/textures beside tools/)
"""
import colorsys
import math
import os
import struct
import sys
import zlib


def save_png(path, width, height, depth, colour, texel, extra=()):
    """Writes a PNG of `texel(x, y) -> bytes` (y = 0 the top row), `depth`
    bits per channel, colour type `colour`, with `extra` chunks before the
    pixels; written beside and renamed, so a failure leaves no half file."""
    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter: none
        for x in range(width):
            rows.extend(texel(x, y))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, 0))
    for kind, data in extra:
        png += chunk(kind, data)
    png += chunk(b"IDAT", zlib.compress(bytes(rows), 9))
    png += chunk(b"IEND", b"")
    tmp = path + ".tmp"
    with open(tmp, "wb") as out:
        out.write(png)
    os.replace(tmp, path)


def write_png(path, width, height, pixel):
    """Writes `pixel(x, y) -> (r, g, b)` (bytes, y = 0 the top row) as sRGB PNG."""
    save_png(path, width, height, 8, 2, pixel, [(b"sRGB", b"\x00")])


def write_grey16_png(path, width, height, height_at):
    """Writes `height_at(x, y) -> [0, 1]` (y = 0 the top row) as 16-bit grey PNG."""

    def texel(x, y):
        return struct.pack(">H", int(round(max(0.0, min(1.0, height_at(x, y))) * 65535)))

    save_png(path, width, height, 16, 0, texel)


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


def floor_height(x, y):
    tile = 64
    # Texel centres, in tile units from the tile's grout corner.
    gx, gy = (x % tile) + 0.5, (y % tile) + 0.5
    grout = 1.5
    bevel = 3.0
    edge = min(gx, gy, tile - gx + grout, tile - gy + grout) - grout
    if edge <= 0:
        return 0.02 + hash2(x, y, 11) * 0.02
    tx, ty = x // tile, y // tile
    top = 0.6 + hash2(tx, ty, 13) * 0.2
    tilt = (hash2(tx, ty, 17) - 0.5) * 0.1 * (gx / tile) + (hash2(tx, ty, 19) - 0.5) * 0.1 * (gy / tile)
    slab = top + tilt + (hash2(x // 2, y // 2, 23) - 0.5) * 0.03
    ramp = min(1.0, edge / bevel)
    return slab * (ramp * (2 - ramp))


def bumps_height(x, y):
    period = 16
    fx = ((x + 0.5) % period) / period - 0.5
    fy = ((y + 0.5) % period) / period - 0.5
    r = math.sqrt(fx * fx + fy * fy) * 2.2
    return 0.5 * (1 + math.cos(math.pi * min(1.0, r)))


# Riveted plating: the rows' seams (y), each row's joints (x) and the
# rivets' spacing, in texels of the 512-texel map. Uneven on purpose, so
# that no seam follows a patch edge of the models it is mapped on.
PANEL_ROWS = (37, 151, 290, 404)
PANEL_JOINTS = ((101, 333), (229, 467), (61, 283), (171, 409))
RIVET_STEP = 32


def panels_height(x, y):
    size = 512
    cx, cy = x + 0.5, y + 0.5

    def seam(d):
        # A groove 3 texels wide at the bottom, bevelled over 2 more.
        return min(1.0, max(0.0, (abs(d) - 1.5) / 2.0))

    def wrapped(d):
        return (d + size / 2) % size - size / 2

    row = sum(1 for r in PANEL_ROWS if cy >= r + 0.5) % len(PANEL_ROWS)
    depth = min(seam(wrapped(cy - r - 0.5)) for r in PANEL_ROWS)
    depth = min([depth] + [seam(wrapped(cx - j - 0.5)) for j in PANEL_JOINTS[row]])
    height = 0.1 + 0.5 * depth
    # Rivets: domes of radius 3.5 texels, 7 texels either side of each row seam.
    for r in PANEL_ROWS:
        for side in (-7, 7):
            dy = wrapped(cy - (r + 0.5 + side))
            dx = wrapped(cx - (round(cx / RIVET_STEP) * RIVET_STEP))
            d = math.sqrt(dx * dx + dy * dy) / 3.5
            if d < 1:
                height = max(height, 0.6 + 0.3 * math.sqrt(1 - d * d))
    return height


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
    for name, size, height_at in (
        ("kitchen_floor_height.png", 256, floor_height),
        ("bumps_height.png", 128, bumps_height),
        ("panels_height.png", 512, panels_height),
    ):
        path = os.path.join(out, name)
        write_grey16_png(path, size, size, height_at)
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
