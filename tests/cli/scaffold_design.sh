#!/usr/bin/env bash
# scaffold's design from targets (docs/scaffolds.md, "Design from targets") on G members of
# --grid 32 --fast in one 2 mm cell (slow: each network evaluated is a CMC member, 10-30 s of
# CPU each at 32^3, and 16^3 has no G network below solid fraction 0.3; the solve's logic runs
# on nodal cells in the ScaffoldDesign.* unit tests): --target-modulus solves a network's
# porosity and the modulus recomputed by `cmcsurf properties` on the written part's member is
# within 5 % of the target; --pore-size 0.6 solves the cell size and the part's mean pore is
# within 5 % of 0.6 mm; a modulus no sheet of the searched porosities reaches exits 1 naming the
# range; a graded sheet follows its porosity ramp; --strict-min-wall refuses a part whose
# thinnest wall is too thin, writing nothing; the options' misuse exits 2 before any work.
set -u
source "$(dirname "$0")/usage.bash" "$1"
export OMP_NUM_THREADS=1
common=(--surface G --grid 32 --fast --units mm --cache "$work/cache")

"$bin" scaffold "${common[@]}" --solid network --target-modulus 8 --material 110,0.34 \
  --size 2 --out "$work/net.stl" 2>"$work/net.err" ||
  { echo "FAIL: --target-modulus"; cat "$work/net.err"; fail=1; }
grep -q "^design: porosity" "$work/net.err" || { echo "FAIL: no design line"; fail=1; }
python3 - "$work/net.stl.json" "$work/args" <<'PY' || fail=1
import json, sys
r = json.load(open(sys.argv[1]))
d = r["design"]
assert d["solved_by"]["porosity"] == "--target-modulus", d["solved_by"]
a = d["achieved"]["modulus_gpa"]
assert a["target"] == 8 and abs(a["relative_error"]) < 0.05, a
assert 2 <= len(d["evaluations"]) <= 8 and d["seconds"] > 0, d
# The part is the solved porosity (within the network's 1e-3 trimming tolerance).
assert abs(r["porosity"] - d["solved"]["porosity"]) < 2e-3, (r["porosity"], d["solved"])
open(sys.argv[2], "w").write(r["member"]["cache"] + "\n")
PY
if [ -s "$work/args" ]; then
  # Recomputed independently: `properties` on the part's member (its phase 1 is the cell).
  "$bin" properties --from "$(cat "$work/args")/field.vti" --only elastic --material 110,0.34 \
    --quiet --out "$work/props.json" || { echo "FAIL: properties"; fail=1; }
  python3 - "$work/props.json" <<'PY' || fail=1
import json, sys
e = json.load(open(sys.argv[1]))["youngs_modulus_gpa"]
mean = sum(e) / 3
assert abs(mean / 8 - 1) < 0.05, mean
PY
fi

# --pore-size at a given porosity: the cell size solved from one measurement.
"$bin" scaffold "${common[@]}" --solid network --porosity 0.7 --pore-size 0.6 --size 1.5 \
  --min-wall 0.01 --quiet --out "$work/pore.stl" || { echo "FAIL: --pore-size"; fail=1; }
python3 - "$work/pore.stl.json" <<'PY' || fail=1
import json, sys
r = json.load(open(sys.argv[1]))
pore = r["morphometry"]["pore_size"]["mean"]
assert abs(pore / 0.6 - 1) < 0.05, pore
d = r["design"]
assert d["solved_by"]["cell_size"] == "--pore-size" and d["cell_size"] == d["solved"]["cell_size"]
assert d["achieved"]["min_wall"]["met"] is True, d["achieved"]
w = r["morphometry"]["wall_thickness"]
assert w["min"] <= w["p5"] <= w["p50"] <= w["p95"] <= w["max"], w
t = r["morphometry"]["throat"]
assert 0 < t["min"] <= r["morphometry"]["pore_size"]["max"], t
PY

