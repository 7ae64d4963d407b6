#!/usr/bin/env python3
"""End-to-end benchmark: the whole `cmcsurf run` command beside its solve.

For each surface, volume fraction, grid and mode it runs the command as a user does (every
output written: field.vti, preview.png, report.html, ...) and prints the whole command's time
(process start to exit), the solve (report.json `wall_seconds`) and what follows it: the final
measures, the quality stage, the preview, the report page's meshes, the writes and the rest
(process start-up and exit, report.html's serialisation: the command's time less all of the
above). Beside them: steps, V-cycles, the finest grid's V-cycles, time per V-cycle, the
V-cycle's achieved bandwidth (its minimum traffic over its time; runs on one grid only), the
peak resident memory of the whole command per finest cell, and a STREAM-like triad measured
by cmcsurf_bench in the same invocation, so every figure is also a ratio to the day's machine.

Modes: `faithful` is `cmcsurf run --paper` (the paper's algorithm), `fast` is plain `cmcsurf
run` (the fast mode, the default since 2026-11-27), `tight` is the fast mode run to an
equilibrium residual of 1e-5 (the reference for the local-H spread), and --variant
LABEL:OPTIONS adds more. A non-faithful run's area and volume fraction are printed relative to
the faithful run of the same member when both ran, and each run's local-H spread
(mean_curvature_std) relative to the tight run's when that ran. CPU seconds (user + system of
the command) are printed beside the wall time: on a shared machine they are the steadier
figure.

usage: bench/end_to_end.py [--build build] [--grids 256] [--surfaces P,D,G]
                           [--volume-fractions 0.3,0.5] [--threads 2] [--modes fast]
                           [--json rows.json] [--plot breakdown.png] [--extra "..."]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

# Minimum finest-level traffic of one V-cycle in bytes per cell (see bench/kernels_bench.cpp):
# 4 smoothing sweeps x 48 + defect 48 + restrictions 2 x 9 + corrections 2 x 18 + the defect
# norm after the cycle 48 + 16, times 8/7 for the coarse levels.
VCYCLE_BYTES_PER_CELL = 358 * 8 / 7

# The stages of a run after its solve, as report.json times them.
POST_STAGES = ("measure_seconds", "quality_seconds", "preview_seconds", "page_seconds",
               "write_seconds")


def triad_bandwidth(build, n, threads):
    n = min(max(n, 64), 256)  # the sizes cmcsurf_bench has (64^3 in cache, 256^3 in memory)
    out = subprocess.run(
        [os.path.join(build, "cmcsurf_bench"), f"--benchmark_filter=BM_StreamTriad/{n}/",
         "--benchmark_format=json", "--benchmark_min_time=0.5"],
        check=True, capture_output=True, text=True,
        env=dict(os.environ, OMP_NUM_THREADS=str(threads))).stdout
    return json.loads(out)["benchmarks"][0]["bytes_per_second"]


def run_command(cmd):
    """Runs cmd; returns (seconds from start to exit, peak resident bytes of the process)."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd)
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise subprocess.CalledProcessError(proc.returncode, cmd)
    # ru_maxrss is in KiB on Linux
    return seconds, usage.ru_maxrss * 1024, usage.ru_utime + usage.ru_stime


def finest_vcycles(history_path, n):
    """V-cycles spent on the finest grid (history.csv stages without an @coarse suffix)."""
    import csv
    with open(history_path, newline="") as f:
        return sum(int(r["vcycles"]) for r in csv.DictReader(f) if "@" not in r["stage"])


