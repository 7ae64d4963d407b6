#!/usr/bin/env python3
"""The CMC-versus-nodal flow table of docs/properties.md ("Flow: CMC against nodal").

Runs the members (as bench/properties_table.py does, sharing its runs/ folder) and
`cmcsurf properties --only flow --compare-nodal` on each, and prints the markdown table:

    python3 bench/flow_table.py --cmcsurf build/cmcsurf --out /tmp/table

A network at porosity P is phase 1 of the member at volume fraction 1 - P; a sheet is the
wall around the balanced member (volume fraction 0.5) at porosity P. The flow is along each
axis; the wall shear stress is the mean over the axes, for a superficial velocity of 1 mm/s
through a 1 mm cell of water at 37 C (the command's defaults), and normalised by mu U / L.
"""
import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import properties_table  # noqa: E402  (member(): the runs, reused; the options)


def flow(args, folder, surface, kind, porosity):
    """Runs (or reuses) the flow-only properties call; returns the JSON's dictionary."""
    out = os.path.join(args.out, "props", f"{surface}_{kind}_{porosity:g}_flow.json")
    if not (args.reuse and os.path.exists(out)):
        cmd = [args.cmcsurf, "properties", "--from", folder, "--only", "flow",
               "--compare-nodal", "--cell-size", "1", "--units", "mm", "--velocity", "1",
               "--threads", str(args.threads), "--quiet", "--out", out]
        if kind == "sheet":
            cmd += ["--solid", "sheet", "--porosity", f"{porosity:g}"]
        subprocess.run(cmd, check=True)
    with open(out) as f:
        return json.load(f)


def numbers(p):
    """k (cell-size^2, mean diagonal), tortuosity, c, tau mean and p95 (mu U / L), tau mPa."""
    k = sum(p["permeability"][a][a] for a in range(3)) / 3
    tau = p.get("wall_shear_stress_axis_mean", {})
    mpa = p.get("wall_shear_stress_mpa_axis_mean", {})
    return [k, sum(p["hydraulic_tortuosity"]) / 3, p["kozeny_carman_constant"],
            tau.get("mean", float("nan")), tau.get("p95", float("nan")),
            mpa.get("mean", float("nan"))]


HEAD = ["k / cell²", "CMC/nodal - 1", "tortuosity", "Kozeny-Carman c", "τ mean / (μU/L)",
        "τ p95 / (μU/L)", "τ mean (mPa)", "MINRES its", "seconds"]
# Formats of numbers()[1:], each cell "CMC / nodal".
FORMATS = ["{:.3f}", "{:.2f}", "{:.2f}", "{:.2f}", "{:.3f}"]


def table(rows):
    lines = ["| surface | solid | porosity | " + " | ".join(HEAD) + " |",
             "|" + "---|" * (len(HEAD) + 3)]
    for surface, kind, porosity, p, reason in rows:
        if p is None:
            lines.append(f"| {surface} | {kind} | {porosity:.2f} | no member: {reason} |"
                         + " |" * (len(HEAD) - 1))
            continue
        a, b = numbers(p), numbers(p["nodal"])
        cells = [f"{a[0]:.4e} / {b[0]:.4e}", f"{100 * (a[0] / b[0] - 1):+.2f}%"]
        cells += [f"{f.format(a[i + 1])} / {f.format(b[i + 1])}" for i, f in enumerate(FORMATS)]
        its = max(p["solver"]["flow"]["iterations"])
        cells += [f"{its} / {max(p['nodal']['solver']['flow']['iterations'])}",
                  f"{p['properties_seconds']:.0f}"]
        lines.append(f"| {surface} | {kind} | {p['porosity']:.3f} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    properties_table.add_common_arguments(ap, [0.5, 0.6, 0.7, 0.8, 0.9])
    ap.add_argument("--sheets", nargs="*", default=["G"], help="surfaces whose sheet is added")
    args = ap.parse_args()
    properties_table.make_folders(args)
    rows = []
    cases = [(s, "network") for s in args.surfaces] + [(s, "sheet") for s in args.sheets]
    for surface, kind in cases:
        for porosity in args.porosities:
            fraction = 0.5 if kind == "sheet" else round(1 - porosity, 6)
            folder, reason = properties_table.member(args, surface, fraction)
            p = flow(args, folder, surface, kind, porosity) if folder else None
            rows.append((surface, kind, porosity, p, reason))
            print(f"done {surface} {kind} {porosity:g}", file=sys.stderr, flush=True)
    print(f"Flow (CMC / nodal), grid {args.grid}^3, threads {args.threads}\n")
    print(table(rows))


if __name__ == "__main__":
    main()
