#!/usr/bin/env python3
"""Relax a noisy user field to a CMC surface: a thresholded, noisy gyroid-like volume (as a
segmented tomography scan might give) made with NumPy, relaxed by cmcsurf.relax (with a tqdm
progress bar where python3-tqdm is installed), measured before and after, and meshed to an STL.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/relax_noisy.py --grid 32

$CMCSURF_EXAMPLE_GRID overrides --grid's default.
"""
import argparse
import os

import numpy as np

import cmcsurf

try:  # a progress bar where tqdm is installed (Debian python3-tqdm)
    from tqdm import tqdm
except ImportError:
    tqdm = None


def noisy_segmented_field(n, noise, seed):
    # Cell centres in index order [i, j, k] = (x, y, z), as cmcsurf expects.
    c = 2 * np.pi * (np.arange(n) + 0.5) / n
    x, y, z = np.meshgrid(c, c, c, indexing="ij")
    g = np.sin(x) * np.cos(y) + np.sin(y) * np.cos(z) + np.sin(z) * np.cos(x)
    rng = np.random.default_rng(seed)
    return (g + noise * rng.standard_normal(g.shape) > 0.3).astype(np.uint8)  # 0/1 voxels


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--grid", type=int, default=int(os.environ.get("CMCSURF_EXAMPLE_GRID", 32)))
    ap.add_argument("--noise", type=float, default=0.1)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--out", default="relaxed.stl")
    args = ap.parse_args()
    n = args.grid
    epsilon = 0.64 / n  # as the CLI's default 0.01 at 64^3; wider ones can merge the channels

    voxels = noisy_segmented_field(n, args.noise, args.seed)
    before = cmcsurf.measure(voxels, epsilon)
    print(f"segmented: {voxels.mean():.4f} of the voxels in phase 1; "
          f"local H std {before['mean_curvature_std']:.3g}")
    bar = tqdm(unit=" steps", desc="relax", leave=False) if tqdm else None

    def progress(step):
        if bar is not None:
            bar.set_postfix(area=f"{step['area']:.5f}", refresh=False)
            bar.update()

    # Section 4.4 from the voxels, at their own volume fraction (volume_fraction=None).
    # paper=True: the paper's stop rule (|dA| <= tol); the fast mode's equilibrium rule would
    # follow this coarse field on into a slow change of topology.
    result = cmcsurf.relax(voxels, epsilon=epsilon, tol=1e-5, paper=True, progress=progress)
    if bar is not None:
        bar.close()
    rep = result.report
    print(f"relaxed in {rep['steps']} steps: area {rep['area']:.5f}  "
          f"H {rep['mean_curvature']:+.4f} (local std {rep['mean_curvature_std']:.3g})  "
          f"volume fraction {rep['volume_fraction']:.4f}")
    if rep["area"] == 0.0:
        print("note: the structure dissolved at this grid and epsilon (no phi = 1/2 surface "
              "left); try a finer --grid")
    mesh = cmcsurf.mesh(result, tile=2, solid="network", cell_size=5.0, units="mm")
    mesh.save(args.out)
    print(f"wrote {args.out}: {len(mesh.faces)} triangles, closed "
          f"{mesh.report['checks']['closed']}, volume {mesh.report['volume']:.2f} mm^3")


if __name__ == "__main__":
    main()
