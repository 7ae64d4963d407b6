"""run(), Result.save() and measure() against the command line, bit for bit."""
import csv
import inspect
import pathlib
import re

import numpy as np
import pytest

import cmcsurf
from conftest import comparable, load_report


def test_run_report_equals_cli_report_json(gyroid_result, gyroid_cli):
    cli = load_report(gyroid_cli)
    ours = gyroid_result.report
    # The same keys (checkpoints_written, build, version, ...), but the times of what runs in
    # save(): the preview, the page's meshes and the writes (documented on Result.report).
    saved_only = {"preview_seconds", "page_seconds", "write_seconds"}
    assert set(cli) - set(ours) == saved_only and set(ours) <= set(cli)
    assert ours["checkpoints_written"] == 0 and ours["checkpoint_seconds"] == 0
    assert comparable(ours) == comparable({k: v for k, v in cli.items() if k not in saved_only})
    # Exact equality of the numbers, not closeness: the same code path at the same threads.
    assert ours["area"] == cli["area"] and ours["steps"] == cli["steps"] > 0


def test_history_equals_cli_history_csv(gyroid_result, gyroid_cli):
    with open(gyroid_cli / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    h = gyroid_result.history
    assert len(rows) == len(h["step"]) == gyroid_result.report["steps"] + \
        gyroid_result.report["prerelax_steps"]
    for key in ("time", "area", "d_area", "d_phi", "energy", "mass", "dt"):  # %.17g: exact
        assert np.array_equal(h[key], np.array([float(r[key]) for r in rows])), key
    assert list(h["stage"]) == [r["stage"] for r in rows]
    assert np.array_equal(h["vcycles"], [int(r["vcycles"]) for r in rows])


def test_save_writes_the_cli_run_folder(gyroid_result, gyroid_cli, tmp_path):
    out = gyroid_result.save(tmp_path / "run")
    assert isinstance(out, pathlib.Path) and out == tmp_path / "run"
    # The files of `cmcsurf run`'s default folder, no more, no fewer.
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in gyroid_cli.iterdir())
    # field.vti holds phi and the run's area in full precision: identical bytes (history.csv
    # has the wall-clock column elapsed; test_history_equals_cli_history_csv compares the rest).
    for name in ("field.vti", "curvature_histogram.csv", "preview.png"):
        assert (out / name).read_bytes() == (gyroid_cli / name).read_bytes(), name
    saved = load_report(out)
    assert saved["preview_seconds"] > 0
    assert comparable(saved) == comparable(load_report(gyroid_cli))
    # report.html: the same page but for the numbers of the wall-clock times.
    def page(folder):
        html = (folder / "report.html").read_text(encoding="utf-8")
        return re.sub(r"[-+]?\d+(\.\d+)?([eE][-+]?\d+)?", "#", html)
    assert page(out) == page(gyroid_cli) and len(page(out)) > 10000
    # --no-preview --no-report; into the same folder the earlier outputs go first.
    gyroid_result.save(out, preview=False, report=False)
    assert not (out / "preview.png").exists() and not (out / "report.html").exists()
    assert "preview_seconds" not in load_report(out) and "page_seconds" not in load_report(out)


def test_phi_is_read_only_float64_cube(gyroid_result):
    phi = gyroid_result.phi
    assert phi.shape == (32, 32, 32) and phi.dtype == np.float64 and phi.flags.c_contiguous
    assert not phi.flags.writeable
    assert abs(phi.mean() - gyroid_result.report["mass"]) < 1e-12


def test_measure_of_the_run_phi_equals_its_report(gyroid_result):
    m = cmcsurf.measure(gyroid_result.phi, epsilon=0.01, surface="G", threads=1)
    r = gyroid_result.report
    for key in ("area", "area_error", "mean_curvature", "mean_curvature_error",
                "total_mean_curvature", "area_diffuse", "mean_curvature_diffuse",
                "mean_curvature_mu", "volume_fraction", "volume_fraction_cells", "mass",
                "energy", "mean_curvature_std", "nodal_area", "nodal_mean_curvature_std",
                "nodal_area_excess"):
        assert m[key] == r[key], key


