#!/usr/bin/env bash
# report.json's `parameters` of three fixed runs (--paper, the defaults before the fast mode;
# --fast at 64^3; every run option given another value) equal run_parameters.json beside this
# script, key for key and in order: written by the build before the run option table
# (model/run_schema.cpp) existed, so the table maps every option to the key and value it
# always had (the keys added since, equilibrium_tol, paper, anderson_depth and
# continued_dt_factor, --fast's equilibrium rule in place of settle_tol and its
# continued_dt_factor 8 were added to it by hand). Then a sweep resumed with any one
# of those options changed is refused (exit 2, the option named): resume compares every option
# of the table by its key, those under the "solver" heading too (the lipid pair once, together).
set -u
bin="$1"
here=$(cd "$(dirname "$0")" && pwd)
command -v python3 >/dev/null || { echo "SKIP: python3 missing"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
quiet=(--threads 1 --quiet --no-preview --no-report)
every=(--surface D --volume-fraction 0.4 --grid 16 --epsilon 0.05 --dt-factor 0.25 --stop phi
       --tol 1e-5 --max-steps 2 --smoother lex --constrain mass --volume-tol 1e-3 --radius 0.3
       --seed 7 --mg-tol 1e-8 --mg-rtol 0.02 --mg-rtol-finest 0.2 --coarse-levels 1 --extrapolate
       --dt-max-factor 4 --continued-dt-factor 2 --settle-tol 1e-4 --equilibrium-tol 2e-3
       --anderson-depth 2
       --max-vcycles 50 --pre-sweeps 3
       --post-sweeps 1
       --prerelax-steps 2 --prerelax-epsilon-factor 4 --bisection-tol 1e-5 --bisection-max-it 40
       --max-volume-corrections 4 --parallel-distances 0.03 --lipid-length 2 --lipid-fraction 0.5
       --distance-field)

"$bin" run --paper --grid 16 --max-steps 2 --out "$work/default" "${quiet[@]}" || fail=1
"$bin" run --grid 64 --fast --max-steps 1 --out "$work/fast" "${quiet[@]}" || fail=1
"$bin" run --paper "${every[@]}" --out "$work/every" "${quiet[@]}" || fail=1
python3 - "$here/run_parameters.json" "$work" <<'EOF' || fail=1
import json, sys
expected = json.load(open(sys.argv[1]))
for name, want in expected.items():
    got = json.load(open(f"{sys.argv[2]}/{name}/report.json"))["parameters"]
    assert list(got.items()) == list(want.items()), (name, got, want)
EOF

# One sweep, then a resume per option (each refused before any work).
"$bin" sweep --paper --grid 8 --surface G --volume-fractions 0.5 --max-steps 3 --out "$work/sweep" \
  "${quiet[@]}" >/dev/null 2>&1 || { echo "FAIL: the sweep"; exit 1; }
i=4  # --grid onwards: a sweep has lists of surfaces and volume fractions
while [ $i -lt ${#every[@]} ]; do
  opt=${every[$i]}
  value=()
  next=${every[$((i + 1))]:-}
  if [ -n "$next" ] && [ "${next#--}" = "$next" ]; then value=("$next"); i=$((i + 1)); fi
  i=$((i + 1))
  # One of the lipid pair alone is refused as such (both or neither), before resume compares.
  case "$opt" in --lipid-length|--lipid-fraction) continue ;; esac
  before=$(md5sum "$work/sweep/sweep.json")
  "$bin" sweep --resume "$work/sweep" "$opt" "${value[@]}" --quiet 2>"$work/err" >/dev/null
  rc=$?
  [ $rc = 2 ] && grep -q -- "^error: $opt .*was written by a run with" "$work/err" ||
    { echo "FAIL: sweep --resume with $opt ${value[*]} exited $rc:"; cat "$work/err"; fail=1; }
  [ "$before" = "$(md5sum "$work/sweep/sweep.json")" ] ||
    { echo "FAIL: $opt changed sweep.json"; fail=1; }
done
"$bin" sweep --resume "$work/sweep" --lipid-length 2 --lipid-fraction 0.5 --quiet 2>"$work/err" \
  >/dev/null
[ $? = 2 ] && grep -q -- "^error: --lipid-length .*was written by a run with" "$work/err" ||
  { echo "FAIL: sweep --resume with the lipid pair:"; cat "$work/err"; fail=1; }
"$bin" sweep --resume "$work/sweep" --fast --quiet 2>"$work/err" >/dev/null
[ $? = 2 ] && grep -q -- "^error: --fast true:" "$work/err" || { echo "FAIL: --fast"; fail=1; }
exit $fail
