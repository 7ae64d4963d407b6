#!/usr/bin/env bash
# cmcsurf mesh / graded / run --mesh on bad input: exit 2, a message naming the option, and
# nothing written.
source "$(dirname "$0")/usage.bash" "$1"
export OMP_NUM_THREADS=1  # the solver spins threads on shared cores
"$bin" run --paper --surface P --grid 16 --max-steps 2 --quiet --out "$work/run" ||
  { echo "FAIL: run"; exit 1; }
before=$(ls "$work/run" | sort)
expect_usage() { check_usage out.stl "$@"; }  # <option> <args...>
r="$work/run"
expect_usage --from      mesh --from "$work/missing"
expect_usage --tile      mesh --from "$r" --tile 0x1x1
expect_usage --tile      mesh --from "$r" --tile 2x2
expect_usage --tile      mesh --from "$r" --tile 3x3x3x3
expect_usage --tile      mesh --from "$r" --tile axbxc
expect_usage --tile      mesh --from "$r" --tile 1000
expect_usage --cell-size mesh --from "$r" --cell-size 0
expect_usage --cell-size mesh --from "$r" --cell-size -2
expect_usage --units     mesh --from "$r" --units furlong
expect_usage --solid     mesh --from "$r" --solid foam
expect_usage --thickness mesh --from "$r" --solid sheet
expect_usage --thickness mesh --from "$r" --solid sheet --thickness 0.9
expect_usage --thickness mesh --from "$r" --solid network --thickness 0.1
expect_usage --other-phase mesh --from "$r" --solid sheet --thickness 0.2 --other-phase
expect_usage --format    mesh --from "$r" --format step
expect_usage --threads   mesh --from "$r" --threads -1
expect_usage --members   graded --members "$r" --from-fraction 0.4 --to-fraction 0.5
expect_usage --axis      graded --members "$r,$r" --axis w --from-fraction 0.4 --to-fraction 0.5
expect_usage --from-fraction graded --members "$r,$r" --from-fraction 1.5 --to-fraction 0.5
expect_usage --solid     graded --members "$r,$r" --from-fraction 0.4 --to-fraction 0.5 \
  --solid sheet
expect_usage --unknown   mesh --from "$r" --unknown 1
# --format cannot come from a name without a known extension.
"$bin" mesh --from "$r" --out "$work/out.mesh" >/dev/null 2>"$work/stderr"
rc=$?
if [ "$rc" -ne 2 ] || ! grep -q -- --format "$work/stderr"; then
  echo "FAIL: unknown extension: rc $rc"
  fail=1
fi
# run --mesh with a bad format fails before the run and writes nothing.
"$bin" run --paper --grid 16 --max-steps 2 --mesh step \
  --out "$work/run2" >/dev/null 2>"$work/stderr"
rc=$?
if [ "$rc" -ne 2 ] || ! grep -q -- --mesh "$work/stderr" || [ -e "$work/run2" ]; then
  echo "FAIL: run --mesh step: rc $rc"; cat "$work/stderr"; fail=1
fi
[ "$(ls "$work/run" | sort)" = "$before" ] || { echo "FAIL: the run directory changed"; fail=1; }
[ "$fail" -eq 0 ] && echo "mesh_bad_options: all passed"
exit "$fail"
