"""The examples run at small grids."""
import os
import pathlib
import subprocess
import sys

import pytest

import cmcsurf

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def run_example(name, tmp_path, *args):
    # The package under test, wherever it was imported from (the build tree under CTest).
    package_root = str(pathlib.Path(cmcsurf.__file__).resolve().parents[1])
    path = os.pathsep.join(p for p in (package_root, os.environ.get("PYTHONPATH")) if p)
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=path)
    return subprocess.run([sys.executable, str(EXAMPLES / name), *args], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120)


def test_fig11(tmp_path):
    pytest.importorskip("matplotlib")
    p = run_example("fig11.py", tmp_path, "--grid", "16", "--fractions", "0.4,0.5,0.6",
                    "--out", "fig11.png")
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "fig11.png").stat().st_size > 10000
    members = [line for line in p.stdout.splitlines() if ": area " in line]
    assert len(members) == 9  # 3 surfaces x 3 fractions
    assert not any("area 0.00000" in line for line in members)  # none dissolved


def test_relax_noisy(tmp_path):
    # 24^3: the smallest grid of the multigrid's on which the noisy field keeps a surface.
    p = run_example("relax_noisy.py", tmp_path, "--grid", "24", "--out", "relaxed.stl")
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "relaxed.stl").exists() and "closed True" in p.stdout
    assert "dissolved" not in p.stdout
