#!/usr/bin/env bash
# --structure double with --constrain components: the double gyroid at 0.35 relaxes to two
# networks that keep their volumes and share H, listed as two report.json `interfaces`, with
# no warning; with one shared volume constraint the same seed is warned about on stderr and in
# report.json `warnings`. The single gyroid lists one interface.
set -u
bin="$1"
export OMP_NUM_THREADS=1
command -v python3 >/dev/null || { echo "SKIP: python3 not found"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
quiet=(--threads 1 --no-preview --no-report --grid 32 --epsilon 0.02 --tol 1e-5
       --volume-fraction 0.35)
"$bin" run --surface G --structure double --constrain components --out "$work/double" \
  "${quiet[@]}" >/dev/null 2>"$work/double.err" ||
  { echo "FAIL: double"; cat "$work/double.err"; exit 1; }
grep -q "^warning" "$work/double.err" &&
  { echo "FAIL: a warning:"; cat "$work/double.err"; fail=1; }
"$bin" run --surface G --structure double --constrain volume --max-steps 3 --out "$work/shared" \
  "${quiet[@]}" >/dev/null 2>"$work/shared.err" || { echo "FAIL: shared"; exit 1; }
grep -q "^warning: the seed's phase 1 has 2 components that share one volume constraint" \
  "$work/shared.err" ||
  { echo "FAIL: no warning about the shared constraint:"; cat "$work/shared.err"; fail=1; }
"$bin" run --surface G --max-steps 3 --out "$work/single" "${quiet[@]}" >/dev/null 2>&1 ||
  { echo "FAIL: single"; exit 1; }
python3 - "$work" <<'PY' || fail=1
import json, sys
work = sys.argv[1]
r = json.load(open(f"{work}/double/report.json"))
assert r["parameters"]["structure"] == "double" and r["constrain"] == "components", r["parameters"]
assert r["prerelax_steps"] == 0 and r["warnings"] == [], r
assert (r["components_phase1"], r["components_phase2"]) == (2, 1), r
pieces = r["interfaces"]
assert len(pieces) == 2, pieces
for t, v in zip(r["component_volume_targets"], r["component_volumes"]):
    assert abs(t - 0.175) < 1e-6 and abs(v - t) < 1e-6, (t, v)
h = [p["mean_curvature"] for p in pieces]
assert abs(h[0] / h[1] - 1) < 0.01, h
assert all(p["euler_characteristic"] == -8 for p in pieces), pieces
assert abs(sum(p["area"] for p in pieces) - r["area"]) < 1e-9 * r["area"], (pieces, r["area"])
assert "interfaces" in r["conventions"] and "warnings" in r["conventions"]
s = json.load(open(f"{work}/shared/report.json"))
assert any("--constrain components holds each" in w for w in s["warnings"]), s["warnings"]
g = json.load(open(f"{work}/single/report.json"))
assert len(g["interfaces"]) == 1 and g["warnings"] == [], (g["interfaces"], g["warnings"])
assert g["parameters"]["structure"] == "single"
PY
exit $fail
