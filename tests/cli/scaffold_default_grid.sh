#!/usr/bin/env bash
# cmcsurf scaffold without --grid or --resolution solves its member at grid 32, the run's
# epsilon kept (the part's lattice is the member's grid tiled: the run's default 128 made the
# default 10 mm part 640^3 nodes and 24 GB); --grid, when given, is kept as given
# (docs/scaffolds.md, "Resolution and size").
set -u
bin="$1"
command -v python3 >/dev/null || { echo "SKIP: python3 missing"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
common=(--surface G --porosity 0.7 --size 2 --cell-size 2 --units mm --tolerance 0 --no-page --quiet
        --cache "$work/cache")
"$bin" scaffold "${common[@]}" --out "$work/default.stl" ||
  { echo "FAIL: scaffold with the default grid"; fail=1; }
"$bin" scaffold "${common[@]}" --grid 16 --out "$work/grid.stl" ||
  { echo "FAIL: scaffold --grid 16"; fail=1; }
python3 - "$work" <<'PY' || fail=1
import json, sys
w = sys.argv[1]
bad = []
for name, grid, eps in [("default", 32, 0.01), ("grid", 16, 0.01)]:
    j = json.load(open(f"{w}/{name}.stl.json"))
    p = j["member"]["parameters"]
    got = (j["mesh_size"]["grid"], p["grid"], p["epsilon"], j["mesh_size"]["lattice_spacing"])
    want = (grid, grid, eps, 2.0 / grid)
    if got != want:
        bad.append(f"{name}: (mesh grid, member grid, epsilon, spacing) {got} != {want}")
for b in bad:
    print("FAIL:", b)
sys.exit(1 if bad else 0)
PY
exit $fail
