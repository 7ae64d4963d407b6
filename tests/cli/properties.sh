#!/usr/bin/env bash
# cmcsurf properties (docs/properties.md): the stiffness and conductivities of a 24^3 gyroid's
# network and sheet, with the nodal twins and the grid check; every number in its range (a
# cubic member gives a cubic, symmetric tensor below its Hashin-Shtrikman bound), the directional
# Young's modulus pictures beside the JSON files, run/sweep --properties (youngs_modulus.png, the
# designer's chart and its fit, exact through two members), and bad options refused with exit 2,
# naming the option, writing nothing.
set -u
source "$(dirname "$0")/usage.bash" "$1"
export OMP_NUM_THREADS=1
"$bin" run --paper --surface G --volume-fraction 0.3 --grid 24 --epsilon 0.03 --quiet --no-preview \
  --no-report --out "$work/g" || { echo "FAIL: the run"; exit 1; }

"$bin" properties --from "$work/g" --compare-nodal --material 110,0.34 --quiet ||
  { echo "FAIL: network"; fail=1; }
"$bin" properties --from "$work/g/field.vti" --solid sheet --porosity 0.7 --compare-nodal \
  --grid-check --quiet --out "$work/sheet.json" || { echo "FAIL: sheet"; fail=1; }
python3 - "$work/g/properties.json" "$work/sheet.json" "$(dirname "$0")/../page" <<'PY' || fail=1
import json, os, sys
net, sheet = (json.load(open(f)) for f in sys.argv[1:3])
sys.path.insert(0, sys.argv[3])
from png_check import read_png, region_stats
for f, j in ((sys.argv[1], net), (sys.argv[2], sheet)):
    picture = os.path.join(os.path.dirname(f), j["youngs_picture"])
    assert j["youngs_picture"] == os.path.basename(f)[:-5] + "-youngs.png", j["youngs_picture"]
    w, h, rows = read_png(picture)
    var, coloured = region_stats(rows, 0, 0, w, h)
    assert w > 600 and h > 600 and var > 100 and coloured > 0.1, (picture, w, h, var, coloured)
    assert j["youngs_picture_seconds"] > 0
def cubic(p, tol):
    c = p["stiffness_voigt"]
    for i in range(6):
        for j in range(6):
            assert abs(c[i][j] - c[j][i]) <= 1e-9, (i, j)
    assert abs(c[0][0] - c[1][1]) <= tol * c[0][0] and abs(c[0][0] - c[2][2]) <= tol * c[0][0]
    assert abs(c[3][3] - c[5][5]) <= tol * c[3][3]
    for i in range(3):
        for j in range(3, 6):
            assert abs(c[i][j]) <= tol * c[0][0], (i, j, c[i][j])
for p in (net, net["nodal"], sheet, sheet["nodal"], sheet["nodal_offset"]):
    cubic(p, 2e-2)
    for key in ("bulk_modulus", "shear_modulus", "conductivity_solid", "conductivity_pore"):
        assert 0 < p["fraction_of_bound"][key] <= 1.0 + 1e-9, (key, p["fraction_of_bound"])
    assert p["solver"]["elastic"]["converged"] and not p["warnings"], p["warnings"]
assert abs(net["porosity"] - 0.7) < 2e-3 and net["solid"] == "network" and net["phase"] == 1
assert abs(net["nodal"]["porosity"] - net["porosity"]) < 1e-6
assert abs(net["youngs_modulus_gpa"][0] - 110 * net["youngs_modulus"][0]) < 1e-9
assert abs(sheet["porosity"] - 0.7) < 1e-6 and sheet["thickness"] > 0
assert abs(sheet["nodal_offset"]["porosity"] - 0.7) < 1e-6
assert all(e >= 0 for e in sheet["youngs_modulus_error"])
assert sheet["grid_check"]["coarse_grid"] == 12
# Flow (in the default set): the cubic member's permeability isotropic and diagonal, with the
# grid check's error and the solver converged.
for p in (net, net["nodal"], sheet):
    k = p["permeability"]
    assert k[0][0] > 0 and p["solver"]["flow"]["converged"], p["solver"]["flow"]
    for i in range(3):
        assert abs(k[i][i] - k[0][0]) <= 2e-2 * k[0][0], k
        assert abs(k[i][(i + 1) % 3]) <= 2e-2 * k[0][0], k
    assert all(t > 1 for t in p["hydraulic_tortuosity"]) and p["kozeny_carman_constant"] > 0
    assert "permeability_m2" not in p  # --units cell: no physical size
assert all(e >= 0 for row in sheet["permeability_error"] for e in row)
PY

# Flow alone in physical units: k in m^2 (cell 2 mm), the wall shear stress in mPa and the
# pressure drop for a superficial velocity of 1 mm/s (Darcy: dP/dz = mu U / k_zz).
"$bin" properties --from "$work/g" --only flow --cell-size 2 --units mm --velocity 1 --quiet \
  --out "$work/flow.json" || { echo "FAIL: flow"; fail=1; }
python3 - "$work/flow.json" <<'PY' || fail=1
import json, sys
p = json.load(open(sys.argv[1]))
assert "stiffness_voigt" not in p and "conductivity_solid" not in p
k = p["permeability"][2][2]
assert abs(p["permeability_m2"][2][2] - k * 4e-6) <= 1e-12 * k
dp = p["pressure_drop_pa_per_m"]
assert abs(dp - 0.692e-3 * 1e-3 / (k * 4e-6)) <= 1e-9 * dp
tau = p["wall_shear_stress_mpa"]
assert 0 < tau["p5"] <= tau["median"] <= tau["p95"] <= tau["max"], tau
assert abs(sum(tau["histogram"]) - 1) < 1e-9
# The flow along each axis: z is the key above; the axes' mean is the mean of the three, which
# agree for a cubic member (its relaxed field is cubic to the solver's tolerance).
axes = p["wall_shear_stress_mpa_per_axis"]
assert sorted(axes) == ["x", "y", "z"] and axes["z"]["mean"] == tau["mean"], axes
mean = p["wall_shear_stress_mpa_axis_mean"]
assert mean["axes"] == 3
for key in ("mean", "median", "p95"):
    assert abs(mean[key] - sum(axes[a][key] for a in "xyz") / 3) <= 1e-12 * mean[key], key
    assert max(abs(axes[a][key] / mean[key] - 1) for a in "xyz") < 0.02, (key, axes)
