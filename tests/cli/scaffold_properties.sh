#!/usr/bin/env bash
# scaffold --properties (docs/scaffolds.md, docs/properties.md): the unit cell of a 16^3 G
# network and sheet part, as scaffold builds it, in FILE.json's properties with --material in
# GPa and the nodal twins; the same numbers (to round-off) as `cmcsurf properties` on the cached
# member with the part's wall thickness; a ramp or --material alone refused with exit 2.
set -u
source "$(dirname "$0")/usage.bash" "$1"
export OMP_NUM_THREADS=1
common=(--surface G --grid 16 --epsilon 0.04 --fast --cell-size 2 --units mm --size 2
        --cache "$work/cache")
"$bin" scaffold "${common[@]}" --solid network --porosity 0.6 --properties --compare-nodal \
  --material 110,0.34 --out "$work/net.stl" 2>"$work/net.err" ||
  { echo "FAIL: network scaffold --properties"; cat "$work/net.err"; fail=1; }
grep -q "unit cell properties" "$work/net.err" || { echo "FAIL: no summary"; fail=1; }
"$bin" scaffold "${common[@]}" --solid sheet --porosity 0.7 --properties --quiet \
  --out "$work/sheet.stl" || { echo "FAIL: sheet scaffold --properties"; fail=1; }
python3 - "$work/net.stl.json" "$work/sheet.stl.json" "$work/args" <<'PY' || fail=1
import json, sys
net, sheet = (json.load(open(f)) for f in sys.argv[1:3])
p = net["properties"]
assert p["solid"] == "network" and p["phase"] == 1, p["solid"]
# The network cell is the member's phase 1: its porosity is the member's (1 - 0.4 to the run's
# volume tolerance and the sharp measure).
assert abs(p["porosity"] - 0.6) < 5e-3, p["porosity"]
assert abs(p["youngs_modulus_gpa"][0] - 110 * p["youngs_modulus"][0]) < 1e-9
assert p["material"]["poisson_ratio"] == 0.34 and "nodal" in p and p["properties_seconds"] > 0
for solid in (p, p["nodal"]):
    for key in ("bulk_modulus", "conductivity_solid"):
        assert 0 < solid["fraction_of_bound"][key] <= 1 + 1e-9, (key, solid["fraction_of_bound"])
s = sheet["properties"]
# The sheet cell is the wall of the part's solved thickness, in the part's units.
assert s["solid"] == "sheet" and s["thickness_units"] == "mm"
assert abs(s["thickness"] - sheet["sheet"]["thickness"]) < 1e-12, (s["thickness"], sheet["sheet"])
assert abs(s["porosity"] - 0.7) < 0.02, s["porosity"]
assert "nodal" not in s and "youngs_modulus_gpa" not in s
open(sys.argv[3], "w").write(f'{sheet["member"]["cache"]} {s["thickness"]!r}\n')
PY
[ -s "$work/args" ] || { echo "FAIL: no parts to compare"; exit 1; }
read -r cache thickness <"$work/args"
"$bin" properties --from "$cache/field.vti" --solid sheet --thickness "$thickness" \
  --cell-size 2 --units mm --quiet --out "$work/cmd.json" || { echo "FAIL: properties"; fail=1; }
python3 - "$work/sheet.stl.json" "$work/cmd.json" <<'PY' || fail=1
import json, sys
a, b = json.load(open(sys.argv[1]))["properties"], json.load(open(sys.argv[2]))
for key in ("relative_density", "bulk_modulus", "zener_ratio"):
    assert abs(a[key] - b[key]) <= 1e-12 * abs(b[key]), (key, a[key], b[key])
for i in range(6):
    for j in range(6):
        assert abs(a["stiffness_voigt"][i][j] - b["stiffness_voigt"][i][j]) <= 1e-12, (i, j)
PY

# Refused before any work: exit 2, the option named, nothing written.
check_usage bad.stl --material scaffold "${common[@]}" --porosity 0.7 --material 110
check_usage bad.stl --properties scaffold "${common[@]}" --porosity 0.6:0.8 --properties
check_usage bad.stl --material scaffold "${common[@]}" --porosity 0.7 --properties --material x
check_usage bad.stl --material scaffold "${common[@]}" --porosity 0.7 --properties \
  --material 110,0.7

[ "$fail" = 0 ] && echo "scaffold_properties: all checks passed"
exit "$fail"
