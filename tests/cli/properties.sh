#!/usr/bin/env bash
# cmcsurf properties (docs/properties.md): the stiffness and conductivities of a 24^3 gyroid's
# network and sheet, with the nodal twins and the grid check; every number in its range (a
# cubic member gives a cubic, symmetric tensor below its Hashin-Shtrikman bound), and bad
# options refused with exit 2, naming the option, writing nothing.
set -u
source "$(dirname "$0")/usage.bash" "$1"
export OMP_NUM_THREADS=1
"$bin" run --surface G --volume-fraction 0.3 --grid 24 --epsilon 0.03 --quiet --no-preview \
  --no-report --out "$work/g" || { echo "FAIL: the run"; exit 1; }

"$bin" properties --from "$work/g" --compare-nodal --material 110,0.34 --quiet ||
  { echo "FAIL: network"; fail=1; }
"$bin" properties --from "$work/g/field.vti" --solid sheet --porosity 0.7 --compare-nodal \
  --grid-check --quiet --out "$work/sheet.json" || { echo "FAIL: sheet"; fail=1; }
python3 - "$work/g/properties.json" "$work/sheet.json" <<'PY' || fail=1
import json, sys
net, sheet = (json.load(open(f)) for f in sys.argv[1:3])
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
PY

# The --properties stage of run and sweep: report.json's properties and properties_* scalars
# (sweep.csv's columns), the same numbers as the command's.
"$bin" run --surface G --volume-fraction 0.3 --grid 24 --epsilon 0.03 --quiet --no-preview \
  --no-report --properties-nodal --out "$work/gp" || { echo "FAIL: run --properties"; fail=1; }
"$bin" sweep --surface G --volume-fractions 0.3 --grid 24 --epsilon 0.03 --quiet --no-preview \
  --no-report --no-plot --properties --out "$work/sp" ||
    { echo "FAIL: sweep --properties"; fail=1; }
"$bin" properties --from "$work/gp" --quiet --out "$work/gp.json" || fail=1
python3 - "$work/gp.json" "$work/gp/report.json" "$work/sp/sweep.csv" <<'PY' || fail=1
import csv, json, sys
cmd, run = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
row = next(csv.DictReader(open(sys.argv[3])))
e = sum(cmd["youngs_modulus"]) / 3
assert abs(run["properties_youngs_modulus"] - e) < 1e-12, (run["properties_youngs_modulus"], e)
assert run["properties"]["nodal"]["porosity"] > 0 and "properties_nodal_youngs_modulus" in run
assert run["properties_seconds"] > 0
assert abs(float(row["properties_youngs_modulus"]) - e) < 1e-9 * e, row["properties_youngs_modulus"]
PY

# Bad options: exit 2, the option named, nothing written.
props() { check_usage "$1" "$2" properties --from "$work/g" "${@:3}"; }
for bad in "--solid rod" "--phase 3" "--only flow" "--material abc" "--material 0" \
           "--material 110,0.6" "--tolerance 1" "--cell-size -1"; do
  set -- $bad
  props "bad.json" "$1" "$@"
done
props bad.json --porosity --porosity 0.5             # a network's porosity is its member's
props bad.json --solid --solid sheet                 # neither --porosity nor --thickness
props bad.json --porosity --solid sheet --porosity 1.5
props bad.json --thickness --solid sheet --thickness 0.7
"$bin" properties --from "$work/missing" --out "$work/x.json" 2>/dev/null
[ $? = 2 ] && [ ! -e "$work/x.json" ] || { echo "FAIL: a missing --from"; fail=1; }
# A field file without --out: where to write is not guessed.
"$bin" properties --from "$work/g/field.vti" 2>"$work/err"
[ $? = 2 ] && grep -q -- "--out" "$work/err" || { echo "FAIL: --from FILE without --out"; fail=1; }

[ "$fail" = 0 ] && echo "properties: all checks passed"
exit "$fail"
