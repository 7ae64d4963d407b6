#!/usr/bin/env python3
"""A closed box as ASCII STL, a shape for `cmcsurf scaffold --shape` (docs/scaffolds.md).

usage: box_stl.py OUT.stl XLO,YLO,ZLO XHI,YHI,ZHI   (corners, in the part's units)

Twelve triangles wound counter-clockwise seen from outside; the facet normals are written as
0 0 0 (readers take them from the winding).
"""
import sys


def main():
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    lo, hi = ([float(x) for x in a.split(",")] for a in sys.argv[2:4])
    if len(lo) != 3 or len(hi) != 3 or not all(lo[c] < hi[c] for c in range(3)):
        print(f"box_stl.py: corners {sys.argv[2]} {sys.argv[3]}: accepted: X,Y,Z with each "
              "low < high", file=sys.stderr)
        return 2
    v = [(hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2])
         for c in range(8)]
    t = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3),
         (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    with open(sys.argv[1], "w") as f:
        f.write("solid block\n")
        for tri in t:
            f.write(" facet normal 0 0 0\n  outer loop\n")
            for q in tri:
                f.write("   vertex %g %g %g\n" % v[q])
            f.write("  endloop\n endfacet\n")
        f.write("endsolid block\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
