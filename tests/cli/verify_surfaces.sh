#!/usr/bin/env bash
# `surfaces` lists the paper's surfaces; `verify` runs (a shortened Section 4.2), prints the
# paper's reference values beside ours and fails (exit 1) when a check fails; the lexicographic
# smoother runs end to end. (verify_quick.sh runs `verify --quick`, which must pass.)
set -eu
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=$("$bin" surfaces)
for s in P D G sphere cube noise; do
  echo "$out" | grep -q "^$s " || { echo "FAIL: surfaces does not list $s"; exit 1; }
done
# Two steps leave the cube a cube: the checks fail and so does the command (exit 1).
rc=0
out=$("$bin" verify --only cube --cube-grid 16 --cube-steps 2 --quiet) || rc=$?
[ "$rc" -eq 1 ] ||
  { echo "FAIL: verify of an unrelaxed cube exited $rc, want 1"; echo "$out"; exit 1; }
echo "$out" | grep -q "sphericity" || { echo "FAIL: verify cube output"; echo "$out"; exit 1; }
echo "$out" | grep -q "cube 0.806, sphere 1" || { echo "FAIL: verify prints no reference"; exit 1; }
echo "$out" | grep -q "^  FAIL relaxed within 2 steps" ||
  { echo "FAIL: no failed check"; echo "$out"; exit 1; }
echo "$out" | grep -q "check(s) FAILED" || { echo "FAIL: no failure summary"; echo "$out"; exit 1; }
rc=0
"$bin" verify --only cube --cube-steps 0 >/dev/null 2>&1 || rc=$?
[ "$rc" -eq 2 ] || { echo "FAIL: --cube-steps 0 exited $rc, want 2"; exit 1; }
"$bin" run --paper --surface G --grid 16 --epsilon 0.04 --smoother lex --constrain mass \
  --max-steps 20 \
  --quiet --out "$work/lex"
grep -q '"smoother": "lex"' "$work/lex/report.json" || { echo "FAIL: lex run report"; exit 1; }
echo "verify_surfaces: all passed"
