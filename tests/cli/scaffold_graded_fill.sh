#!/usr/bin/env bash
# cmcsurf scaffold's graded fill of a shape (docs/scaffolds.md, "Graded fill of a shape" and
# "Graded sheets"): --grade-by surface grades the porosity by the depth below a --shape's
# surface (A at the surface, B at --grade-depth and deeper) for a network (members blended per
# node) and a sheet (its wall per node); a sheet graded along --axis fills a shape too. The
# porosity measured on the lattice near the surface and in the core, and the sheet's wall at
# both ends, against the targets; the network's page shows its profile with FILE.json's
# numbers; the misuses refused before any work (exit 2).
set -u
source "$(dirname "$0")/usage.bash" "$1"
here=$(cd "$(dirname "$0")" && pwd)
export OMP_NUM_THREADS=1  # the solver spins threads on shared cores
common=(--paper --surface G --cell-size 1 --units mm --cache "$work/cache" --quiet --tolerance 0
        --no-page)
# Cylinders 6 mm across and 4 mm high, and 4 mm across and 3 mm high (64 sides).
python3 "$here/../../scripts/cylinder_stl.py" "$work/cyl.stl" 6 4 64 &&
  python3 "$here/../../scripts/cylinder_stl.py" "$work/cyl4.stl" 4 3 64 ||
  { echo "FAIL: cylinder_stl.py"; exit 1; }

# A network at grid 16 (three members, solid fraction 0.3, 0.4, 0.5); sheets at grid 32, where
# the porous end's wall is 3 voxels (at 16 it is 1.5, too few for the lattice to count).
"$bin" scaffold "${common[@]}" --grid 16 --porosity 0.5:0.7 --grade-by surface \
  --grade-depth 1.5 --shape "$work/cyl.stl" --out "$work/net.stl" ||
  { echo "FAIL: network by depth"; fail=1; }
"$bin" scaffold "${common[@]}" --grid 32 --solid sheet --porosity 0.5:0.7 --grade-by surface \
  --grade-depth 1 --shape "$work/cyl4.stl" --out "$work/sheet.stl" ||
  { echo "FAIL: sheet by depth"; fail=1; }
"$bin" scaffold "${common[@]}" --grid 32 --solid sheet --porosity 0.7:0.5 --axis z \
  --shape "$work/cyl4.stl" --out "$work/sheet_z.stl" || { echo "FAIL: sheet along z"; fail=1; }
python3 - "$work" <<'PY' || { echo "FAIL: report values"; fail=1; }
import json, sys
w = sys.argv[1]


def part(name):
    r = json.load(open(f"{w}/{name}.stl.json"))
    assert r["checks"]["closed"] and r["checks"]["manifold"], (name, r["checks"])
    t = r["topology"]
    assert t["solid_components"] - t["fragments"] == 1 and t["closed_pores"] == 0, (name, t)
    # The level solve meets the ramp's mean over the shape's nodes (a network within its
    # trimming tolerance 1e-3, a sheet 1e-4).
    assert abs(r["porosity"] - r["graded"]["porosity_mean"]) <= 1e-3, (name, r["porosity"])
    return r


# Near the surface (the outer quarter of the depth, a shell of many cells) and in the core the
# lattice's porosity is the target's: a sheet's within 0.02 (its wall is set per node; an
# ungraded part's bands scatter by up to 0.016), a network's within 0.05 (between two members
# the blend of their fields reads up to 0.03 denser than the target, as along an axis). The
# rim and the core differ by the ramp (0.18 and 0.15 between their targets), not by noise.
for name, depth, tol in (("net", 1.5, 0.05), ("sheet", 1.0, 0.02)):
    r = part(name)
    g = r["graded"]
    assert g["by"] == "surface" and g["depth"] == depth and g["axis"] is None, g
    bands = g["profile"]
    assert len(bands) == 5 and bands[-1]["depth_to"] is None, bands
    for b in (bands[0], bands[-1]):
        assert abs(b["porosity_nodes"] - b["porosity_target"]) < tol, (name, b)
    assert abs(bands[-1]["porosity_target"] - 0.7) < 1e-9, bands[-1]
    assert bands[-1]["porosity_nodes"] > bands[0]["porosity_nodes"] + 0.12, (name, bands)
    print(name, [(round(b["porosity_target"], 3), round(b["porosity_nodes"], 3)) for b in bands])

