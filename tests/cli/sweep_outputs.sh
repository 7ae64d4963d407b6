#!/usr/bin/env bash
# A small sweep writes sweep.csv (a row per member, the report's scalars as columns), one
# folder per member and the Fig. 11 figures (when /usr/bin/python3 has matplotlib).
# P and G: at 16^3 and epsilon 0.04 the D members flattened into two planes (area 2, H 0) after
# seven volume corrections each, two thirds of this test's time under the sanitizers.
set -eu
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" sweep --paper --surface P,G --volume-fractions 0.4:0.6:0.2 --grid 16 --epsilon 0.04 \
  --max-steps 100 --quiet --out "$work/s" 2>"$work/stderr" || { cat "$work/stderr"; exit 1; }
for m in P_0.40 P_0.60 G_0.40 G_0.60; do
  for f in report.json field.vti history.csv curvature_histogram.csv; do
    [ -s "$work/s/$m/$f" ] || { echo "FAIL: missing $m/$f"; exit 1; }
  done
done
[ -s "$work/s/sweep.csv" ] && [ -s "$work/s/sweep.json" ] ||
  { echo "FAIL: sweep.csv/json"; exit 1; }
if find "$work/s" -name '*tmp*' | grep -q .; then echo "FAIL: temporary left behind"; exit 1; fi
python3 - "$work/s" <<'PY'
import csv, json, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(f"{d}/sweep.csv")))
assert len(rows) == 4, len(rows)
assert [(r["surface"], float(r["volume_fraction_target"])) for r in rows] == \
    [("P", 0.4), ("P", 0.6), ("G", 0.4), ("G", 0.6)], rows
need = ["surface", "volume_fraction_target", "volume_fraction", "area", "mean_curvature",
        "mean_curvature_mu", "mean_curvature_std", "nodal_area", "nodal_mean_curvature",
        "nodal_mean_curvature_std", "nodal_area_excess", "area_iso", "nodal_area_iso",
        "area_error", "mean_curvature_error", "area_diffuse", "mean_curvature_diffuse",
        "total_mean_curvature_diffuse", "nodal_std_ratio", "quality_seconds", "measure_seconds",
        "steps", "converged", "wall_seconds", "member", "started_from"]
missing = [k for k in need if k not in rows[0]]
assert not missing, f"missing columns {missing}"
for r in rows:
    rep = json.load(open(f"{d}/{r['member']}/report.json"))
    scalars = [k for k, v in rep.items() if not isinstance(v, (dict, list))]
    assert set(scalars) <= set(rows[0]), set(scalars) - set(rows[0])
    assert float(r["area"]) == rep["area"] and r["started_from"] == "nodal"
    hist = list(csv.DictReader(open(f"{d}/{r['member']}/curvature_histogram.csv")))
    assert abs(sum(float(h["relaxed"]) for h in hist) - 1) < 1e-9
    assert abs(sum(float(h["nodal"]) for h in hist) - 1) < 1e-9
print("sweep csv: ok")
PY
if /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  for f in families.png families.svg; do
    [ -s "$work/s/$f" ] || { echo "FAIL: missing $f"; cat "$work/stderr"; exit 1; }
  done
  head -c 8 "$work/s/families.png" | grep -q PNG || { echo "FAIL: not a PNG"; exit 1; }
else
  echo "SKIP image check: /usr/bin/python3 has no matplotlib"
  grep -q "matplotlib" "$work/stderr" || { echo "FAIL: no warning about matplotlib"; exit 1; }
  # The rest passed, but the pictures were not checked: a skip (exit 77), not a pass.
  echo "sweep_outputs: the rest passed; reported as skipped"
  exit 77
fi
echo "sweep_outputs: all passed"
