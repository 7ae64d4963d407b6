#!/usr/bin/env python3
"""Fig. 11 of the paper from a `cmcsurf sweep` folder, with matplotlib: a user's script.

usage: plot_families.py SWEEP_CSV OUT_PREFIX   -> OUT_PREFIX.png and OUT_PREFIX.svg

`cmcsurf sweep` draws families.png itself (docs/families.md); this script is for figures a
user restyles. (a) mean curvature vs volume fraction, (b) area per computed cell vs volume
fraction, one curve per surface family: the sharp values (`area`, `mean_curvature`) with their
error bars (`area_error`, `mean_curvature_error`), the diffuse layer's (`area_diffuse`) dotted
beside them. The literature constants (the minimal surfaces' areas, the I_scp profile of
Section 2.3) are not written here: they are read from sweep.json's "literature" beside
SWEEP_CSV, which cmcsurf writes from measure/literature.h.
Exit code 3 when matplotlib is missing, 1 when sweep.json has no "literature".
"""
import csv
import json
import os
import sys


def read_literature(csv_path):
    """sweep.json's "literature" beside the table: {surface: area} and the I_scp samples."""
    path = os.path.join(os.path.dirname(os.path.abspath(csv_path)), "sweep.json")
    with open(path) as f:
        lit = json.load(f)["literature"]
    areas = {k: v["area"] for k, v in lit["minimal_surface_areas"].items()}
    return areas, lit["i_scp"]["volume_fraction"], lit["i_scp"]["area"]


def number(r, key):
    try:
        return float(r[key]) if r.get(key) else float("nan")
    except ValueError:
        return float("nan")


def read_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    families = {}
    for r in rows:
        try:
            a = float(r["volume_fraction_target"])
            families.setdefault(r["surface"], []).append(
                (a, float(r["mean_curvature"]), float(r["area"]), number(r, "area_diffuse"),
                 number(r, "mean_curvature_error"), number(r, "area_error")))
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
    try:
        minimal_area, scp_alpha, scp_area = read_literature(sys.argv[1])
    except (OSError, KeyError, ValueError) as e:
        print(f"plot_families.py: no literature constants in the sweep.json beside "
              f"{sys.argv[1]} ({e}); rerun the sweep with this cmcsurf", file=sys.stderr)
        return 1
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
        err = [0 if p[4] != p[4] else p[4] for p in pts]
        ax_h.errorbar(a, [p[1] for p in pts], yerr=err, marker=markers[i % len(markers)], ms=4,
                      capsize=2, label=label)
        err = [0 if p[5] != p[5] else p[5] for p in pts]
        line = ax_a.errorbar(a, [p[2] for p in pts], yerr=err, marker=markers[i % len(markers)],
                             ms=4, capsize=2, label=label).lines[0]
        if any(p[3] == p[3] for p in pts):  # diffuse-layer area, where the table has it
            ax_a.plot(a, [p[3] for p in pts], ls=":", lw=1, color=line.get_color(),
                      label=f"{label} (diffuse layer, Appendix B)")
        if name in minimal_area:
            ax_a.plot([0.5], [minimal_area[name]], marker="x", color="k", ms=7, ls="none",
                      label="minimal surface (literature)" if i == 0 or not any(
                          n in minimal_area for n in list(families)[:i]) else None)
    lo, hi = min(alphas), max(alphas)
    pad = max(0.02, 0.05 * (hi - lo))
    xs = [(x, y) for x, y in zip(scp_alpha, scp_area) if lo - pad <= x <= hi + pad]
    ax_a.plot([x for x, _ in xs], [y for _, y in xs], "k--", lw=1,
              label=r"$I_{scp}(\min(\alpha, 1-\alpha))$")
    ax_h.axhline(0.0, color="0.6", lw=0.6)
    ax_h.set_xlabel(r"volume fraction $\alpha$")
    ax_h.set_ylabel("mean curvature H a (computed cell, a = 1)")
    ax_h.set_title("(a) mean curvature", loc="left")
    ax_a.set_xlabel(r"volume fraction $\alpha$")
    ax_a.set_ylabel("area A per computed cell (a = 1)")
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
