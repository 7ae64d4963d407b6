#!/usr/bin/env python3
"""Writes fuzz/corpus/pvti/: inputs of fuzz/pvti_fuzz.cpp, each records of a 4-byte
little-endian length and that many bytes (the .pvti, then piece_0000.vti, piece_0001.vti, ...).
The files are laid out as cmcsurf's write_pvti / write_vti lay them out (io/pvti.h, io/vti.h).
Not part of any build; from the repository root: python3 fuzz/make_pvti_seeds.py"""
import math
import os
import struct

OUT = "fuzz/corpus/pvti"
N = 4
TAIL = b"\n  </AppendedData>\n</VTKFile>\n"


def phi(i, j, k):
    t = 2 * math.pi / N
    x, y, z = t * (i + 0.5), t * (j + 0.5), t * (k + 0.5)
    return 0.5 + 0.3 * (math.sin(x) * math.cos(y) + math.sin(y) * math.cos(z)
                        + math.sin(z) * math.cos(x))


def piece(ext, arrays=("phi",), f32=False, layout="periodic", short=0):
    """A piece .vti: points ext (x0 x1 y0 y1 z0 z1), each point holding cell (i mod N, ...)."""
    e = " ".join(map(str, ext))
    typ = "Float32" if f32 else "Float64"
    pts = [(i % N, j % N, k % N) for k in range(ext[4], ext[5] + 1)
           for j in range(ext[2], ext[3] + 1) for i in range(ext[0], ext[1] + 1)]
    data = struct.pack("<%d%s" % (len(pts), "f" if f32 else "d"), *(phi(*p) for p in pts))
    head = '<?xml version="1.0"?>\n<!-- cmcsurf\n'
    head += f"layout={layout}\n" if layout else ""
    head += "-->\n"
    head += ('<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" '
             'header_type="UInt64">\n')
    head += f'  <ImageData WholeExtent="{e}" Origin="0.125 0.125 0.125" Spacing="0.25 0.25 0.25">\n'
    head += f'    <Piece Extent="{e}">\n      <PointData Scalars="{arrays[0]}">\n'
    for a, name in enumerate(arrays):
        head += (f'        <DataArray type="{typ}" Name="{name}" format="appended" '
                 f'offset="{a * (8 + len(data))}"/>\n')
    head += ("      </PointData>\n      <CellData>\n      </CellData>\n    </Piece>\n"
             '  </ImageData>\n  <AppendedData encoding="raw">\n   _')
    body = b"".join(struct.pack("<Q", len(data)) + data for _ in arrays)
    return head.encode() + body[:len(body) - short] + TAIL


def pvti(pieces, arrays=("phi",), f32=False, layout="periodic", n=N):
    typ = "Float32" if f32 else "Float64"
    t = '<?xml version="1.0"?>\n<!-- cmcsurf\n' + (f"layout={layout}\n" if layout else "")
    t += "-->\n"
    t += ('<VTKFile type="PImageData" version="1.0" byte_order="LittleEndian" '
          'header_type="UInt64">\n')
    t += (f'  <PImageData WholeExtent="0 {n} 0 {n} 0 {n}" GhostLevel="0" '
          'Origin="0.125 0.125 0.125" Spacing="0.25 0.25 0.25">\n')
    t += f'    <PPointData Scalars="{arrays[0]}">\n'
    for name in arrays:
        t += f'      <PDataArray type="{typ}" Name="{name}"/>\n'
    t += "    </PPointData>\n    <PCellData>\n    </PCellData>\n"
    for q, (ext, source) in enumerate(pieces):
        src = source if source is not None else f"field/piece_{q:04d}.vti"
        t += f'    <Piece Extent="{" ".join(map(str, ext))}" Source="{src}"/>\n'
    t += "  </PImageData>\n</VTKFile>\n"
    return t.encode()


def records(*parts):
    return b"".join(struct.pack("<I", len(p)) + p for p in parts)


def put(name, data):
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(data)


WHOLE = (0, N, 0, N, 0, N)
LOW, HIGH = (0, 2, 0, N, 0, N), (2, N, 0, N, 0, N)
os.makedirs(OUT, exist_ok=True)
put("ok-one-piece.bin", records(pvti([(WHOLE, None)]), piece(WHOLE)))
put("ok-two-pieces.bin", records(pvti([(LOW, None), (HIGH, None)]), piece(LOW), piece(HIGH)))
put("ok-two-arrays-f32.bin",
    records(pvti([(WHOLE, None)], ("phi", "mu"), True), piece(WHOLE, ("phi", "mu"), True)))
put("bad-empty.bin", b"")
put("bad-truncated-pvti.bin", records(pvti([(WHOLE, None)])[:200], piece(WHOLE)))
put("bad-no-layout.bin", records(pvti([(WHOLE, None)], layout=None), piece(WHOLE)))
put("bad-unknown-layout.bin", records(pvti([(WHOLE, None)], layout="tiled"), piece(WHOLE)))
put("bad-overlap.bin", records(pvti([(WHOLE, None), (WHOLE, None)]), piece(WHOLE), piece(WHOLE)))
put("bad-gap.bin", records(pvti([(LOW, None)]), piece(LOW)))
put("bad-outside.bin", records(pvti([((0, N + 1, 0, N, 0, N), None)]), piece(WHOLE)))
put("bad-dotdot-source.bin", records(pvti([(WHOLE, "../field/piece_0000.vti")]), piece(WHOLE)))
put("bad-absolute-source.bin", records(pvti([(WHOLE, "/etc/passwd")]), piece(WHOLE)))
put("bad-missing-piece.bin", records(pvti([(LOW, None), (HIGH, None)]), piece(LOW)))
put("bad-piece-extent.bin", records(pvti([(LOW, None), (HIGH, None)]), piece(HIGH), piece(LOW)))
put("bad-piece-type.bin", records(pvti([(WHOLE, None)], f32=True), piece(WHOLE)))
put("bad-piece-layout.bin", records(pvti([(WHOLE, None)]), piece(WHOLE, layout="tiled")))
put("bad-piece-short.bin", records(pvti([(WHOLE, None)]), piece(WHOLE, short=8)))
put("bad-piece-too-small.bin", records(pvti([(WHOLE, None)]), piece(WHOLE)[:300]))
put("bad-n-over-limit.bin", records(pvti([((0, 64, 0, 64, 0, 64), None)], n=64), piece(WHOLE)))
