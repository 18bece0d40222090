#!/usr/bin/env python3
"""Regenerates the textured built-in scene's models and textures in scenes/meshes/atrium/ (run
from the repository root). Everything is written here from integer arithmetic and a fixed
linear congruential generator, so the files are the same on every machine (CC0).

  tiles.png   64x64 RGBA8, opaque: two stone colours in 16-texel tiles with grout lines
  bricks.png  64x64 RGBA8, opaque: running-bond bricks (16x8 texels) with mortar
  leaf.png    64x64 RGBA8: a leaf-shaped alpha mask (alpha 0 outside the leaf, 210 inside,
              a soft 3-texel rim), green with darker veins -- the thesis's foliage (figures 2.5,
              3.2): fully transparent texels that still count as layers for the weighted average
  glass.png   32x32 RGBA8, sRGB colours: a stained-glass lattice of coloured panes (alpha 110-150)
              with opaque dark leading
  floor.obj   the floor: a 10x10 quad at y = 0, texture coordinates 0..5 (the tiles repeat)
  columns.obj two rows of four square columns (0.5 x 3 x 0.5), every face u 0..1, v 0..3
  wall.obj    the back wall: 10 x 4, u 0..5, v 0..2
  leaves.obj  48 leaf quads (0.35-0.6 wide) in two hanging clusters, at seeded angles
  pane.obj    one unit quad for the stained glass (its texture is named by the scene file)
Each model's .mtl names its diffuse texture (map_Kd), beside it, as the thesis keeps them.
"""
import math
import os
import struct
import zlib

OUT = "scenes/meshes/atrium"


def png(path, w, h, pixels):
    """pixels: list of rows, top row first, each w (r, g, b, a) tuples of 0..255."""
    raw = b"".join(b"\x00" + bytes(c for p in row for c in p) for row in pixels)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


class Lcg:
    def __init__(self, seed):
        self.state = seed

    def next(self):  # Numerical Recipes' constants, 32 bits
        self.state = (1664525 * self.state + 1013904223) % (1 << 32)
        return self.state

    def uniform(self, lo, hi):
        return lo + (hi - lo) * (self.next() / float(1 << 32))


