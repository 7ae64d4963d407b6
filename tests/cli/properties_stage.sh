#!/usr/bin/env bash
# The --properties stage's grid check and sheets (docs/properties.md): a two-member 24^3 sweep
# with --properties-grid-check draws an error bar per member on the designer's chart, each equal
# to the member's properties_*_error in report.json and sweep.csv; run --properties-solid sheet
# gives the wall asked for (thickness or porosity); a ramp of porosities is the chart's sheet
# curve, kept by a resume; bad stage options exit 2 naming the option and write nothing.
set -u
source "$(dirname "$0")/usage.bash" "$1"
export OMP_NUM_THREADS=1
"$bin" sweep --paper --surface G --volume-fractions 0.3,0.4 --grid 24 --epsilon 0.03 --quiet \
  --no-preview --no-report --properties-grid-check --out "$work/s" ||
  { echo "FAIL: sweep --properties-grid-check"; exit 1; }
"$bin" run --paper --surface G --volume-fraction 0.5 --grid 16 --epsilon 0.04 --quiet --no-report \
  --properties-solid sheet --properties-thickness 0.12 --out "$work/t" ||
  { echo "FAIL: run --properties-solid sheet --properties-thickness"; fail=1; }
"$bin" run --paper --surface G --volume-fraction 0.5 --grid 16 --epsilon 0.04 --quiet --no-report \
  --no-preview --properties-solid sheet --properties-porosity 0.7 --properties-nodal \
  --out "$work/p" || { echo "FAIL: run --properties-solid sheet --properties-porosity"; fail=1; }
# A ramp of sheet porosities around one balanced member: the chart's sheet curve.
"$bin" sweep --paper --surface G --volume-fractions 0.5 --grid 16 --epsilon 0.04 --quiet \
  --no-preview \
  --no-report --properties-solid sheet --properties-porosity 0.6,0.75,0.9 --out "$work/r" ||
  { echo "FAIL: sweep --properties-porosity 0.6,0.75,0.9"; fail=1; }
# A resume of the finished sweep restores the stage from sweep.json: the chart is redrawn.
"$bin" sweep --resume "$work/r" --quiet || { echo "FAIL: sweep --resume of the ramp"; fail=1; }
python3 - "$work/s" "$work/t" "$work/p" "$work/r" <<'PY' || fail=1
import csv, json, math, os, sys
s, t, p, ramp_dir = sys.argv[1:5]
rows = list(csv.DictReader(open(os.path.join(s, "sweep.csv"))))
chart = json.load(open(os.path.join(s, "sweep.json")))["properties_chart"]
bars = chart["error_bars"]
assert len(rows) == 2 and len(bars) == 6, (len(rows), bars)  # 2 members x (E, k_solid, k)
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
    # The permeability panel's bar: at the porosity 1 - rho.
    error = report["properties_permeability_error"]
    assert 0 < error < 0.05 * report["properties_permeability"], error
    (bar,) = [b for b in bars if b["quantity"] == "permeability" and
              b["porosity"] == 1 - report["properties_relative_density"]]
    assert bar["error"] == error and bar["value"] == report["properties_permeability"], bar
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
# The ramp: one report, three sheets; the chart's fit is the least-squares line through them.
(member,) = [m for m in os.listdir(ramp_dir) if m.startswith("G_")]
rr = json.load(open(os.path.join(ramp_dir, member, "report.json")))
ramp = rr["properties_ramp"]
assert [round(e["properties_porosity"], 6) for e in ramp] == [0.6, 0.75, 0.9], ramp
assert rr["properties"]["solid"] == "sheet" and abs(rr["properties"]["porosity"] - 0.6) < 1e-6
fits = json.load(open(os.path.join(ramp_dir, "sweep.json")))["properties_chart"]["fits"]
(f,) = [f for f in fits if f["quantity"] == "youngs_modulus"]
assert f["solid"] == "sheet" and f["points"] == 3 and f["valid"], f
x = [math.log(e["properties_relative_density"]) for e in ramp]
y = [math.log(e["properties_youngs_modulus"]) for e in ramp]
mx, my = sum(x) / 3, sum(y) / 3
n = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
assert abs(f["exponent"] - n) < 1e-9 * n, (f["exponent"], n)
assert 1.0 < n < 2.5, n  # a sheet: between stretching (1) and bending (2) dominated, roughly
PY

# Bad stage options: exit 2, the option named, nothing written.
run_bad() { check_usage "$1" "$2" run --surface G --volume-fraction 0.5 --grid 16 "${@:3}"; }
run_bad bad --properties-solid --properties-solid rod
run_bad bad --properties-porosity --properties-porosity 0.7       # a network's is its member's
run_bad bad --properties-solid --properties-solid sheet           # neither porosity nor thickness
run_bad bad --properties-porosity --properties-solid sheet --properties-porosity 1.5
run_bad bad --properties-thickness --properties-solid sheet --properties-thickness 0.6
run_bad bad --properties-porosity --properties-solid sheet --properties-porosity 0.5,,0.7
check_usage bad --properties-grid-check run --surface G --volume-fraction 0.5 --grid 12 \
  --properties-grid-check                                          # 12 has no half >= 8
check_usage bad --properties-solid sweep --surface G --volume-fractions 0.3,0.4 --grid 16 \
  --properties-solid sheet --properties-thickness 0.1 --properties-porosity 0.7

[ "$fail" = 0 ] && echo "properties_stage: all checks passed"
exit "$fail"
