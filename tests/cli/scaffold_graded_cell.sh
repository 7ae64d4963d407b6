#!/usr/bin/env bash
# cmcsurf scaffold's graded cell size, graded fill of a shape and the measures of the part as
# trimmed (docs/scaffolds.md, "Graded cell size", "Graded fill of a shape" and "Measures on the
# part"): --cell-size A:B --axis z blends one member at two cell sizes into one connected,
# percolating network at its porosity; --porosity A:B with --shape grades a network inside a
# shape; morphometry.part measures the part itself beside its cells' keys.
source "$(dirname "$0")/usage.bash" "$1"  # bin, work (removed on exit), fail
here=$(cd "$(dirname "$0")" && pwd)
export OMP_NUM_THREADS=1  # the solver spins threads on shared cores
common=(--paper --surface G --porosity 0.7 --grid 16 --units mm --cache "$work/cache" --quiet
        --tolerance 0 --no-page)

"$bin" scaffold "${common[@]}" --cell-size 1:0.5 --axis z --size 1.5x1.5x3 \
  --out "$work/cells.stl" || { echo "FAIL: scaffold --cell-size 1:0.5"; fail=1; }
"$bin" scaffold "${common[@]}" --cell-size 1 --size 2x2x1.5 --out "$work/box.stl" ||
  { echo "FAIL: scaffold box"; fail=1; }
# A block 3 x 3 x 4 mm (ASCII STL) filled with porosity 0.7 at its bottom, 0.6 at its top (the
# members at solid fraction 0.3, cached above, and 0.4).
python3 "$here/../../scripts/box_stl.py" "$work/block.stl" 0.5,0.5,0.5 3.5,3.5,4.5 ||
  { echo "FAIL: box_stl.py"; fail=1; }
"$bin" scaffold --paper --surface G --porosity 0.7:0.6 --axis z --grid 16 --units mm \
  --cache "$work/cache" --quiet --tolerance 0 --no-page --cell-size 1 --shape "$work/block.stl" \
  --out "$work/filled.stl" || { echo "FAIL: scaffold --porosity 0.7:0.6 --shape"; fail=1; }
python3 - "$work" <<'PY' || { echo "FAIL: report values"; fail=1; }
import json, sys
w = sys.argv[1]
r = json.load(open(f"{w}/cells.stl.json"))
assert r["checks"]["closed"] and r["checks"]["manifold"], r["checks"]
t = r["topology"]
assert t["solid_components"] - t["fragments"] == 1 and all(t["pore_percolates"]), t
assert abs(r["porosity"] - 0.7) <= 1e-3, r["porosity"]
g = r["graded_cell_size"]
assert (g["cell_size_from"], g["cell_size_to"], g["axis"]) == (1.0, 0.5, "z"), g
# Per 0.5 mm slab the nodes' porosity stays near the target: the blend neither closes nor
# empties the transition (0.05: a slab of 16^3 nodes of a blended field).
assert all(abs(b["porosity_nodes"] - 0.7) < 0.05 for b in g["profile"]), g["profile"]
cells = r["morphometry"]["members"]
assert [c["cell_size"] for c in cells] == [1.0, 0.5], cells
# One member's cell measured at two sizes: the same voxels, every length halved.
for key in ("wall_thickness", "pore_size"):
    assert abs(cells[1][key]["mean"] / cells[0][key]["mean"] - 0.5) < 1e-9, (key, cells)
part = r["morphometry"]["part"]
v = part["voxel"]
for key in ("wall_thickness", "pore_size"):
    p = part[key]
    assert 0 < p["min"] <= p["p5"] <= p["p50"] <= p["p95"] <= p["max"], p
    # The part's median lies between its two cells' medians (a voxel's leeway).
    lo, hi = cells[1][key]["p50"], cells[0][key]["p50"]
    assert lo - 2 * v <= p["p50"] <= hi + 2 * v, (key, p["p50"], lo, hi, v)
assert part["throat"]["diameter"][2] > 0, part["throat"]
# A box of whole cells: the part's walls are its cell's but where the box cuts them, so the
# median agrees within two voxels (the cell is measured at 64^3, the part at the lattice).
b = json.load(open(f"{w}/box.stl.json"))["morphometry"]
for key in ("wall_thickness", "pore_size"):
    assert abs(b["part"][key]["p50"] - b[key]["p50"]) <= 2 * b["part"]["voxel"], (key, b)
assert min(b["part"]["throat"]["diameter"]) > 0, b["part"]["throat"]
# The graded fill: the ramp inside the shape, per 1 mm slab (0.05: the slab's nodes of a
# blended field; the end slabs hold the shape's margin), the mean over the shape's volume.
f = json.load(open(f"{w}/filled.stl.json"))
assert f["checks"]["closed"] and f["checks"]["manifold"], f["checks"]
assert f["topology"]["closed_pores"] == 0 and abs(f["shape"]["volume"] - 36) < 1e-9, f["shape"]
assert abs(f["graded"]["porosity_mean"] - 0.65) < 1e-9, f["graded"]  # a prism: the mid value
assert abs(f["porosity"] - 0.65) <= 1e-3, f["porosity"]
prof = f["graded"]["profile"]
assert len(prof) == 4, prof
assert all(abs(b["porosity_nodes"] - b["porosity_target"]) < 0.05 for b in prof), prof
assert prof[0]["porosity_nodes"] > prof[-1]["porosity_nodes"] + 0.05, prof
PY
# Refused before any work, naming the option (exit 2).
for bad in "--cell-size 1:1" "--cell-size 1:x" "--cell-size 1:0.5 --solid sheet" \
           "--cell-size 1:0.5 --compare-nodal"; do
  # shellcheck disable=SC2086
  "$bin" scaffold "${common[@]}" $bad --size 2 --out "$work/bad.stl" 2>"$work/bad.txt"
  rc=$?
  if [ "$rc" != 2 ] || ! grep -q -- "--cell-size" "$work/bad.txt"; then
    echo "FAIL: $bad: exit $rc"; cat "$work/bad.txt"; fail=1
  fi
done
test ! -e "$work/bad.stl" || { echo "FAIL: a refused part was written"; fail=1; }
exit $fail
