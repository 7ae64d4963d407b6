#!/usr/bin/env bash
# Families computed apart share one table (docs/families.md): two sweeps of 2 members each,
# merged, give the sweep.csv of the 4-member sweep over both (timings aside), a families.png,
# and a sweep folder that `sweep --resume` keeps whole; sweeps with other parameters, a member
# in two sources or a missing member are refused with exit 2, writing nothing. `sweep
# --structure double` passes the option to its members.
set -u
bin="$1"
support="$(cd "$(dirname "$0")/../support" && pwd)"  # report_keys.py: the timing keys
export CMCSURF_BIN="$bin"  # report_keys.py reads the timing keys from its `schema --json`
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
small=(--paper --grid 16 --max-steps 100 --no-preview --no-report --quiet)
quick=("${small[@]}" --epsilon 0.04)
"$bin" sweep --surface P --volume-fractions 0.4,0.6 "${quick[@]}" --out "$work/p" &&
  "$bin" sweep --surface D --volume-fractions 0.4,0.6 "${quick[@]}" --out "$work/d" &&
  "$bin" sweep --surface P,D --volume-fractions 0.4,0.6 "${quick[@]}" --out "$work/whole" ||
  { echo "FAIL: the sweeps"; exit 1; }
"$bin" merge "$work/p" "$work/d" --out "$work/m" 2>"$work/log" ||
  { echo "FAIL: merge"; cat "$work/log"; exit 1; }
head -c 8 "$work/m/families.png" | grep -q PNG || { echo "FAIL: no families.png"; fail=1; }
PYTHONPATH="$support" python3 - "$work/whole" "$work/m" "$work/p" "$work/d" <<'PY' || fail=1
import csv, json, sys
from report_keys import differing_keys
whole, merged = (list(csv.DictReader(open(f"{d}/sweep.csv"))) for d in sys.argv[1:3])
assert len(whole) == len(merged) == 4, (len(whole), len(merged))
assert list(whole[0]) == list(merged[0]), "columns differ"
for x, y in zip(whole, merged):
    diff = differing_keys(x, y)
    assert not diff, f"{x['member']}: {diff}"
s = json.load(open(f"{sys.argv[2]}/sweep.json"))
assert s["complete"] and s["members"] == 4, s
assert s["surfaces"] == ["P", "D"] and s["volume_fractions"] == [0.4, 0.6], s
assert s["merged_from"] == sys.argv[3:5], s["merged_from"]
assert s["literature"]["minimal_surface_areas"]["G"]["area"] == 3.0915
points = s["families_figure"]["points"]
assert len(points) == 4 and all(p["area_error"] >= 0 for p in points), points
print("merge: ok")
PY
"$bin" sweep --resume "$work/m" 2>"$work/log" || { echo "FAIL: resume merged"; fail=1; }
[ "$(grep -c "complete, kept" "$work/log")" = 4 ] ||
  { echo "FAIL: the merged members were not kept"; cat "$work/log"; fail=1; }

# Refusals: exit 2 naming the problem, no folder written.
"$bin" sweep --surface G --volume-fractions 0.5 "${small[@]}" --epsilon 0.05 --out "$work/g" ||
  { echo "FAIL: the G sweep"; exit 1; }
check_refused() {  # pattern, merge arguments...
  local pattern="$1"
  shift
  "$bin" merge "$@" --out "$work/refused" 2>"$work/err"
  local rc=$?
  [ $rc = 2 ] && grep -q -- "$pattern" "$work/err" ||
    { echo "FAIL: merge $*: exit $rc"; cat "$work/err"; fail=1; }
  [ ! -e "$work/refused" ] ||
    { echo "FAIL: a refused merge wrote"; fail=1; rm -rf "$work/refused"; }
}
check_refused "epsilon" "$work/p" "$work/g"
check_refused "is in" "$work/p" "$work/whole"
"$bin" sweep --surface P --volume-fractions 0.5 "${quick[@]}" --out "$work/p5" ||
  { echo "FAIL: the P 0.5 sweep"; exit 1; }
check_refused "no source has member D_0.50" "$work/d" "$work/p5"

# --structure double reaches the members (their parameters, sweep.json's, and the seed: two
# networks after 3 steps, as cli.double_structure's run).
"$bin" sweep --structure double --constrain volume --surface G --volume-fractions 0.35 \
  --grid 32 --epsilon 0.02 --tol 1e-5 --max-steps 3 --threads 1 --no-preview --no-report \
  --no-plot --quiet --out "$work/double" 2>"$work/err" ||
  { echo "FAIL: sweep --structure double"; cat "$work/err"; fail=1; }
python3 - "$work/double" <<'PY' || fail=1
import json, sys
d = sys.argv[1]
r = json.load(open(f"{d}/G_0.35/report.json"))
assert r["parameters"]["structure"] == "double", r["parameters"]
assert len(r["interfaces"]) == 2, r["interfaces"]
assert json.load(open(f"{d}/sweep.json"))["parameters"]["structure"] == "double"
PY
[ $fail = 0 ] && echo "sweep_merge: all passed"
exit $fail
