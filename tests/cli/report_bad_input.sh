#!/usr/bin/env bash
# cmcsurf report with bad input: exit 2 for usage (no DIR, not a directory, not a run or sweep
# folder), exit 1 for a damaged folder (unreadable report.json, truncated field.vti), a message
# naming the problem, and no report.html written.
set -u
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
expect() {  # expect CODE PATTERN DIR...
  local code="$1" pattern="$2"; shift 2
  "$bin" report "$@" >"$work/out" 2>"$work/err"
  local rc=$?
  if [ "$rc" -ne "$code" ]; then
    echo "FAIL: report $* exited $rc, want $code"
    cat "$work/err"
    fail=1
  fi
  if ! grep -q -- "$pattern" "$work/err"; then
    echo "FAIL: report $*: message does not say '$pattern':"; cat "$work/err"; fail=1
  fi
}
expect 2 "DIR is required"
expect 2 "is not a directory" "$work/missing"
mkdir "$work/empty"
expect 2 "neither report.json" "$work/empty"
"$bin" run --paper --surface P --grid 16 --epsilon 0.04 --max-steps 3 --quiet --no-preview \
  --no-report \
  --out "$work/run"
cp -r "$work/run" "$work/badjson"
echo '{"surface": ' >"$work/badjson/report.json"
expect 1 "report.json' is not valid JSON" "$work/badjson"
cp -r "$work/run" "$work/badvti"
head -c 3000 "$work/run/field.vti" >"$work/badvti/field.vti"
expect 1 "field.vti" "$work/badvti"
cp -r "$work/run" "$work/nohist"
rm "$work/nohist/history.csv"
expect 1 "history.csv" "$work/nohist"
# A sweep.json whose surface makes a member name outside the sweep folder: refused, and the
# folder it names is not read (a complete run sits there, so following the name would succeed).
mkdir -p "$work/victim" "$work/escape"
: >"$work/escape/.cmcsurf"  # a cmcsurf folder, so that the member names are what is refused
cp -r "$work/run" "$work/victim/P_0.50"
echo '{"surfaces": ["../victim/P"], "volume_fractions": [0.5]}' >"$work/escape/sweep.json"
expect 1 "sweep.json.*member name '../victim/P_0.50'" "$work/escape"
if compgen -G "$work/escape/gallery.png*" >/dev/null; then
  echo "FAIL: escape: wrote gallery.png"
  fail=1
fi
for d in empty badjson badvti nohist escape; do
  if compgen -G "$work/$d/report.html*" >/dev/null; then
    echo "FAIL: $d: wrote report.html"
    fail=1
  fi
done
[ "$fail" -eq 0 ] && echo "report_bad_input: all passed"
exit "$fail"
