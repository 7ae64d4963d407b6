"""volume_mesh(): the periodic tet mesh written as the command writes it, its report, and the
option errors. Skipped where the module was built without CGAL."""
import json

import numpy as np
import pytest

import cmcsurf


def mesh_or_skip(*args, **kwargs):
    try:
        return cmcsurf.volume_mesh(*args, **kwargs)
    except RuntimeError as e:
        if "without CGAL" in str(e):
            pytest.skip("cmcsurf built without CGAL")
        raise


def test_volume_mesh_writes_a_paired_mesh_and_its_report(gyroid_result, tmp_path):
    out = tmp_path / "g.vtu"
    r = mesh_or_skip(gyroid_result, out, "network", tile=(2, 1, 1), cell_size=2.0, size=0.3)
    assert out.exists()
    written = json.loads((tmp_path / "g.vtu.json").read_text())  # plus file, format, ...
    assert {k: written[k] for k in r} == r
    assert written["format"] == "vtu" and r["tiles"] == [2, 1, 1]
    assert r["checks"]["unmatched_boundary_faces"] == 0
    assert r["checks"]["components_periodic"] == 1
    assert r["checks"]["pair_mismatch"] <= 1e-12
    assert abs(r["volume_relative_error"]) < 0.005
    assert r["pairing"]["period"] == [4.0, 2.0, 2.0]
    assert r["cut"]["faces"] == "flat" and r["checks"]["unmirrored_faces"] == 0
    assert r["checks"]["periodic_faces_off_plane"] == 0


def test_volume_mesh_of_an_array_and_its_errors(gyroid_result, tmp_path):
    phi = np.asarray(gyroid_result.phi)
    r = mesh_or_skip(phi, tmp_path / "s.inp", "sheet", thickness=0.15, size=0.2)
    assert r["solid"] == "sheet" and r["checks"]["inverted_tets"] == 0
    with pytest.raises(ValueError, match="--porosity"):
        cmcsurf.volume_mesh(phi, tmp_path / "x.msh", "network", porosity=0.5)
    with pytest.raises(ValueError, match="--size"):
        cmcsurf.volume_mesh(phi, tmp_path / "x.msh", size=0.9)
    with pytest.raises(ValueError, match="--cut"):
        cmcsurf.volume_mesh(phi, tmp_path / "x.msh", cut="round")
    with pytest.raises(ValueError, match="format"):
        cmcsurf.volume_mesh(phi, tmp_path / "x.stl")
    assert not list(tmp_path.glob("x.*"))
