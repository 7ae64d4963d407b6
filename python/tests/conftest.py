"""Shared fixtures: the command line to compare with, and one 32^3 gyroid run reused by the
tests that only read it (a run is immutable)."""
import json
import os
import pathlib
import subprocess

import pytest

import cmcsurf

ROOT = pathlib.Path(__file__).resolve().parents[2]

# The 32^3 gyroid of the comparisons: the command line's defaults otherwise, one thread (the
# reductions' order depends on the thread count, so both sides use one).
GYROID = {"surface": "G", "volume_fraction": 0.5, "grid": 32}


def cli_path():
    given = os.environ.get("CMCSURF_CLI")
    if given:
        return given
    for build in ("build-py", "build"):
        p = ROOT / build / "cmcsurf"
        if p.exists():
            return str(p)
    pytest.skip("no cmcsurf binary (set CMCSURF_CLI)")


def run_cli(*args, check=True):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    return subprocess.run([cli_path(), *args], capture_output=True, text=True, env=env,
                          check=check)


_page_flags = None


def page_flags():
    """--no-preview / --no-report where the CLI has them: the comparisons need only the run
    folder's data files, and the preview image costs time."""
    global _page_flags
    if _page_flags is None:
        help_text = run_cli("run", "--help").stdout
        _page_flags = [f for f in ("--no-preview", "--no-report") if f in help_text]
    return _page_flags


@pytest.fixture(scope="session")
def gyroid_result():
    return cmcsurf.run(**GYROID, threads=1)


@pytest.fixture(scope="session")
def gyroid_cli(tmp_path_factory):
    """`cmcsurf run` with its default outputs (preview.png, report.html) at GYROID, one thread."""
    out = tmp_path_factory.mktemp("cli") / "gyroid"
    run_cli("run", "--surface", "G", "--volume-fraction", "0.5", "--grid", "32", "--threads",
            "1", "--quiet", "--out", str(out))
    return out


def load_report(folder):
    return json.loads((pathlib.Path(folder) / "report.json").read_text())


def volatile(key):
    """Keys whose values differ between two identical runs: wall-clock times and the process's
    peak memory."""
    return (key.endswith("_seconds") or key.startswith("peak_memory")
            or key in ("seconds", "seconds_per_vcycle"))


def comparable(report):
    """The report with the values of volatile keys replaced by a mark: the keys themselves must
    agree, and every other value exactly."""
    if isinstance(report, dict):
        return {k: "<volatile>" if volatile(k) else comparable(v) for k, v in report.items()}
    if isinstance(report, list):
        return [comparable(v) for v in report]
    return report


def pytest_sessionfinish(session, exitstatus):
    """A test skipped for a missing dependency makes the whole run a skip (exit 77, CTest's
    SKIP_RETURN_CODE for python.pytest), never a pass; -rs names what was skipped and why."""
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if exitstatus == 0 and reporter is not None and reporter.stats.get("skipped"):
        session.exitstatus = 77
