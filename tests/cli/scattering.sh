#!/usr/bin/env bash
# cmcsurf scattering on a 32^3 G run at 0.5: the outputs, the space groups of the sheet (Ia-3d)
# and of one labyrinth (I4_132), the indexing of synthetic peaks; bad input: exit 2, the option
# named, nothing written.
source "$(dirname "$0")/usage.bash" "$1"
export OMP_NUM_THREADS=1
r="$work/g"
"$bin" run --surface G --volume-fraction 0.5 --grid 32 --epsilon 0.03 --fast --quiet \
  --no-preview --no-report --out "$r" || { echo "FAIL: run"; exit 1; }
# Synthetic peaks of Ia-3d at a = 12 nm: q = 2 pi sqrt(s) / a for s = 6, 8, 14, 16.
peaks=$(python3 -c "import math
print(','.join('%.6f' % (2 * math.pi * math.sqrt(s) / 12) for s in (6, 8, 14, 16)))")
"$bin" scattering --from "$r" --density bilayer:0.05 --lattice 12 --peaks "$peaks" \
  --quiet || { echo "FAIL: scattering"; exit 1; }
"$bin" scattering --from "$r" --quiet --out "$work/step" || { echo "FAIL: step"; exit 1; }
for f in reflections.csv saxs.csv saxs.png scattering.json; do
  [ -s "$r/scattering/$f" ] || { echo "FAIL: missing scattering/$f"; exit 1; }
done
if ls "$r/scattering" | grep -q tmp; then echo "FAIL: temporary left behind"; exit 1; fi
python3 - "$r/scattering" "$work/step" <<'PY' || fail=1
import csv, json, sys
d, step = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(f"{d}/reflections.csv")))
assert list(rows[0].keys()) == ["h", "k", "l", "s", "multiplicity", "intensity", "amplitude",
                                "phase"], rows[0].keys()
r = json.load(open(f"{d}/scattering.json"))
assert r["space_group"]["symbol"] == "Ia-3d", r["space_group"]
assert [2, 1, 1] in r["allowed"] and [2, 2, 0] in r["allowed"] and [1, 1, 0] in r["absent"]
assert abs(r["indexing"]["lattice_nm"] - 12) < 1e-4, r["indexing"]
assert r["indexing"]["s"] == [6, 8, 14, 16], r["indexing"]
saxs = list(csv.DictReader(open(f"{d}/saxs.csv")))
assert len(saxs) > 100 and float(saxs[-1]["q"]) > 0
s = json.load(open(f"{step}/scattering.json"))
assert s["space_group"]["symbol"] == "I4_132" and [1, 1, 0] in s["allowed"], s["space_group"]
PY
expect_usage() { check_usage out "$@"; }  # <option> <args...>
expect_usage --from         scattering --from "$work/missing"
expect_usage --density      scattering --from "$r" --density sheet
expect_usage --density      scattering --from "$r" --density bilayer:0.3
expect_usage --smax         scattering --from "$r" --smax 226
expect_usage --smax         scattering --from "$r" --smax -1
expect_usage --lattice      scattering --from "$r" --lattice 0
expect_usage --peaks        scattering --from "$r" --peaks 0.5
expect_usage --peaks        scattering --from "$r" --peaks 0.5,x
expect_usage --peaks        scattering --from "$r" --peaks 0.5,0.5
expect_usage --debye-waller scattering --from "$r" --debye-waller -1
expect_usage --peak-width   scattering --from "$r" --peak-width -0.1
expect_usage --peak-shape   scattering --from "$r" --peak-shape voigt
expect_usage --absent-tol   scattering --from "$r" --absent-tol 0
expect_usage --index-tol    scattering --from "$r" --index-tol 1
expect_usage --threads      scattering --from "$r" --threads -1
# A field without a surface: the run's field with every phi set to 0.2.
mkdir -p "$work/flat"
python3 - "$r/field.vti" "$work/flat/field.vti" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
at = data.index(b'<AppendedData encoding="raw">')
start = data.index(b"_", at) + 1
size = struct.unpack("<Q", data[start:start + 8])[0]
body = struct.pack("<%dd" % (size // 8), *([0.2] * (size // 8)))
open(sys.argv[2], "wb").write(data[:start + 8] + body + data[start + 8 + size:])
PY
expect_usage --from scattering --from "$work/flat/field.vti"
# Peaks no Ia-3d cell fits: an error, nothing written.
"$bin" scattering --from "$r" --density bilayer:0.05 --peaks 1,1.05,1.9 --index-tol 0.001 \
  --out "$work/nofit" 2>"$work/stderr" && { echo "FAIL: unindexable peaks accepted"; fail=1; }
grep -q "no assignment" "$work/stderr" || { echo "FAIL: message"; cat "$work/stderr"; fail=1; }
[ -e "$work/nofit" ] && { echo "FAIL: wrote $work/nofit"; fail=1; }
exit $fail
