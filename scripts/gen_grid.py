#!/usr/bin/env python3
"""Writes a grid of COLS x ROWS quads as a Wavefront OBJ (v, vt, f; two
triangles per quad) for the memory and work bounds (docs/RELIABILITY.md).

    scripts/gen_grid.py COLS ROWS OUT.obj [--bump AMPLITUDE] [--texture IMAGE]

The grid spans [-1, 1] in x and [-ROWS/COLS, ROWS/COLS] in y at z = 0 and is
textured once over [0, 1]^2; --bump displaces z by AMPLITUDE times a product
of sines (four bumps along each side), so neighbouring triangles face
different directions; --texture writes a material library OUT.mtl next to
it whose diffuse map is IMAGE (a path relative to the OBJ). The files depend
only on the arguments.
"""
import argparse
import math
import os
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cols", type=int)
    ap.add_argument("rows", type=int)
    ap.add_argument("out")
    ap.add_argument("--bump", type=float, default=0.0)
    ap.add_argument("--texture")
    a = ap.parse_args()
    if a.cols < 1 or a.rows < 1:
        sys.exit("gen_grid.py: COLS and ROWS must be at least 1")
    aspect = a.rows / a.cols
    with open(a.out, "w", encoding="ascii") as f:
        f.write("# %d x %d quads\n" % (a.cols, a.rows))
        if a.texture:
            mtl = os.path.splitext(a.out)[0] + ".mtl"
            with open(mtl, "w", encoding="ascii") as m:
                m.write("newmtl grid\nKd 1 1 1\nmap_Kd %s\n" % a.texture)
            f.write("mtllib %s\nusemtl grid\n" % os.path.basename(mtl))
        for j in range(a.rows + 1):
            t = j / a.rows
            for i in range(a.cols + 1):
                s = i / a.cols
                z = a.bump * math.sin(8 * math.pi * s) * math.sin(8 * math.pi * t)
                f.write("v %.6f %.6f %.6f\n" % (2 * s - 1, (2 * t - 1) * aspect, z))
        for j in range(a.rows + 1):
            for i in range(a.cols + 1):
                f.write("vt %.6f %.6f\n" % (i / a.cols, j / a.rows))
        n = a.cols + 1
        for j in range(a.rows):
            for i in range(a.cols):
                p = j * n + i + 1  # OBJ indices start at 1
                q, r, s = p + 1, p + n + 1, p + n
                f.write("f %d/%d %d/%d %d/%d\n" % (p, p, q, q, r, r))
                f.write("f %d/%d %d/%d %d/%d\n" % (p, p, r, r, s, s))


if __name__ == "__main__":
    main()
