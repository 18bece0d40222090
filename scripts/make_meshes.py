#!/usr/bin/env python3
"""Regenerates the meshes in scenes/meshes/ (run from the repository root).

  sphere.obj    UV sphere, radius 1, 32 x 16 segments (written here; CC0)
  triangle.obj  one triangle (written here; CC0)
  bunny.ply     the Stanford bunny (Stanford 3D Scanning Repository), as packaged by the npm
                package "bunny" 1.0.1 (public domain): pass the path of its index.js, e.g.
                  npm pack bunny@1.0.1 && tar xzf bunny-1.0.1.tgz
                  scripts/make_meshes.py package/index.js
"""
import json
import math
import re
import sys


def sphere(path, slices=32, stacks=16):
    v, f = [], []
    for i in range(stacks + 1):
        phi = math.pi * i / stacks
        for j in range(slices):
            theta = 2 * math.pi * j / slices
            v.append((math.sin(phi) * math.cos(theta), math.cos(phi), math.sin(phi) * math.sin(theta)))
    for i in range(stacks):
        for j in range(slices):
            a, b = i * slices + j, i * slices + (j + 1) % slices
            c, d = a + slices, b + slices
            if i > 0:
                f.append((a, b, c))
            if i < stacks - 1:
                f.append((b, d, c))
    with open(path, "w") as out:
        out.write("# UV sphere, radius 1, %d x %d segments. Written by scripts/make_meshes.py (CC0).\n" % (slices, stacks))
        for p in v:
            out.write("v %.6f %.6f %.6f\n" % p)
        for t in f:
            out.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def triangle(path):
    with open(path, "w") as out:
        out.write("# One triangle. Written by scripts/make_meshes.py (CC0).\n")
        out.write("v -0.5 -0.4 0\nv 0.5 -0.4 0\nv 0 0.5 0\nf 1 2 3\n")


def bunny(index_js, path):
    text = open(index_js).read()
    positions = json.loads(re.search(r"exports\.positions=(\[.*?\]\])", text).group(1))
    cells = json.loads(re.search(r"exports\.cells=(\[.*?\]\])", text).group(1))
    with open(path, "w") as out:
        out.write("ply\nformat ascii 1.0\n")
        out.write("comment The Stanford bunny (Stanford 3D Scanning Repository), from the npm package bunny 1.0.1 (public domain)\n")
        out.write("element vertex %d\nproperty float x\nproperty float y\nproperty float z\n" % len(positions))
        out.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(cells))
        for p in positions:
            out.write("%g %g %g\n" % tuple(p))
        for c in cells:
            out.write("3 %d %d %d\n" % tuple(c))


if __name__ == "__main__":
    sphere("scenes/meshes/sphere.obj")
    triangle("scenes/meshes/triangle.obj")
    if len(sys.argv) > 1:
        bunny(sys.argv[1], "scenes/meshes/bunny.ply")
