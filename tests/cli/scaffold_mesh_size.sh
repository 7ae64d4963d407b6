#!/usr/bin/env bash
# cmcsurf scaffold's mesh size in a printer's terms and its small defects (docs/scaffolds.md,
# "Mesh size"): the default chordal tolerance decimates within it (0.01 mm measured both ways)
# and keeps the part closed, manifold and one shell, --tolerance 0 leaves it undecimated,
# --resolution picks the grid (and is refused with --grid), the page and preview are written
# and `cmcsurf report FILE.json` remakes them; the --min-feature warning prints once, the
# printed lines use porosity / solid fraction / wall / pore (no alpha, volume fraction or
# phase 1); a graded part of two members has each member's morphometry in FILE.json and its
# warnings once per phase, and scripts/plot_scaffold.py draws it (skipped, exit 77, without
# matplotlib).
set -u
bin="$1"
here=$(cd "$(dirname "$0")" && pwd)
export OMP_NUM_THREADS=1  # the solver spins threads on shared cores
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
common=(--surface G --cell-size 2 --units mm --cache "$work/cache" --fast)

# The default tolerance (0.01 mm), with --resolution 0.125 mm in place of --grid 16.
"$bin" scaffold "${common[@]}" --porosity 0.7 --solid sheet --size 3x3x2 --resolution 0.125 \
  --min-feature 0.5 --out "$work/a.stl" 2> "$work/a.err" || { echo "FAIL: scaffold a"; fail=1; }
cat "$work/a.err"
# The undecimated part, for the distance below.
"$bin" scaffold "${common[@]}" --porosity 0.7 --solid sheet --size 3x3x2 --grid 16 \
  --tolerance 0 --no-page --quiet --out "$work/full.stl" || { echo "FAIL: scaffold full"; fail=1; }
grep -q 'is below --min-feature' "$work/a.err" || { echo "FAIL: no --min-feature warning"; fail=1; }
if [ -n "$(grep 'is below --min-feature' "$work/a.err" | sort | uniq -d)" ]; then
  echo "FAIL: a --min-feature warning is printed twice"; fail=1
fi
if grep -Eiq 'alpha|volume fraction|phase 1' "$work/a.err"; then
  echo "FAIL: printed lines say alpha, volume fraction or phase 1"; fail=1
fi
for f in a.stl.html a.stl.png; do
  [ -s "$work/$f" ] || { echo "FAIL: missing $f"; fail=1; }
done
[ -e "$work/full.stl.html" ] && { echo "FAIL: --no-page wrote a page"; fail=1; }
python3 - "$work" <<'PY' || { echo "FAIL: mesh size checks"; fail=1; }
import json, struct, sys
w = sys.argv[1]
a = json.load(open(f"{w}/a.stl.json"))
full = json.load(open(f"{w}/full.stl.json"))
ms = a["mesh_size"]
assert ms["tolerance_default"] and ms["tolerance"] == 0.01 and ms["grid"] == 16, ms
assert ms["resolution"] == 0.125 and ms["lattice_spacing"] == 0.125, ms
d = a["decimation"]
assert d["applied"] and d["error"] <= 0.01, d
assert a["checks"]["closed"] and a["checks"]["manifold"], a["checks"]
assert a["triangles"] < full["triangles"], (a["triangles"], full["triangles"])
assert d["triangles_before"] == full["triangles"], (d, full["triangles"])
assert abs(a["porosity"] - 0.7) < 2e-3, a["porosity"]
assert "decimation" not in full and full["mesh_size"]["tolerance"] == 0, full["mesh_size"]
assert a["seconds"]["page_view"] >= 0 and a["seconds"]["page_slices"] >= 0, a["seconds"]
print(f"scaffold_mesh_size: {full['triangles']} -> {a['triangles']} triangles, "
      f"error {d['error']:.4f} mm, porosity {a['porosity']:.4f}")
