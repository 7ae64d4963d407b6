#!/usr/bin/env bash
# A member of another topology than its family's is refused by scaffold and mesh
# (exit 1, both Euler characteristics named, nothing written) unless --accept-topology-change;
# the scaffold cache keeps a CRC-32 of each member's field and recomputes a damaged entry.
set -u
bin="$1"
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
command -v python3 >/dev/null || { echo "SKIP: python3 not found"; exit 77; }
cache="$work/cache"
sc=(scaffold --surface P --solid network --porosity 0.5 --cell-size 2 --size 4 --grid 16 --fast
    --cache "$cache")
"$bin" "${sc[@]}" --quiet --out "$work/a.stl" || { echo "FAIL: scaffold"; exit 1; }
entry=$(echo "$cache"/P-*)
py() { python3 - "$entry" "$work" "$@"; }
# The entry's checksum and the run's two Euler characteristics.
py <<'PY' || fail=1
import json, sys, zlib
entry, work = sys.argv[1:3]
m = json.load(open(f"{entry}/member.json"))
crc = zlib.crc32(open(f"{entry}/field.vti", "rb").read())
assert m["field_crc32"] == crc, (m.get("field_crc32"), crc)
run = json.load(open(f"{work}/a.stl.json"))["member"]["run"]
assert run["euler_characteristic_start"] == -2 and run["topology_changed"] is False, run
PY
rerun() {  # <out> <want rc> <want on stderr...>: runs the scaffold again
  local out="$1" want="$2"; shift 2
  "$bin" "${sc[@]}" --out "$work/$out" >/dev/null 2>"$work/err"
  local rc=$?
  [ "$rc" -eq "$want" ] || { echo "FAIL: $out: exit $rc, want $want"; cat "$work/err"; fail=1; }
  for w in "$@"; do
    grep -q -- "$w" "$work/err" || { echo "FAIL: $out: no '$w' in:"; cat "$work/err"; fail=1; }
  done
}
rerun b.stl 0 "reusing the member"
# A flipped bit in the field's data, then a truncated field: recomputed with a note.
py <<'PY'
import sys
f = sys.argv[1] + "/field.vti"
data = bytearray(open(f, "rb").read())
data[len(data) // 2] ^= 0x10
open(f, "wb").write(data)
PY
rerun c.stl 0 "fails its CRC-32); recomputing" "computing the member"
py <<'PY' || { echo "FAIL: the recomputed entry's checksum"; fail=1; }
import json, sys, zlib
m = json.load(open(sys.argv[1] + "/member.json"))
assert m["field_crc32"] == zlib.crc32(open(sys.argv[1] + "/field.vti", "rb").read())
PY
truncate -s 2000 "$entry/field.vti"
rerun d.stl 0 "not reused" "computing the member"
rerun e.stl 0 "reusing the member"
# The member's report says another topology (a plates member has chi -1): refused.
py <<'PY'
import json, sys
f = sys.argv[1] + "/member.json"
m = json.load(open(f))
m["run"]["euler_characteristic"] = -1
json.dump(m, open(f, "w"))
PY
rerun f.stl 1 "Euler characteristic -1 (genus 2)" "family's .* -2 (genus 3)" \
  "--accept-topology-change"
compgen -G "$work/f.stl*" >/dev/null && { echo "FAIL: f.stl written"; fail=1; }
"$bin" "${sc[@]}" --accept-topology-change --quiet --out "$work/g.stl" ||
  { echo "FAIL: --accept-topology-change"; fail=1; }

# mesh --from a run folder whose report says the same.
"$bin" run --paper --surface P --grid 16 --max-steps 2 --quiet --out "$work/run" ||
  { echo "FAIL: run"; exit 1; }
"$bin" mesh --from "$work/run" --solid network --quiet --out "$work/m0.stl" ||
  { echo "FAIL: mesh of an unchanged member"; fail=1; }
python3 - "$work/run/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["topology_changed"] is False and r["euler_characteristic_start"] == -2, r
r["euler_characteristic"] = 1
json.dump(r, open(sys.argv[1], "w"))
PY
for from in "$work/run" "$work/run/field.vti"; do
  "$bin" mesh --from "$from" --solid network --out "$work/m1.stl" 2>"$work/err"
  rc=$?
  if [ "$rc" -ne 1 ] || ! grep -q "Euler characteristic 1" "$work/err" ||
      compgen -G "$work/m1.stl*" >/dev/null; then
    echo "FAIL: mesh --from $from of a changed member: rc $rc"; cat "$work/err"; fail=1
  fi
done
"$bin" mesh --from "$work/run" --solid network --accept-topology-change --quiet \
  --out "$work/m2.stl" || { echo "FAIL: mesh --accept-topology-change"; fail=1; }

# The tester's case: a P network at porosity 0.8 ends on separate balls (chi 1) at --grid 32.
# Refused by its topology; with --accept-topology-change, by its 26 fragments (removing them
# would leave porosity 0.975, and no level brings it back).
real=(scaffold --paper --surface P --solid network --porosity 0.8 --cell-size 2 --size 4 --grid 32
      --cache "$cache")
"$bin" "${real[@]}" --out "$work/r.stl" >/dev/null 2>"$work/err"
rc=$?
if [ "$rc" -ne 1 ] || ! grep -q "Euler characteristic 1 (genus 0), its family's .* -2 (genus 3)" \
    "$work/err"; then
  echo "FAIL: the balls member: rc $rc"; cat "$work/err"; fail=1
fi
"$bin" "${real[@]}" --accept-topology-change --out "$work/r.stl" >/dev/null 2>"$work/err"
rc=$?
if [ "$rc" -ne 1 ] || ! grep -q "removing .* fragments" "$work/err" ||
    ! grep -q -- "--keep-fragments" "$work/err"; then
  echo "FAIL: the balls member's fragments: rc $rc"; cat "$work/err"; fail=1
fi
compgen -G "$work/r.stl*" >/dev/null && { echo "FAIL: r.stl written"; fail=1; }
[ "$fail" -eq 0 ] && echo "scaffold_topology: all passed"
exit "$fail"
