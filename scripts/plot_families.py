#!/usr/bin/env python3
"""Fig. 11 of the paper from a `cmcsurf sweep` table.

usage: plot_families.py SWEEP_CSV OUT_PREFIX   -> OUT_PREFIX.png and OUT_PREFIX.svg

(a) mean curvature vs volume fraction, (b) area per unit cell vs volume fraction, one curve per
surface family: the surface's own values (report keys `area`, `mean_curvature`, the sharp
estimators), with the diffuse layer's (Appendix B: `area_diffuse`) dotted beside them where the
table has them; (b) also shows the spheres-cylinders-planes profile I_scp(V) of Section 2.3 at
V = min(alpha, 1 - alpha) (the smaller phase: I_scp is defined for the enclosed volume V in
(0, pi/6), and the enclosing surface of a phase is also that of its complement), and the
literature areas of the P, D and G minimal surfaces at alpha = 1/2.
Exit code 3 when matplotlib is missing (cmcsurf sweep turns that into a warning).
"""
import csv
import math
import os
import sys

# Area per unit cubic cell of the minimal surfaces (see docs/families.md for the sources).
MINIMAL_AREA = {"P": 2.3451, "D": 3.8377, "G": 3.0919}


def i_scp(v):
    """Section 2.3: least area of spheres, cylinders and plane pairs enclosing volume v."""
    if v <= 4 * math.pi / 81:
        return (36 * math.pi * v * v) ** (1 / 3)
    if v <= 1 / math.pi:
        return 2 * math.sqrt(math.pi * v)
    return 2.0


def read_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    families = {}
    for r in rows:
        try:
            a = float(r["volume_fraction_target"])
            iso = float(r["area_diffuse"]) if r.get("area_diffuse") else float("nan")
            families.setdefault(r["surface"], []).append(
                (a, float(r["mean_curvature"]), float(r["area"]), iso))
        except (KeyError, ValueError):
            continue
    for v in families.values():
        v.sort()
    return families


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_families.py: matplotlib is not installed", file=sys.stderr)
        return 3
    families = read_rows(sys.argv[1])
    if not families:
        print(f"plot_families.py: no rows in {sys.argv[1]}", file=sys.stderr)
        return 1
    prefix = sys.argv[2]
    plt.rcParams.update({"font.size": 9, "svg.fonttype": "none", "svg.hashsalt": "cmcsurf"})
    fig, (ax_h, ax_a) = plt.subplots(1, 2, figsize=(11.0, 3.8), constrained_layout=True)
    markers = ["o", "s", "^", "D", "v", "<", ">", "p", "h", "*"]
    alphas = []
    for i, (name, pts) in enumerate(families.items()):
        a = [p[0] for p in pts]
        alphas += a
        label = name if len(name) <= 24 else name[:21] + "..."
        ax_h.plot(a, [p[1] for p in pts], marker=markers[i % len(markers)], ms=4, label=label)
        line, = ax_a.plot(a, [p[2] for p in pts], marker=markers[i % len(markers)], ms=4,
                          label=label)
        if any(p[3] == p[3] for p in pts):  # diffuse-layer area, where the table has it
            ax_a.plot(a, [p[3] for p in pts], ls=":", lw=1, color=line.get_color(),
                      label=f"{label} (diffuse layer, Appendix B)")
        if name in MINIMAL_AREA:
            ax_a.plot([0.5], [MINIMAL_AREA[name]], marker="x", color="k", ms=7, ls="none",
                      label="minimal surface (literature)" if i == 0 or not any(
                          n in MINIMAL_AREA for n in list(families)[:i]) else None)
    lo, hi = min(alphas), max(alphas)
    pad = max(0.02, 0.05 * (hi - lo))
    xs = [lo - pad + (hi - lo + 2 * pad) * k / 400 for k in range(401)]
    xs = [x for x in xs if 0 < x < 1]
    ax_a.plot(xs, [i_scp(min(x, 1 - x)) for x in xs], "k--", lw=1,
              label=r"$I_{scp}(\min(\alpha, 1-\alpha))$")
    ax_h.axhline(0.0, color="0.6", lw=0.6)
    ax_h.set_xlabel(r"volume fraction $\alpha$")
    ax_h.set_ylabel("mean curvature H (unit cell = 1)")
    ax_h.set_title("(a) mean curvature", loc="left")
    ax_a.set_xlabel(r"volume fraction $\alpha$")
    ax_a.set_ylabel("area per unit cell")
    ax_a.set_title("(b) surface area", loc="left")
    for ax in (ax_h, ax_a):
        ax.grid(True, lw=0.3, alpha=0.5)
    ax_h.legend(fontsize=7)
    ax_a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    for ext in ("png", "svg"):
        tmp = f"{prefix}.tmp.{os.getpid()}.{ext}"
        fig.savefig(tmp, dpi=110 if ext == "png" else None, format=ext,
                    metadata={"Date": None} if ext == "svg" else None)
        os.replace(tmp, f"{prefix}.{ext}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
