#!/usr/bin/env bash
# Bad input: exit code 2, a message naming the option, and nothing written.
source "$(dirname "$0")/usage.bash" "$1"
expect_usage() { check_usage out "$@"; }  # <option> <args...>
expect_usage --grid        run --grid 50
expect_usage --grid        run --grid 4
expect_usage --grid        run --grid abc
expect_usage --volume-fraction run --volume-fraction 1.2
expect_usage --volume-fraction run --volume-fraction 0
expect_usage --epsilon     run --epsilon 0
expect_usage --epsilon     run --epsilon -0.01
expect_usage --surface     run --surface Q
expect_usage --stop        run --stop energy
expect_usage --smoother    run --smoother jacobi
expect_usage --constrain   run --constrain area
expect_usage --volume-tol  run --volume-tol 0
expect_usage --dt-factor   run --dt-factor 0
expect_usage --max-steps   run --max-steps 0
expect_usage --tol         run --tol -1
expect_usage --radius      run --surface sphere --radius 0.7
expect_usage --threads     run --threads -1
expect_usage --threads     run --threads 5000
expect_usage --seed        run --surface noise --seed -1
expect_usage --dt-max-factor run --dt-max-factor 0.25
expect_usage --mg-rtol     run --fast --mg-rtol 1
expect_usage --coarse-levels run --grid 32 --coarse-levels 3
expect_usage --unknown-option run --unknown-option 3
# A file where the output directory should be.
touch "$work/file"
"$bin" run --grid 16 --out "$work/file" >/dev/null 2>"$work/stderr"
rc=$?
if [ "$rc" -ne 2 ] || ! grep -q -- --out "$work/stderr"; then echo "FAIL: --out on a file: rc $rc"; fail=1; fi
"$bin" --help >/dev/null || { echo "FAIL: --help"; fail=1; }
"$bin" run --help | grep -q -- --volume-fraction || { echo "FAIL: run --help"; fail=1; }
[ "$fail" -eq 0 ] && echo "bad_options: all passed"
exit "$fail"
