"""cmcsurf.properties returns the dictionary `cmcsurf properties` writes (docs/properties.md)."""
import json

import numpy as np
import pytest

import cmcsurf
from conftest import run_cli


@pytest.fixture(scope="module")
def member():
    # paper=True: at 24^3 the fast mode's equilibrium rule follows G at 0.3 into a slow
    # topology change that the paper's area rule stops before.
    return cmcsurf.run("G", 0.3, 24, epsilon=0.03, paper=True, threads=1)


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


def _strip(d, volatile=("seconds", "properties_seconds", "solver", "youngs_picture_seconds")):
    if isinstance(d, dict):
        return {k: _strip(v, volatile) for k, v in d.items() if k not in volatile}
    return d


def test_run_properties_equal_the_cli_report(tmp_path):
    got = cmcsurf.run("G", 0.3, 24, epsilon=0.03, threads=1, properties_grid_check=True)
    run_cli("run", "--surface", "G", "--volume-fraction", "0.3", "--grid", "24", "--epsilon",
            "0.03", "--threads", "1", "--quiet", "--no-preview", "--no-report",
            "--properties-grid-check", "--out", str(tmp_path / "g"))
    cli = json.loads((tmp_path / "g" / "report.json").read_text())
    keys = {k for k in cli if k.startswith("properties")}
    assert keys >= {"properties", "properties_youngs_modulus", "properties_youngs_modulus_error",
                    "properties_conductivity_solid_error", "properties_seconds"}
    assert keys == {k for k in got.report if k.startswith("properties")}
    assert _strip({k: got.report[k] for k in keys}) == _strip({k: cli[k] for k in keys})
    # save() writes the same keys into the folder's report.json
    got.save(tmp_path / "py", preview=False, report=False)
    saved = json.loads((tmp_path / "py" / "report.json").read_text())
    assert saved["properties_youngs_modulus"] == got.report["properties_youngs_modulus"]


def test_sweep_properties_sheet_columns():
    results, table = cmcsurf.sweep("G", [0.4, 0.5], 16, epsilon=0.04, threads=1,
                                   properties_solid="sheet", properties_thickness=0.1)
    assert len(results) == 2
    for i, r in enumerate(results):
        p = r.report["properties"]
        assert p["solid"] == "sheet" and abs(p["thickness"] - 0.1) < 1e-12
        assert table["properties_youngs_modulus"][i] == r.report["properties_youngs_modulus"]
        assert "properties_youngs_modulus_error" not in r.report  # no grid check asked
    # a thinner wall around a surface of other area: the members differ in density
    rho = table["properties_relative_density"]
    assert 0.15 < rho[0] < 0.45 and 0.15 < rho[1] < 0.45 and rho[0] != rho[1], rho


def test_run_properties_sheet_ramp():
    r = cmcsurf.run("G", 0.5, 16, epsilon=0.04, threads=1, properties_solid="sheet",
                    properties_porosity=(0.6, 0.8))
    ramp = r.report["properties_ramp"]
    assert [round(e["properties_porosity"], 6) for e in ramp] == [0.6, 0.8]
    assert ramp[0]["properties_youngs_modulus"] == r.report["properties_youngs_modulus"]
    one = cmcsurf.run("G", 0.5, 16, epsilon=0.04, threads=1, properties_solid="sheet",
                      properties_porosity=0.8)
    assert "properties_ramp" not in one.report
    assert one.report["properties_youngs_modulus"] == ramp[1]["properties_youngs_modulus"]


def test_properties_stage_bad_arguments():
    # refused before the solve, naming the command line's option
    with pytest.raises(ValueError, match="--properties-solid"):
        cmcsurf.run("G", 0.3, 16, properties_solid="rod")
    with pytest.raises(ValueError, match="--properties-porosity"):
        cmcsurf.run("G", 0.3, 16, properties_porosity=0.7)  # a network's is its member's
    with pytest.raises(ValueError, match="exactly one"):
        cmcsurf.sweep("G", [0.3], 16, properties_solid="sheet")
    with pytest.raises(ValueError, match="--properties-grid-check"):
        cmcsurf.run("G", 0.3, 12, properties_grid_check=True)
    with pytest.raises(TypeError):
        cmcsurf.run("G", 0.3, 16, properties_porosity="0.7", properties_solid="sheet")
