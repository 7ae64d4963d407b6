#!/usr/bin/env bash
# cmcsurf mesh / graded on damaged or hostile field files: a non-zero exit, a message naming
# the file and the problem, and no mesh written.
set -u
bin="$1"
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
"$bin" run --paper --surface P --grid 16 --max-steps 2 --quiet --out "$work/run" ||
  { echo "FAIL: run"; exit 1; }
# Damage copies of field.vti with Python: a NaN in phi, a truncated file, a header with no end.
python3 - "$work" <<'PY'
import os, struct, sys
work = sys.argv[1]
data = open(f"{work}/run/field.vti", "rb").read()
start = data.index(b"<AppendedData")
marker = data.index(b"_", start) + 1
os.makedirs(f"{work}/nan"); os.makedirs(f"{work}/cut"); os.makedirs(f"{work}/endless")
at = marker + 8 + 8 * 100  # the 101st value of phi
open(f"{work}/nan/field.vti", "wb").write(data[:at] + struct.pack("<d", float("nan"))
                                          + data[at + 8:])
open(f"{work}/cut/field.vti", "wb").write(data[: len(data) // 2])
open(f"{work}/endless/field.vti", "wb").write(data[:start] + b"<!-- " + b"x" * (3 << 20))
PY
for case in nan:non-finite cut:truncated endless:"first 1048576 bytes"; do
  name=${case%%:*}
  want=${case#*:}
  "$bin" mesh --from "$work/$name" --out "$work/$name.stl" --quiet 2>"$work/err"
  rc=$?
  if [ "$rc" = 0 ]; then echo "FAIL: $name: exit 0"; fail=1; fi
  grep -q "$want" "$work/err" || { echo "FAIL: $name: no '$want' in: $(cat "$work/err")"; fail=1; }
  grep -q "$work/$name/field.vti" "$work/err" ||
    { echo "FAIL: $name: the file is not named"; fail=1; }
  if ls "$work" | grep -q "^$name.stl"; then echo "FAIL: $name: a mesh was written"; fail=1; fi
done
# graded reads its members the same way.
"$bin" graded --members "$work/run,$work/nan" --from-fraction 0.45 --to-fraction 0.5 \
  --out "$work/g.stl" --quiet 2>"$work/err"
if [ $? = 0 ] || ! grep -q "non-finite" "$work/err" || [ -e "$work/g.stl" ]; then
  echo "FAIL: graded accepted a NaN member: $(cat "$work/err")"; fail=1
fi
[ "$fail" = 0 ] && echo "mesh_bad_data: all passed"
exit "$fail"
