#!/usr/bin/env python3
"""Markdown tables (one per surface) from a cmcsurf sweep.csv, as in docs/families.md.

usage: scripts/sweep_table.py DIR/sweep.csv
"""
import csv
import sys

COLUMNS = [  # (header, csv column, format)
    ("alpha", "volume_fraction_target", "{:.2f}"),
    ("V (sharp)", "volume_fraction", "{:.4f}"),
    ("area", "area", "{:.4f}"),
    ("area (diffuse)", "area_diffuse", "{:.4f}"),
    ("H", "mean_curvature", "{:+.4f}"),
    ("H (diffuse)", "mean_curvature_diffuse", "{:+.4f}"),
    ("H std", "mean_curvature_std", "{:.4f}"),
    ("nodal H", "nodal_mean_curvature", "{:+.4f}"),
    ("nodal H std", "nodal_mean_curvature_std", "{:.3f}"),
    ("std ratio", "nodal_std_ratio", "{:.0f}"),
    ("nodal excess", "nodal_area_excess", "{:+.3%}"),
    ("steps", "steps", "{:.0f}"),
    ("s", "wall_seconds", "{:.1f}"),
]


def main(path):
    rows = list(csv.DictReader(open(path)))
    for surface in dict.fromkeys(r["surface"] for r in rows):
        print(f"**{surface}**\n")
        print("| " + " | ".join(h for h, _, _ in COLUMNS) + " |")
        print("|" + "---|" * len(COLUMNS))
        for r in rows:
            if r["surface"] != surface:
                continue
            cells = []
            for _, key, fmt in COLUMNS:
                v = r.get(key, "")
                cells.append(fmt.format(float(v)) if v not in ("", None) else "")
            print("| " + " | ".join(cells) + " |")
        print()


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
