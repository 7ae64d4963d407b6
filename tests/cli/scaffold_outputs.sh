#!/usr/bin/env bash
# cmcsurf scaffold (docs/scaffolds.md): network and sheet parts in one command, the member
# cache, the report's checks, --compare-nodal, decimation, a deflated 3MF, the closed-cell
# refusal. Graded parts, --shape and graded's --help example: scaffold_modes.sh.
set -u
bin="$1"
export OMP_NUM_THREADS=1  # the solver spins threads on shared cores
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
check() { if ! "$@"; then echo "FAIL: $*"; fail=1; fi; }
json_has() { grep -q -- "\"$2\": $3" "$1" || { echo "FAIL: $1 lacks \"$2\": $3"; fail=1; }; }
common=(--grid 16 --cell-size 2 --units mm --cache "$work/cache" --quiet)

"$bin" scaffold --paper --surface G --porosity 0.7 --solid network --size 5x4x3 "${common[@]}" \
  --compare-nodal --out "$work/net.3mf" || { echo "FAIL: scaffold network"; fail=1; }
check test -s "$work/net.3mf"
json_has "$work/net.3mf.json" closed true
json_has "$work/net.3mf.json" manifold true
json_has "$work/net.3mf.json" x true
json_has "$work/net.3mf.json" closed_pores 0
check test "$(ls "$work/cache")" != ""
# The same member again: reused, not recomputed.
"$bin" scaffold --paper --surface G --porosity 0.7 --solid network --size 4 --grid 16 \
  --cell-size 2 \
  --cache "$work/cache" --out "$work/again.stl" 2>"$work/again.txt" || fail=1
check grep -q "reusing the member" "$work/again.txt"
json_has "$work/again.stl.json" reused true
"$bin" scaffold --paper --surface P --porosity 0.6 --solid sheet --size 4x4x5 "${common[@]}" \
  --min-feature 5 --out "$work/sheet.stl" 2>"$work/sheet.txt" ||
    { echo "FAIL: scaffold sheet"; fail=1; }
json_has "$work/sheet.stl.json" closed true
check grep -q '"thickness":' "$work/sheet.stl.json"
check grep -q "below --min-feature" "$work/sheet.txt"
python3 - "$work" <<'PY' || { echo "FAIL: report values"; fail=1; }
import json, sys, zipfile
w = sys.argv[1]
for name, target in (("net.3mf", 0.7), ("sheet.stl", 0.6)):
    r = json.load(open(f"{w}/{name}.json"))
    assert abs(r["porosity"] - target) <= 1e-3, (name, r["porosity"])
    assert r["topology"]["solid_components"] - (r["topology"]["fragments"]) == 1, r["topology"]
    m = r["morphometry"]
    assert 0 < m["wall_thickness"]["min"] <= m["wall_thickness"]["mean"], m["wall_thickness"]
    assert 0 < m["pore_size"]["min"] <= m["pore_size"]["mean"], m["pore_size"]
c = json.load(open(f"{w}/net.3mf.json"))["compare_nodal"]
# Both sides measured (at 16^3 the interface is under-resolved, so no ordering is asserted).
assert abs(c["nodal"]["porosity"] - 0.7) <= 1e-3, c
assert all(c[s]["mean_curvature_std"] > 0 and c[s]["wall_thickness"]["mean"] > 0
           for s in ("cmc", "nodal")), c
z = zipfile.ZipFile(f"{w}/net.3mf")
assert z.testzip() is None
info = z.getinfo("3D/3dmodel.model")
assert info.compress_type == zipfile.ZIP_DEFLATED and info.compress_size < info.file_size / 3, info
model = z.read("3D/3dmodel.model").decode()
assert all(s in model for s in ('unit="millimeter"', "<build", "<item ", 'name="Description"')), \
    model[:600]
PY
# Decimation to a budget: applied, within it, still a closed manifold.
"$bin" scaffold --paper --surface G --porosity 0.7 --size 4x4x3 "${common[@]}" \
  --max-triangles 20000 \
  --out "$work/small.stl" || { echo "FAIL: scaffold --max-triangles"; fail=1; }
json_has "$work/small.stl.json" applied true
json_has "$work/small.stl.json" within_budget true
json_has "$work/small.stl.json" closed true
json_has "$work/small.stl.json" manifold true
check test "$(stat -c %s "$work/small.stl")" -le $((84 + 50 * 20000))
# A budget the part already meets: nothing attempted, no warning, the report says why.
"$bin" scaffold --paper --surface G --porosity 0.7 --size 4x4x3 "${common[@]}" \
  --max-triangles 10000000 \
  --out "$work/big.stl" 2>"$work/big.txt" || { echo "FAIL: scaffold --max-triangles 1e7"; fail=1; }
json_has "$work/big.stl.json" attempts 0
json_has "$work/big.stl.json" applied false
check grep -q '"note": "the input is within the budget' "$work/big.stl.json"
check test ! -s "$work/big.txt"
# A closed-cell design (P at porosity 0.05: isolated pores) is refused, and nothing written:
# first as a member of another topology than P's, then, taken anyway, as closed.
"$bin" scaffold --paper --surface P --porosity 0.05 --max-steps 20 --size 4 "${common[@]}" \
  --out "$work/closed.stl" 2>"$work/closed.txt"
rc=$?
check test "$rc" -eq 1
check grep -q "Euler characteristic" "$work/closed.txt"
"$bin" scaffold --paper --surface P --porosity 0.05 --max-steps 20 --size 4 "${common[@]}" \
  --accept-topology-change --out "$work/closed.stl" 2>"$work/closed.txt"
rc=$?
check test "$rc" -eq 1
check grep -q "closed-cell" "$work/closed.txt"
check test ! -e "$work/closed.stl"
check test ! -e "$work/closed.stl.json"

if ls "$work" | grep -q 'cmcsurf-tmp'; then echo "FAIL: temporary files left"; fail=1; fi
[ "$fail" -eq 0 ] && echo "scaffold_outputs: all passed"
exit "$fail"
