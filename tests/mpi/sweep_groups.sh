#!/usr/bin/env bash
# mpirun -np P cmcsurf sweep (docs/scaling.md, "Sweeps across nodes"): the ranks split into
# groups, each running its members decomposed over the group, world rank 0 writing sweep.csv,
# the figures and sweep.json. Against the serial sweep: the same members, files and columns,
# areas to 1e-12 (bit for bit on groups of one process); with --continuation every family
# stays on one group; sweep --resume under groups keeps complete members and continues members
# a SIGTERM stopped; an error in one group ends the sweep with exit 1 without hanging the
# others; bad --groups exits 2; no environment variable is needed.
# Usage: sweep_groups.sh <cmcsurf> <ranks> <mpiexec>
set -u
bin="$1"
support="$(cd "$(dirname "$0")/../support" && pwd)"  # report_keys.py: the timing keys
export CMCSURF_BIN="$bin"  # report_keys.py reads the timing keys from its `schema --json`
np="$2"
mpiexec="$3"
export OMP_NUM_THREADS=1  # the serial reference on one thread, as each rank below
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
mpi() { timeout 60 "$mpiexec" -np "$np" --oversubscribe "$bin" "$@"; }
# A fixed number of steps (--tol far below reach) and the mass constraint: no stop decision
# that round-off could flip between a whole grid and blocks (tests/mpi/run_vs_serial.sh).
args=(sweep --surface P,D --volume-fractions 0.4,0.6 --grid 16 --max-steps 12 --tol 1e-30
      --constrain mass --no-report)

# compare.py SERIAL MPI TOL: same members in the same order, the serial columns all present,
# the non-timing columns equal: areas, volume fractions, mass and energy within TOL relative
# (TOL 0: bit for bit), the other numbers within max(TOL, 1e-10) x max(|value|, 1) (curvatures
# near 0 after cancellation: 2e-12 relative seen on D at 0.5, absolute 2e-14; the last step's
# change of area final_d_area: 2e-11 relative, 9e-16 absolute).
cat >"$work/compare.py" <<'PY'
import csv, sys
a, b = (list(csv.DictReader(open(f"{d}/sweep.csv"))) for d in sys.argv[1:3])
tol = float(sys.argv[3])
from report_keys import TIMING_KEYS
timing = TIMING_KEYS | {"threads"}  # the serial sweep and the groups use other thread counts
bad = []
if [r["member"] for r in a] != [r["member"] for r in b]:
    bad.append(f"members {[r['member'] for r in a]} vs {[r['member'] for r in b]}")
missing = set(a[0]) - set(b[0]) if a and b else set()
if missing: bad.append(f"columns missing under mpirun: {sorted(missing)}")
worst = 0.0
for x, y in zip(a, b):
    for k in set(x) - timing - missing:
        if x[k] == y[k]: continue
        try:
            u, v = float(x[k]), float(y[k])
        except ValueError:
            bad.append(f"{x['member']} {k}: {x[k]!r} vs {y[k]!r}"); continue
        rel = abs(u - v) / max(abs(u), 1e-300)
        strict = k in ("area", "area_iso", "area_diffuse", "nodal_area", "nodal_area_iso",
                       "nodal_area_diffuse", "nodal_area_tanh", "volume_fraction", "mass",
                       "energy")
        if strict: worst = max(worst, rel)
        ok = rel <= tol if strict else abs(u - v) <= max(tol, 1e-10) * max(abs(u), 1.0)
        if not ok or k in ("steps", "vcycles", "prerelax_steps"):
            bad.append(f"{x['member']} {k}: {u!r} vs {v!r} (rel {rel:.1e})")
    print(f"{x['member']}: area serial {x['area']} mpi {y['area']} group {y.get('sweep_group')}")
print(f"{len(a)} members, largest relative difference in areas, volume, mass, energy "
      f"{worst:.1e} (allowed {tol:g})")
for m in bad: print("FAIL:", m)
sys.exit(1 if bad else 0)
PY
# A member run on a group of several ranks writes field.pvti with one piece per rank where a
# serial member writes field.vti (io/pvti.h): the same file for this comparison.
files() {
  (cd "$1" && find . -type f ! -name '*.png' ! -name '*.svg' |
     sed -e 's|/field\.pvti$|/field.vti|' -e '/\/field\/piece_[0-9]*\.vti$/d' | sort)
}

"$bin" "${args[@]}" --quiet --out "$work/serial" || { echo "FAIL: serial sweep"; exit 1; }

# 2 groups (np 2: of one rank; np 4: of two ranks, each member decomposed 1 x 1 x 2).
mpi "${args[@]}" --groups 2 --out "$work/g2" 2>"$work/g2.log"
rc=$?
[ $rc = 0 ] ||
  { echo "FAIL: mpirun -np $np sweep --groups 2 exited $rc"; cat "$work/g2.log"; exit 1; }