PY
# One shell in the file: STL vertices joined by their coordinates.
python3 - "$work/a.stl" <<'PY' || { echo "FAIL: one shell"; fail=1; }
import struct, sys
data = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<I", data, 80)[0]
ids, parent = {}, []
def find(x):
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x
for t in range(n):
    vs = []
    for c in range(3):
        p = struct.unpack_from("<3f", data, 84 + 50 * t + 12 + 12 * c)
        if p not in ids:
            ids[p] = len(parent)
            parent.append(len(parent))
        vs.append(ids[p])
    for v in vs[1:]:
        a, b = find(vs[0]), find(v)
        if a != b:
            parent[max(a, b)] = min(a, b)
roots = {find(x) for x in range(len(parent))}
assert len(roots) == 1, len(roots)
PY
# The page again from FILE.json alone.
rm "$work/a.stl.html" "$work/a.stl.png"
"$bin" report "$work/a.stl.json" --quiet || { echo "FAIL: report FILE.json"; fail=1; }
[ -s "$work/a.stl.html" ] && [ -s "$work/a.stl.png" ] || { echo "FAIL: report's page"; fail=1; }
# Usage errors.
"$bin" scaffold "${common[@]}" --porosity 0.7 --size 3 --resolution 0.1 --grid 16 \
  --out "$work/b.stl" 2> "$work/b.err"
[ $? -eq 2 ] && grep -q -- "--resolution: not with --grid" "$work/b.err" || {
  echo "FAIL: --resolution with --grid"; cat "$work/b.err"; fail=1; }
"$bin" scaffold "${common[@]}" --porosity 0.7 --size 3 --resolution 3 --out "$work/b.stl" \
  2> "$work/b.err"
[ $? -eq 2 ] && grep -q -- "--resolution: got 3" "$work/b.err" || {
  echo "FAIL: --resolution above the cell size"; cat "$work/b.err"; fail=1; }
# A graded part's picture (KeyError: 'wall_thickness' before).
# Its --min-feature warnings: one per phase for the part, not one per member. Two members (the
# default would be three): each member's morphometry is a 64^3 local thickness, most of this
# test's time under the sanitizers.
"$bin" scaffold "${common[@]}" --porosity 0.8:0.6 --axis z --size 2x2x4 --grid 16 --no-page \
  --graded-members 2 --min-feature 3 --out "$work/graded.stl" 2> "$work/g.err" || {
  echo "FAIL: scaffold graded"; fail=1; }
walls=$(grep -c 'thinnest wall' "$work/g.err")
pores=$(grep -c 'narrowest pore' "$work/g.err")
[ "$walls" -eq 1 ] && [ "$pores" -eq 1 ] || {
  echo "FAIL: a graded part's --min-feature warnings"; grep warning "$work/g.err"; fail=1; }
# The members' morphometry (Part.GradedPorosityFollowsTheRamp builds its part without it).
python3 - "$work/graded.stl.json" <<'PY' || { echo "FAIL: a graded part's members"; fail=1; }
import json, sys
g = json.load(open(sys.argv[1]))
members = g["morphometry"]["members"]
porosities = [round(m["porosity"], 3) for m in members]
assert porosities == [0.8, 0.6], porosities
for m in members:
    assert 0 < m["wall_thickness"]["min"] <= m["wall_thickness"]["mean"], m["wall_thickness"]
    assert 0 < m["pore_size"]["min"] <= m["pore_size"]["mean"], m["pore_size"]
PY
skip=0
/usr/bin/python3 "$here/../../scripts/plot_scaffold.py" "$work/graded.stl" "$work/graded.png"
rc=$?
if [ $rc -eq 3 ]; then
  echo "SKIP: plot_scaffold.py needs matplotlib and numpy"; skip=1
elif [ $rc -ne 0 ] || [ ! -s "$work/graded.png" ]; then
  echo "FAIL: plot_scaffold.py on a graded part (exit $rc)"; fail=1
fi
[ "$fail" -eq 0 ] || exit 1
[ "$skip" -eq 0 ] || exit 77
echo "scaffold_mesh_size: all passed"
