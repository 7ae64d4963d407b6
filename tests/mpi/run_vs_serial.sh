#!/usr/bin/env bash
# mpirun -np P cmcsurf run against the same run on one process: same steps and V-cycles,
# area, volume fraction and mass to round-off; outputs written once (the field: one piece per
# rank, field.pvti); the field readable by `cmcsurf mesh`; bad input under mpirun exits 2 on
# every rank, writing nothing.
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
# The stages after the solve run on the blocks too (sums reduced over the ranks).
for key in ("area", "volume_fraction", "mass", "energy", "mean_curvature", "area_iso",
            "area_diffuse", "mean_curvature_diffuse", "mean_curvature_std", "area_error",
            "mean_curvature_error", "mean_curvature_local_mean", "nodal_level",
            "nodal_volume_fraction", "nodal_area", "nodal_area_diffuse", "nodal_mean_curvature",
            "nodal_mean_curvature_diffuse", "nodal_mean_curvature_std", "nodal_std_ratio",
            "mean_curvature_mu_gap"):
    rel = abs(s[key] - m[key]) / max(abs(s[key]), 1e-12)
    print(f"{key}: serial {s[key]!r} mpi {m[key]!r} rel {rel:.2e}")
    if rel > 1e-10: bad.append(f"{key}: relative difference {rel:.2e} > 1e-10")
if s["euler_characteristic"] != m["euler_characteristic"]: bad.append("euler_characteristic")
if m["mpi_ranks"] != np: bad.append(f"mpi_ranks {m['mpi_ranks']} != {np}")
if len(m.get("peak_memory_bytes_per_rank", [])) != np: bad.append("peak_memory_bytes_per_rank")
if len(m["process_grid"]) != 3: bad.append("process_grid")
for b in bad: print("FAIL:", b)
sys.exit(1 if bad else 0)
PY
cmp -s "$work/serial/preview.png" "$work/mpi/preview.png" \
  || { echo "FAIL: preview.png differs from the serial run's"; fail=1; }
[ "$(ls "$work/mpi/field" | grep -c '^piece_[0-9]*\.vti$')" = "$np" ] \
  || { echo "FAIL: field/ does not hold $np pieces"; ls "$work/mpi/field"; fail=1; }
[ ! -e "$work/mpi/field.vti" ] || { echo "FAIL: an MPI run wrote field.vti"; fail=1; }
# VTK's own reader opens the partitioned field; its points equal the serial field.vti's.
if /usr/bin/python3 -c "import vtk" 2>/dev/null; then
  /usr/bin/python3 - "$work/serial/field.vti" "$work/mpi/field.pvti" <<'PY' || fail=1
import sys, vtk
from vtk.util.numpy_support import vtk_to_numpy
def read(reader, path):
    reader.SetFileName(path)
    reader.Update()
    out = reader.GetOutput()
    return out.GetDimensions(), vtk_to_numpy(out.GetPointData().GetArray("phi"))
ds, s = read(vtk.vtkXMLImageDataReader(), sys.argv[1])
dm, m = read(vtk.vtkXMLPImageDataReader(), sys.argv[2])
diff = abs(s - m).max() if ds == dm else float("inf")
print(f"field.pvti against field.vti: dimensions {dm} {ds}, max |difference| {diff:.2e}")
sys.exit(0 if diff < 1e-12 else 1)
PY
fi
[ "$(wc -l <"$work/serial/history.csv")" = "$(wc -l <"$work/mpi/history.csv")" ] \
  || { echo "FAIL: history.csv lengths differ"; fail=1; }
# The field of an MPI run meshes like any other (cmcsurf mesh is serial).
"$bin" mesh --from "$work/mpi" --out "$work/mpi.stl" --quiet ||
  { echo "FAIL: mesh of mpi field"; fail=1; }
test -s "$work/mpi.stl" || { echo "FAIL: no mesh"; fail=1; }
# run --mesh under mpirun meshes plane by plane on rank 0 (no whole-grid gather): the serial
# mesher's file of the same field, byte for byte.
cmp -s "$work/mpi.stl" "$work/mpi/surface.stl" \
  || { echo "FAIL: run --mesh under mpirun differs from mesh --from of its field"; fail=1; }

# The fast mode's per-step algorithms (extrapolated guesses, adaptive dt, relative V-cycle
# stop) on blocks: the same steps and result as on one process.
fast=(--extrapolate --dt-max-factor 8 --mg-rtol 1e-2)
"$bin" "${args[@]}" "${fast[@]}" --out "$work/serial-fast" ||
  { echo "FAIL: serial fast run"; exit 1; }
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
  [ "$rc" -eq 2 ] ||
    { echo "FAIL: '$*' under mpirun exited $rc, want 2"; cat "$work/stderr"; fail=1; }
  grep -q -- "$opt" "$work/stderr" ||
    { echo "FAIL: '$*' does not name $opt"; cat "$work/stderr"; fail=1; }
  [ "$(grep -c '^error:' "$work/stderr")" -eq 1 ] ||
    { echo "FAIL: not one message:"; cat "$work/stderr"; fail=1; }
  if compgen -G "$work/$name*" >/dev/null; then echo "FAIL: '$*' wrote $name"; fail=1; fi
}
expect_usage lex "--smoother" "${args[@]}" --smoother lex
expect_usage mgtol "--mg-tol" "${args[@]}" --mg-tol -1
expect_usage graded "mpirun" graded --members a,b --from-fraction 0.3 --to-fraction 0.6
exit $fail
