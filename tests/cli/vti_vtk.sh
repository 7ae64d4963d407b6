#!/usr/bin/env bash
# field.vti read by VTK itself (python3-vtk9), when it is installed: dimensions, spacing, origin
# and the values (their mean is report.json's mass).
set -eu
bin="$1"
if ! /usr/bin/python3 -c "import vtk" 2>/dev/null; then
  echo "vti_vtk: skipped (python3-vtk9 not installed: apt-get install python3-vtk9 to run it)"
  exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" run --surface D --volume-fraction 0.4 --grid 16 --epsilon 0.04 --max-steps 50 --quiet \
  --out "$work/d"
/usr/bin/python3 - "$work/d" <<'PY'
import json, sys, vtk
d = sys.argv[1]
r = vtk.vtkXMLImageDataReader()
r.SetFileName(f"{d}/field.vti")
r.Update()
img = r.GetOutput()
assert img.GetDimensions() == (16, 16, 16), img.GetDimensions()
assert abs(img.GetSpacing()[0] - 1 / 16) < 1e-15 and abs(img.GetOrigin()[0] - 1 / 32) < 1e-15
a = img.GetPointData().GetArray("phi")
assert a is not None and a.GetNumberOfTuples() == 16 ** 3
mean = sum(a.GetValue(i) for i in range(a.GetNumberOfTuples())) / 16 ** 3
rep = json.load(open(f"{d}/report.json"))
assert abs(mean - rep["mass"]) < 1e-12, (mean, rep["mass"])
print("vti_vtk: VTK reads field.vti; mean", mean)
PY
