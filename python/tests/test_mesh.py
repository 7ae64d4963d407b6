"""mesh(): NumPy arrays of a closed, manifold, consistently oriented mesh, and its files."""
import json
from collections import Counter

import numpy as np
import pytest

import cmcsurf


def edge_counts(faces):
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    undirected = Counter(map(tuple, np.sort(directed, axis=1)))
    return Counter(map(tuple, directed)), undirected


@pytest.mark.parametrize("solid,thickness", [("network", None), ("sheet", 0.1)])
def test_mesh_is_closed_and_manifold(gyroid_result, solid, thickness):
    m = cmcsurf.mesh(gyroid_result, tile=(2, 1, 1), solid=solid, thickness=thickness,
                     cell_size=1.0)
    v, f = m.vertices, m.faces
    assert v.dtype == np.float64 and v.shape[1] == 3 and f.dtype == np.int64 and f.shape[1] == 3
    assert f.min() >= 0 and f.max() < len(v)
    directed, undirected = edge_counts(f)
    assert set(undirected.values()) == {2}      # every edge in exactly two faces: closed
    assert set(directed.values()) == {1}        # once each way: consistently oriented
    assert m.report["checks"]["closed"] and m.report["checks"]["manifold"]
    assert m.report["triangles"] == len(f) and m.report["vertices"] == len(v)
    assert np.allclose(v.max(axis=0) - v.min(axis=0), [2, 1, 1], atol=0.1)


def test_mesh_of_result_equals_mesh_of_its_phi(gyroid_result):
    a = cmcsurf.mesh(gyroid_result, solid="network")
    b = cmcsurf.mesh(gyroid_result.phi, solid="network")
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)


@pytest.mark.parametrize("name", ["part.stl", "part.3mf", "part.obj", "part.ply"])
def test_save_writes_the_file_and_its_report(gyroid_result, tmp_path, name):
    m = cmcsurf.mesh(gyroid_result, tile=2, solid="network", cell_size=2.5, units="mm")
    out = m.save(tmp_path / name)
    assert out.exists() and out.stat().st_size > 1000
    report = json.loads((tmp_path / (name + ".json")).read_text())
    assert report["file"] == name and report["triangles"] == len(m.faces)


@pytest.mark.parametrize("kwargs,error,words", [
    ({"tile": (0, 1, 1)}, ValueError, "--tile"),
    ({"tile": (1, 1)}, TypeError, "tile"),
    ({"solid": "foam"}, ValueError, "--solid"),
    ({"solid": "sheet"}, ValueError, "--thickness"),
    ({"thickness": 0.1}, ValueError, "--thickness"),
    ({"units": "ft"}, ValueError, "--units"),
    ({"cell_size": -1}, ValueError, "--cell-size"),
    ({"cell_size": "2"}, TypeError, "cell_size: got '2' of type str; accepted: a real number"),
    ({"thickness": "0.1", "solid": "sheet"}, TypeError, "thickness"),
    ({"units": 5}, TypeError, "units"),
    ({"other_phase": 1}, TypeError, "other_phase"),
])
def test_bad_mesh_options(gyroid_result, kwargs, error, words):
    with pytest.raises(error, match=words):
        cmcsurf.mesh(gyroid_result, **kwargs)


def test_save_refuses_unknown_format(gyroid_result, tmp_path):
    m = cmcsurf.mesh(gyroid_result)
    with pytest.raises(ValueError, match="--format"):
        m.save(tmp_path / "part.xyz")


def test_keep_fragments_keeps_the_pieces_the_box_cuts_off():
    # A slab through the box (one piece with its periodic images) and one cell apart from it:
    # a fragment under 1e-3 of the box, which `cmcsurf mesh` removes unless --keep-fragments.
    n = 16
    x = (np.arange(n) + 0.5) / n
    X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    phi = np.zeros((n, n, n))
    phi[np.abs(Y - 0.25) < 0.12] = 1.0
    phi[8, 12, 8] = 1.0
    removed = cmcsurf.mesh(phi, solid="network")
    kept = cmcsurf.mesh(phi, solid="network", keep_fragments=True)
    assert removed.report["topology"]["fragments"] == kept.report["topology"]["fragments"] == 1
    assert removed.report["topology"]["fragments_removed"]
    assert not kept.report["topology"]["fragments_removed"]
    assert len(kept.faces) > len(removed.faces)
    # The kept ball is the difference in volume the report gives for the fragment.
    assert kept.report["volume"] - removed.report["volume"] == pytest.approx(
        removed.report["topology"]["fragment_volume"], rel=1e-9)
    with pytest.raises(TypeError, match="keep_fragments"):
        cmcsurf.mesh(phi, solid="network", keep_fragments="yes")


def test_a_solid_in_pieces_is_refused_not_trimmed():
    # A ball beside the slab is 1.4 % of the box; removing it would move the volume
    # fraction past its tolerance without a word, so mesh() raises unless keep_fragments.
    n = 16
    x = (np.arange(n) + 0.5) / n
    X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    phi = np.zeros((n, n, n))
    phi[np.abs(Y - 0.25) < 0.12] = 1.0
    phi[(X - 0.5) ** 2 + (Y - 0.75) ** 2 + (Z - 0.5) ** 2 < 0.15 ** 2] = 1.0
    with pytest.raises(RuntimeError, match="pieces"):
        cmcsurf.mesh(phi, solid="network")
    kept = cmcsurf.mesh(phi, solid="network", keep_fragments=True)
    assert kept.report["topology"]["fragments"] == 1


def test_save_writes_the_file_json_of_cmcsurf_mesh(gyroid_result, gyroid_cli, tmp_path):
    from conftest import comparable, run_cli
    options = ["--tile", "2", "--solid", "network", "--cell-size", "2.5", "--units", "mm"]
    run_cli("mesh", "--from", str(gyroid_cli), *options, "--quiet",
            "--out", str(tmp_path / "cli.stl"))
    cli = json.loads((tmp_path / "cli.stl.json").read_text())
    cmcsurf.mesh(gyroid_result, tile=2, solid="network", cell_size=2.5, units="mm").save(
        tmp_path / "py.stl")
    ours = json.loads((tmp_path / "py.stl.json").read_text())
    # The same keys (source included) and numbers: field.vti holds the run's phi exactly.
    assert comparable({k: v for k, v in ours.items() if k not in ("file", "source")}) == \
        comparable({k: v for k, v in cli.items() if k not in ("file", "source")})
    assert cli["source"] == str(gyroid_cli) and ours["source"].startswith("cmcsurf.Result: G")
    assert (tmp_path / "py.stl").read_bytes() == (tmp_path / "cli.stl").read_bytes()


def test_a_member_of_another_topology_is_refused():
    # P at volume fraction 0.2 on 32^3 ends on separate balls (Euler characteristic
    # 1) where its family, the nodal P it starts from, is the genus-3 network (-2).
    balls = cmcsurf.run("P", 0.2, 32, threads=1)
    assert balls.report["topology_changed"] and balls.report["euler_characteristic_start"] == -2
    with pytest.raises(RuntimeError, match="Euler characteristic 1 .* -2 "):
        cmcsurf.mesh(balls, solid="network")
    # Taken anyway, the balls are pieces that fragment removal may not silently drop.
    with pytest.raises(RuntimeError, match="pieces"):
        cmcsurf.mesh(balls, solid="network", accept_topology_change=True)
    m = cmcsurf.mesh(balls, solid="network", accept_topology_change=True, keep_fragments=True)
    assert m.report["topology"]["solid_components"] > 1
