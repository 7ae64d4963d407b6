#!/usr/bin/env bash
# A --fast run with two coarse levels (64^3 from 16^3 and 32^3; --fast itself takes two
# levels from 128^3 on, too slow here) stopped by SIGTERM on each coarse grid and the finest,
# then `run --resume`: the same bits as the uninterrupted run (docs/reliability.md).
set -u
bin="$1"
support="$(cd "$(dirname "$0")/../support" && pwd)"  # report_keys.py: the timing keys
export CMCSURF_BIN="$bin"  # report_keys.py reads the timing keys from its `schema --json`
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
args=(run --surface P --volume-fraction 0.3 --grid 64 --fast --coarse-levels 2 --tol 1e-5 --mesh stl
      --no-preview --no-report)
"$bin" "${args[@]}" --quiet --out "$work/whole" || { echo "FAIL: the plain run"; exit 1; }

# Stops the run when its progress starts relaxation number nth (on 16^3, 32^3, 64^3).
python3 - "$bin" "$work" "${args[@]}" <<'PY' || fail=1
import json, signal, subprocess, sys
bin, work, args = sys.argv[1], sys.argv[2], sys.argv[3:]
ok = True
for name, nth, grids in (("coarse", 1, (16,)), ("middle", 2, (32,)), ("finest", 3, (64,))):
    p = subprocess.Popen([bin] + args + ["--out", f"{work}/{name}"], stderr=subprocess.PIPE,
                         text=True)
    seen = 0
    for line in p.stderr:
        if line.startswith("relax "):
            seen += 1
            if seen == nth:
                p.send_signal(signal.SIGTERM)
                break
    p.stderr.read()
    rc = p.wait()
    stop = json.load(open(f"{work}/{name}/report.json")).get("checkpoint", {})
    if rc != 143 or stop.get("grid") not in grids:
        print(f"FAIL: {name}: exit {rc}, stopped at {stop}, wanted a grid in {grids}")
        ok = False
    else:
        print(f"{name}: stopped in {stop['stage']} on {stop['grid']}^3 at step {stop['step']}")
sys.exit(0 if ok else 1)
PY

for name in coarse middle finest; do
  "$bin" run --resume "$work/$name" --quiet || { echo "FAIL: resume of $name"; fail=1; continue; }
  PYTHONPATH="$support" python3 - "$work/whole" "$work/$name" <<'PY' || fail=1
import json, os, sys
from report_keys import differing_keys
a, b = (json.load(open(f"{d}/report.json")) for d in sys.argv[1:3])
diff = differing_keys(a, b)
assert not diff, f"{sys.argv[2]}: resumed report differs in {diff}"
assert b["coarse_steps"] > 0 and b["parameters"]["coarse_levels"] == 2
files = [sorted(os.listdir(d)) for d in sys.argv[1:3]]
assert files[0] == files[1], f"the folders hold {files[0]} and {files[1]}"
PY
  cmp -s <(grep -av seconds "$work/whole/field.vti") <(grep -av seconds "$work/$name/field.vti") ||
    { echo "FAIL: $name/field.vti differs"; fail=1; }
  cmp -s "$work/whole/surface.stl" "$work/$name/surface.stl" ||
    { echo "FAIL: $name/surface.stl differs"; fail=1; }
done
[ $fail = 0 ] && echo "checkpoint_resume_fast: all passed"
exit $fail
