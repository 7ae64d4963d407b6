#!/usr/bin/env python3
"""A closed cylinder as binary STL, a shape for `cmcsurf scaffold --shape` (docs/scaffolds.md).

usage: cylinder_stl.py OUT.stl [DIAMETER HEIGHT [SEGMENTS]]   (default 10 10 256, in mm)

The axis is z, the base at z = 0, centred on x = y = 0; SEGMENTS sides around.
"""
import math
import struct
import sys


def main():
    if len(sys.argv) in (2, 4, 5) and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0
    if len(sys.argv) not in (2, 4, 5) or sys.argv[1].startswith("-"):
        print(__doc__, file=sys.stderr)
        return 2
    out = sys.argv[1]
    d, h = (float(sys.argv[2]), float(sys.argv[3])) if len(sys.argv) >= 4 else (10.0, 10.0)
    n = int(sys.argv[4]) if len(sys.argv) == 5 else 256
    r = d / 2
    ring = [(r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n))
            for k in range(n)]
    tris = []
    for k in range(n):
        (x0, y0), (x1, y1) = ring[k], ring[(k + 1) % n]
        tris += [((0, 0, 0), (x1, y1, 0), (x0, y0, 0)), ((0, 0, h), (x0, y0, h), (x1, y1, h)),
                 ((x0, y0, 0), (x1, y1, 0), (x1, y1, h)), ((x0, y0, 0), (x1, y1, h), (x0, y0, h))]
    with open(out, "wb") as f:
        f.write(b"cmcsurf cylinder".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<3f", 0, 0, 0))
            for p in t:
                f.write(struct.pack("<3f", *p))
            f.write(b"\0\0")
    return 0


if __name__ == "__main__":
    sys.exit(main())
