#!/usr/bin/env bash
# cmcsurf scaffold on real CMC members (docs/scaffolds.md): G and P, sheet and network, at
# 32^3 with --fast, one cache folder for all (three members are computed: G and P
# at alpha 0.5, G at 0.3; the other parts reuse them). Each part is one piece whose pores
# percolate along x, y and z, with the porosity within 1e-3 of the target; the G sheet's 3MF is
# read back by lib3mf itself (through ctypes: triangle count, unit, Description, build item,
# one shell); a decimated sheet keeps its budget, is closed, manifold, one shell and within
# 0.5 % of the undecimated volume.
set -u
bin="$1"
export OMP_NUM_THREADS=1  # the solver spins threads on shared cores
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
common=(--grid 32 --fast --cell-size 2 --units mm --cache "$work/cache" --quiet)

# Boxes that trim the lattice (1.5 cells and 1.5 x 1.5 x 2.25 cells): the caps and the fragment
# removal are exercised, not just whole cells.
parts=(
  "G sheet 0.7 3 gs.3mf"
  "G network 0.5 3 gn50.stl"
  "G network 0.7 3x3x4.5 gn70.stl"
  "P sheet 0.6 3 ps.stl"
  "P network 0.5 3 pn50.stl"
)
for p in "${parts[@]}"; do
  read -r surface solid porosity size out <<<"$p"
  "$bin" scaffold --surface "$surface" --solid "$solid" --porosity "$porosity" --size "$size" \
    "${common[@]}" --out "$work/$out" || { echo "FAIL: scaffold $p"; fail=1; }
done
# A sheet decimated to a budget (about a fifth of its 81k triangles): the G member is reused.
"$bin" scaffold --surface G --solid sheet --porosity 0.7 --size 2 "${common[@]}" \
  --max-triangles 15000 --out "$work/gs_small.stl" ||
    { echo "FAIL: scaffold --max-triangles"; fail=1; }
"$bin" scaffold --surface G --solid sheet --porosity 0.7 --size 2 "${common[@]}" \
  --tolerance 0 --out "$work/gs_full.stl" || { echo "FAIL: scaffold undecimated"; fail=1; }
check_members=$(ls "$work/cache" | wc -l)
[ "$check_members" -eq 3 ] ||
  { echo "FAIL: $check_members members cached, want 3 (G 0.5, G 0.3, P 0.5)"; fail=1; }

/usr/bin/python3 - "$work" "${parts[@]}" <<'PY' || { echo "FAIL: part checks"; fail=1; }
import ctypes, json, struct, sys
import numpy as np

work = sys.argv[1]


def shells(tri):
    """Connected components of a triangle mesh by shared vertices (hooking + pointer jumping)."""
    tri = np.asarray(tri, dtype=np.int64).reshape(-1, 3)
    used = np.unique(tri)
    parent = np.arange(tri.max() + 1)
    edges = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]]])
    while True:
        a, b = parent[edges[:, 0]], parent[edges[:, 1]]
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        moved = lo != hi
        if not moved.any():
            break
        np.minimum.at(parent, hi[moved], lo[moved])
        while True:
            nxt = parent[parent]
            if (nxt == parent).all():
                break
            parent = nxt
    return int((parent[used] == used).sum())


def stl_triangles(path):
    """Indexed triangles of a binary STL (vertices merged by exact coordinates)."""
    data = open(path, "rb").read()
    n = struct.unpack_from("<I", data, 80)[0]
    rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                        count=n, offset=84)
    _, index = np.unique(rec["v"].reshape(-1, 3), axis=0, return_inverse=True)
    return index.reshape(-1, 3)


