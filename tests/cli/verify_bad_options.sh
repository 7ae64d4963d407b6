#!/usr/bin/env bash
# cmcsurf verify with options out of range: exit 2 naming the option and what is accepted,
# before any experiment runs (a grid of 4096^3 was once taken and allocated). Memory is capped
# so that a regression fails fast instead of swapping (not for a sanitizer build, whose shadow
# memory needs more address space: it cannot start under the cap, and aborts on a huge
# allocation anyway).
set -u
bin="$1"
command -v timeout >/dev/null || { echo "SKIP: no timeout"; exit 77; }
if (ulimit -v 8000000 && "$bin" --help >/dev/null 2>&1); then ulimit -v 8000000; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
expect() {  # expect OPTION PATTERN ARGS...
  local opt="$1" pattern="$2"; shift 2
  timeout 60 "$bin" verify --quiet "$@" >"$work/out" 2>"$work/err"
  local rc=$?
  if [ "$rc" -ne 2 ]; then echo "FAIL: verify $* exited $rc, want 2"; cat "$work/err"; fail=1; fi
  grep -q -- "$opt" "$work/err" && grep -q -- "$pattern" "$work/err" ||
    { echo "FAIL: verify $*: no '$opt' and '$pattern' in: $(cat "$work/err")"; fail=1; }
  if grep -q "^==" "$work/out"; then echo "FAIL: verify $*: an experiment ran"; fail=1; fi
}
expect --transition-grid "N <= 2048" --only transition --transition-grid 4096
expect --transition-grid "N <= 2048" --only transition --transition-grid 2147483647
expect --transition-grid "N >= 8" --only transition --transition-grid 4
expect --cube-grid "N <= 2048" --only cube --cube-grid 4096
expect --cube-steps ">= 1" --only cube --cube-steps 0
expect --threads "accepted" --only cube --threads -1
expect --only "transition" --only sphere
[ "$fail" -eq 0 ] && echo "verify_bad_options: all passed"
exit "$fail"
