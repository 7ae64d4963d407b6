#!/usr/bin/env python3
"""The CMC-versus-nodal table of docs/properties.md ("CMC against nodal: G, P, D").

Runs the members and the properties calls with a given cmcsurf binary into an output folder
and prints the markdown tables (networks, sheets, grid checks):

    python3 bench/properties_table.py --cmcsurf build/cmcsurf --out /tmp/table
    python3 bench/properties_table.py --cmcsurf build/cmcsurf --out /tmp/table --reuse \
        --grid-check G:network:0.7 G:sheet:0.7

A network at porosity P is phase 1 of the member at volume fraction 1 - P; a sheet at any
porosity is the wall around the balanced member (volume fraction 0.5). A member whose run
fails or changes topology is a "no member" row with the reason; nothing is forced.
"""
import argparse
import json
import os
import subprocess
import sys


def add_common_arguments(ap, porosities):
    """The options this script and bench/flow_table.py share (their runs/ folder is one)."""
    ap.add_argument("--cmcsurf", required=True, help="the cmcsurf binary")
    ap.add_argument("--out", required=True, help="folder for runs/ and props/")
    ap.add_argument("--grid", type=int, default=64)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--surfaces", nargs="+", default=["G", "P", "D"])
    ap.add_argument("--porosities", nargs="+", type=float, default=porosities)
    ap.add_argument("--reuse", action="store_true", help="keep runs and JSON already there")


def make_folders(args):
    for sub in ("runs", "props"):
        os.makedirs(os.path.join(args.out, sub), exist_ok=True)


def member(args, surface, fraction):
    """Runs (or reuses) runs/S_A; returns (folder, None) or (None, reason)."""
    folder = os.path.join(args.out, "runs", f"{surface}_{fraction:g}")
    report = os.path.join(folder, "report.json")
    if not (args.reuse and os.path.exists(report)):
        cmd = [args.cmcsurf, "run", "--surface", surface, "--volume-fraction", f"{fraction:g}",
               "--grid", str(args.grid), "--fast", "--quiet", "--no-preview", "--no-report",
               "--out", folder]
        done = subprocess.run(cmd, capture_output=True, text=True,
                              env=dict(os.environ, OMP_NUM_THREADS=str(args.threads)))
        if done.returncode != 0:
            last = (done.stderr.strip().splitlines() or ["(no message)"])[-1]
            return None, f"run exit {done.returncode}: {last}"
    with open(report) as f:
        r = json.load(f)
    if r.get("topology_changed"):
        return None, (f"topology changed (chi {r['euler_characteristic_start']} -> "
                      f"{r['euler_characteristic']})")
    if not r.get("converged", True):
        return None, f"not converged ({r.get('stop_reason')})"
    return folder, None


def properties(args, folder, surface, kind, porosity, grid_check=False):
    """Runs (or reuses) the properties call; returns the JSON's dictionary."""
    tag = "_gridcheck" if grid_check else ""
    out = os.path.join(args.out, "props", f"{surface}_{kind}_{porosity:g}{tag}.json")
    if not (args.reuse and os.path.exists(out)):
        cmd = [args.cmcsurf, "properties", "--from", folder, "--compare-nodal",
               "--threads", str(args.threads), "--quiet", "--out", out]
        if kind == "sheet":
            cmd += ["--solid", "sheet", "--porosity", f"{porosity:g}"]
        if grid_check:
            cmd += ["--grid-check"]
        subprocess.run(cmd, check=True)
    with open(out) as f:
        return json.load(f)


def values(p):
    """The table's numbers of one solid (the top level, nodal or nodal_offset)."""
    hs = p["fraction_of_bound"]
    return [p["youngs_modulus"][0], p["shear_modulus"][0], p["poisson_ratio"][0],
            p["zener_ratio"], p["conductivity_solid"][0][0], p["conductivity_pore"][0][0],
            hs["bulk_modulus"], hs["conductivity_solid"]]


