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
    # Timings, provenance, and the picture the command draws beside its file (Python draws none)
    volatile = {"seconds", "properties_seconds", "source", "version", "solver", "youngs_picture",
                "youngs_picture_seconds"}

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
    with pytest.raises(ValueError, match="flow-area"):
        cmcsurf.properties(phi, only="flow", flow_rate=1.0, units="mm")


def test_flow_keys_in_physical_units(member):
    p = cmcsurf.properties(member, only="flow", cell_size=2.0, units="mm", flow_rate=1.0,
                           flow_area=16.0, threads=1)
    assert "stiffness_voigt" not in p and "conductivity_solid" not in p
    k = p["permeability"]
    assert all(abs(k[i][i] - k[0][0]) < 1e-6 * k[0][0] for i in range(3))  # a cubic member
    assert abs(p["permeability_m2"][0][0] - k[0][0] * 2e-3 ** 2) < 1e-12 * k[0][0]
    u = 1e-6 / 60 / 16e-6  # 1 mL/min through 16 mm^2, m/s
    assert abs(p["wall_shear_stress_mpa"]["superficial_velocity_m_s"] - u) < 1e-15
    # Darcy: dP/dz = mu U / k (mu of water at 37 C, 0.692 mPa s)
    assert abs(p["pressure_drop_pa_per_m"] - 0.692e-3 * u / p["permeability_m2"][2][2]) < 1e-9
    tau = p["wall_shear_stress_mpa"]
    assert 0 < tau["p5"] <= tau["median"] <= tau["p95"] <= tau["max"]
    assert abs(sum(tau["histogram"]) - 1) < 1e-9
    assert p["hydraulic_tortuosity"][0] > 1 and p["kozeny_carman_constant"] > 0


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
