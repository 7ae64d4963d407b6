#!/usr/bin/env bash
# A full disk during the writes: exit 1, an error that says so, no report.json (the folder reads
# as incomplete) and no temporary or partial file under a final name. Needs a small tmpfs, so
# root with mount rights; skipped otherwise.
set -u
bin="$1"
export OMP_NUM_THREADS=1
work=$(mktemp -d)
mkdir -p "$work/small"
if ! mount -t tmpfs -o size=200k tmpfs "$work/small" 2>/dev/null; then
  rm -rf "$work"
  echo "disk_full: skipped (cannot mount a tmpfs here)"
  exit 0
fi
trap 'umount "$work/small"; rm -rf "$work"' EXIT
fail=0
"$bin" run --surface G --grid 32 --max-steps 3 --quiet --out "$work/small/run" 2>"$work/err"
rc=$?
[ "$rc" = 1 ] || { echo "FAIL: exit $rc, expected 1"; fail=1; }
grep -q "No space left on device" "$work/err" || { echo "FAIL: message: $(cat "$work/err")"; fail=1; }
[ -e "$work/small/run/report.json" ] && { echo "FAIL: report.json written"; fail=1; }
[ -e "$work/small/run/field.vti" ] && { echo "FAIL: a partial field.vti under its final name"; fail=1; }
if ls "$work/small/run" | grep -q tmp; then echo "FAIL: temporary left: $(ls "$work/small/run")"; fail=1; fi
[ "$fail" = 0 ] && echo "disk_full: all passed"
exit "$fail"
