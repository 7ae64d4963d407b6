#!/usr/bin/env bash
# A full disk during the writes: exit 1, an error that says so, no report.json (the folder reads
# as incomplete) and no temporary or partial file under a final name; during a periodic
# checkpoint, a warning and the run goes on; during a signal's checkpoint, exit 1 saying so.
# Needs a small tmpfs, so root with mount rights; skipped otherwise.
set -u
bin="$1"
export OMP_NUM_THREADS=1
work=$(mktemp -d)
mkdir -p "$work/small"
if ! mount -t tmpfs -o size=200k tmpfs "$work/small" 2>/dev/null; then
  rm -rf "$work"
  echo "disk_full: skipped (cannot mount a tmpfs here)"
  exit 77
fi
mkdir -p "$work/tiny"
mount -t tmpfs -o size=108k tmpfs "$work/tiny"
trap 'umount "$work/small" "$work/tiny"; rm -rf "$work"' EXIT
fail=0
"$bin" run --paper --surface G --grid 32 --max-steps 3 --quiet --out "$work/small/run" 2>"$work/err"
rc=$?
[ "$rc" = 1 ] || { echo "FAIL: exit $rc, expected 1"; fail=1; }
grep -q "No space left on device" "$work/err" ||
  { echo "FAIL: message: $(cat "$work/err")"; fail=1; }
[ -e "$work/small/run/report.json" ] && { echo "FAIL: report.json written"; fail=1; }
[ -e "$work/small/run/field.vti" ] &&
  { echo "FAIL: a partial field.vti under its final name"; fail=1; }
if ls "$work/small/run" | grep -q tmp; then
  echo "FAIL: temporary left: $(ls "$work/small/run")"
  fail=1
fi

# report.json is written last: a disk that fills while report.html (250-830 KB, with or without
# the 3D viewer) is written
# leaves no report.json, and the solved field is kept.
mkdir -p "$work/page"
mount -t tmpfs -o size=200k tmpfs "$work/page"
"$bin" run --paper --surface G --grid 16 --epsilon 0.04 --no-preview --quiet \
  --out "$work/page/run" \
  2>"$work/err"
rc=$?
[ "$rc" = 1 ] && grep -q "report.html.*No space left" "$work/err" ||
  { echo "FAIL: full disk at report.html: exit $rc"; cat "$work/err"; fail=1; }
[ ! -e "$work/page/run/report.json" ] || { echo "FAIL: report.json beside no report.html"; fail=1; }
[ -s "$work/page/run/field.vti" ] && grep -q "solved field is kept" "$work/err" ||
  { echo "FAIL: the solved field was not kept: $(ls "$work/page/run")"; fail=1; }
umount "$work/page"

# FILE.json marks a mesh FILE complete: a disk with room for the STL (340 KB for this 16^3
# gyroid) but not its FILE.json leaves neither (before, the STL stayed, looking complete).
"$bin" run --paper --surface G --grid 16 --epsilon 0.04 --no-preview --no-report --quiet \
  --out "$work/forMesh" || fail=1
mount -t tmpfs -o size=340k tmpfs "$work/page"
"$bin" mesh --from "$work/forMesh" --out "$work/page/m.stl" 2>"$work/err"
rc=$?
[ "$rc" = 1 ] && grep -q "No space left" "$work/err" ||
  { echo "FAIL: full disk at FILE.json: exit $rc"; cat "$work/err"; fail=1; }
[ -z "$(ls -A "$work/page")" ] || { echo "FAIL: left: $(ls -A "$work/page")"; fail=1; }
umount "$work/page"

# On 108 KB, a checkpoint does not fit (24^3: phi alone is 110 KB) but the outputs do (a
# Float32 field of 55 KB): a warning and the run goes on; no checkpoint or temporary stays.
"$bin" run --paper --surface P --volume-fraction 0.3 --grid 24 --epsilon 0.05 --extrapolate \
  --max-steps 30 --constrain mass --float32 --no-preview --no-report --checkpoint-every 0.01 \
  --quiet --out "$work/tiny/ck" 2>"$work/err"
rc=$?
[ "$rc" = 0 ] ||
  { echo "FAIL: a run whose checkpoints do not fit exited $rc"; cat "$work/err"; fail=1; }
grep -q "warning: no checkpoint written (.*No space left on device.*); the run goes on" \
  "$work/err" ||
  { echo "FAIL: no warning: $(cat "$work/err")"; fail=1; }
python3 -c "
import json; r = json.load(open('$work/tiny/ck/report.json'))
assert r['checkpoints_written'] == 0 and r['stop_reason'] != 'interrupted', r['checkpoints_written']
" || fail=1
if ls "$work/tiny/ck" | grep -q "tmp\|checkpoint"; then
  echo "FAIL: left: $(ls "$work/tiny/ck")"
  fail=1
fi

rm -rf "$work/tiny/ck"  # each case starts on the empty 108 KB disk, whatever a run writes

# SIGTERM when its checkpoint cannot be written: exit 1 saying so, and no report that claims a
# checkpoint.
"$bin" run --paper --surface P --volume-fraction 0.3 --grid 24 --epsilon 0.05 --tol 1e-9 \
  --extrapolate \
  --constrain mass --float32 --no-preview --no-report --out "$work/tiny/sig" 2>"$work/err" &
pid=$!
for _ in $(seq 1 500); do grep -q "^relax " "$work/err" && break; sleep 0.01; done
kill -TERM $pid
wait $pid
rc=$?
[ "$rc" = 1 ] &&
  grep -q "interrupted at step .*, but no checkpoint was written: .*No space left" "$work/err" ||
  { echo "FAIL: SIGTERM without room for the checkpoint: exit $rc"; cat "$work/err"; fail=1; }
[ ! -e "$work/tiny/sig/checkpoint.bin" ] || { echo "FAIL: a checkpoint.bin"; fail=1; }
if [ -e "$work/tiny/sig/report.json" ]; then
  python3 -c "
import json; r = json.load(open('$work/tiny/sig/report.json'))
assert r['stop_reason'] == 'interrupted' and r['checkpoint']['file'] == '', r['checkpoint']
" || fail=1
fi
if ls "$work/tiny/sig" | grep -q tmp; then
  echo "FAIL: temporary left: $(ls "$work/tiny/sig")"
  fail=1
fi
[ "$fail" = 0 ] && echo "disk_full: all passed"
exit "$fail"