COLUMNS = ["E/E_s", "G/E_s", "nu", "Zener", "k_solid,xx", "k_pore,xx", "HS bulk",
           "HS k_solid"]
FORMATS = ["{:.4f}", "{:.4f}", "{:.3f}", "{:.3f}", "{:.4f}", "{:.4f}", "{:.3f}", "{:.3f}"]


def table(rows, solids, gain_label):
    """Markdown: one row per case, each column 'CMC / nodal[ / offset]'."""
    head = ["surface", "porosity"] + COLUMNS + [gain_label, "seconds"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for surface, porosity, p, reason in rows:
        if p is None:
            cells = [f"no member: {reason}"] + [""] * (len(head) - 3)
            lines.append(f"| {surface} | {porosity:.3f} | " + " | ".join(cells) + " |")
            continue
        sets = [values(p)] + [values(p[s]) for s in solids]
        cells = [" / ".join(fmt.format(v[i]) for v in sets) for i, fmt in enumerate(FORMATS)]
        gain = " / ".join(f"{100 * (sets[0][0] / v[0] - 1):+.1f}%" for v in sets[1:])
        cells += [gain, f"{p['properties_seconds']:.0f}"]
        lines.append(f"| {surface} | {p['porosity']:.3f} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def error_table(checks):
    """Markdown: the Richardson error estimates of --grid-check next to the values."""
    keys = [("youngs_modulus", 0), ("shear_modulus", 0), ("conductivity_solid", 0)]
    head = ["case", "solid"] + [f"{k} (error)" for k, _ in keys]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for case, p in checks:
        for name, q in [("CMC", p)] + [(s, p[s]) for s in ("nodal", "nodal_offset") if s in p]:
            cells = []
            for key, i in keys:
                v, e = q[key], q.get(key + "_error")
                v = v[i][i] if isinstance(v[0], list) else v[i]
                if isinstance(e, list):
                    e = e[i][i] if isinstance(e[0], list) else e[i]
                cells.append(f"{v:.4f} ({100 * e / v:.2f}%)" if e is not None else f"{v:.4f}")
            lines.append(f"| {case} | {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_common_arguments(ap, [0.7, 0.5, 0.9])
    ap.add_argument("--grid-check", nargs="*", default=[], metavar="S:KIND:P",
                    help="cases also solved with --grid-check, e.g. G:network:0.7")
    args = ap.parse_args()
    make_folders(args)

    networks, sheets = [], []
    for porosity in args.porosities:
        for surface in args.surfaces:
            folder, reason = member(args, surface, round(1 - porosity, 6))
            p = properties(args, folder, surface, "network", porosity) if folder else None
            networks.append((surface, porosity, p, reason))
            folder, reason = member(args, surface, 0.5)
            p = properties(args, folder, surface, "sheet", porosity) if folder else None
            sheets.append((surface, porosity, p, reason))
            print(f"done {surface} {porosity:g}", file=sys.stderr, flush=True)
    order = {s: i for i, s in enumerate(args.surfaces)}
    key = lambda row: (order[row[0]], row[1])  # noqa: E731
    print(f"Networks (CMC / nodal), grid {args.grid}^3, threads {args.threads}\n")
    print(table(sorted(networks, key=key), ["nodal"], "E: CMC/nodal - 1"))
    print(f"\nSheets (CMC / nodal band / nodal offset), grid {args.grid}^3\n")
    print(table(sorted(sheets, key=key), ["nodal", "nodal_offset"],
                "E: CMC/band - 1 / CMC/offset - 1"))

    checks = []
    for case in args.grid_check:
        surface, kind, porosity = case.split(":")
        porosity = float(porosity)
        fraction = 0.5 if kind == "sheet" else round(1 - porosity, 6)
        folder, reason = member(args, surface, fraction)
        if folder:
            checks.append((case, properties(args, folder, surface, kind, porosity, True)))
    if checks:
        print("\nGrid check (value on N; Richardson error estimate from N/2, % of value)\n")
        print(error_table(checks))


if __name__ == "__main__":
    main()
