#!/usr/bin/env bash
# Bad sweep input: exit code 2, a message naming the option, and nothing written.
source "$(dirname "$0")/usage.bash" "$1"
expect_usage() { local opt="$1"; shift; check_usage out "$opt" sweep "$@" --grid 16; }
expect_usage --volume-fractions --volume-fractions 0.75:0.25:0.05
expect_usage --volume-fractions --volume-fractions 0.25:0.75:0
expect_usage --volume-fractions --volume-fractions 0.25:0.75:-0.05
expect_usage --volume-fractions --volume-fractions 0:0.5:0.1
expect_usage --volume-fractions --volume-fractions 0.5:1.0:0.1
expect_usage --volume-fractions --volume-fractions 0.3,1.2
expect_usage --volume-fractions --volume-fractions 0.3,x
expect_usage --volume-fractions --volume-fractions 0.2:0.8
expect_usage --surface --surface P,Q
expect_usage --surface --surface G,sphere
expect_usage --surface --surface "expr:cos(x"
expect_usage --grid --grid 50
expect_usage --epsilon --epsilon 0
expect_usage --volume-fraction --volume-fraction 0.3
expect_usage --groups --groups 2  # one process: only 1 (or 0, automatic)
expect_usage --groups --groups -1
"$bin" sweep --help | grep -q -- --continuation || { echo "FAIL: sweep --help"; fail=1; }
"$bin" sweep --help | grep -q -- "--groups.*mpirun" ||
  { echo "FAIL: sweep --help lacks --groups"; fail=1; }
"$bin" --help | grep -q sweep || { echo "FAIL: sweep hidden from --help"; fail=1; }
[ "$fail" -eq 0 ] && echo "sweep_bad_options: all passed"
exit "$fail"
