#!/usr/bin/env bash
# A FIFO (or another non-regular file) where cmcsurf reads a file: refused before it is opened,
# with a message naming the path; never a hang (each command runs under `timeout 20`, whose exit
# code 124 is a failure here).
set -u
bin="$1"
export OMP_NUM_THREADS=1
command -v mkfifo >/dev/null || { echo "SKIP: no mkfifo"; exit 77; }
command -v timeout >/dev/null || { echo "SKIP: no timeout"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
expect_refused() {  # expect_refused NAME PATH ARGS...: exits non-zero, not 124, naming PATH
  local name="$1" path="$2"; shift 2
  timeout 20 "$bin" "$@" >"$work/out" 2>"$work/err" </dev/null
  local rc=$?
  if [ "$rc" -eq 124 ]; then echo "FAIL: $name: hung on the FIFO $path"; fail=1; return; fi
  if [ "$rc" -eq 0 ]; then echo "FAIL: $name: exit 0"; fail=1; fi
  grep -qF -- "$path" "$work/err" ||
    { echo "FAIL: $name: $path not named in: $(cat "$work/err")"; fail=1; }
  grep -q "not a regular file" "$work/err" || {
    echo "FAIL: $name: no 'not a regular file' in: $(cat "$work/err")"; fail=1; }
}
# Real folders (so that nothing but the FIFO is wrong), each file then replaced by a FIFO.
small=(--grid 16 --epsilon 0.04 --max-steps 2 --no-preview --no-report --quiet)
"$bin" run --paper --surface P "${small[@]}" --out "$work/run" || { echo "FAIL: run"; exit 1; }
"$bin" sweep --paper --surface G --volume-fractions 0.5 --no-plot "${small[@]}" \
  --out "$work/sweep" ||
  { echo "FAIL: sweep"; exit 1; }
rm -f "$work/run/checkpoint.bin" "$work/run/report.json" "$work/sweep/sweep.json"
mkfifo "$work/run/checkpoint.bin" "$work/run/report.json" "$work/sweep/sweep.json"
# run --resume: checkpoint.bin
expect_refused "run --resume" "$work/run/checkpoint.bin" run --resume "$work/run" --quiet
# report: a run folder's report.json, a sweep folder's sweep.json
rm "$work/run/checkpoint.bin"
expect_refused "report (run)" "$work/run/report.json" report "$work/run" --quiet
expect_refused "report (sweep)" "$work/sweep/sweep.json" report "$work/sweep" --quiet
# sweep --resume: sweep.json
expect_refused "sweep --resume" "$work/sweep/sweep.json" sweep --resume "$work/sweep" --quiet
# mesh --from: a .vti, a .pvti, a .pvti's piece
mkfifo "$work/field.vti" "$work/field.pvti"
expect_refused "mesh --from .vti" "$work/field.vti" mesh --from "$work/field.vti" \
  --out "$work/m.stl" --quiet
expect_refused "mesh --from .pvti" "$work/field.pvti" mesh --from "$work/field.pvti" \
  --out "$work/m.stl" --quiet
mkdir -p "$work/p/field"
cat >"$work/p/field.pvti" <<'PVTI'
<?xml version="1.0"?>
<!-- cmcsurf
layout=periodic
-->
<VTKFile type="PImageData" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <PImageData WholeExtent="0 16 0 16 0 16" GhostLevel="0" Origin="0 0 0" Spacing="1 1 1">
    <PPointData Scalars="phi">
      <PDataArray type="Float64" Name="phi"/>
    </PPointData>
    <Piece Extent="0 16 0 16 0 16" Source="field/piece_0000.vti"/>
  </PImageData>
</VTKFile>
PVTI
mkfifo "$work/p/field/piece_0000.vti"
expect_refused "mesh --from (piece)" "piece_0000.vti" mesh --from "$work/p/field.pvti" \
  --out "$work/m.stl" --quiet
# scaffold --shape: the STL
mkfifo "$work/shape.stl"
expect_refused "scaffold --shape" "$work/shape.stl" scaffold --shape "$work/shape.stl" \
  --porosity 0.5 --grid 16 --cache "$work/cache" \
  --out "$work/s.stl" --quiet
if compgen -G "$work/m.stl*" >/dev/null || compgen -G "$work/s.stl*" >/dev/null; then
  echo "FAIL: a mesh was written"; fail=1
fi
[ "$fail" -eq 0 ] && echo "fifo_inputs: all passed"
exit "$fail"
