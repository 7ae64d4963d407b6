#!/usr/bin/env bash
# Threads per rank under mpirun (docs/scaling.md, "Threads per rank"): without OMP_NUM_THREADS
# and --threads the ranks of a node divide the CPUs they are bound to, so the issue-16 run
# (which spun for over 10 minutes with one thread per visible core in every rank) ends in
# seconds; an explicit count is respected, and rank 0 warns once when it oversubscribes.
# Usage: threads.sh <cmcsurf> <ranks> <mpiexec>
set -u
bin="$1"
np="$2"
mpiexec="$3"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
# This machine is the node (nproc obeys OMP_*).
cpus=$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)
# CTest's environment sets OMP_NUM_THREADS=1 for the MPI tests; the defaults are the point
# here, so every mpirun below runs under `env -u OMP_NUM_THREADS` or sets it.

# check REPORT WANT: threads_per_rank has one entry per rank, each WANT (or, for "default",
# at least 1 and at most the CPUs), and their sum (ranks x threads on this node) at most the CPUs
# unless there are more ranks than CPUs (one thread each then).
check() {
  python3 - "$1" "$np" "$cpus" "$2" <<'PY'
import json, sys
report, np, cpus = json.load(open(sys.argv[1])), int(sys.argv[2]), int(sys.argv[3])
want = sys.argv[4]
per_rank = report.get("threads_per_rank")
print(f"{sys.argv[1]}: threads {report['threads']} threads_per_rank {per_rank} on {cpus} CPUs, "
      f"wall {report['wall_seconds']:.2f} s")
bad = []
if not isinstance(per_rank, list) or len(per_rank) != np:
    bad.append(f"threads_per_rank {per_rank!r}: want {np} entries")
elif per_rank[0] != report["threads"]:
    bad.append("threads is not rank 0's count")
elif want == "default":
    if min(per_rank) < 1: bad.append("a rank with no thread")
    if sum(per_rank) > max(cpus, np): bad.append(f"{sum(per_rank)} threads > {max(cpus, np)}")
elif want == "unbound":  # every rank sees every CPU: an equal share
    share = max(1, cpus // np)
    if per_rank != [share] * np: bad.append(f"want {share} each")
elif per_rank != [int(want)] * np:
    bad.append(f"want {want} each")
for b in bad: print("FAIL:", b)
sys.exit(1 if bad else 0)
PY
}

# The issue's command with mpirun's default binding; a minute is ~20x what it needs.
start=$(date +%s%N)
timeout 60 env -u OMP_NUM_THREADS "$mpiexec" -np "$np" --oversubscribe \
  "$bin" run --surface D --grid 32 --quiet --no-preview --no-report --out "$work/default" \
  2>"$work/stderr"
rc=$?
ms=$((($(date +%s%N) - start) / 1000000))
echo "mpirun -np $np run --surface D --grid 32: exit $rc in $ms ms"
[ "$rc" -eq 0 ] || { echo "FAIL: exit $rc (124: over 60 s)"; cat "$work/stderr"; exit 1; }
check "$work/default/report.json" default || fail=1
if grep -q "^warning: .*OpenMP threads" "$work/stderr"; then
  echo "FAIL: default threads warned"; cat "$work/stderr"; fail=1
fi

# Unbound ranks all see every CPU: each takes an equal share, at least 1.
args=(run --surface D --grid 16 --max-steps 3 --quiet --no-preview --no-report)
timeout 60 env -u OMP_NUM_THREADS "$mpiexec" -np "$np" --oversubscribe --bind-to none \
  "$bin" "${args[@]}" --out "$work/unbound" 2>"$work/stderr" \
  || { echo "FAIL: unbound run"; cat "$work/stderr"; fail=1; }
check "$work/unbound/report.json" unbound || fail=1

# Explicit counts are respected; rank 0 warns once when the node gets more threads than CPUs
# (and than ranks). Passive waiting keeps the deliberately oversubscribed threads from spinning.
# expect_explicit NAME WANT OMP_NUM_THREADS [run options]
expect_explicit() {
  local name="$1" want="$2" env_threads="$3"; shift 3
  OMP_WAIT_POLICY=passive OMP_NUM_THREADS="$env_threads" timeout 60 \
    "$mpiexec" -np "$np" --oversubscribe "$bin" "${args[@]}" "$@" --out "$work/$name" \
    2>"$work/stderr" || { echo "FAIL: $name run"; cat "$work/stderr"; fail=1; return; }
  check "$work/$name/report.json" "$want" || fail=1
  local warnings expect=0
  warnings=$(grep -c "^warning: .*OpenMP threads" "$work/stderr")
  [ $((want * np)) -gt $((cpus > np ? cpus : np)) ] && expect=1
  [ "$warnings" -eq "$expect" ] \
    || { echo "FAIL: $name: $warnings oversubscription warnings, want $expect"; cat "$work/stderr"
         fail=1; }
}
over=$((cpus + 1))  # more than the node's CPUs on any number of ranks
expect_explicit env "$over" "$over"
expect_explicit option 1 "$over" --threads 1  # --threads wins over OMP_NUM_THREADS
exit $fail