# Below every sheet of porosity 0.5 .. 0.9 (one member, the solve's ends evaluated on it):
# exit 1, the range named, nothing written.
"$bin" scaffold "${common[@]}" --solid sheet --target-modulus 0.01 --material 110 --size 2 \
  --out "$work/soft.stl" 2>"$work/soft.err"
rc=$?
[ "$rc" = 1 ] ||
  { echo "FAIL: unreachable modulus exited $rc, want 1"; cat "$work/soft.err"; fail=1; }
grep -q "reachable .* GPa (porosity 0.5 .. 0.9" "$work/soft.err" ||
  { echo "FAIL: no reachable range"; cat "$work/soft.err"; fail=1; }
compgen -G "$work/soft.stl*" >/dev/null && { echo "FAIL: wrote soft.stl"; fail=1; }

# A graded sheet (its one member cached above): the wall grades the porosity 0.8 -> 0.6 along z,
# each cell's node porosity within 0.01 of the ramp, the mean within the sheet's 1e-4 before the
# default decimation (0.01 mm) and within 5e-4 after it (measured 1.4e-4).
"$bin" scaffold "${common[@]}" --solid sheet --porosity 0.8:0.6 --axis z --size 2x2x6 --quiet \
  --out "$work/graded.stl" || { echo "FAIL: graded sheet"; fail=1; }
python3 - "$work/graded.stl.json" <<'PY' || fail=1
import json, sys
r = json.load(open(sys.argv[1]))
assert abs(r["porosity_unsimplified"] - 0.7) < 1e-4, r["porosity_unsimplified"]
assert abs(r["porosity"] - 0.7) < 5e-4, r["porosity"]
prof = r["graded"]["profile"]
assert len(prof) == 3, prof
for b in prof:
    assert abs(b["porosity_nodes"] - b["porosity_target"]) < 0.01, b
assert prof[0]["porosity_nodes"] > prof[1]["porosity_nodes"] > prof[2]["porosity_nodes"], prof
s = r["sheet"]
assert s["thickness_from"] < s["thickness"] < s["thickness_to"], s
PY

# --strict-min-wall: the thinnest wall below 1 mm refuses the part (exit 1), writing nothing.
"$bin" scaffold "${common[@]}" --porosity 0.7 --cell-size 2 --size 2 --min-wall 1 \
  --strict-min-wall --out "$work/thin.stl" 2>"$work/thin.err"
rc=$?
[ "$rc" = 1 ] || { echo "FAIL: --strict-min-wall exited $rc, want 1"; fail=1; }
grep -q -- "--min-wall" "$work/thin.err" || { echo "FAIL: no --min-wall message"; fail=1; }
compgen -G "$work/thin.stl*" >/dev/null && { echo "FAIL: wrote thin.stl"; fail=1; }

# Refused before any work: exit 2, the option named, nothing written.
base=(scaffold --surface G --grid 32 --fast --cache "$work/cache" --size 2)
check_usage bad.stl --material "${base[@]}" --target-modulus 3
check_usage bad.stl --target-modulus "${base[@]}" --target-modulus 3 --porosity 0.7 \
  --material 110
check_usage bad.stl --target-modulus "${base[@]}" --target-modulus 100 --material 110
check_usage bad.stl --target-modulus "${base[@]}" --target-modulus x --material 110
check_usage bad.stl --porosity "${base[@]}"
check_usage bad.stl --cell-size "${base[@]}" --porosity 0.7 --pore-size 0.6 --cell-size 2
check_usage bad.stl --pore-size "${base[@]}" --porosity 0.7 --pore-size 0.6 \
  --target-permeability 1e-9
check_usage bad.stl --strict-min-wall "${base[@]}" --porosity 0.7 --strict-min-wall
check_usage bad.stl --target-modulus "${base[@]}" --target-modulus 3:8 --material 110 \
  --properties
check_usage bad.stl --target-permeability "${base[@]}" --target-permeability 1e-9:2e-9 \
  --porosity 0.7

[ "$fail" = 0 ] && echo "scaffold_design: all checks passed"
exit "$fail"
