#!/usr/bin/env bash
# cmcsurf scaffold's other modes (docs/scaffolds.md): a porosity ramp (--porosity A:B),
# --shape with and without --skin; and graded's --help example, whose members' measured
# fractions straddle their targets (issue 17, item 5).
set -u
bin="$1"
export OMP_NUM_THREADS=1  # the solver spins threads on shared cores
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
check() { if ! "$@"; then echo "FAIL: $*"; fail=1; fi; }
json_has() { grep -q -- "\"$2\": $3" "$1" || { echo "FAIL: $1 lacks \"$2\": $3"; fail=1; }; }
common=(--grid 16 --cell-size 2 --units mm --cache "$work/cache" --quiet)

# A graded part: porosity 0.8 -> 0.6 along z from members computed at 0.2, 0.3, 0.4.
"$bin" scaffold --surface G --porosity 0.8:0.6 --axis z --size 4x4x6 "${common[@]}" \
  --out "$work/graded_part.stl" || { echo "FAIL: scaffold graded"; fail=1; }
json_has "$work/graded_part.stl.json" closed true
python3 - "$work/graded_part.stl.json" <<'PY' || { echo "FAIL: graded profile"; fail=1; }
import json, sys
r = json.load(open(sys.argv[1]))
p = r["graded"]["profile"]
assert len(p) == 3 and len(r["graded"]["member_volume_fractions"]) == 3, r["graded"]
assert all(abs(b["porosity_nodes"] - b["porosity_target"]) < 0.03 for b in p), p
assert p[0]["porosity_nodes"] > p[1]["porosity_nodes"] > p[2]["porosity_nodes"], p
PY
# --shape: an ASCII STL block 6 x 5 x 4 mm placed at (1, 2, 3), filled as is and with a skin.
python3 - "$work/block.stl" <<'PY'
import sys
lo, hi = (1, 2, 3), (7, 7, 7)
v = [(hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2]) for c in range(8)]
t = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3), (3, 6, 7),
     (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
with open(sys.argv[1], "w") as f:
    f.write("solid block\n")
    for tri in t:
        f.write(" facet normal 0 0 0\n  outer loop\n")
        for q in tri:
            f.write("   vertex %g %g %g\n" % v[q])
        f.write("  endloop\n endfacet\n")
    f.write("endsolid block\n")
PY
for skin in 0 0.1; do
  "$bin" scaffold --surface G --porosity 0.6 --shape "$work/block.stl" --skin "$skin" \
    --grid 16 --cell-size 2 --cache "$work/cache" --quiet --out "$work/shape$skin.stl" \
    || { echo "FAIL: scaffold --shape --skin $skin"; fail=1; }
  json_has "$work/shape$skin.stl.json" closed true
  json_has "$work/shape$skin.stl.json" manifold true
done
python3 - "$work" <<'PY' || { echo "FAIL: shape values"; fail=1; }
import json, sys
for skin in ("0", "0.1"):
    r = json.load(open(f"{sys.argv[1]}/shape{skin}.stl.json"))
    assert abs(r["porosity"] - 0.6) <= 1e-3, (skin, r["porosity"])
    assert abs(r["shape"]["volume"] - 120) < 1e-6, r["shape"]
    b = r["bounding_box"]
    assert all(b["min"][c] >= (1, 2, 3)[c] - 1e-3 and b["max"][c] <= 7 + 1e-3 for c in range(3)), b
PY
# graded --help's example with members computed for 0.3 .. 0.6 (fractions within 1e-4).
for a in 30 40 50 60; do
  "$bin" run --surface G --grid 16 --volume-fraction "0.$a" --quiet --no-report --no-preview \
    --out "$work/g$a" || { echo "FAIL: run 0.$a"; fail=1; }
done
(cd "$work" && "$bin" graded --members g30,g40,g50,g60 --axis z --from-fraction 0.3 \
  --to-fraction 0.6 --tile 2x2x6 --cell-size 2.5 --solid network --out graded.stl --quiet) \
  || { echo "FAIL: graded --help example"; fail=1; }
json_has "$work/graded.stl.json" closed true
if ls "$work" | grep -q '\.tmp\.'; then echo "FAIL: temporary files left"; fail=1; fi
[ "$fail" -eq 0 ] && echo "scaffold_modes: all passed"
exit "$fail"
