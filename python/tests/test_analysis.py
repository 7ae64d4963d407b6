"""The analysis functions: the welded periodic mesh, the signed distance, and load() of run and
sweep folders made here (docs/science.md)."""
import numpy as np
import pytest

import cmcsurf
from conftest import page_flags, run_cli


def test_periodic_mesh_is_closed_with_the_surfaces_euler_characteristic(gyroid_result):
    m = cmcsurf.periodic_mesh(gyroid_result)
    s = m["stats"]
    assert s["closed"] and s["manifold"]
    assert s["euler_characteristic"] == gyroid_result.report["euler_characteristic_surface"] == -8
    assert m["vertices"].shape == (s["vertices"], 3)
    assert m["triangles"].shape == (s["triangles"], 3)
    assert m["offsets"].shape == (s["triangles"], 3, 3)
    assert (m["offsets"][:, 0] == 0).all() and np.abs(m["offsets"]).max() == 1
    assert ((m["vertices"] >= 0) & (m["vertices"] < 1)).all()
    np.testing.assert_allclose(np.linalg.norm(m["normals"], axis=1), 1.0, atol=1e-12)
    # The area of the welded triangles is the report's sharp area, up to the mesher keeping
    # vertices 1e-3 of an edge away from its nodes (measured 5e-6).
    corners = m["vertices"][m["triangles"]] + m["offsets"]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    area = 0.5 * np.linalg.norm(cross, axis=1).sum()
    assert area == pytest.approx(gyroid_result.report["area"], rel=2e-5)
    # G at 1/2: H near 0 everywhere on average.
    assert abs(m["mean_curvature"].mean()) < 0.05


def test_signed_distance_has_the_phases_signs(gyroid_result):
    d = cmcsurf.signed_distance(gyroid_result)
    phi = gyroid_result.phi
    assert d.shape == phi.shape
    assert ((d > 0) == (phi > 0.5)).all()
    eps = gyroid_result.report["epsilon"]
    np.testing.assert_allclose(cmcsurf.signed_distance(phi, eps), d)
    with pytest.raises(TypeError, match="epsilon"):
        cmcsurf.signed_distance(phi)


def test_load_reads_a_run_and_a_sweep_folder(gyroid_result, tmp_path):
    run = cmcsurf.load(gyroid_result.save(tmp_path / "run", preview=False, report=False))
    assert run["kind"] == "run"
    np.testing.assert_array_equal(run["phi"], gyroid_result.phi)
    assert run["distance"] is None
    assert run["report"]["area"] == gyroid_result.report["area"]
    np.testing.assert_array_equal(run["history"]["step"], gyroid_result.history["step"])
    np.testing.assert_allclose(run["history"]["area"], gyroid_result.history["area"])
    out = tmp_path / "sweep"
    run_cli("sweep", "--surface", "G", "--volume-fractions", "0.45,0.5", "--grid", "16",
            "--epsilon", "0.04", "--threads", "1", "--quiet", "--no-plot", "--distance-field",
            *page_flags(), "--out", str(out))
    sweep = cmcsurf.load(out)
    assert sweep["kind"] == "sweep"
    assert sorted(sweep["members"]) == ["G_0.45", "G_0.50"]
    member = sweep["members"]["G_0.45"]
    assert member["phi"].shape == (16, 16, 16)
    np.testing.assert_allclose(
        member["distance"],
        cmcsurf.signed_distance(member["phi"], member["report"]["epsilon"]), rtol=1e-6, atol=1e-9)
    assert all(len(column) == 2 for column in sweep["table"].values())
    with pytest.raises(FileNotFoundError, match="not a folder"):
        cmcsurf.load(tmp_path / "nothing")
