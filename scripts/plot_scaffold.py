#!/usr/bin/env python3
"""Pictures of a `cmcsurf scaffold` part for docs/scaffolds.md.

usage: plot_scaffold.py PART.stl OUT.png

(a), (b): the part cut by the planes z and x at 0.4 of the box (the binary STL's
triangles intersected with the plane, drawn as segments; the solid is on one side of them),
(c): the wall and pore distributions of PART.stl.json (local thickness on the unit cell,
`morphometry`; a graded part has one per member, `morphometry.members`, drawn each),
(d), a graded part only: its porosity profile, target and measured per band along the axis or
by depth below the shape's surface (`graded.profile`, or `graded_cell_size.profile`).
Draws what cmcsurf computed; computes nothing of its own beyond the plane cuts. Exit code 3
when matplotlib or numpy is missing.
"""
import json
import struct
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    import numpy as np
except ImportError as e:  # pragma: no cover
    print(f"plot_scaffold: {e}", file=sys.stderr)
    sys.exit(3)


def read_stl(path):
    with open(path, "rb") as f:
        f.read(80)
        (count,) = struct.unpack("<I", f.read(4))
        data = np.frombuffer(f.read(50 * count), dtype=np.uint8).reshape(count, 50)
    return data[:, 12:48].copy().view("<f4").reshape(count, 3, 3).astype(np.float64)


def cut(tri, axis, value):
    """Segments where the triangles cross the plane x[axis] = value, in the other two axes."""
    d = tri[:, :, axis] - value
    side = d > 0
    crossing = side.any(axis=1) & ~side.all(axis=1)
    tri, d = tri[crossing], d[crossing]
    other = [c for c in range(3) if c != axis]
    segments = []
    for t, s in zip(tri, d):
        points = []
        for a, b in ((0, 1), (1, 2), (2, 0)):
            if (s[a] > 0) != (s[b] > 0):
                w = s[a] / (s[a] - s[b])
                p = t[a] + w * (t[b] - t[a])
                points.append(p[other])
        if len(points) == 2:
            segments.append(points)
    return np.array(segments), other


def distributions(m):
    """(the cell's morphometry, its name in the legend, line style) for each distribution:
    the part's one cell, or a graded part's members (their porosity named)."""
    if "wall_thickness" in m and "pore_size" in m:
        return [(m, "", "-")]
    styles = ["-", "--", ":", "-."]
    return [(c, f" (porosity {c['porosity']:.2f})", styles[i % len(styles)])
            for i, c in enumerate(m.get("members", []))
            if "wall_thickness" in c and "pore_size" in c]


def profile(report):
    """(bands, by depth, where) of a graded part's porosity profile, or None."""
    for key in ("graded", "graded_cell_size"):
        g = report.get(key)
        if isinstance(g, dict) and g.get("profile"):
            depth = g.get("by") == "surface"
            return g["profile"], depth, ("by depth" if depth else f"along {g['axis']}")
    return None


def draw_profile(ax, bands, by_depth, where, units):
    """Target (line) and measured (dots) porosity at each band's middle; the core (a depth
    band without an end) one band wide past the last."""
    mids, width = [], 0.0
    for b in bands:
        lo = b["depth_from"] if by_depth else b["from"]
        hi = b["depth_to"] if by_depth else b["to"]
        hi = lo + width if hi is None else hi
        width = hi - lo
        mids.append(0.5 * (lo + hi))
    nan = float("nan")
    target = [nan if b["porosity_target"] is None else b["porosity_target"] for b in bands]
    nodes = [nan if b["porosity_nodes"] is None else b["porosity_nodes"] for b in bands]
    ax.plot(mids, target, "-", color="C0", label="target")
    ax.plot(mids, nodes, "o", color="C1", label="measured (lattice nodes)")
    ax.set_xlabel(f"depth below the surface ({units}); last: the core" if by_depth
                  else f"position {where} ({units})")
    ax.set_ylabel("porosity")
    ax.set_title(f"porosity {where}")
    ax.legend(fontsize="small")


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    part, out = sys.argv[1], sys.argv[2]
    report = json.load(open(part + ".json"))
    tri = read_stl(part)
    lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
    units = report["units"] if "units" in report else report["design"]["units"]
    graded = profile(report)
    fig, axes = plt.subplots(1, 4 if graded else 3, figsize=(20 if graded else 15, 5))
    names = "xyz"
    for ax, axis in zip(axes[:2], (2, 0)):
        mid = lo[axis] + 0.4 * (hi[axis] - lo[axis])  # off the lattice's mirror planes
        segments, other = cut(tri, axis, mid)
        ax.add_collection(LineCollection(segments, linewidths=0.6, colors="k"))
        ax.set_xlim(lo[other[0]], hi[other[0]])
        ax.set_ylim(lo[other[1]], hi[other[1]])
        ax.set_aspect("equal")
        ax.set_xlabel(f"{names[other[0]]} ({units})")
        ax.set_ylabel(f"{names[other[1]]} ({units})")
        ax.set_title(f"cut at {names[axis]} = {mid:.3g} {units}")
    m = report["morphometry"]
    ax = axes[2]
    for cell, name, style in distributions(m):
        for key, label, color in (("wall_thickness", "wall", "C0"), ("pore_size", "pore", "C1")):
            s = cell[key]
            edges = np.array(s["histogram_edges"])
            ax.stairs(np.array(s["histogram"]), edges, color=color, linestyle=style,
                      label=f"{label}{name}: mean {s['mean']:.3g}, min {s['min']:.3g} {units}")
    ax.set_xlabel(f"local thickness ({units})")
    ax.set_ylabel("fraction of the wall or pore volume")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize="small")
    if graded:
        draw_profile(axes[3], *graded, units)
    d = report["design"]
    if "graded" in report:
        g = report["graded"]
        where = (f"from the surface to {g['depth']} {units} deep" if g.get("by") == "surface"
                 else f"along {g['axis']}")
        target = f"{g['porosity_from']} to {g['porosity_to']} {where}"
    else:
        target = d["porosity"]
    fig.suptitle(f"{d['solid']} scaffold: porosity {report['porosity']:.4f} "
                 f"(target {target}), cell size {d['cell_size']} {units}, "
                 f"specific surface {m['specific_surface']:.3g} 1/{units}")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
