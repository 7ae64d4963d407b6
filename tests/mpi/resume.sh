#!/usr/bin/env bash
# Under mpirun, SIGTERM to the ranks stops every rank at the same step (one decision, shared), rank 0 writes
# the gathered checkpoint, and `mpirun -np P cmcsurf run --resume` ends on the uninterrupted
# mpirun run's report and field bit for bit (docs/reliability.md).
# Usage: resume.sh <cmcsurf> <ranks> <mpiexec>
set -u
bin="$1"
np="$2"
mpiexec="$3"
export OMP_NUM_THREADS=1
# One process count is enough to show the shared decision and the gathered checkpoint; np 4
# would only repeat it at twice the cost.
[ "$np" = 2 ] || { echo "mpi resume: run for np 2 only"; exit 0; }
work=$(mktemp -d)
trap 'kill -9 $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
fail=0
mpi() { "$mpiexec" -np "$np" --oversubscribe "$bin" "$@"; }
args=(run --surface P --volume-fraction 0.3 --grid 32 --tol 1e-8 --no-preview --no-report)

mpi "${args[@]}" --quiet --out "$work/whole" || { echo "FAIL: the plain mpirun run"; exit 1; }
mpi "${args[@]}" --out "$work/cut" 2>"$work/cut.log" &
pid=$!
for _ in $(seq 1 1000); do
  grep -q "^relax " "$work/cut.log" && break
  sleep 0.02
done
# The ranks get the signal, as from a batch system's scancel. (mpirun itself, signalled, sends
# SIGKILL 1 s after its SIGTERM: docs/reliability.md says how to give the ranks time.)
pkill -TERM -P $pid
wait $pid
echo "mpirun exited $? after SIGTERM to its ranks"
python3 -c "
import json; r = json.load(open('$work/cut/report.json'))
assert r['stop_reason'] == 'interrupted' and r['mpi_ranks'] == $np, r.get('stop_reason')
assert 'mpirun -np $np' in r['resume'], r['resume']
" || { echo "FAIL: interrupted report"; cat "$work/cut.log"; fail=1; }
[ -s "$work/cut/checkpoint.bin" ] || { echo "FAIL: no checkpoint"; fail=1; }

mpi run --resume "$work/cut" --quiet || { echo "FAIL: mpirun resume"; fail=1; }
python3 - "$work/whole" "$work/cut" <<'PY' || fail=1
import json, sys
a, b = (json.load(open(f"{d}/report.json")) for d in sys.argv[1:3])
timing = {"wall_seconds", "solver_seconds", "measure_seconds", "quality_seconds",
          "volume_seconds", "seconds_per_vcycle", "peak_memory_bytes",
          "peak_memory_bytes_per_cell", "checkpoints_written", "checkpoint_seconds",
          "resumed_from_step", "preview_seconds", "mpi_rank0"}
diff = [k for k in set(a) | set(b) if k not in timing and a.get(k) != b.get(k)]
assert not diff, f"resumed report differs in {diff}"
PY
cmp -s <(grep -av seconds "$work/whole/field.vti") <(grep -av seconds "$work/cut/field.vti") ||
  { echo "FAIL: field.vti differs"; fail=1; }
[ $fail = 0 ] && echo "mpi resume (np $np): all passed"
exit $fail