def tiles():
    rng = Lcg(7)
    rows = []
    for y in range(64):
        row = []
        for x in range(64):
            if x % 16 == 0 or y % 16 == 0:
                row.append((70, 66, 60, 255))
                continue
            light = ((x // 16) + (y // 16)) % 2 == 0
            n = rng.next() % 12
            base = (188, 176, 150) if light else (120, 104, 86)
            row.append((base[0] + n, base[1] + n, base[2] + n, 255))
        rows.append(row)
    return 64, 64, rows


def bricks():
    rng = Lcg(11)
    rows = []
    for y in range(64):
        row = []
        course = y // 8
        for x in range(64):
            xs = (x + (8 if course % 2 else 0)) % 64
            if y % 8 == 0 or xs % 16 == 0:
                row.append((200, 196, 184, 255))
                continue
            n = rng.next() % 20
            row.append((150 + n, 70 + n // 2, 50 + n // 3, 255))
        rows.append(row)
    return 64, 64, rows


def leaf():
    rows = []
    for y in range(64):
        row = []
        for x in range(64):
            # The leaf: |u| < half-width(v), v along the midrib from the stem (bottom) to the tip.
            v = (63 - y) / 63.0
            u = (x - 31.5) / 31.5
            half = 0.85 * math.sin(math.pi * min(max(v, 0.0), 1.0)) ** 0.8
            inside = half - abs(u)  # > 0 inside, in units of the half-width (0..1)
            if inside <= 0.0 or v < 0.06:
                row.append((40, 90, 30, 0))
                continue
            rim = min(1.0, inside * 31.5 / 3.0)  # a 3-texel soft edge
            alpha = int(round(210 * rim))
            vein = abs(u) < 0.04 or abs(abs(u) - 0.6 * (v % 0.2) / 0.2) < 0.035
            g = 95 if vein else 150 + int(60 * v)
            row.append((40 + int(40 * v), g, 35, alpha))
        rows.append(row)
    return 64, 64, rows


def glass():
    colours = [(200, 40, 40), (40, 80, 200), (230, 190, 40), (40, 160, 80)]
    rows = []
    for y in range(32):
        row = []
        for x in range(32):
            if x % 8 in (0, 7) or y % 8 in (0, 7):
                row.append((30, 28, 26, 255))
                continue
            c = colours[((x // 8) + 2 * (y // 8)) % 4]
            alpha = 110 + 10 * (((x // 8) * 3 + (y // 8)) % 5)
            row.append((c[0], c[1], c[2], alpha))
        rows.append(row)
    return 32, 32, rows


class Obj:
    def __init__(self, texture):
        self.v, self.vt, self.f, self.texture = [], [], [], texture

    def quad(self, corners, uvs):
        """corners: four points counter-clockwise seen from the front; uvs likewise."""
        base = len(self.v) + 1
        self.v += corners
        self.vt += uvs
        self.f += [(base, base + 1, base + 2), (base, base + 2, base + 3)]

    def write(self, name):
        with open(os.path.join(OUT, name + ".mtl"), "w") as m:
            m.write("newmtl %s\nKd 1 1 1\nmap_Kd %s\n" % (name, self.texture))
        with open(os.path.join(OUT, name + ".obj"), "w") as o:
            o.write("# scripts/make_atrium.py (CC0)\nmtllib %s.mtl\nusemtl %s\n" % (name, name))
            for p in self.v:
                o.write("v %.6f %.6f %.6f\n" % p)
            for t in self.vt:
                o.write("vt %.6f %.6f\n" % t)
            for a, b, c in self.f:
                o.write("f %d/%d %d/%d %d/%d\n" % (a, a, b, b, c, c))


def box(obj, x, z, w, h):
    """A column: four sides (no top or bottom), u 0..1 per face, v 0..h."""
    x0, x1, z0, z1 = x - w / 2, x + w / 2, z - w / 2, z + w / 2
    uv = [(0, 0), (1, 0), (1, h), (0, h)]
    obj.quad([(x0, 0, z1), (x1, 0, z1), (x1, h, z1), (x0, h, z1)], uv)  # +z
    obj.quad([(x1, 0, z0), (x0, 0, z0), (x0, h, z0), (x1, h, z0)], uv)  # -z
    obj.quad([(x1, 0, z1), (x1, 0, z0), (x1, h, z0), (x1, h, z1)], uv)  # +x
    obj.quad([(x0, 0, z0), (x0, 0, z1), (x0, h, z1), (x0, h, z0)], uv)  # -x


def leaves():
    obj = Obj("leaf.png")
    rng = Lcg(23)
    for cluster in ((-1.3, 2.2, 0.6), (1.4, 2.0, -0.4)):
        for _ in range(24):
            cx = cluster[0] + rng.uniform(-0.7, 0.7)
            cy = cluster[1] + rng.uniform(-0.8, 0.6)
            cz = cluster[2] + rng.uniform(-0.6, 0.6)
            size = rng.uniform(0.35, 0.6)
            yaw = rng.uniform(0, 2 * math.pi)
            tilt = rng.uniform(-0.9, 0.9)
            # The leaf's width axis (horizontal, turned by yaw) and length axis (tilted from vertical).
            ax = (math.cos(yaw) * size / 2, 0.0, math.sin(yaw) * size / 2)
            lx = (-math.sin(yaw) * math.sin(tilt) * size, -math.cos(tilt) * size, math.cos(yaw) * math.sin(tilt) * size)
            stem = (cx, cy, cz)
            corners = [
                (stem[0] - ax[0], stem[1] - ax[1], stem[2] - ax[2]),
                (stem[0] + ax[0], stem[1] + ax[1], stem[2] + ax[2]),
                (stem[0] + ax[0] + lx[0], stem[1] + ax[1] + lx[1], stem[2] + ax[2] + lx[2]),
                (stem[0] - ax[0] + lx[0], stem[1] - ax[1] + lx[1], stem[2] - ax[2] + lx[2]),
            ]
            # The stem (v = 0) at the top where the leaf hangs from, the tip (v = 1) below.
            obj.quad(corners, [(0, 0), (1, 0), (1, 1), (0, 1)])
    obj.write("leaves")


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, make in (("tiles", tiles), ("bricks", bricks), ("leaf", leaf), ("glass", glass)):
        w, h, rows = make()
        png(os.path.join(OUT, name + ".png"), w, h, rows)
    floor = Obj("tiles.png")
    floor.quad([(-5, 0, 5), (5, 0, 5), (5, 0, -5), (-5, 0, -5)], [(0, 0), (5, 0), (5, 5), (0, 5)])
    floor.write("floor")
    columns = Obj("bricks.png")
    for x in (-3.0, -1.0, 1.0, 3.0):
        for z in (-2.5, 1.0):
            box(columns, x, z, 0.5, 3.0)
    columns.write("columns")
    wall = Obj("bricks.png")
    wall.quad([(-5, 0, -4), (5, 0, -4), (5, 4, -4), (-5, 4, -4)], [(0, 0), (5, 0), (5, 2), (0, 2)])
    wall.write("wall")
    leaves()
    pane = Obj("glass.png")
    pane.quad([(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)], [(0, 0), (1, 0), (1, 1), (0, 1)])
    pane.write("pane")


if __name__ == "__main__":
    main()