assert p["pressure_drop_pa_per_m_per_axis"][2] == dp
PY

# The --properties stage of run and sweep: report.json's properties and properties_* scalars
# (sweep.csv's columns), the same numbers as the command's.
"$bin" run --paper --surface G --volume-fraction 0.3 --grid 24 --epsilon 0.03 --quiet \
  --no-report --properties-nodal --out "$work/gp" || { echo "FAIL: run --properties"; fail=1; }
"$bin" sweep --paper --surface G --volume-fractions 0.3,0.4 --grid 24 --epsilon 0.03 --quiet \
  --no-preview --no-report --properties --out "$work/sp" ||
    { echo "FAIL: sweep --properties"; fail=1; }
"$bin" properties --from "$work/gp" --quiet --out "$work/gp.json" || fail=1
python3 - "$work/gp.json" "$work/gp/report.json" "$work/sp/sweep.csv" "$work/sp/sweep.json" \
  <<'PY' || fail=1
import csv, json, math, os, sys
cmd, run = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
rows = list(csv.DictReader(open(sys.argv[3])))
row = rows[0]
# The chart's Gibson-Ashby fits through two members are the line through their points.
chart = json.load(open(sys.argv[4]))["properties_chart"]
assert chart["file"] == "properties_chart.png" and chart["seconds"] > 0
assert os.path.getsize(os.path.join(os.path.dirname(sys.argv[4]), chart["file"])) > 10000
(f,) = [f for f in chart["fits"] if f["part"] == "cmc" and f["quantity"] == "youngs_modulus"]
rho = [float(r["properties_relative_density"]) for r in rows]
e_ = [float(r["properties_youngs_modulus"]) for r in rows]
n = math.log(e_[1] / e_[0]) / math.log(rho[1] / rho[0])
assert f["valid"] and f["points"] == 2 and abs(f["exponent"] - n) < 1e-8 * abs(n), (f, n)
assert abs(f["coefficient"] - e_[0] / rho[0] ** n) < 1e-8 * f["coefficient"], f
assert 1.2 < n < 3.0, n  # bending-dominated network: Gibson-Ashby's 2, ASLI's 1.71
# The Kozeny-Carman constant of the chart: the geometric mean of the members' c, each
# eps^3 / (k S^2) from their sweep.csv columns.
(f,) = [f for f in chart["fits"]
        if f["part"] == "cmc" and f["quantity"] == "kozeny_carman_constant"]
c = [(1 - float(r["properties_relative_density"])) ** 3 / (float(r["properties_permeability"])
     * float(r["properties_specific_surface"]) ** 2) for r in rows]
for r, ci in zip(rows, c):
    assert abs(ci / float(r["properties_kozeny_carman_constant"]) - 1) < 1e-9, (ci, r)
assert abs(f["coefficient"] - math.exp(sum(map(math.log, c)) / 2)) < 1e-9 * f["coefficient"], f
assert os.path.exists(os.path.join(os.path.dirname(sys.argv[2]), "youngs_modulus.png"))
sweep = os.path.dirname(sys.argv[4])  # --no-preview: no member draws youngs_modulus.png
assert not [m for m in os.listdir(sweep)
            if os.path.exists(os.path.join(sweep, m, "youngs_modulus.png"))]
e = sum(cmd["youngs_modulus"]) / 3
assert abs(run["properties_youngs_modulus"] - e) < 1e-12, (run["properties_youngs_modulus"], e)
assert run["properties"]["nodal"]["porosity"] > 0 and "properties_nodal_youngs_modulus" in run
assert run["properties_seconds"] > 0
assert abs(float(row["properties_youngs_modulus"]) - e) < 1e-9 * e, row["properties_youngs_modulus"]
PY

# Bad options: exit 2, the option named, nothing written.
props() { check_usage "$1" "$2" properties --from "$work/g" "${@:3}"; }
for bad in "--solid rod" "--phase 3" "--only pressure" "--material abc" "--material 0" \
           "--material 110,0.6" "--tolerance 1" "--cell-size -1" "--viscosity 0" \
           "--flow-rate 1" "--velocity -1"; do
  set -- $bad
  props "bad.json" "$1" "$@"
done
props bad.json --porosity --porosity 0.5             # a network's porosity is its member's
props bad.json --solid --solid sheet                 # neither --porosity nor --thickness
props bad.json --porosity --solid sheet --porosity 1.5
props bad.json --thickness --solid sheet --thickness 0.7
props bad.json --units --velocity 1                  # no physical size: no m/s to scale by
"$bin" properties --from "$work/missing" --out "$work/x.json" 2>/dev/null
[ $? = 2 ] && [ ! -e "$work/x.json" ] || { echo "FAIL: a missing --from"; fail=1; }
# A field file without --out: where to write is not guessed.
"$bin" properties --from "$work/g/field.vti" 2>"$work/err"
[ $? = 2 ] && grep -q -- "--out" "$work/err" || { echo "FAIL: --from FILE without --out"; fail=1; }

[ "$fail" = 0 ] && echo "properties: all checks passed"
exit "$fail"
