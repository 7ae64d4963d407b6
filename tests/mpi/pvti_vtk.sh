#!/usr/bin/env bash
# field.pvti opened by VTK itself (python3-vtk9, when installed): vtkXMLPImageDataReader
# assembles the P pieces that `mpirun -np P` wrote (one per rank, io/pvti.h) into the image that
# vtkXMLImageDataReader reads from the serial writer's field.vti of the same field: the same
# dimensions, origin, spacing and values bit for bit, Float64 and Float32, and the same
# contour at 0.5. The files come from the tests/mpi gtest binary beside cmcsurf
# (Pvti.AssembledPiecesEqualTheSerialFile with CMCSURF_PVTI_KEEP).
# Usage: pvti_vtk.sh <cmcsurf> <ranks> <mpiexec>
set -eu
bin="$1"
np="$2"
mpiexec="$3"
tests="$(dirname "$bin")/cmcsurf_mpi_tests"
if ! /usr/bin/python3 -c "import vtk, numpy" 2>/dev/null; then
  echo "pvti_vtk: skipped (python3-vtk9 and numpy not installed)"
  exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
CMCSURF_PVTI_KEEP="$work" "$mpiexec" -np "$np" --oversubscribe "$tests" \
  --gtest_filter=Pvti.AssembledPiecesEqualTheSerialFile >"$work/log" 2>&1 ||
  { cat "$work/log"; echo "FAIL: the gtest writer"; exit 1; }
[ "$(ls "$work/field" | wc -l)" = "$np" ] || { echo "FAIL: not $np pieces"; exit 1; }
/usr/bin/python3 - "$work" "$np" <<'PY'
import sys, numpy, vtk
from vtk.util.numpy_support import vtk_to_numpy
work, np_ = sys.argv[1], int(sys.argv[2])

def contour_area(reader):
    c = vtk.vtkContourFilter()
    c.SetInputConnection(reader.GetOutputPort())
    c.SetValue(0, 0.5)
    t = vtk.vtkTriangleFilter()
    t.SetInputConnection(c.GetOutputPort())
    m = vtk.vtkMassProperties()
    m.SetInputConnection(t.GetOutputPort())
    m.Update()
    return m.GetSurfaceArea()

for suffix, dtype in (("", numpy.float64), ("32", numpy.float32)):
    p = vtk.vtkXMLPImageDataReader()
    p.SetFileName(f"{work}/field{suffix}.pvti")
    p.Update()
    assert p.GetNumberOfPieces() == np_, (p.GetNumberOfPieces(), np_)
    s = vtk.vtkXMLImageDataReader()
    s.SetFileName(f"{work}/serial{suffix}.vti")
    s.Update()
    a, b = p.GetOutput(), s.GetOutput()
    # 16 cells per axis: 17 points, the last the periodic wrap.
    assert a.GetDimensions() == b.GetDimensions() == (17, 17, 17), \
        (a.GetDimensions(), b.GetDimensions())
    assert a.GetExtent() == b.GetExtent() and a.GetOrigin() == b.GetOrigin() and \
        a.GetSpacing() == b.GetSpacing()
    for name in ("phi", "nu"):
        x = vtk_to_numpy(a.GetPointData().GetArray(name))
        y = vtk_to_numpy(b.GetPointData().GetArray(name))
        assert x.dtype == y.dtype == dtype, (x.dtype, y.dtype)
        assert x.shape == y.shape == (17 ** 3,), (x.shape, y.shape)
        assert x.tobytes() == y.tobytes(), f"{name}{suffix}: {numpy.abs(x - y).max()}"
    assert a.GetPointData().GetScalars().GetName() == "phi"
    ca, cb = contour_area(p), contour_area(s)
    assert ca > 0 and ca == cb, (ca, cb)
    print(f"pvti_vtk: {np_} pieces of field{suffix}.pvti equal serial{suffix}.vti in VTK "
          f"({dtype.__name__}), contour area {ca}")
PY
