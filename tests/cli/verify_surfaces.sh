#!/usr/bin/env bash
# `surfaces` lists the paper's surfaces; `verify` runs (a shortened Section 4.2) and prints the
# paper's reference values beside ours; the lexicographic smoother runs end to end.
set -eu
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=$("$bin" surfaces)
for s in P D G sphere cube noise; do
  echo "$out" | grep -q "^$s " || { echo "FAIL: surfaces does not list $s"; exit 1; }
done
out=$("$bin" verify --only cube --cube-steps 2 --quiet)
echo "$out" | grep -q "sphericity" || { echo "FAIL: verify cube output"; echo "$out"; exit 1; }
echo "$out" | grep -q "cube 0.806, sphere 1" || { echo "FAIL: verify prints no reference"; exit 1; }
"$bin" verify --only cube --cube-steps 0 >/dev/null 2>&1 && { echo "FAIL: --cube-steps 0 accepted"; exit 1; }
"$bin" run --surface G --grid 16 --epsilon 0.04 --smoother lex --constrain mass --max-steps 20 \
  --quiet --out "$work/lex"
grep -q '"smoother": "lex"' "$work/lex/report.json" || { echo "FAIL: lex run report"; exit 1; }
echo "verify_surfaces: all passed"
