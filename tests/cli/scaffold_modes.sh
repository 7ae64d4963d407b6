#!/usr/bin/env bash
# cmcsurf scaffold's other modes (docs/scaffolds.md): a porosity ramp (--porosity A:B),
# --shape with and without --skin, a curved --shape (a sphere) with --compare-nodal; and
# graded's --help example, whose members' measured fractions straddle their targets
# (accepted within the volume tolerance).
source "$(dirname "$0")/usage.bash" "$1"  # bin, work (removed on exit), fail
here=$(cd "$(dirname "$0")" && pwd)
export OMP_NUM_THREADS=1  # the solver spins threads on shared cores
check() { if ! "$@"; then echo "FAIL: $*"; fail=1; fi; }
json_has() { grep -q -- "\"$2\": $3" "$1" || { echo "FAIL: $1 lacks \"$2\": $3"; fail=1; }; }
common=(--grid 16 --cell-size 2 --units mm --cache "$work/cache" --quiet)

# A graded part: porosity 0.8 -> 0.6 along z from members computed at 0.2, 0.3, 0.4.
"$bin" scaffold --paper --surface G --porosity 0.8:0.6 --axis z --size 4x4x6 "${common[@]}" \
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
python3 "$here/../../scripts/box_stl.py" "$work/block.stl" 1,2,3 7,7,7 ||
  { echo "FAIL: box_stl.py"; fail=1; }
for skin in 0 0.1; do
  "$bin" scaffold --paper --surface G --porosity 0.6 --shape "$work/block.stl" --skin "$skin" \
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
# A curved shape: a sphere of radius 3 mm around (4, 4, 4), an icosphere of 5120 triangles
# (binary STL), filled with a G network at porosity 0.6 beside its nodal twin (--compare-nodal
# builds the twin inside the same sphere: about as many triangles, not the bounding box's 1.9x).
/usr/bin/python3 - "$work/ball.stl" <<'PY'
import math, struct, sys
t = (1 + 5 ** 0.5) / 2
v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
     (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
     (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
     (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
for _ in range(4):  # 20 * 4^4 = 5120 triangles
    mid, g = {}, []
    def m(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            p = [(x + y) / 2 for x, y in zip(v[a], v[b])]
            r = math.sqrt(sum(x * x for x in p))
            v.append(tuple(x / r for x in p))
            mid[key] = len(v) - 1
        return mid[key]
    for a, b, c in f:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    f = g
with open(sys.argv[1], "wb") as out:
    out.write(b"icosphere".ljust(80, b" ") + struct.pack("<I", len(f)))
    for tri in f:
        out.write(struct.pack("<3f", 0, 0, 0))
        for q in tri:
            out.write(struct.pack("<3f", *(4 + 3 * x for x in v[q])))
        out.write(b"\0\0")
PY
"$bin" scaffold --paper --surface G --porosity 0.6 --shape "$work/ball.stl" --compare-nodal \
  --grid 16 \
  --cell-size 2 --cache "$work/cache" --quiet --out "$work/ball_part.stl" \
  || { echo "FAIL: scaffold --shape ball.stl"; fail=1; }
/usr/bin/python3 - "$work" <<'PY' || { echo "FAIL: curved shape values"; fail=1; }
import json, struct, sys
import numpy as np
w = sys.argv[1]
def stl(path):
    data = open(path, "rb").read()
    n = struct.unpack_from("<I", data, 80)[0]
    rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                        count=n, offset=84)
    return rec["v"].astype(np.float64)
ball = stl(f"{w}/ball.stl")
assert len(ball) == 5120
# The polyhedron's volume (divergence theorem), a little under 4/3 pi 27 = 113.1.
c = ball - 4.0
volume = np.einsum("ij,ij->i", c[:, 0], np.cross(c[:, 1], c[:, 2])).sum() / 6
r = json.load(open(f"{w}/ball_part.stl.json"))
assert abs(r["shape"]["volume"] / volume - 1) < 1e-6, (r["shape"]["volume"], volume)
assert abs(r["porosity"] - 0.6) <= 1e-3, r["porosity"]
assert abs(r["volume"] / volume - 0.4) <= 1e-3, (r["volume"], volume)
t = r["topology"]
assert t["solid_components"] - t["fragments"] == 1 and t["closed_pores"] == 0, t
assert r["checks"]["closed"] and r["checks"]["manifold"], r["checks"]
part = stl(f"{w}/ball_part.stl")
radius = np.sqrt(((part - 4.0) ** 2).sum(axis=2)).max()
assert radius <= 3.0 + 1e-3, radius  # inside the sphere
cmp = r["compare_nodal"]
assert cmp["shape"] and abs(cmp["nodal"]["porosity"] - 0.6) <= 1e-3, cmp
ratio = cmp["nodal"]["triangles"] / cmp["cmc"]["triangles"]
assert 0.8 < ratio < 1.25, ratio
print(f"scaffold_modes: sphere of volume {volume:.3f}: porosity {r['porosity']:.5f}, one piece, "
      f"radius {radius:.4f}; nodal twin {ratio:.2f}x the triangles")
PY
# graded --help's example with members computed for 0.3 .. 0.6 (fractions within 1e-4).
for a in 30 40 50 60; do
  "$bin" run --paper --surface G --grid 16 --volume-fraction "0.$a" --quiet --no-report \
    --no-preview \
    --out "$work/g$a" || { echo "FAIL: run 0.$a"; fail=1; }
done
(cd "$work" && "$bin" graded --members g30,g40,g50,g60 --axis z --from-fraction 0.3 \
  --to-fraction 0.6 --tile 2x2x6 --cell-size 2.5 --solid network --out graded.stl --quiet) \
  || { echo "FAIL: graded --help example"; fail=1; }
json_has "$work/graded.stl.json" closed true
if ls "$work" | grep -q 'cmcsurf-tmp'; then echo "FAIL: temporary files left"; fail=1; fi
[ "$fail" -eq 0 ] && echo "scaffold_modes: all passed"
exit "$fail"
