#!/usr/bin/env bash
# mpirun -np P cmcsurf run against the same run on one process: same steps and V-cycles,
# area, volume fraction and mass to round-off; outputs written once (the field: one piece per
# rank, field.pvti); the field readable by `cmcsurf mesh`; bad input under mpirun exits 2 on every rank, writing nothing.
# Usage: run_vs_serial.sh <cmcsurf> <ranks> <mpiexec>
set -u
bin="$1"
np="$2"
mpiexec="$3"
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
mpi() { "$mpiexec" -np "$np" --oversubscribe "$bin" "$@"; }
# A fixed number of steps (--tol far below reach) and the mass constraint: no stop decision
# that round-off could flip. (With the stop rule and the volume constraint's secant, a flipped
# decision changes the result by up to the run's tolerances, as between thread counts of a
# serial run: docs/scaling.md.)
args=(run --surface G --volume-fraction 0.3 --grid 16 --max-steps 12 --tol 1e-30 --constrain mass
      --quiet)

"$bin" "${args[@]}" --out "$work/serial" || { echo "FAIL: serial run"; exit 1; }
mpi "${args[@]}" --mesh stl --out "$work/mpi" >"$work/stdout" 2>"$work/stderr" \
  || { echo "FAIL: mpirun -np $np run"; cat "$work/stderr"; exit 1; }
for f in report.json history.csv curvature_histogram.csv surface.stl; do
  test -s "$work/mpi/$f" || { echo "FAIL: mpi run lacks $f"; fail=1; }
done
# The field: one piece per rank under field/ and field.pvti (io/pvti.h), or field.vti.
if [ -e "$work/mpi/field.pvti" ]; then
  [ "$(ls "$work/mpi/field" | grep -c '^piece_[0-9]*\.vti$')" = "$np" ] &&
    [ "$(grep -c '<Piece ' "$work/mpi/field.pvti")" = "$np" ] ||
    { echo "FAIL: field.pvti without one piece per rank"; fail=1; }
  [ ! -e "$work/mpi/field.vti" ] || { echo "FAIL: both field.vti and field.pvti"; fail=1; }
else
  test -s "$work/mpi/field.vti" || { echo "FAIL: mpi run lacks field.vti or field.pvti"; fail=1; }
fi
python3 - "$work/serial/report.json" "$work/mpi/report.json" "$np" <<'PY' || fail=1
import json, sys
s, m, np = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), int(sys.argv[3])
bad = []
for key in ("steps", "prerelax_steps", "vcycles", "converged"):
    if s[key] != m[key]: bad.append(f"{key}: serial {s[key]} mpi {m[key]}")
# Red-black smoothing is independent of the decomposition; only the order of the sums over
# blocks differs, so the results agree to round-off (observed ~1e-14 relative).
for key in ("area", "volume_fraction", "mass", "energy", "mean_curvature", "area_iso",
            "area_diffuse", "mean_curvature_diffuse", "mean_curvature_std"):
    rel = abs(s[key] - m[key]) / max(abs(s[key]), 1e-12)
    print(f"{key}: serial {s[key]!r} mpi {m[key]!r} rel {rel:.2e}")
    if rel > 1e-10: bad.append(f"{key}: relative difference {rel:.2e} > 1e-10")
if m["mpi_ranks"] != np: bad.append(f"mpi_ranks {m['mpi_ranks']} != {np}")
if len(m["process_grid"]) != 3: bad.append("process_grid")
for b in bad: print("FAIL:", b)
sys.exit(1 if bad else 0)
PY
[ "$(wc -l <"$work/serial/history.csv")" = "$(wc -l <"$work/mpi/history.csv")" ] \
  || { echo "FAIL: history.csv lengths differ"; fail=1; }
# The field of an MPI run meshes like any other (cmcsurf mesh is serial).
"$bin" mesh --from "$work/mpi" --out "$work/mpi.stl" --quiet || { echo "FAIL: mesh of mpi field"; fail=1; }
test -s "$work/mpi.stl" || { echo "FAIL: no mesh"; fail=1; }

# The fast mode's per-step algorithms (extrapolated guesses, adaptive dt, relative V-cycle
# stop) on blocks: the same steps and result as on one process.
fast=(--extrapolate --dt-max-factor 8 --mg-rtol 1e-2)
"$bin" "${args[@]}" "${fast[@]}" --out "$work/serial-fast" || { echo "FAIL: serial fast run"; exit 1; }
mpi "${args[@]}" "${fast[@]}" --out "$work/mpi-fast" >"$work/stdout" 2>"$work/stderr" \
  || { echo "FAIL: mpirun -np $np fast run"; cat "$work/stderr"; exit 1; }
python3 - "$work/serial-fast/report.json" "$work/mpi-fast/report.json" <<'PY' || fail=1
import json, sys
s, m = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
bad = [k for k in ("steps", "vcycles", "dt_max") if s[k] != m[k]]
for key in ("area", "volume_fraction", "mass"):
    rel = abs(s[key] - m[key]) / max(abs(s[key]), 1e-12)
    print(f"fast {key}: rel {rel:.2e}")
    if rel > 1e-10: bad.append(key)
for b in bad: print("FAIL: fast mode under mpirun differs in", b)
sys.exit(1 if bad else 0)
PY

# Refused under mpirun: lexicographic ordering, commands other than run and sweep
# (tests/mpi/sweep_groups.sh); exit 2, nothing written.
expect_usage() {
  local name="$1" opt="$2"; shift 2
  mpi "$@" --out "$work/$name" >"$work/stdout" 2>"$work/stderr"
  local rc=$?
  [ "$rc" -eq 2 ] || { echo "FAIL: '$*' under mpirun exited $rc, want 2"; cat "$work/stderr"; fail=1; }
  grep -q -- "$opt" "$work/stderr" || { echo "FAIL: '$*' does not name $opt"; cat "$work/stderr"; fail=1; }
  [ "$(grep -c '^error:' "$work/stderr")" -eq 1 ] || { echo "FAIL: not one message:"; cat "$work/stderr"; fail=1; }
  if compgen -G "$work/$name*" >/dev/null; then echo "FAIL: '$*' wrote $name"; fail=1; fi
}
expect_usage lex "--smoother" "${args[@]}" --smoother lex
expect_usage mgtol "--mg-tol" "${args[@]}" --mg-tol -1
expect_usage graded "mpirun" graded --members a,b --from-fraction 0.3 --to-fraction 0.6
exit $fail