def plot_breakdown(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    labels = [f"{r['surface']} {r['alpha']:g} {r['mode']}\n{r['grid']}^3" for r in rows]
    parts = [("solve", "solve_seconds", "#4c72b0"), ("measures", "measure_seconds", "#55a868"),
             ("quality", "quality_seconds", "#c44e52"), ("preview", "preview_seconds", "#8172b2"),
             ("page meshes", "page_seconds", "#ccb974"), ("writes", "write_seconds", "#64b5cd"),
             ("rest", "other_seconds", "#999999")]
    fig, ax = plt.subplots(figsize=(max(6, 0.9 * len(rows) + 2), 4.2))
    bottom = [0.0] * len(rows)
    for name, key, colour in parts:
        values = [max(0.0, r[key]) for r in rows]
        ax.bar(range(len(rows)), values, bottom=bottom, color=colour, label=name, width=0.7)
        bottom = [b + v for b, v in zip(bottom, values)]
    for i, r in enumerate(rows):
        ax.text(i, r["command_seconds"], f"{r['command_seconds']:.1f}", ha="center",
                va="bottom", fontsize=8)
    ax.set_xticks(range(len(rows)))
    ax.set_xticklabels(labels, fontsize=7)
    ax.set_ylabel("seconds (process start to exit)")
    ax.set_title(f"cmcsurf run: the whole command, {rows[0]['threads']} threads, "
                 f"triad {rows[0]['triad_gbs']:.1f} GB/s")
    ax.legend(fontsize=7, ncol=4, loc="upper left")
    ax.set_ylim(0, max(r["command_seconds"] for r in rows) * 1.25)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--grids", default="64,128")
    ap.add_argument("--surfaces", default="P,D,G")
    ap.add_argument("--volume-fractions", default="0.5")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--epsilon", default="0.01")
    ap.add_argument("--modes", default="faithful,fast",
                    help="comma list of faithful, fast, tight and labels given by --variant")
    ap.add_argument("--variant", action="append", default=[], metavar="LABEL:OPTIONS",
                    help="a mode LABEL that adds OPTIONS to the faithful run, e.g. "
                         "'rtol:--mg-rtol 1e-2' (repeatable; LABEL is also added to --modes)")
    ap.add_argument("--extra", default="", help="more cmcsurf run options, quoted")
    ap.add_argument("--json", help="also write the rows to this file")
    ap.add_argument("--plot", help="draw the whole command's breakdown into this PNG")
    a = ap.parse_args()
    variants = {"faithful": ["--paper"], "fast": [], "tight": ["--equilibrium-tol", "1e-5"]}
    modes = a.modes.split(",")
    for v in a.variant:
        label, _, opts = v.partition(":")
        variants[label] = opts.split()
        if label not in modes:
            modes.append(label)
    print(f"{'member':>9} {'N':>4} {'mode':>8} {'cmd s':>6} {'solve':>6} {'meas':>5} "
          f"{'qual':>5} {'prev':>5} {'page':>5} {'write':>5} {'rest':>5} {'post%':>5} "
          f"{'steps':>5} {'V-cyc':>5} {'V@N':>4} {'ms/V':>7} {'V/triad':>7} {'triad':>6} "
          f"{'B/cell':>6} {'area':>9} {'d area':>8} {'d V':>8} {'cpu s':>6} {'H std':>7} "
          f"{'/tight':>6} {'eq res':>7} {'chi':>4}")
    rows = []
    for n in [int(x) for x in a.grids.split(",")]:
        # Triad over arrays of the same N^3 size, so cache effects match the run's.
        triad = triad_bandwidth(a.build, n, a.threads)
        for s in a.surfaces.split(","):
            for alpha in [float(x) for x in a.volume_fractions.split(",")]:
                faithful = None
                # The tight run first, so that the others' local-H spread has its reference.
                tight = None
                for mode in sorted(modes, key=lambda m: m != "tight"):
                    with tempfile.TemporaryDirectory() as d:
                        cmd = [os.path.join(a.build, "cmcsurf"), "run", "--surface", s,
                               "--grid", str(n), "--epsilon", a.epsilon,
                               "--volume-fraction", str(alpha), "--threads", str(a.threads),
                               "--checkpoint-every", "0", "--quiet", "--out", d]
                        cmd += variants[mode] + a.extra.split()
                        command_seconds, peak_bytes, cpu_seconds = run_command(cmd)
                        r = json.load(open(os.path.join(d, "report.json")))
                        v_fine = finest_vcycles(os.path.join(d, "history.csv"), n)
                    post = {k: r.get(k, 0.0) for k in POST_STAGES}
                    other = command_seconds - r["wall_seconds"] - sum(post.values())
                    row = dict(surface=s, alpha=alpha, grid=n, mode=mode, threads=a.threads,
                               command_seconds=command_seconds, solve_seconds=r["wall_seconds"],
                               other_seconds=other, steps=r["steps"] + r["prerelax_steps"] +
                               r["coarse_steps"], vcycles=r["vcycles"], finest_vcycles=v_fine,
                               seconds_per_vcycle=r["seconds_per_vcycle"],
                               peak_bytes_per_cell=peak_bytes / n ** 3, area=r["area"],
                               volume_fraction=r["volume_fraction"],
                               stop_reason=r["stop_reason"], triad_gbs=triad / 1e9,
                               cpu_seconds=cpu_seconds,
                               mean_curvature_std=r["mean_curvature_std"],
                               equilibrium_residual=r.get("equilibrium_residual"),
                               euler_characteristic=r["euler_characteristic"], **post)
                    if mode == "faithful":
                        faithful = row
                    if mode == "tight":
                        tight = row
                    spread = f"{'-':>6}"
                    if tight and mode != "tight":
                        row["mean_curvature_std_vs_tight"] = (
                            r["mean_curvature_std"] / tight["mean_curvature_std"] - 1)
                        spread = f"{row['mean_curvature_std_vs_tight']:>+6.2f}"
                    spv = r["seconds_per_vcycle"]
                    ratio = (f"{VCYCLE_BYTES_PER_CELL * n ** 3 / spv / triad:>7.2f}"
                             if r["coarse_steps"] == 0 and spv > 0 else f"{'-':>7}")
                    if faithful and mode != "faithful":
                        row["area_vs_faithful"] = r["area"] / faithful["area"] - 1
                        row["volume_fraction_vs_faithful"] = (
                            r["volume_fraction"] - faithful["volume_fraction"])
                        diff = (f"{row['area_vs_faithful']:>+8.1e} "
                                f"{row['volume_fraction_vs_faithful']:>+8.1e}")
                    else:
                        diff = f"{'':>8} {'':>8}"
                    post_share = 100 * (command_seconds - r["wall_seconds"]) / command_seconds
                    print(f"{s + '_' + format(alpha, 'g'):>9} {n:>4} {mode:>8} "
                          f"{command_seconds:>6.2f} {r['wall_seconds']:>6.2f} "
                          + " ".join(f"{post[k]:>5.2f}" for k in POST_STAGES)
                          + f" {other:>5.2f} {post_share:>5.1f} {row['steps']:>5} "
                          f"{r['vcycles']:>5} {v_fine:>4} {1e3 * spv:>7.1f} {ratio} "
                          f"{triad / 1e9:>6.1f} {row['peak_bytes_per_cell']:>6.1f} "
                          f"{r['area']:>9.6f} {diff} {cpu_seconds:>6.2f} "
                          f"{r['mean_curvature_std']:>7.4f} {spread} "
                          f"{r.get('equilibrium_residual', float('nan')):>7.1e} "
                          f"{r['euler_characteristic']:>4}", flush=True)
                    rows.append(row)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)
    if a.plot:
        plot_breakdown(rows, a.plot)


if __name__ == "__main__":
    sys.exit(main())