def read_3mf(path):
    """The model through lib3mf 1.8's C API: unit, metadata, build items, first mesh's triangles."""
    lib = ctypes.CDLL("lib3MF.so.1")
    u32, ptr = ctypes.c_uint32, ctypes.c_void_p

    def ok(rc, what):
        assert rc == 0, f"lib3mf {what} failed: {rc:#x}"

    model, reader = ptr(), ptr()
    ok(lib.lib3mf_createmodel(ctypes.byref(model)), "createmodel")
    ok(lib.lib3mf_model_queryreader(model, b"3mf", ctypes.byref(reader)), "queryreader")
    ok(lib.lib3mf_reader_readfromfileutf8(reader, path.encode()), "read")
    unit = u32()
    ok(lib.lib3mf_model_getunit(model, ctypes.byref(unit)), "getunit")
    count, meta = u32(), {}
    ok(lib.lib3mf_model_getmetadatacount(model, ctypes.byref(count)), "getmetadatacount")
    for i in range(count.value):
        kv = []
        for get in (lib.lib3mf_model_getmetadatakeyutf8, lib.lib3mf_model_getmetadatavalueutf8):
            need = u32()
            ok(get(model, u32(i), None, u32(0), ctypes.byref(need)), "getmetadata")
            buf = ctypes.create_string_buffer(need.value + 1)
            ok(get(model, u32(i), buf, u32(len(buf)), ctypes.byref(need)), "getmetadata")
            kv.append(buf.value.decode())
        meta[kv[0]] = kv[1]
    it, obj, more = ptr(), ptr(), ctypes.c_int()
    ok(lib.lib3mf_model_getmeshobjects(model, ctypes.byref(it)), "getmeshobjects")
    ok(lib.lib3mf_resourceiterator_movenext(it, ctypes.byref(more)), "movenext")
    assert more.value, "no mesh object"
    ok(lib.lib3mf_resourceiterator_getcurrent(it, ctypes.byref(obj)), "getcurrent")
    nt = u32()
    ok(lib.lib3mf_meshobject_gettrianglecount(obj, ctypes.byref(nt)), "gettrianglecount")
    tri = (u32 * (3 * nt.value))()
    ok(lib.lib3mf_meshobject_gettriangleindices(obj, tri, nt, None), "gettriangleindices")
    items, builds = ptr(), 0
    ok(lib.lib3mf_model_getbuilditems(model, ctypes.byref(items)), "getbuilditems")
    while True:
        ok(lib.lib3mf_builditemiterator_movenext(items, ctypes.byref(more)), "movenext")
        if not more.value:
            break
        builds += 1
    for h in (obj, it, items, reader, model):
        lib.lib3mf_release(h)
    return unit.value, meta, np.ctypeslib.as_array(tri), builds


for spec in sys.argv[2:]:
    surface, solid, porosity, size, out = spec.split()
    r = json.load(open(f"{work}/{out}.json"))
    t = r["topology"]
    name = f"{surface} {solid} {porosity}"
    assert abs(r["porosity"] - float(porosity)) <= 1e-3, (name, r["porosity"])
    assert r["checks"]["closed"] and r["checks"]["manifold"], (name, r["checks"])
    assert t["solid_components"] - t["fragments"] == 1 and \
        (t["fragments"] == 0 or t["fragments_removed"]), (name, t)
    assert all(t["pore_percolates"][a] for a in "xyz") and t["closed_pores"] == 0, (name, t)
    if out.endswith(".3mf"):
        unit, meta, tri, builds = read_3mf(f"{work}/{out}")
        assert unit == 1, f"lib3mf unit {unit}, want 1 (millimeter)"
        assert len(tri) == 3 * r["triangles"], (len(tri) // 3, r["triangles"])
        assert builds == 1, builds
        d = meta.get("Description", "")
        assert f"surface={surface}" in d and f"solid={solid}" in d and "porosity=" in d and \
            "thickness=" in d, meta
        assert shells(tri) == 1, f"{name}: {shells(tri)} shells"
    else:
        assert shells(stl_triangles(f"{work}/{out}")) == 1, name
    print(f"scaffold_cmc: {name}: porosity {r['porosity']:.5f}, {r['triangles']} triangles, "
          f"{t['fragments']} fragments removed, one shell")

small = json.load(open(f"{work}/gs_small.stl.json"))
full = json.load(open(f"{work}/gs_full.stl.json"))
dm = small["decimation"]
assert dm["applied"] and dm["within_budget"] and small["triangles"] <= 15000, dm
assert dm["triangles_before"] == full["triangles"] and full["triangles"] > 3 * 15000, \
    (dm, full["triangles"])
assert small["checks"]["closed"] and small["checks"]["manifold"], small["checks"]
assert abs(small["volume"] / full["volume"] - 1) <= 5e-3, (small["volume"], full["volume"])
assert 0 < dm["error"] <= dm["hausdorff_bound"] < 0.1, dm  # mm, for 2 mm cells
assert shells(stl_triangles(f"{work}/gs_small.stl")) == 1
assert abs(small["porosity"] - 0.7) <= 1e-3, small["porosity"]
print(f"scaffold_cmc: decimated {dm['triangles_before']} -> {dm['triangles_after']}, volume "
      f"{small['volume'] / full['volume'] - 1:+.1e}, error {dm['error']:.4f} mm")
PY

if ls "$work" | grep -q 'cmcsurf-tmp'; then echo "FAIL: temporary files left"; fail=1; fi
[ "$fail" -eq 0 ] && echo "scaffold_cmc: all passed"
exit "$fail"
