#!/usr/bin/env bash
# A small run writes report.json (every contract key), history.csv and field.vti, no temporaries.
set -eu
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" run --paper --surface P --volume-fraction 0.4 --grid 16 --epsilon 0.04 --max-steps 400 \
  --quiet --out "$work/p"
for f in report.json history.csv field.vti; do
  [ -s "$work/p/$f" ] || { echo "FAIL: missing $f"; exit 1; }
done
if ls "$work/p" | grep -q tmp; then echo "FAIL: temporary left behind"; ls "$work/p"; exit 1; fi
python3 - "$work/p" <<'PY'
import csv, json, sys
d = sys.argv[1]
r = json.load(open(f"{d}/report.json"))
keys = ["surface", "grid", "epsilon", "dt", "volume_fraction_target", "steps", "vcycles",
        "converged", "area", "mean_curvature", "mean_curvature_mu", "total_mean_curvature",
        "volume_fraction", "mass", "energy", "wall_seconds", "version", "parameters"]
missing = [k for k in keys if k not in r]
assert not missing, f"missing report keys {missing}"
assert r["surface"] == "P" and r["grid"] == 16 and r["volume_fraction_target"] == 0.4
# --constrain volume (the default) moves the mass until the sharp volume fraction is alpha.
assert r["constrain"] == "volume" and r["volume_converged"], r.get("volume_iterates")
assert abs(r["volume_fraction"] - 0.4) <= 1e-4, r["volume_fraction"]
assert abs(r["volume_iterates"][0]["mass"] - 0.4) < 1e-9, r["volume_iterates"]
assert abs(r["mass"] - r["volume_iterates"][-1]["mass"]) < 1e-9
assert "volume_fraction_cells" in r
for k in ["surface", "volume_fraction", "grid", "epsilon", "dt_factor", "stop", "tol",
          "max_steps", "smoother", "radius"]:
    assert k in r["parameters"], f"parameter {k} missing"
rows = list(csv.DictReader(open(f"{d}/history.csv")))
for k in ["step", "time", "area", "energy", "mass", "vcycles", "residual"]:
    assert k in rows[0], f"history column {k} missing"
assert len(rows) == r["steps"] + r["prerelax_steps"], (len(rows), r["steps"])
assert sum(row["stage"] == "volume" for row in rows) == r["volume_steps"]
assert [int(row["step"]) for row in rows] == list(range(1, len(rows) + 1))
head = open(f"{d}/field.vti", "rb").read(600).decode("latin-1")
assert 'type="ImageData"' in head and 'WholeExtent="0 16 0 16 0 16"' in head, head
print("run_outputs: all passed")
PY
# A second run into the same folder replaces the first one's outputs, and leaves none of them
# behind (here the first run's surface mesh, which the second does not write).
"$bin" run --paper --surface P --grid 16 --max-steps 3 --mesh stl --quiet --out "$work/again"
[ -s "$work/again/surface.stl" ] || { echo "FAIL: first run wrote no surface.stl"; exit 1; }
"$bin" run --paper --surface G --grid 16 --max-steps 3 --quiet --out "$work/again"
if [ -e "$work/again/surface.stl" ] || [ -e "$work/again/surface.stl.json" ]; then
  echo "FAIL: the first run's surface mesh was left beside the second run's report"; exit 1
fi
grep -q '"surface": "G"' "$work/again/report.json" || { echo "FAIL: report not replaced"; exit 1; }
echo "run_outputs: reuse of --out passed"