grep -q "in 2 groups of $((np / 2))" "$work/g2.log" ||
  { echo "FAIL: no plan printed"; cat "$work/g2.log"; fail=1; }
PYTHONPATH="$support" python3 "$work/compare.py" "$work/serial" "$work/g2" 1e-12 || fail=1
if [ "$np" = 4 ]; then  # groups of two: every member's field in two pieces, read by mesh --from
  for d in "$work"/g2/*/; do
    [ "$(ls "$d/field" 2>/dev/null | grep -c '^piece_[0-9]*\.vti$')" = 2 ] ||
      { echo "FAIL: $d holds no field.pvti in 2 pieces"; ls -R "$d"; fail=1; }
  done
  "$bin" mesh --from "$work/g2/P_0.40" --out "$work/p40.stl" --quiet ||
    { echo "FAIL: mesh --from a member's field.pvti"; fail=1; }
fi
[ "$(files "$work/serial")" = "$(files "$work/g2")" ] ||
  { echo "FAIL: files differ:"; diff <(files "$work/serial") <(files "$work/g2"); fail=1; }
[ -s "$work/g2/gallery.png" ] || { echo "FAIL: no gallery.png"; fail=1; }
if /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  [ -s "$work/g2/families.png" ] || { echo "FAIL: world rank 0 drew no families.png"; fail=1; }
fi
python3 - "$work/g2" "$np" <<'PY' || fail=1
import csv, json, sys
d, np = sys.argv[1], int(sys.argv[2])
s = json.load(open(f"{d}/sweep.json"))
assert s["complete"] and s["members"] == 4, s
assert s["mpi"] == {"ranks": np, "groups": 2, "ranks_per_group": np // 2}, s["mpi"]
rows = list(csv.DictReader(open(f"{d}/sweep.csv")))
# Members dealt round robin: P_0.40 D_0.40 on group 0, P_0.60 D_0.60 on group 1.
assert [int(r["sweep_group"]) for r in rows] == [0, 1, 0, 1], [r["sweep_group"] for r in rows]
assert all(int(r["mpi_ranks"]) == np // 2 for r in rows)
for r in rows:
    rep = json.load(open(f"{d}/{r['member']}/report.json"))
    assert float(r["area"]) == rep["area"] and rep["process_grid"][2] == np // 2, rep
PY

# The automatic plan: a member per rank (np groups of one), the serial code bit for bit.
mpi "${args[@]}" --no-plot --out "$work/auto" 2>"$work/auto.log" ||
  { echo "FAIL: mpirun sweep without --groups"; cat "$work/auto.log"; fail=1; }
grep -q "in $np groups of 1" "$work/auto.log" ||
  { echo "FAIL: automatic plan"; cat "$work/auto.log"; fail=1; }
PYTHONPATH="$support" python3 "$work/compare.py" "$work/serial" "$work/auto" 0 || fail=1

# Continuation: each family runs in order on one group (np 4: 2 groups of 2).
cargs=(sweep --surface P,D --volume-fractions 0.4,0.5,0.6 --grid 16 --max-steps 12 --tol 1e-30
       --constrain mass --continuation --no-plot --no-report --no-preview)
"$bin" "${cargs[@]}" --quiet --out "$work/cserial" || { echo "FAIL: serial continuation"; exit 1; }
mpi "${cargs[@]}" --out "$work/cmpi" 2>"$work/cmpi.log" ||
  { echo "FAIL: mpirun sweep --continuation"; cat "$work/cmpi.log"; fail=1; }
grep -q "group 0 (ranks .*): P_0.40, P_0.50, P_0.60$" "$work/cmpi.log" ||
  { echo "FAIL: a family split between groups"; cat "$work/cmpi.log"; fail=1; }
PYTHONPATH="$support" python3 "$work/compare.py" "$work/cserial" "$work/cmpi" 1e-12 || fail=1

# Resume under groups: the first member of each family complete, the rest to run (from the
# kept member's field.vti, cut into the group's blocks).
cp -r "$work/cserial" "$work/cres"
rm -rf "$work/cres/P_0.50" "$work/cres/P_0.60" "$work/cres/D_0.50" "$work/cres/D_0.60"
mpi sweep --resume "$work/cres" 2>"$work/cres.log" ||
  { echo "FAIL: mpirun sweep --resume"; cat "$work/cres.log"; fail=1; }
PYTHONPATH="$support" python3 "$work/compare.py" "$work/cserial" "$work/cres" 1e-12 || fail=1
python3 -c "
import json, sys; s = json.load(open('$work/cres/sweep.json'))
ok = s['complete'] and s['resumed'] == {'members_kept': 2, 'members_resumed': 0}
sys.exit(0 if ok else 1)" ||
  { echo "FAIL: resumed sweep.json"; cat "$work/cres/sweep.json"; fail=1; }

# SIGTERM to the ranks (mpirun passes it on): every group stops its member after one agreed
# step with a checkpoint, mpirun exits 143, and the printed resume finishes the sweep on the
# bits of the uninterrupted mpirun sweep, in the fast mode with its Anderson mixing (a
# checkpoint carries the mixer's history, so a member stopped mid-mixing resumes to the same
# bits). Against the serial sweep the mixing makes the sums' other order on a group of several
# ranks show more (3.1e-12 relative in area_diffuse on np 4, groups of 2 ranks), so the bits
# are compared with the uninterrupted mpirun sweep.
sargs=(sweep --surface P --volume-fractions 0.4,0.6 --grid 32 --max-steps 120 --tol 1e-30
       --constrain mass --no-plot --no-preview --no-report)
mpi "${sargs[@]}" --quiet --out "$work/smpi" || { echo "FAIL: mpirun 32^3 sweep"; exit 1; }
timeout 60 "$mpiexec" -np "$np" --oversubscribe "$bin" "${sargs[@]}" --out "$work/cut" \
  2>"$work/cut.log" &
pid=$!
while kill -0 $pid 2>/dev/null; do  # until world rank 0's member relaxes
  grep -q "^relax " "$work/cut.log" && break
  sleep 0.01
done
# To the ranks, the children of mpiexec (a signal to mpiexec itself makes it exit 1).
pkill -TERM -P "$(pgrep -P $pid | head -1)"
wait $pid
rc=$?
[ $rc = 143 ] ||
  { echo "FAIL: SIGTERM to the ranks: exit $rc, want 143"; cat "$work/cut.log"; fail=1; }
grep -q "resume with: mpirun -np $np .* sweep --resume $work/cut" "$work/cut.log" ||
  { echo "FAIL: no resume hint"; cat "$work/cut.log"; fail=1; }
[ -s "$work/cut/P_0.40/checkpoint.bin" ] || { echo "FAIL: no checkpoint of P_0.40"; fail=1; }
mpi sweep --resume "$work/cut" 2>"$work/resume.log" ||
  { echo "FAIL: resume after SIGTERM"; cat "$work/resume.log"; fail=1; }
PYTHONPATH="$support" python3 "$work/compare.py" "$work/smpi" "$work/cut" 0 || fail=1
if find "$work/cut" -name 'checkpoint*' | grep -q .; then echo "FAIL: checkpoint left"; fail=1; fi

# An error in one group (a file where its member's folder goes, in a folder that is the sweep's
# own): that group stops, the other finishes its members, world rank 0 says which group
# failed, every rank exits 1, no hang.
mkdir "$work/err" && : >"$work/err/.cmcsurf" && echo x >"$work/err/P_0.60"
mpi "${args[@]}" --groups 2 --no-plot --no-preview --out "$work/err" 2>"$work/err.log"
rc=$?
[ $rc = 1 ] ||
  { echo "FAIL: an error in one group exited $rc, want 1"; cat "$work/err.log"; fail=1; }
grep -q "^group 1: error: .*P_0.60" "$work/err.log" ||
  { echo "FAIL: no group 1 error"; cat "$work/err.log"; fail=1; }
for m in P_0.40 D_0.40; do
  [ -s "$work/err/$m/report.json" ] || { echo "FAIL: group 0 did not finish $m"; fail=1; }
done

# Bad --groups: exit 2 on every rank, one message naming the option, nothing written.
for g in 3 8 -1; do  # none divides 2 or 4
  mpi "${args[@]}" --groups "$g" --out "$work/bad" >/dev/null 2>"$work/bad.log"
  rc=$?
  [ $rc = 2 ] || { echo "FAIL: --groups $g exited $rc"; cat "$work/bad.log"; fail=1; }
  [ "$(grep -c '^error: --groups' "$work/bad.log")" = 1 ] && grep -q "accepted" "$work/bad.log" ||
    { echo "FAIL: --groups $g message"; cat "$work/bad.log"; fail=1; }
  [ ! -e "$work/bad" ] || { echo "FAIL: --groups $g wrote $work/bad"; fail=1; }
done

# Without any environment variable (threads per rank from the CPUs, src/parallel/threads.*).
env -u OMP_NUM_THREADS timeout 60 "$mpiexec" -np "$np" --oversubscribe "$bin" "${args[@]}" \
  --no-plot --no-preview --quiet --out "$work/noenv" ||
  { echo "FAIL: mpirun sweep without OMP_NUM_THREADS"; fail=1; }
[ -s "$work/noenv/sweep.csv" ] || { echo "FAIL: no sweep.csv without OMP_NUM_THREADS"; fail=1; }

[ $fail = 0 ] && echo "sweep_groups (np $np): all passed"
exit $fail
