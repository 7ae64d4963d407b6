#!/usr/bin/env bash
# mesh, graded and scaffold inputs. Numbers without a finite range (--cell-size
# 1e-300 wrote an all-zero STL), a field with no surface, empty or foreign graded members, and
# outputs that are their own inputs (by file identity, not by name): refused before any work,
# nothing written, the input untouched.
source "$(dirname "$0")/usage.bash" "$1"
export OMP_NUM_THREADS=1
command -v python3 >/dev/null || { echo "SKIP: python3 not found"; exit 77; }
r="$work/run"
"$bin" run --paper --surface P --grid 16 --max-steps 2 --quiet --out "$r" \
  || { echo "FAIL: run"; exit 1; }
"$bin" run --paper --surface G --grid 16 --max-steps 2 --quiet --out "$work/g" ||
  { echo "FAIL: run G"; exit 1; }
"$bin" run --paper --surface P --grid 16 --max-steps 2 --volume-fraction 0.4 --quiet \
  --out "$work/p40" \
  || { echo "FAIL: run P 0.4"; exit 1; }

# Ranges.
check_usage a.stl --cell-size mesh --from "$r" --cell-size 1e-300
check_usage b.stl --cell-size mesh --from "$r" --cell-size 1e300
check_usage c.stl --cell-size graded --members "$r,$work/p40" --from-fraction 0.42 \
  --to-fraction 0.48 --cell-size 1e-300
s=(scaffold --grid 16 --cache "$work/cache" --porosity 0.7)
check_usage d.stl --cell-size "${s[@]}" --cell-size 1e-300
check_usage e.stl --size "${s[@]}" --size 1e-300
check_usage f.stl --tolerance "${s[@]}" --tolerance 1e300
check_usage g.stl --min-feature "${s[@]}" --min-feature 1e300
check_usage h.stl --max-triangles "${s[@]}" --max-triangles 9000000000000
"$bin" mesh --from "$r" --cell-size 1e-300 --out "$work/x.stl" 2>"$work/stderr"
grep -q -- "--cell-size: got 1e-300; accepted: 0.001 .. 1e+06" "$work/stderr" ||
  { echo "FAIL: the range is not named: $(cat "$work/stderr")"; fail=1; }

# A field with no surface (every phi 0): exit 1 naming the file, nothing written.
python3 - "$r/field.vti" "$work/zero.vti" <<'PY'
import struct, sys
data = bytearray(open(sys.argv[1], "rb").read())
marker = data.index(b"_", data.index(b"<AppendedData")) + 1
size = struct.unpack("<Q", bytes(data[marker:marker + 8]))[0]
data[marker + 8:marker + 8 + size] = bytes(size)
open(sys.argv[2], "wb").write(data)
PY
for solid in surface network; do
  "$bin" mesh --from "$work/zero.vti" --solid "$solid" --out "$work/zero.stl" 2>"$work/stderr"
  rc=$?
  if [ "$rc" -ne 1 ] || ! grep -q "zero.vti" "$work/stderr" || ! grep -q "no phi = 1/2 surface" \
      "$work/stderr" || compgen -G "$work/zero.stl*" >/dev/null; then
    echo "FAIL: a field with no surface ($solid): rc $rc"; cat "$work/stderr"; fail=1
  fi
done

# graded: an empty item, members of two families.
check_usage i.stl --members graded --members "$r,,$work/p40" --from-fraction 0.42 --to-fraction 0.48
grep -q "item 2 .* is empty" "$work/stderr" || { echo "FAIL: empty item not named"; fail=1; }
check_usage j.stl --members graded --members "$r,$work/g" --from-fraction 0.49 --to-fraction 0.5
grep -q "$work/g" "$work/stderr" || { echo "FAIL: the G member is not named"; fail=1; }

# Outputs that are inputs: by any name (another spelling, a symlink, the FILE.json sidecar).
sum() { cksum "$r/report.json" "$r/field.vti" "$work/shape.stl" 2>/dev/null; }
printf 'solid s\nendsolid s\n' >"$work/shape.stl"
ln -s "$r/field.vti" "$work/link.stl"
before=$(sum)
expect_same() {  # <option named> <args...>
  local opt="$1"; shift
  "$bin" "$@" >/dev/null 2>"$work/stderr"
  local rc=$?
  if [ "$rc" -ne 2 ] || ! grep -q -- "$opt" "$work/stderr" ||
      ! grep -q "same file" "$work/stderr"; then
    echo "FAIL: '$*' exited $rc:"; cat "$work/stderr"; fail=1
  fi
  [ "$(sum)" = "$before" ] || { echo "FAIL: '$*' changed an input"; fail=1; before=$(sum); }
}
expect_same --from mesh --from "$r" --out "$r/report.json"
expect_same --from mesh --from "$r/field.vti" --out "$r/field.vti"
expect_same --from mesh --from "$r" --out "$work/./run/../run/field.vti"
expect_same --from mesh --from "$r" --out "$work/link.stl"
expect_same "--out's report" mesh --from "$r" --out "$r/report" --format stl
expect_same --members graded --members "$r,$work/p40" --from-fraction 0.42 --to-fraction 0.48 \
  --out "$work/p40/field.vti"
expect_same --shape scaffold --grid 16 --cache "$work/cache" --porosity 0.7 \
  --shape "$work/shape.stl" --out "$work/shape.stl"
[ -e "$work/cache" ] && { echo "FAIL: scaffold computed a member before refusing"; fail=1; }
[ "$fail" -eq 0 ] && echo "mesh_inputs: all passed"
exit "$fail"
