#!/usr/bin/env python3
"""Fig. 11 from Python: area and mean curvature of the P, D and G families of CMC surfaces
over volume fraction, with matplotlib.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/fig11.py --grid 32 --out fig11.png

The paper's figure is at 128^3 with fractions 0.25:0.75:0.05 (README: `cmcsurf sweep ... --fast`,
~8 minutes); the defaults here take seconds. $CMCSURF_EXAMPLE_GRID overrides --grid's default.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import cmcsurf  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--grid", type=int, default=int(os.environ.get("CMCSURF_EXAMPLE_GRID", 32)))
    ap.add_argument("--fractions", default="0.3,0.5,0.7", help="a,b,c or start:stop:step")
    ap.add_argument("--epsilon", type=float, default=None,
                    help="interface parameter (default: 0.64 grid spacings, the CLI's 0.01 "
                         "at 64^3; wider ones dissolve the thin members)")
    ap.add_argument("--out", default="fig11.png")
    args = ap.parse_args()
    epsilon = args.epsilon or 0.64 / args.grid

    def progress(step):
        if step["step"] % 50 == 0:
            print(f"  {step['stage']:>8} step {step['step']:5d}  area {step['area']:.5f}",
                  flush=True)

    results, table = cmcsurf.sweep(("P", "D", "G"), args.fractions, grid=args.grid,
                                   epsilon=epsilon, fast=True, progress=progress)
    fig, (ax_a, ax_h) = plt.subplots(1, 2, figsize=(9, 3.6))
    for surface, marker in (("P", "o"), ("D", "s"), ("G", "^")):
        rows = table["surface"] == surface
        v = table["volume_fraction"][rows]
        ax_a.plot(v, table["area"][rows], marker=marker, label=surface)
        ax_h.plot(v, table["mean_curvature"][rows], marker=marker, label=surface)
    ax_a.set(xlabel="volume fraction", ylabel="area per unit cell")
    ax_h.set(xlabel="volume fraction", ylabel="mean curvature H")
    ax_h.axhline(0.0, color="0.7", lw=0.8)
    ax_a.legend()
    fig.suptitle(f"CMC families at N = {args.grid}, epsilon = {epsilon:.3g}")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    for r in results:
        rep = r.report
        print(f"{rep['member']:>8}: area {rep['area']:.5f}  H {rep['mean_curvature']:+.4f}  "
              f"V {rep['volume_fraction']:.4f}")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
