#!/usr/bin/env bash
# sweep --continuation: each later member starts from the previous one and goes through the
# same volume correction as a run from the nodal formula, which its report records.
set -eu
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" sweep --paper --surface G --volume-fractions 0.3,0.35 --grid 32 --epsilon 0.02 \
  --continuation \
  --no-plot --quiet --out "$work/s" 2>"$work/stderr" || { cat "$work/stderr"; exit 1; }
python3 - "$work/s" <<'PY'
import json, sys
d = sys.argv[1]
first = json.load(open(f"{d}/G_0.30/report.json"))
r = json.load(open(f"{d}/G_0.35/report.json"))
assert first["started_from"] == "nodal", first["started_from"]
assert r["started_from"] == "G_0.30", r["started_from"]
assert r["volume_fraction_target"] == 0.35, r["volume_fraction_target"]
assert r["constrain"] == "volume" and "constrain_note" not in r, r.get("constrain_note")
assert r["volume_corrections"] >= 1, r["volume_corrections"]
assert len(r["volume_iterates"]) == r["volume_corrections"] + 1, r["volume_iterates"]
assert r["volume_converged"] is True
assert abs(r["volume_fraction"] - 0.35) <= 1e-4, r["volume_fraction"]
assert r["volume_iterates"][-1]["volume_fraction"] == r["volume_fraction"]
print("sweep continuation: ok", r["volume_corrections"], "corrections, V =", r["volume_fraction"])
PY
echo "sweep_continuation: all passed"
