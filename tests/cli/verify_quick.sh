#!/usr/bin/env bash
# `verify --quick` (Sections 4.1, 4.2 and Table 1 on 32^3 grids, about 10 s) passes every check
# (exit 0) and prints each check with its accepted range; --quick with --with-256 is refused.
set -u
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
"$bin" verify --quick --quiet >"$work/out" 2>"$work/err"
rc=$?
if [ "$rc" -ne 0 ]; then
  echo "FAIL: verify --quick exited $rc, want 0"
  cat "$work/out" "$work/err"
  fail=1
fi
for section in "Section 4.1" "Section 4.2" "Table 1"; do
  grep -q "$section" "$work/out" || { echo "FAIL: no $section in the output"; fail=1; }
done
passed=$(grep -c "^  PASS " "$work/out")
if [ "$passed" -lt 10 ]; then echo "FAIL: $passed checks passed, want at least 10"; fail=1; fi
if grep -q "^  FAIL " "$work/out"; then
  echo "FAIL: failed checks:"
  grep "^  FAIL " "$work/out"
  fail=1
fi
grep -q "all checks passed" "$work/out" || { echo "FAIL: no summary"; fail=1; }
"$bin" verify --quick --with-256 >"$work/out" 2>"$work/err"
rc=$?
if [ "$rc" -ne 2 ] || ! grep -q -- "--with-256" "$work/err"; then
  echo "FAIL: --quick --with-256 exited $rc, want 2 naming the option"; cat "$work/err"; fail=1
fi
[ "$fail" -eq 0 ] && echo "verify_quick: all passed"
exit "$fail"