# The sheets' walls at both ends: thickness_from (the porosity 0.5 end) thicker than
# thickness_to (0.7), each the end cell's measured wall median within two of its voxels.
for name in ("sheet", "sheet_z"):
    r = json.load(open(f"{w}/{name}.stl.json")) if name == "sheet" else part(name)
    s, cells = r["sheet"], r["morphometry"]["members"]
    ends = {"sheet": ("thickness_from", "thickness_to"),
            "sheet_z": ("thickness_to", "thickness_from")}[name]  # the porosity 0.5 end first
    thick, thin = s[ends[0]], s[ends[1]]
    assert thick > 1.3 * thin, (name, s)
    for c in cells:
        want = thick if abs(c["porosity"] - 0.5) < 1e-9 else thin
        assert abs(c["wall_thickness"]["p50"] - want) <= 2 * c["voxel"], (name, c, want)
    print(name, "walls", round(thick, 4), round(thin, 4))
z = part("sheet_z")["graded"]
assert z["by"] == "axis" and z["axis"] == "z" and len(z["profile"]) == 3, z
assert all(abs(b["porosity_nodes"] - b["porosity_target"]) < 0.02 for b in z["profile"]), z
PY

# The graded part's page (`report FILE.json` remakes it from FILE.json and the part): the
# profile's chart draws the five bands, target and measured, and every number cell of its table
# and of the members' table is FILE.json's at its pointer, to all 17 digits.
"$bin" report "$work/net.stl.json" >/dev/null 2>&1 || { echo "FAIL: report net.stl.json"; fail=1; }
python3 - "$work" <<'PY' || { echo "FAIL: the graded profile on the page"; fail=1; }
import json, re, sys
w = sys.argv[1]
r = json.load(open(f"{w}/net.stl.json"))
html = open(f"{w}/net.stl.html").read()
chart = re.search(r'data-title="porosity profile" data-bands="(\d+)" data-drawn="(\d+)"', html)
assert chart and chart.groups() == ("5", "5"), chart and chart.groups()
assert "Porosity by depth below the surface: target and measured" in html
assert f"cmcsurf part: G network, porosity 0.5 to 0.7, mean {r['porosity']:.4f}" in html
cells = re.findall(r'<td data-path="(/(?:graded/profile|morphometry/members)/[^"]+)" '
                   r'data-value="([^"]+)">', html)
for path, value in cells:
    at = r
    for key in path.strip("/").split("/"):
        at = at[int(key)] if isinstance(at, list) else at[key]
    assert float(value) == at, (path, value, at)
assert len(cells) == 5 * 2 + 3 * 5, len(cells)  # bands x (target, measured); members x 5
print("page: profile of 5 bands and 3 members equal FILE.json")
PY

shape=(--shape "$work/cyl.stl")
common+=(--grid 16)
check_usage bad.stl --grade-by scaffold "${common[@]}" --porosity 0.5:0.7 --grade-by radial \
  "${shape[@]}"
check_usage bad.stl --grade-by scaffold "${common[@]}" --porosity 0.5:0.7 --grade-by surface
check_usage bad.stl --grade-by scaffold "${common[@]}" --porosity 0.6 --grade-by surface \
  "${shape[@]}"
check_usage bad.stl --grade-by scaffold "${common[@]}" --porosity 0.5:0.7 --grade-by surface \
  --axis x "${shape[@]}"
check_usage bad.stl --grade-depth scaffold "${common[@]}" --porosity 0.5:0.7 --grade-depth 1 \
  "${shape[@]}"
check_usage bad.stl --grade-depth scaffold "${common[@]}" --porosity 0.5:0.7 \
  --grade-by surface --grade-depth 2.5 "${shape[@]}"
exit $fail
