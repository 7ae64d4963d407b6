"""scaffold() is `cmcsurf scaffold` (one library call, pipeline/scaffold_run.h): the same
FILE.json numbers for the same options; morphometry() measures one cell as scaffold does."""
import json
import math
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import cmcsurf
from conftest import ROOT, run_cli

# A small part of a few cells at grid 32 (one member, cached and shared by both sides).
CLI_ARGS = ["--surface", "G", "--porosity", "0.7", "--solid", "network", "--cell-size", "2",
            "--size", "4x4x3", "--grid", "32", "--threads", "1", "--quiet", "--no-page"]
KWARGS = dict(surface="G", porosity=0.7, solid="network", cell_size=2, size=(4, 4, 3),
              grid=32, threads=1, no_page=True)

# Keys that hold the clock, the machine or the file's own name.
VARYING = {"seconds", "write_seconds", "file", "file_bytes", "version", "build", "threads",
           "member", "cache"}


def numbers(report, prefix=""):
    """Every number of a report by its path, the varying keys left out."""
    out = {}
    if isinstance(report, dict):
        for k, v in report.items():
            if k not in VARYING and not k.endswith("_seconds"):
                out.update(numbers(v, f"{prefix}/{k}"))
    elif isinstance(report, list):
        for i, v in enumerate(report):
            out.update(numbers(v, f"{prefix}[{i}]"))
    elif isinstance(report, (int, float)) and not isinstance(report, bool):
        out[prefix] = report
    return out


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("members")


def test_scaffold_returns_the_cli_numbers(tmp_path, cache):
    run_cli("scaffold", *CLI_ARGS, "--cache", str(cache), "--out", str(tmp_path / "cli.stl"))
    cli = json.loads((tmp_path / "cli.stl.json").read_text())
    py = cmcsurf.scaffold(tmp_path / "py.stl", cache=str(cache), **KWARGS)
    assert py == json.loads((tmp_path / "py.stl.json").read_text())  # FILE.json as written
    a, b = numbers(cli), numbers(py)
    assert a.keys() == b.keys()
    # One library call on the same member with one thread: the same bits.
    assert {k: v for k, v in a.items() if v != b[k]} == {}
    assert abs(py["porosity"] - 0.7) <= 1e-3
    assert (tmp_path / "py.stl").stat().st_size == (tmp_path / "cli.stl").stat().st_size


# Graded fills at grid 16 in paper mode, as tests/cli/scaffold_graded_fill.sh makes them:
# two network members (solid fraction 0.3 and 0.5: each cell's wall and pore measures are most
# of the time) shared by both tests and both sides, undecimated (tolerance 0), without a page:
# about 4 s of CPU a side.
GRADED_CLI = ["--paper", "--surface", "G", "--grid", "16", "--cell-size", "1", "--units", "mm",
              "--porosity", "0.5:0.7", "--graded-members", "2", "--tolerance", "0",
              "--threads", "1", "--quiet", "--no-page"]
GRADED_KWARGS = dict(paper=True, surface="G", grid=16, cell_size=1, units="mm",
                     porosity=(0.5, 0.7), graded_members=2, tolerance=0, threads=1,
                     no_page=True)


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    """A cylinder 4 mm across and 3 mm high (64 sides), the CLI test's smaller one."""
    path = tmp_path_factory.mktemp("shape") / "cyl4.stl"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "cylinder_stl.py"), str(path), "4",
                    "3", "64"], check=True)
    return path


@pytest.mark.parametrize("how", ["depth", "axis"])
def test_graded_scaffold_returns_the_cli_numbers(tmp_path, cache, cylinder, how):
    """A network graded by depth below a shape's surface, and one along z in a box: scaffold()
    writes and returns the command line's FILE.json, every number to the bit (one library call
    on the same cached members with one thread), the profile and its notes included."""
    if how == "depth":
        cli_extra = ["--grade-by", "surface", "--grade-depth", "1", "--shape", str(cylinder)]
        py_extra = dict(grade_by="surface", grade_depth=1, shape=str(cylinder))
    else:
        cli_extra = ["--axis", "z", "--size", "2x2x3"]
        py_extra = dict(axis="z", size=(2, 2, 3))
    run_cli("scaffold", *GRADED_CLI, *cli_extra, "--cache", str(cache), "--out",
            str(tmp_path / "cli.stl"))
    cli = json.loads((tmp_path / "cli.stl.json").read_text())
    py = cmcsurf.scaffold(tmp_path / "py.stl", cache=str(cache), **GRADED_KWARGS, **py_extra)
    assert py == json.loads((tmp_path / "py.stl.json").read_text())  # FILE.json as written
    a, b = numbers(cli), numbers(py)
    assert a.keys() == b.keys()
    assert {k: v for k, v in a.items() if v != b[k]} == {}
    assert py["graded"] == cli["graded"]
    g = py["graded"]
    assert g["by"] == ("surface" if how == "depth" else "axis")
    assert len(g["profile"]) == (5 if how == "depth" else 3)  # 4 bands and the core; 3 cells
    assert len(g["member_volume_fractions"]) == 2
    # The level solve meets the ramp's mean within the network's trimming tolerance.
    assert abs(py["porosity"] - g["porosity_mean"]) <= 1e-3
    assert (tmp_path / "py.stl").stat().st_size == (tmp_path / "cli.stl").stat().st_size


