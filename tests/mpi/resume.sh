#!/usr/bin/env bash
# Under mpirun, SIGTERM to the ranks stops every rank at the same step (one decision, shared),
# every rank writes its piece of the checkpoint (format 7: checkpoint.bin and
# checkpoint.parts/, no whole grid on any rank), mpirun exits 143, and the printed
# `mpirun -np P cmcsurf run --resume` ends on the uninterrupted mpirun run's report and field
# bit for bit (docs/reliability.md): a --fast run with a coarse level (32^3 from 16^3, split
# over the P ranks on both grids) stopped on the coarse grid and on the finest. A copy with one
# piece damaged is refused by every rank (exit 2, the piece named).
# Usage: resume.sh <cmcsurf> <ranks> <mpiexec>
set -u
bin="$1"
support="$(cd "$(dirname "$0")/../support" && pwd)"  # report_keys.py: the timing keys
export CMCSURF_BIN="$bin"  # report_keys.py reads the timing keys from its `schema --json`
np="$2"
mpiexec="$3"
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'kill -9 $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
fail=0
mpi() { "$mpiexec" -np "$np" --oversubscribe "$bin" "$@"; }
args=(run --surface P --volume-fraction 0.3 --grid 32 --fast --coarse-levels 1 --tol 1e-7
      --no-preview --no-report)

mpi "${args[@]}" --quiet --out "$work/whole" || { echo "FAIL: the plain mpirun run"; exit 1; }
# nth: the relaxation whose start the signal follows (1: on 16^3, 2: on 32^3).
for nth in 1 2; do
  out="$work/cut$nth"
  grid=$([ $nth = 1 ] && echo 16 || echo 32)
  "$mpiexec" -np "$np" --oversubscribe "$bin" "${args[@]}" --out "$out" 2>"$out.log" &
  pid=$!  # mpirun's own (a function in the background would add a subshell between)
  # The progress lines come at each new stage and every 5 s: on cores loaded by other work a
  # 16^3 relaxation printed two "relax" lines and the signal landed there. The finest grid's
  # relaxation is the first "relax" line after a "volume" one (16^3's mass corrections).
  for _ in $(seq 1 3000); do
    awk -v nth=$nth '/^volume /{v = 1} /^relax / && (nth == 1 || v) {f = 1} END {exit !f}' \
      "$out.log" 2>/dev/null && break
    sleep 0.01
  done
  # The ranks get the signal, as from a batch system's scancel. (mpirun itself, signalled,
  # sends SIGKILL 1 s after its SIGTERM: docs/reliability.md says how to give the ranks time.)
  pkill -TERM -P $pid
  wait $pid
  rc=$?
  [ $rc = 143 ] || { echo "FAIL: mpirun exited $rc after SIGTERM to its ranks, want 143"; fail=1; }
  python3 -c "
import json; r = json.load(open('$out/report.json'))
assert r['stop_reason'] == 'interrupted' and r['mpi_ranks'] == $np, r.get('stop_reason')
assert r['checkpoint']['grid'] == $grid, r['checkpoint']
assert 'mpirun -np $np' in r['resume'], r['resume']
c = r['checkpoint']  # where the signal landed: mid-mixing when the mixer holds columns
print(f\"np $np: stopped before step {c['step'] + 1} ({c['stage']} on {c['grid']}^3), \"
      f\"Anderson columns {c['anderson_columns']}\")
" || { echo "FAIL: interrupted report (wanted a stop on $grid^3)"; cat "$out.log"; fail=1; }
  [ -s "$out/checkpoint.bin" ] || { echo "FAIL: no checkpoint"; fail=1; }
  pieces=("$out"/checkpoint.parts/*-r*.bin)
  [ ${#pieces[@]} = "$np" ] || { echo "FAIL: ${#pieces[@]} checkpoint pieces, want $np"; fail=1; }

  # A flipped byte in the last piece (read by one rank only): every rank refuses, naming it.
  cp -r "$out" "$out.bad"
  bad=("$out.bad"/checkpoint.parts/*-r*.bin)
  bad="${bad[$((np - 1))]}"
  python3 -c "
import sys; p = sys.argv[1]; b = bytearray(open(p, 'rb').read()); b[60] ^= 1
open(p, 'wb').write(b)" "$bad"
  mpi run --resume "$out.bad" --quiet 2>"$out.bad.log"
  rc=$?
  [ $rc = 2 ] || { echo "FAIL: resume of a damaged piece exited $rc, want 2"; fail=1; }
  grep -q "$(basename "$bad").*checksum" "$out.bad.log" ||
    { echo "FAIL: the damaged piece is not named"; cat "$out.bad.log"; fail=1; }

  # The printed command (with --oversubscribe, as this machine has fewer cores than ranks).
  hint=$(sed -n 's/^resume with: //p' "$out.log")
  case "$hint" in
    "mpirun -np $np "*)
      "$mpiexec" -np "$np" --oversubscribe ${hint#mpirun -np $np } --quiet ||
        { echo "FAIL: mpirun resume"; fail=1; } ;;
    *) echo "FAIL: resume hint '$hint'"; fail=1 ;;
  esac
  PYTHONPATH="$support" python3 - "$work/whole" "$out" <<'PY' || fail=1
import json, sys
from report_keys import differing_keys
a, b = (json.load(open(f"{d}/report.json")) for d in sys.argv[1:3])
# Besides the timings, the per-rank counters and memory depend on where the run was cut.
diff = differing_keys(a, b, ignore={"mpi_rank0", "peak_memory_bytes_per_rank",
                                    "peak_memory_bytes_max_rank"})
assert not diff, f"{sys.argv[2]}: resumed report differs in {diff}"
assert b["coarse_steps"] > 0 and b["resumed_from_step"] > 0
PY
  # field.vti, or field.pvti and its pieces (io/pvti.h): the same bytes.
  for f in field.vti field.pvti field/piece_*.vti; do
    [ -e "$work/whole/$f" ] || [ -e "$out/$f" ] || continue
    cmp -s <(grep -av seconds "$work/whole/$f") <(grep -av seconds "$out/$f") ||
      { echo "FAIL: $out/$f differs"; fail=1; }
  done
  [ -e "$out/field.vti" ] || [ -e "$out/field.pvti" ] || { echo "FAIL: no field written"; fail=1; }
  [ ! -e "$out/checkpoint.bin" ] || { echo "FAIL: checkpoint left after completion"; fail=1; }
  [ ! -e "$out/checkpoint.parts" ] ||
    { echo "FAIL: checkpoint pieces left after completion"; fail=1; }
done
[ $fail = 0 ] && echo "mpi resume (np $np): all passed"
exit $fail
