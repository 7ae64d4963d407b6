#!/usr/bin/env bash
# OMP_NUM_THREADS is checked before the first parallel region: a count OpenMP would start
# (100000 threads crashed the run) or misread is a usage error naming it, with nothing written.
source "$(dirname "$0")/usage.bash" "$1"
for bad in 100000 4097 0 abc "4," 2.5 "8,100000" ""; do
  OMP_NUM_THREADS="$bad" check_usage out OMP_NUM_THREADS run --grid 16
  grep -q -- "got '$bad'; accepted: 1 <= T <= 4096" "$work/stderr" ||
    { echo "FAIL: OMP_NUM_THREADS='$bad': no value and range"; cat "$work/stderr"; fail=1; }
done
# Refused with --threads too (which would override its first level): bad input is named, not
# worked around.
OMP_NUM_THREADS=100000 check_usage out OMP_NUM_THREADS run --grid 16 --threads 1
# Accepted: a count, a nesting list, spaces around them.
for good in 1 " 2 " "1,1"; do
  OMP_NUM_THREADS="$good" "$bin" run --paper --grid 16 --max-steps 1 --quiet --no-preview \
    --no-report --out "$work/good" >/dev/null 2>"$work/stderr" ||
    { echo "FAIL: OMP_NUM_THREADS='$good' refused"; cat "$work/stderr"; fail=1; }
  rm -rf "$work/good"
done
# --help needs no threads.
OMP_NUM_THREADS=100000 "$bin" --help >/dev/null || { echo "FAIL: --help"; fail=1; }
[ "$fail" -eq 0 ] && echo "threads_env: all passed"
exit "$fail"
