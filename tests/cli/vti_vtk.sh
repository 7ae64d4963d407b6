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
# 17 points per axis: the 16 cell centres and the periodic wrap (point 16 repeats point 0).
assert img.GetDimensions() == (17, 17, 17), img.GetDimensions()
assert abs(img.GetSpacing()[0] - 1 / 16) < 1e-15 and abs(img.GetOrigin()[0] - 1 / 32) < 1e-15
a = img.GetPointData().GetArray("phi")
assert a is not None and a.GetNumberOfTuples() == 17 ** 3
v = lambda i, j, k: a.GetValue(i + 17 * (j + 17 * k))
assert all(v(16, j, k) == v(0, j, k) and v(j, 16, k) == v(j, 0, k) and v(j, k, 16) == v(j, k, 0)
           for j in range(17) for k in range(17))
mean = sum(v(i, j, k) for i in range(16) for j in range(16) for k in range(16)) / 16 ** 3
rep = json.load(open(f"{d}/report.json"))
assert abs(mean - rep["mass"]) < 1e-12, (mean, rep["mass"])
# Contour at 0.5 covers the whole unit cell (no gaps along the faces): its area is the run's
# sharp area up to the two interpolants' O(h^2) difference; without the wrap a slab of one
# cell along three faces was missing (about 1 - (15/16)^3 = 18 % of the area at 16^3).
c = vtk.vtkContourFilter()
c.SetInputConnection(r.GetOutputPort())
c.SetValue(0, 0.5)
t = vtk.vtkTriangleFilter()
t.SetInputConnection(c.GetOutputPort())
m = vtk.vtkMassProperties()
m.SetInputConnection(t.GetOutputPort())
m.Update()
area = m.GetSurfaceArea()
assert abs(area / rep["area"] - 1) < 0.02, (area, rep["area"])
print("vti_vtk: VTK reads field.vti; mean", mean, "contour area", area, "report", rep["area"])
PY
