#!/usr/bin/env bash
# `run --fast` fills in the fast options it was not given, reports them, and lands on the
# paper-faithful result (area within 0.1 %, same volume fraction); it ends on the equilibrium
# rule, and plain `run` (the default) is the same fast run.
set -eu
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
common=(--surface G --volume-fraction 0.35 --grid 32 --epsilon 0.02 --quiet)
"$bin" run --paper "${common[@]}" --out "$work/faithful"
"$bin" run "${common[@]}" --fast --out "$work/fast"
"$bin" run "${common[@]}" --fast --no-extrapolate --dt-max-factor 4 --out "$work/mixed"
"$bin" run "${common[@]}" --out "$work/default"
python3 - "$work" <<'PY'
import json, sys
w = sys.argv[1]
a, f, m = (json.load(open(f"{w}/{d}/report.json")) for d in ("faithful", "fast", "mixed"))
pa, pf, pm = a["parameters"], f["parameters"], m["parameters"]
assert not pa["fast"] and pa["mg_rtol"] == 0 and pa["coarse_levels"] == 0
assert pa["dt_max_factor"] == 0 and not pa["extrapolate"]
assert pf["fast"] and pf["mg_rtol"] == 1e-2 and pf["dt_max_factor"] == 8 and pf["extrapolate"]
assert pf["coarse_levels"] == 0, "32^3 is too small to continue from 16^3 under --fast"
assert pm["fast"] and pm["dt_max_factor"] == 4 and not pm["extrapolate"], pm
assert pa["paper"] and pa["equilibrium_tol"] == 0 and a["stop_reason"] == "area"
assert abs(pf["equilibrium_tol"] - 1e-3 * (128 / 32) ** 2) < 1e-15 and pf["settle_tol"] == 0
assert pf["anderson_depth"] == 3 and pa["anderson_depth"] == 0, (pf, pa)
assert pf["continued_dt_factor"] == 8 and pa["continued_dt_factor"] == 0, (pf, pa)
d = json.load(open(f"{w}/default/report.json"))
assert d["parameters"] == pf, "plain run is not the --fast run"
assert d["area"] == f["area"]
for r in (f, m):
    assert abs(r["area"] / a["area"] - 1) < 1e-3, (r["area"], a["area"])
    assert abs(r["volume_fraction"] - 0.35) <= 1e-4, r["volume_fraction"]
    assert r["vcycles"] < a["vcycles"], (r["vcycles"], a["vcycles"])
    tol = r["parameters"]["equilibrium_tol"]
    assert r["stop_reason"] == "equilibrium" and r["equilibrium_residual"] <= tol, r
print("run_fast: all passed")
PY
