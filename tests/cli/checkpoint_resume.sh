#!/usr/bin/env bash
# Interrupted runs resume to the same bits (docs/reliability.md): SIGTERM and SIGINT mid-run
# stop with checkpoint.bin and a report marked interrupted (exit 143 / 130); the printed resume
# command alone writes the uninterrupted run's folder (its output options come from the
# checkpoint: Float32 field, PLY mesh, no preview or page), removing a temporary an earlier
# process left; kill -9 after a periodic checkpoint loses only the work since it; disagreeing
# options and a damaged checkpoint are refused with exit 2, changing nothing. Small (16^3) so
# that the sanitizer pass runs it too; checkpoint_resume_stages.sh covers the other stages, a
# second signal, other builds and hostile checkpoints, checkpoint_resume_fast.sh the coarse
# grids of --fast.
set -u
bin="$1"
support="$(cd "$(dirname "$0")/../support" && pwd)"  # report_keys.py: the timing keys
export CMCSURF_BIN="$bin"  # report_keys.py reads the timing keys from its `schema --json`
work=$(mktemp -d)
trap 'kill -9 $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
fail=0
# ~160 steps at 16^3: about 90 of relaxation, then one volume correction (0.3 s; 2 s under ASan).
args=(run --paper --surface P --volume-fraction 0.3 --grid 16 --epsilon 0.04 --tol 1e-7
      --max-volume-corrections 1)
outputs=(--float32 --mesh ply --no-preview --no-report)

"$bin" "${args[@]}" "${outputs[@]}" --quiet --out "$work/whole" ||
  { echo "FAIL: the plain run"; exit 1; }

# Starts a run in the background and waits until its progress shows stage $2 (or a file).
start() {
  local out="$1" wait_for="$2"; shift 2
  "$bin" "${args[@]}" "${outputs[@]}" --out "$out" "$@" 2>"$out.log" &
  pid=$!
  for _ in $(seq 1 1000); do
    if [ -e "$wait_for" ] || grep -q "^$wait_for " "$out.log" 2>/dev/null; then return 0; fi
    sleep 0.01
  done
  echo "FAIL: $wait_for never appeared"; cat "$out.log"; fail=1
}

same_as_whole() {  # $1: folder of a resumed run
  PYTHONPATH="$support" python3 - "$work/whole" "$1" <<'PY' || fail=1
import json, os, sys
from report_keys import differing_keys
a, b = (json.load(open(f"{d}/report.json")) for d in sys.argv[1:3])
diff = differing_keys(a, b)
assert not diff, f"resumed report differs in {diff}"
assert b["resumed_from_step"] > 0 and b["steps"] == a["steps"] and b["vcycles"] == a["vcycles"]
files = [sorted(os.listdir(d)) for d in sys.argv[1:3]]
assert files[0] == files[1], f"the folders hold {files[0]} and {files[1]}"
PY
  # Every field value (Float32, as the run asked): the VTI files differ at most in their
  # timing metadata lines; the meshes are the same bytes.
  cmp -s <(grep -av seconds "$work/whole/field.vti") <(grep -av seconds "$1/field.vti") ||
    { echo "FAIL: $1/field.vti differs from the uninterrupted run's"; fail=1; }
  cmp -s "$work/whole/surface.ply" "$1/surface.ply" ||
    { echo "FAIL: $1/surface.ply differs from the uninterrupted run's"; fail=1; }
  [ ! -e "$1/checkpoint.bin" ] || { echo "FAIL: $1/checkpoint.bin left after completion"; fail=1; }
}

for sig in TERM INT; do
  out="$work/sig$sig"
  start "$out" relax
  kill -$sig $pid
  wait $pid
  rc=$?
  want=$([ $sig = TERM ] && echo 143 || echo 130)
  [ "$rc" = "$want" ] || { echo "FAIL: SIG$sig exited $rc, want $want"; cat "$out.log"; fail=1; }
  hint=$(sed -n 's/^resume with: //p' "$out.log")
  [ "$hint" = "$(realpath "$bin") run --resume $out" ] ||
    { echo "FAIL: resume hint '$hint'"; fail=1; }
  PYTHONPATH="$support" python3 -c "
import json, sys; r = json.load(open('$out/report.json'))
assert r['stop_reason'] == 'interrupted' and not r['converged'], r['stop_reason']
assert r['checkpoint']['file'] == 'checkpoint.bin' and r['resume'].endswith('--resume $out')
assert r['checkpoint']['stage'] == 'relax', r['checkpoint']
from report_keys import undeclared_keys  # the interrupted report's keys are the schema's
assert not undeclared_keys(r), undeclared_keys(r)
" || fail=1
  [ -s "$out/checkpoint.bin" ] || { echo "FAIL: SIG$sig left no checkpoint"; fail=1; }
  if ls "$out" | grep -q tmp; then echo "FAIL: temporary left: $(ls "$out")"; fail=1; fi

  # Options that disagree with the checkpoint: exit 2, nothing changes.
  before=$(md5sum "$out"/* | md5sum)
  "$bin" run --resume "$out" --grid 64 2>"$work/err"
  rc=$?
  [ $rc = 2 ] && grep -q -- "--grid 64" "$work/err" ||
    { echo "FAIL: --resume with --grid 64 exited $rc:"; cat "$work/err"; fail=1; }
  [ "$before" = "$(md5sum "$out"/* | md5sum)" ] ||
    { echo "FAIL: a refused resume changed files"; fail=1; }

  [ $sig = INT ] && break  # its checkpoint is damaged below
  # What a process killed while writing leaves (a dead pid's temporary): the resume removes it.
  echo partial >"$out/checkpoint.bin.cmcsurf-tmp.2147483647.0"
  $hint --quiet || { echo "FAIL: the printed resume command after SIG$sig"; fail=1; }
  same_as_whole "$out"
  [ ! -e "$out/checkpoint.bin.cmcsurf-tmp.2147483647.0" ] ||
    { echo "FAIL: stale temporary kept"; fail=1; }
done

# kill -9 after a periodic checkpoint: the resumed run still ends on the same bits.
out="$work/killed"
mkdir -p "$out"
start "$out" "$out/checkpoint.bin" --checkpoint-every 0.05
kill -9 $pid
wait $pid 2>/dev/null
[ -s "$out/checkpoint.bin" ] || { echo "FAIL: no periodic checkpoint"; fail=1; }
"$bin" run --resume "$out" --quiet || { echo "FAIL: resume after kill -9"; fail=1; }
same_as_whole "$out"

# A damaged checkpoint is refused (exit 2, named), and so is a folder without one.
printf 'X' | dd of="$work/sigINT/checkpoint.bin" bs=1 seek=5000 conv=notrunc status=none
"$bin" run --resume "$work/sigINT" 2>"$work/err"
rc=$?
[ $rc = 2 ] && grep -q "checkpoint.bin.*checksum" "$work/err" ||
  { echo "FAIL: damaged checkpoint: exit $rc"; cat "$work/err"; fail=1; }
"$bin" run --resume "$work/whole" 2>"$work/err"
rc=$?
[ $rc = 2 ] && grep -q "no checkpoint.bin" "$work/err" ||
  { echo "FAIL: resume of a complete run: exit $rc"; cat "$work/err"; fail=1; }

[ $fail = 0 ] && echo "checkpoint_resume: all passed"
exit $fail
