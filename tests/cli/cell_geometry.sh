#!/usr/bin/env bash
# The cell geometry of a run (channel_radius, parallel_surfaces, lipid in report.json; the
# distance array of --distance-field) and `mesh --periodic`: a 32^3 G run at 0.5, whose welded
# periodic mesh is closed with V - E + F = the report's euler_characteristic_surface (-8) and
# mean vertex H near the report's H; the bad options exit 2.
set -u
bin="$1"
export OMP_NUM_THREADS=1
command -v python3 >/dev/null || { echo "SKIP: python3 not found"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
"$bin" run --surface G --grid 32 --epsilon 0.02 --tol 1e-5 --threads 1 --quiet --no-preview \
  --no-report --parallel-distances 0.02,0.05 --lipid-length 2 --lipid-fraction 0.5 \
  --distance-field --out "$work/g" || { echo "FAIL: run"; exit 1; }
"$bin" mesh --from "$work/g" --periodic --out "$work/g.json" --quiet ||
  { echo "FAIL: mesh --periodic"; exit 1; }
python3 - "$work" <<'PY' || fail=1
import json, math, sys
work = sys.argv[1]
r = json.load(open(f"{work}/g/report.json"))
c = r["channel_radius"]
# G at 0.5: two congruent labyrinths (an inversion swaps them): equal radii to the voxel.
assert abs(c["phase1"]["max"] - c["phase2"]["max"]) <= 1 / 32, c
assert 0.15 < c["phase1"]["p50"] < 0.25, c
p = r["parallel_surfaces"]
assert [e["distance"] for e in p["phase1"]] == [0.02, 0.05], p
for side in ("phase1", "phase2"):
    e = p[side][0]
    assert abs(e["volume"] / e["volume_steiner"] - 1) < 0.01, (side, e)
    assert abs(e["area"] / e["area_steiner"] - 1) < 0.02, (side, e)
lipid = r["lipid"]
x = lipid["length_ratio"]
sigma, chi = r["area"], r["euler_characteristic_surface"]
assert abs(2 * sigma * x + 4 * math.pi / 3 * chi * x**3 - 0.5) < 1e-9, lipid
assert abs(lipid["lattice_parameter_nm"] - 2 / x) < 1e-9, lipid
assert abs(lipid["lattice_parameter_measured_nm"] / lipid["lattice_parameter_nm"] - 1) < 0.02, lipid
assert r["geometry_seconds"] >= 0 and "channel_radius" in r["conventions"], r.keys()
m = json.load(open(f"{work}/g.json"))
s = m["stats"]
assert s["closed"] and s["manifold"], s
assert s["euler_characteristic"] == r["euler_characteristic_surface"] == -8, s
assert len(m["offsets"]) == len(m["triangles"]) == s["triangles"], s
assert len(m["mean_curvature"]) == len(m["vertices"]) == len(m["normals"]), s
mean_h = sum(m["mean_curvature"]) / len(m["mean_curvature"])
assert abs(mean_h - r["mean_curvature"]) < 0.05, (mean_h, r["mean_curvature"])
PY
grep -q 'Name="distance"' "$work/g/field.vti" || { echo "FAIL: no distance array"; fail=1; }
bad() {  # expected exit 2 and the option named
  local name="$1"; shift
  "$bin" "$@" >/dev/null 2>"$work/err"
  local rc=$?
  [ $rc = 2 ] && grep -q -- "$name" "$work/err" ||
    { echo "FAIL: $* exited $rc:"; cat "$work/err"; fail=1; }
}
bad --parallel-distances run --grid 16 --parallel-distances 0.3 --out "$work/x"
bad --parallel-distances run --grid 16 --parallel-distances 0.1,x --out "$work/x"
bad --lipid-fraction run --grid 16 --lipid-length 3 --out "$work/x"
bad --lipid-length run --grid 16 --lipid-fraction 0.4 --out "$work/x"
bad --out mesh --from "$work/g" --periodic --out "$work/g.stl"
bad --tile mesh --from "$work/g" --periodic --tile 2 --out "$work/h.json"
exit $fail