def test_keyword_defaults_are_the_cli_defaults():
    defaults = cmcsurf.default_options()
    for fn in (cmcsurf.run, cmcsurf.relax, cmcsurf.sweep):
        for name, p in inspect.signature(fn).parameters.items():
            if name in defaults and p.default is not None and name not in ("surface",):
                if (fn, name) == (cmcsurf.relax, "prerelax_steps"):
                    assert p.default == 0  # documented: step 3 off for a given field
                    continue
                assert p.default == defaults[name], (fn.__name__, name)
    sig = inspect.signature(cmcsurf.run).parameters
    assert sig["surface"].default == defaults["surface"]
    assert sig["grid"].default is None and defaults["grid"] == 128  # --paper: 64


def test_surfaces_lists_the_builtin_table():
    s = {d["name"]: d for d in cmcsurf.surfaces()}
    assert s["G"]["nodal"] and s["G"]["balanced"] is True
    assert s["sphere"]["nodal"] is False and s["sphere"]["balanced"] is None


def test_every_cli_run_option_is_a_keyword_of_run():
    from conftest import run_cli
    help_text = run_cli("run", "--help").stdout
    kwargs = set(inspect.signature(cmcsurf.run).parameters)
    for key in cmcsurf.default_options():
        if "--" + key.replace("_", "-") in help_text:
            assert key in kwargs, key
    assert "--threads" in help_text and "threads" in kwargs


def test_signatures_are_the_run_option_table():
    # run, relax and sweep take the table's options with its defaults (None where --fast
    # chooses), so a new entry reaches them without an edit of __init__.py.
    table = cmcsurf._cmcsurf.run_options()
    defaults = cmcsurf.default_options()
    scopes = {cmcsurf.run: {"surface", "initial", "grid", "solver"},
              cmcsurf.relax: {"solver"}, cmcsurf.sweep: {"grid", "solver"}}
    types = {"float": float, "int": int, "str": str, "bool": bool}
    help_text = __import__("conftest").run_cli("run", "--help").stdout
    for option in table:
        key = option["key"]
        assert option["default"] == defaults[key], key
        assert isinstance(option["default"], types[option["type"]]), key
        assert option["cli"] in help_text, key
        for fn, wanted in scopes.items():
            params = inspect.signature(fn).parameters
            # relax's own: surface=None (a label), volume_fraction=None (phi's own), and
            # prerelax_steps=0 (documented: step 3 off for a given field).
            own = fn is cmcsurf.relax and key in ("surface", "volume_fraction", "prerelax_steps")
            assert own or (key in params) == (option["scope"] in wanted), (fn.__name__, key)
            if key not in params or own:
                continue
            want = None if option["fast"] or option["paper"] else option["default"]
            assert params[key].default == want, (fn.__name__, key)
            assert f"    {key}" in fn.__doc__, (fn.__name__, key)
    assert {o["key"] for o in table} == set(defaults) - {
        "noise_amplitude", "coarsest_max_sweeps", "coarsest_reduction"}


def test_signature_binds_positions_and_refuses_unknown_keywords():
    with pytest.raises(TypeError, match=r"^run\(\) got an unexpected keyword argument 'foo'"):
        cmcsurf.run(foo=1)
    with pytest.raises(TypeError, match=r"^sweep\(\) too many positional arguments"):
        cmcsurf.sweep("G", "0.5", 16, 0.04, 1)
    with pytest.raises(ValueError, match=r"^--settle-tol: got 2; accepted: 0 \(off\) <= T < 1$"):
        cmcsurf.run("G", 0.5, 16, 0.04, settle_tol=2)


def test_the_stub_declares_every_function_of_the_module():
    import ast
    import pathlib
    stub = pathlib.Path(cmcsurf._cmcsurf.__file__).with_name("_cmcsurf.pyi")
    declared = {n.name for n in ast.parse(stub.read_text()).body
                if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    public = {n for n in dir(cmcsurf._cmcsurf) if not n.startswith("_")}
    assert public - declared == set()
