#!/usr/bin/env python3
"""End-to-end benchmark: cmcsurf run on P, D, G with the paper's settings.

Prints per surface: wall time, steps, V-cycles, V-cycles per step, time per V-cycle and the
achieved bandwidth of a V-cycle (its minimum traffic / its time), beside a STREAM-like triad
measured by cmcsurf_bench in the same invocation, so every figure is also a ratio.

usage: bench/end_to_end.py [--build build] [--grids 64,128] [--surfaces P,D,G] [--threads 2]
                           [--epsilon 0.01] [--dt-factor 0.5] [--tol 1e-6] [--extra "..."]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

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
    ap.add_argument("--extra", default="", help="more cmcsurf run options, quoted")
    a = ap.parse_args()
    print(f"{'surface':>7} {'N':>5} {'wall s':>8} {'steps':>6} {'V-cyc':>6} {'V/step':>6} "
          f"{'ms/V':>8} {'GB/s':>6} {'triad':>6} {'ratio':>6}")
    for n in [int(x) for x in a.grids.split(",")]:
        # Triad over arrays of the same N^3 size, so cache effects match the run's.
        triad = triad_bandwidth(a.build, n, a.threads)
        for s in a.surfaces.split(","):
            with tempfile.TemporaryDirectory() as d:
                cmd = [os.path.join(a.build, "cmcsurf"), "run", "--surface", s, "--grid", str(n),
                       "--epsilon", a.epsilon, "--dt-factor", a.dt_factor, "--tol", a.tol,
                       "--volume-fraction", a.volume_fraction, "--threads", str(a.threads),
                       "--quiet", "--out", d] + a.extra.split()
                subprocess.run(cmd, check=True)
                r = json.load(open(os.path.join(d, "report.json")))
            spv = r["seconds_per_vcycle"]
            bw = VCYCLE_BYTES_PER_CELL * n ** 3 / spv if spv > 0 else 0.0
            print(f"{s:>7} {n:>5} {r['wall_seconds']:>8.2f} {r['steps'] + r['prerelax_steps']:>6} "
                  f"{r['vcycles']:>6} {r['vcycles_per_step']:>6.2f} {1e3 * spv:>8.2f} "
                  f"{bw / 1e9:>6.2f} {triad / 1e9:>6.2f} {bw / triad:>6.2f}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
