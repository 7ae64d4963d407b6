#!/usr/bin/env bash
# The --properties stage's grid check and sheets (docs/properties.md): a two-member 24^3 sweep
# with --properties-grid-check draws an error bar per member on the designer's chart, each equal
# to the member's properties_*_error in report.json and sweep.csv; run --properties-solid sheet
# gives the wall asked for (thickness or porosity); bad stage options exit 2 naming the option
# and write nothing.
set -u
source "$(dirname "$0")/usage.bash" "$1"
export OMP_NUM_THREADS=1
"$bin" sweep --surface G --volume-fractions 0.3,0.4 --grid 24 --epsilon 0.03 --quiet \
  --no-preview --no-report --properties-grid-check --out "$work/s" ||
  { echo "FAIL: sweep --properties-grid-check"; exit 1; }
"$bin" run --surface G --volume-fraction 0.5 --grid 16 --epsilon 0.04 --quiet --no-report \
  --properties-solid sheet --properties-thickness 0.12 --out "$work/t" ||
  { echo "FAIL: run --properties-solid sheet --properties-thickness"; fail=1; }
"$bin" run --surface G --volume-fraction 0.5 --grid 16 --epsilon 0.04 --quiet --no-report \
  --no-preview --properties-solid sheet --properties-porosity 0.7 --properties-nodal \
  --out "$work/p" || { echo "FAIL: run --properties-solid sheet --properties-porosity"; fail=1; }
python3 - "$work/s" "$work/t" "$work/p" <<'PY' || fail=1
import csv, json, os, sys
s, t, p = sys.argv[1:4]
rows = list(csv.DictReader(open(os.path.join(s, "sweep.csv"))))
chart = json.load(open(os.path.join(s, "sweep.json")))["properties_chart"]
bars = chart["error_bars"]
assert len(rows) == 2 and len(bars) == 4, (len(rows), bars)  # 2 members x (E, k_solid)
for row in rows:
    report = json.load(open(os.path.join(s, row["member"], "report.json")))
    props = report["properties"]
    assert props["solid"] == "network" and props["grid_check"]["coarse_grid"] == 12
    for q in ("youngs_modulus", "conductivity_solid"):
        error = report[f"properties_{q}_error"]
        assert 0 < error < 0.05 * report[f"properties_{q}"], (q, error)  # N/2 = 12: a few %
        assert float(row[f"properties_{q}_error"]) == error, (row, error)
        (bar,) = [b for b in bars if b["quantity"] == q and
                  b["relative_density"] == report["properties_relative_density"]]
        assert bar["error"] == error and bar["value"] == report[f"properties_{q}"], (bar, error)
        assert bar["surface"] == "G" and bar["part"] == "cmc" and bar["solid"] == "network"
# A sheet of the thickness asked for (in unit cells), its picture, its title; and at a porosity.
tr = json.load(open(os.path.join(t, "report.json")))
assert tr["properties"]["solid"] == "sheet" and abs(tr["properties"]["thickness"] - 0.12) < 1e-12
assert 0.25 < tr["properties_relative_density"] < 0.45, tr["properties_relative_density"]
assert os.path.getsize(os.path.join(t, "youngs_modulus.png")) > 10000
pr = json.load(open(os.path.join(p, "report.json")))["properties"]
assert pr["solid"] == "sheet" and abs(pr["porosity"] - 0.7) < 1e-6, pr["porosity"]
for twin in ("nodal", "nodal_offset"):
    assert abs(pr[twin]["porosity"] - 0.7) < 1e-6, (twin, pr[twin]["porosity"])
assert not os.path.exists(os.path.join(p, "youngs_modulus.png"))  # --no-preview
PY

# Bad stage options: exit 2, the option named, nothing written.
run_bad() { check_usage "$1" "$2" run --surface G --volume-fraction 0.5 --grid 16 "${@:3}"; }
run_bad bad --properties-solid --properties-solid rod
run_bad bad --properties-porosity --properties-porosity 0.7       # a network's is its member's
run_bad bad --properties-solid --properties-solid sheet           # neither porosity nor thickness
run_bad bad --properties-porosity --properties-solid sheet --properties-porosity 1.5
run_bad bad --properties-thickness --properties-solid sheet --properties-thickness 0.6
check_usage bad --properties-grid-check run --surface G --volume-fraction 0.5 --grid 12 \
  --properties-grid-check                                          # 12 has no half >= 8
check_usage bad --properties-solid sweep --surface G --volume-fractions 0.3,0.4 --grid 16 \
  --properties-solid sheet --properties-thickness 0.1 --properties-porosity 0.7

[ "$fail" = 0 ] && echo "properties_stage: all checks passed"
exit "$fail"
