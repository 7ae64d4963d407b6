#!/usr/bin/env python3
"""End-to-end benchmark: cmcsurf run on P, D, G with the paper's settings.

Prints per surface: the whole command's time (process start to exit, every file written), the
solve's wall time (report.json `wall_seconds`), the post-solve stages (`measure_seconds`,
`quality_seconds`), steps, V-cycles, V-cycles per step, time per V-cycle and the
achieved bandwidth of a V-cycle (its minimum traffic / its time), beside a STREAM-like triad
measured by cmcsurf_bench in the same invocation, so every figure is also a ratio.

Modes: `faithful` is plain `cmcsurf run` (the paper's algorithm), `fast` adds `--fast`; the
area of a fast run is printed as its relative difference from the faithful run of the same
surface and grid when both ran. `B/cell` is the peak resident memory per finest grid cell.
For runs with coarse-to-fine continuation (`--fast` included) the V-cycle bandwidth is left
out: their V-cycles mix grid sizes.

usage: bench/end_to_end.py [--build build] [--grids 64,128] [--surfaces P,D,G] [--threads 2]
                           [--modes faithful,fast] [--epsilon 0.01] [--dt-factor 0.5]
                           [--tol 1e-6] [--extra "..."]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

# Minimum finest-level traffic of one V-cycle in bytes per cell (see bench/kernels_bench.cpp):
# 4 smoothing sweeps x 48 + defect 48 + restrictions 2 x 9 + corrections 2 x 18 + the defect
# norm after the cycle 48 + 16, times 8/7 for the coarse levels.
VCYCLE_BYTES_PER_CELL = 358 * 8 / 7


def triad_bandwidth(build, n, threads):
    out = subprocess.run(
        [os.path.join(build, "cmcsurf_bench"), f"--benchmark_filter=BM_StreamTriad/{n}/",
         "--benchmark_format=json", "--benchmark_min_time=0.5"],
        check=True, capture_output=True, text=True,
        env=dict(os.environ, OMP_NUM_THREADS=str(threads))).stdout
    return json.loads(out)["benchmarks"][0]["bytes_per_second"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--grids", default="64,128")
    ap.add_argument("--surfaces", default="P,D,G")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--epsilon", default="0.01")
    ap.add_argument("--dt-factor", default="0.5")
    ap.add_argument("--tol", default="1e-6")
    ap.add_argument("--volume-fraction", default="0.5")
    ap.add_argument("--modes", default="faithful,fast",
                    help="comma list of faithful, fast and labels given by --variant")
    ap.add_argument("--variant", action="append", default=[], metavar="LABEL:OPTIONS",
                    help="a mode LABEL that adds OPTIONS to the faithful run, e.g. "
                         "'rtol:--mg-rtol 1e-2' (repeatable; LABEL is also added to --modes)")
    ap.add_argument("--extra", default="", help="more cmcsurf run options, quoted")
    a = ap.parse_args()
    variants = {"faithful": [], "fast": ["--fast"]}
    modes = a.modes.split(",")
    for v in a.variant:
        label, _, opts = v.partition(":")
        variants[label] = opts.split()
        if label not in modes:
            modes.append(label)
    print(f"{'surface':>7} {'N':>5} {'mode':>10} {'cmd s':>7} {'wall s':>8} {'meas s':>6} "
          f"{'qual s':>6} {'steps':>6} {'V-cyc':>6} "
          f"{'V/step':>6} {'ms/V':>8} {'GB/s':>6} {'triad':>6} {'ratio':>6} {'B/cell':>7} "
          f"{'area':>10} {'vs faithful':>11}")
    for n in [int(x) for x in a.grids.split(",")]:
        # Triad over arrays of the same N^3 size, so cache effects match the run's.
        triad = triad_bandwidth(a.build, n, a.threads)
        for s in a.surfaces.split(","):
            faithful_area = None
            for mode in modes:
                with tempfile.TemporaryDirectory() as d:
                    cmd = [os.path.join(a.build, "cmcsurf"), "run", "--surface", s,
                           "--grid", str(n), "--epsilon", a.epsilon, "--dt-factor", a.dt_factor,
                           "--tol", a.tol, "--volume-fraction", a.volume_fraction,
                           "--threads", str(a.threads), "--quiet", "--out", d]
                    cmd += variants[mode] + a.extra.split()
                    t0 = time.perf_counter()
                    subprocess.run(cmd, check=True)
                    command_seconds = time.perf_counter() - t0
                    r = json.load(open(os.path.join(d, "report.json")))
                spv = r["seconds_per_vcycle"]
                steps = r["steps"] + r["prerelax_steps"] + r["coarse_steps"]
                if mode == "faithful":
                    faithful_area = r["area"]
                if r["coarse_steps"] == 0:  # all V-cycles on N^3: their traffic is known
                    bw = VCYCLE_BYTES_PER_CELL * n ** 3 / spv if spv > 0 else 0.0
                    bw_text = f"{bw / 1e9:>6.2f} {triad / 1e9:>6.2f} {bw / triad:>6.2f}"
                else:
                    bw_text = f"{'-':>6} {triad / 1e9:>6.2f} {'-':>6}"
                diff = (f"{r['area'] / faithful_area - 1:>+11.1e}"
                        if mode != "faithful" and faithful_area else f"{'':>11}")
                print(f"{s:>7} {n:>5} {mode:>10} {command_seconds:>7.2f} {r['wall_seconds']:>8.2f} "
                      f"{r.get('measure_seconds', 0.0):>6.2f} {r.get('quality_seconds', 0.0):>6.2f} "
                      f"{steps:>6} "
                      f"{r['vcycles']:>6} {r['vcycles_per_step']:>6.2f} {1e3 * spv:>8.2f} "
                      f"{bw_text} {r['peak_memory_bytes_per_cell']:>7.0f} {r['area']:>10.6f} "
                      f"{diff}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
