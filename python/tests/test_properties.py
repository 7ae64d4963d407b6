"""cmcsurf.properties returns the dictionary `cmcsurf properties` writes (docs/properties.md)."""
import json

import numpy as np
import pytest

import cmcsurf
from conftest import run_cli


@pytest.fixture(scope="module")
def member():
    return cmcsurf.run("G", 0.3, 24, epsilon=0.03, threads=1)


def test_properties_equal_the_cli_file(member, tmp_path):
    got = cmcsurf.properties(member, "sheet", porosity=0.7, material=(110, 0.34),
                             compare_nodal=True, threads=1)
    member.save(tmp_path / "g", preview=False, report=False)
    run_cli("properties", "--from", str(tmp_path / "g"), "--solid", "sheet", "--porosity",
            "0.7", "--material", "110,0.34", "--compare-nodal", "--threads", "1", "--quiet")
    cli = json.loads((tmp_path / "g" / "properties.json").read_text())
    volatile = {"seconds", "properties_seconds", "source", "version", "solver"}

    def strip(d):
        if isinstance(d, dict):
            return {k: strip(v) for k, v in d.items() if k not in volatile}
        return d
    assert strip(got) == strip(cli)
    assert got["surface"] == "G" and abs(got["porosity"] - 0.7) < 1e-6
    assert set(got) >= {"stiffness_voigt", "youngs_modulus", "conductivity_solid", "nodal",
                        "nodal_offset", "hashin_shtrikman_upper", "stiffness_voigt_gpa"}


def test_properties_of_an_array_and_bad_arguments(member):
    phi = np.array(member.phi)
    p = cmcsurf.properties(phi, only="conductivity", threads=1)
    assert "conductivity_solid" in p and "stiffness_voigt" not in p
    with pytest.raises(ValueError, match="solid"):
        cmcsurf.properties(phi, "rod")
    with pytest.raises(ValueError, match="porosity"):
        cmcsurf.properties(phi, porosity=0.5)  # a network's porosity is its member's
    with pytest.raises(ValueError, match="exactly one"):
        cmcsurf.properties(phi, "sheet")
    with pytest.raises(TypeError, match="material"):
        cmcsurf.properties(phi, material=110)
    with pytest.raises(ValueError, match="compare-nodal"):
        cmcsurf.properties(phi, compare_nodal=True)  # an array names no nodal formula


def test_scattering_equals_the_cli_file(member, tmp_path):
    got = cmcsurf.scattering(member, "bilayer:0.05", lattice=12.0, threads=1)
    member.save(tmp_path / "s", preview=False, report=False)
    run_cli("scattering", "--from", str(tmp_path / "s"), "--density", "bilayer:0.05",
            "--lattice", "12", "--threads", "1", "--quiet")
    cli = json.loads((tmp_path / "s" / "scattering" / "scattering.json").read_text())
    for key in ("space_group", "allowed", "absent", "f000", "smax", "density"):
        assert got[key] == cli[key], key
    # a bilayer around the G member at 0.3: its two labyrinths differ, so not Ia-3d
    assert got["space_group"]["symbol"] == "I4_132"
    r = got["reflections"]
    assert r["h"].dtype == np.int64 and len(r["s"]) == len(r["intensity"]) > 10
    assert got["saxs"]["q"].shape == got["saxs"]["intensity"].shape
    with pytest.raises(ValueError, match="lattice"):
        cmcsurf.scattering(member, lattice=-1)
    with pytest.raises(ValueError, match="density"):
        cmcsurf.scattering(member, "fog")
