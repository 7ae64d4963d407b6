#!/usr/bin/env bash
# A sweep stopped by SIGTERM in its second member resumes (docs/reliability.md): complete
# members are kept, the interrupted one continues from its checkpoint, the rest run, and
# sweep.csv and every field.vti equal the uninterrupted sweep's, with the same files (the
# printed resume command alone restores the output options); disagreeing options and a
# sweep.json whose parameters are out of range are refused.
set -u
bin="$1"
support="$(cd "$(dirname "$0")/../support" && pwd)"  # report_keys.py: the timing keys
export CMCSURF_BIN="$bin"  # report_keys.py reads the timing keys from its `schema --json`
work=$(mktemp -d)
trap 'kill -9 $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
fail=0
args=(sweep --paper --surface P --volume-fractions 0.3,0.4,0.5 --grid 32 --tol 1e-7 --continuation
      --no-plot --no-preview --no-report)
"$bin" "${args[@]}" --quiet --out "$work/whole" || { echo "FAIL: the plain sweep"; exit 1; }

"$bin" "${args[@]}" --out "$work/cut" 2>"$work/cut.log" &
pid=$!
# Until the second member has reached its volume constraint (however slow the build or the
# machine: a sanitizer build on a loaded machine takes minutes for the first member).
while kill -0 $pid 2>/dev/null; do
  grep -q "^\[2/3\] P alpha 0.4" "$work/cut.log" && grep -q "^volume " "$work/cut.log" && break
  sleep 0.01
done
kill -TERM $pid
wait $pid
rc=$?
[ $rc = 143 ] || { echo "FAIL: SIGTERM exited $rc"; cat "$work/cut.log"; fail=1; }
grep -q "resume with: .* sweep --resume $work/cut" "$work/cut.log" ||
  { echo "FAIL: no hint"; fail=1; }
[ -s "$work/cut/P_0.40/checkpoint.bin" ] ||
  { echo "FAIL: no member checkpoint"; ls -R "$work/cut"; fail=1; }
[ ! -e "$work/cut/P_0.50" ] || { echo "FAIL: a later member started"; fail=1; }

"$bin" sweep --resume "$work/cut" --grid 64 2>"$work/err"
rc=$?
[ $rc = 2 ] && grep -q -- "--grid 64" "$work/err" ||
  { echo "FAIL: --grid 64 exit $rc"; cat "$work/err"; fail=1; }
# sweep.json edited out of range (a parameter, a volume fraction): exit 2 naming it, nothing
# changes.
for edit in 's["parameters"]["epsilon"] = -1' 's["volume_fractions"][1] = 1.5'; do
  cp -r "$work/cut" "$work/bad"
  python3 -c "
import json; f = '$work/bad/sweep.json'; s = json.load(open(f)); $edit; json.dump(s, open(f, 'w'))"
  before=$(find "$work/bad" -type f -exec md5sum {} + | sort | md5sum)
  "$bin" sweep --resume "$work/bad" 2>"$work/err"
  rc=$?
  [ $rc = 2 ] && grep -q "sweep.json.*\(epsilon\|1.5\)" "$work/err" ||
    { echo "FAIL: sweep.json with $edit: exit $rc"; cat "$work/err"; fail=1; }
  [ "$before" = "$(find "$work/bad" -type f -exec md5sum {} + | sort | md5sum)" ] ||
    { echo "FAIL: a refused sweep resume changed files"; fail=1; }
  rm -rf "$work/bad"
done

# The printed command alone: the output options (--no-plot, --no-preview, --no-report) come
# from sweep.json.
hint=$(sed -n 's/^resume with: //p' "$work/cut.log")
$hint 2>"$work/resume.log" || { echo "FAIL: resume"; cat "$work/resume.log"; fail=1; }
[ "$(ls "$work/whole")" = "$(ls "$work/cut")" ] ||
  { echo "FAIL: files: $(ls "$work/whole") vs $(ls "$work/cut")"; fail=1; }
grep -q "P_0.30: complete, kept" "$work/resume.log" || { echo "FAIL: P_0.30 not kept"; fail=1; }
PYTHONPATH="$support" python3 - "$work/whole" "$work/cut" <<'PY' || fail=1
import csv, json, sys
from report_keys import differing_keys
a, b = (list(csv.DictReader(open(f"{d}/sweep.csv"))) for d in sys.argv[1:3])
assert len(a) == len(b) == 3, (len(a), len(b))
for x, y in zip(a, b):
    diff = differing_keys(x, y)
    assert not diff, f"{x['member']}: {diff}"
s = json.load(open(f"{sys.argv[2]}/sweep.json"))
assert s["complete"] and s["resumed"] == {"members_kept": 1, "members_resumed": 1}, s
PY
for m in P_0.30 P_0.40 P_0.50; do
  cmp -s <(grep -av seconds "$work/whole/$m/field.vti") \
    <(grep -av seconds "$work/cut/$m/field.vti") ||
    { echo "FAIL: $m/field.vti differs"; fail=1; }
  [ ! -e "$work/cut/$m/checkpoint.bin" ] || { echo "FAIL: $m/checkpoint.bin left"; fail=1; }
done
[ $fail = 0 ] && echo "sweep_resume: all passed"
exit $fail
