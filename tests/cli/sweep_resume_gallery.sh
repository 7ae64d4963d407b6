#!/usr/bin/env bash
# sweep --resume draws gallery.png from every member, the ones an earlier invocation computed
# included, and takes its output options (--no-plot, --no-report, previews on) from sweep.json:
# the resumed folder's gallery.png is the uninterrupted sweep's, byte for byte. `cmcsurf report`
# on a sweep folder without gallery.png draws it again, the same (docs/reliability.md).
set -u
bin="$1"
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
"$bin" sweep --paper --surface P --volume-fractions 0.3,0.4,0.5 --grid 16 --epsilon 0.04 \
  --tol 1e-6 \
  --no-plot --no-report --quiet --out "$work/whole" || { echo "FAIL: the plain sweep"; exit 1; }
[ -s "$work/whole/gallery.png" ] || { echo "FAIL: no gallery.png"; exit 1; }

# A sweep stopped after its second member: the third folder never started, no gallery yet.
cp -r "$work/whole" "$work/cut"
rm -r "$work/cut/P_0.50" "$work/cut/gallery.png"
python3 - "$work/cut/sweep.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["complete"] = False
json.dump(s, open(sys.argv[1], "w"))
PY
"$bin" sweep --resume "$work/cut" 2>"$work/resume.log" ||
  { echo "FAIL: resume"; cat "$work/resume.log"; fail=1; }
[ "$(grep -c "complete, kept" "$work/resume.log")" = 2 ] ||
  { echo "FAIL: not 2 members kept"; cat "$work/resume.log"; fail=1; }
cmp -s "$work/whole/gallery.png" "$work/cut/gallery.png" ||
  { echo "FAIL: the resumed sweep's gallery.png is not the uninterrupted one's"; fail=1; }
[ "$(ls "$work/whole")" = "$(ls "$work/cut")" ] ||
  { echo "FAIL: files: $(ls "$work/whole") vs $(ls "$work/cut")"; fail=1; }

# `cmcsurf report` on a sweep folder without gallery.png draws it from the members' folders.
rm "$work/cut/gallery.png"
"$bin" report "$work/cut" --quiet || { echo "FAIL: report"; fail=1; }
cmp -s "$work/whole/gallery.png" "$work/cut/gallery.png" ||
  { echo "FAIL: report's gallery.png is not the sweep's"; fail=1; }
[ -s "$work/cut/report.html" ] || { echo "FAIL: no report.html"; fail=1; }
[ $fail = 0 ] && echo "sweep_resume_gallery: all passed"
exit $fail