def test_scaffold_refuses_as_the_cli(tmp_path, cache):
    with pytest.raises(ValueError, match="--porosity: got '1.5'"):
        cmcsurf.scaffold(tmp_path / "x.stl", cache=str(cache), porosity=1.5, grid=32)
    with pytest.raises(ValueError, match="--porosity: required"):
        cmcsurf.scaffold(tmp_path / "x.stl", cache=str(cache), grid=32)
    with pytest.raises(ValueError, match="--resolution: not with --grid"):
        cmcsurf.scaffold(tmp_path / "x.stl", porosity=0.7, grid=32, resolution=0.1)
    with pytest.raises(TypeError, match="skin"):
        cmcsurf.scaffold(tmp_path / "x.stl", porosity=0.7, skin="0.1")
    with pytest.raises(TypeError, match="unexpected keyword"):
        cmcsurf.scaffold(tmp_path / "x.stl", porosity=0.7, cell_sise=2)
    assert not list(tmp_path.iterdir())  # nothing written


def test_scaffold_stops_on_ctrl_c(tmp_path):
    """A real SIGINT half a second into a member's solve (64^3, paper mode: tens of seconds)
    stops the call at its next time step: the solve runs without the GIL and polls Python's
    signal handlers, so KeyboardInterrupt arrives and nothing is written or cached."""
    lines = []
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            cmcsurf.scaffold(tmp_path / "part.stl", cache=str(tmp_path / "cache"), porosity=0.7,
                             paper=True, grid=64, size=2, threads=1, no_page=True,
                             progress=lines.append)
    finally:
        timer.cancel()
    # A 64^3 paper-mode step takes well under a second; 20 s bounds a loaded shared machine.
    assert time.monotonic() - start < 20
    assert any("computing the member" in line for line in lines), lines
    assert not (tmp_path / "part.stl").exists()
    assert not list((tmp_path / "cache").glob("*/member.json"))  # no finished cache entry


def test_scaffold_progress_exception_stops_the_call(tmp_path):
    """An exception raised by `progress` stops the call at the next poll and is raised again,
    as Ctrl-C is (here at the member's first time step)."""
    def stop(line):
        raise RuntimeError("stop here")
    start = time.monotonic()
    with pytest.raises(RuntimeError, match="stop here"):
        cmcsurf.scaffold(tmp_path / "part.stl", cache=str(tmp_path / "cache"), porosity=0.7,
                         paper=True, grid=64, size=2, threads=1, no_page=True, progress=stop)
    assert time.monotonic() - start < 20
    assert not (tmp_path / "part.stl").exists()


def test_scaffold_signature_is_the_cli_table():
    import inspect
    params = inspect.signature(cmcsurf.scaffold).parameters
    for o in cmcsurf._cmcsurf.scaffold_options():
        assert o["key"] in params and o["cli"] == "--" + o["key"].replace("_", "-")
    assert params["cell_size"].default == 2.0 and params["surface"].default == "G"
    # grid: None lets the mode choose (128, or --paper's 64), as in run().
    assert params["porosity"].default is None and params["grid"].default is None
    assert "--target-modulus" in cmcsurf.scaffold.__doc__
    # The run options the command takes (add_run_options without the surface's own).
    assert all(k in params for k in ("seed", "epsilon", "fast", "paper", "mg_rtol"))
    assert "volume_fraction" not in params


def test_morphometry_of_the_cell_matches_scaffold_design(gyroid_result, tmp_path):
    net = cmcsurf.morphometry(gyroid_result, "network", cell_size=2.0)
    w, p = net["wall_thickness"], net["pore_size"]
    assert 0 < w["p5"] <= w["p50"] <= w["p95"] and 0 < p["p5"] <= p["p50"] <= p["p95"]
    # The balanced gyroid: both phases congruent, so wall and pore agree within a voxel.
    assert abs(w["mean"] - p["mean"]) <= net["voxel"]
    # Sizes scale with the cell (the same voxels).
    half = cmcsurf.morphometry(gyroid_result.phi, "network", cell_size=1.0)
    assert math.isclose(half["wall_thickness"]["mean"], 0.5 * w["mean"], rel_tol=1e-12)
    # A sheet at a thickness and at the porosity Steiner gives it: the same cell.
    sheet = cmcsurf.morphometry(gyroid_result, "sheet", thickness=0.3, cell_size=2.0)
    again = cmcsurf.morphometry(gyroid_result, "sheet", porosity=sheet["porosity"],
                                cell_size=2.0)
    assert sheet["wall_thickness"] == again["wall_thickness"]
    # The wall's median is the thickness asked within a voxel and a bit (curvature).
    assert abs(sheet["wall_thickness"]["p50"] - 0.3) <= 2 * sheet["voxel"]
    folder = gyroid_result.save(tmp_path / "run", preview=False, report=False)
    assert cmcsurf.morphometry(folder, cell_size=2.0)["wall_thickness"] == w
    with pytest.raises(ValueError, match="a sheet takes one of them"):
        cmcsurf.morphometry(gyroid_result, "sheet")
    with pytest.raises(ValueError, match="solid"):
        cmcsurf.morphometry(np.zeros((32, 32, 32)), "foam")
