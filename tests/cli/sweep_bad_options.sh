#!/usr/bin/env bash
# Bad sweep input: exit code 2, a message naming the option, and nothing written.
set -u
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
expect_usage() {  # expect_usage <option named in message> <args...>
  local opt="$1"; shift
  local out="$work/out"
  "$bin" sweep "$@" --grid 16 --out "$out" >"$work/stdout" 2>"$work/stderr"
  local rc=$?
  if [ "$rc" -ne 2 ]; then echo "FAIL: '$*' exited $rc, want 2"; fail=1; fi
  if ! grep -q -- "$opt" "$work/stderr"; then
    echo "FAIL: '$*' message does not name $opt:"; cat "$work/stderr"; fail=1
  fi
  if [ -e "$out" ]; then echo "FAIL: '$*' wrote $out"; fail=1; rm -rf "$out"; fi
}
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
"$bin" sweep --help | grep -q -- --continuation || { echo "FAIL: sweep --help"; fail=1; }
"$bin" --help | grep -q sweep || { echo "FAIL: sweep hidden from --help"; fail=1; }
[ "$fail" -eq 0 ] && echo "sweep_bad_options: all passed"
exit "$fail"
