"""Analysis of computed surfaces: the welded periodic surface mesh with per-vertex normals, H
and K, the profile's signed distance, and ``load`` of a run or sweep folder (docs/python.md,
"Analysis"). The numbers come from the same library as the command line."""
from __future__ import annotations

import csv
import json
import pathlib
from typing import Any, Dict, List, Optional, Union

import numpy as np

from . import _cmcsurf
from ._cmcsurf import Result

PathLike = Union[str, pathlib.Path]


def _phi_of(source: Any) -> Any:
    return source.phi if isinstance(source, Result) else source


def periodic_mesh(source: Union[Result, Any]) -> Dict[str, Any]:
    """The phi = 1/2 surface of one cell of a :class:`Result` (or an (N, N, N) field) as a
    welded mesh on the 3-torus, as ``cmcsurf mesh --periodic``: ``vertices`` (V, 3) in
    [0, 1)^3, ``triangles`` (F, 3) int64, ``offsets`` (F, 3, 3) int64 (triangle t's corner q is
    ``vertices[triangles[t, q]] + offsets[t, q]``, whole cells), ``normals`` (V, 3) unit,
    into phase 2, ``mean_curvature`` and ``gaussian_curvature`` (V,) from the field's
    derivatives at each vertex (H > 0 where phase 1 is convex), and ``stats`` (vertices, edges,
    triangles, euler_characteristic = V - E + F of the closed surface, area, closed, manifold).
    """
    return _cmcsurf.periodic_mesh(_phi_of(source))


def signed_distance(source: Union[Result, Any], epsilon: Optional[float] = None) -> np.ndarray:
    """The signed distance to the phi = 1/2 surface that the tanh profile encodes, in cell
    units (> 0 in phase 1): 2 sqrt(2) epsilon atanh(2 phi - 1), as ``run --distance-field``
    writes it. ``epsilon``: the run's (a :class:`Result`'s own unless given)."""
    if epsilon is None:
        if not isinstance(source, Result):
            raise TypeError("epsilon: required for an array (a Result knows its own)")
        epsilon = float(source.report["epsilon"])
    return _cmcsurf.signed_distance(_phi_of(source), float(epsilon))


def _read_csv(path: pathlib.Path) -> Dict[str, np.ndarray]:
    """Columns of a CSV file with a header: numbers as float64 (int64 where every value is a
    whole number), other columns as str arrays."""
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    columns: Dict[str, np.ndarray] = {}
    for c, name in enumerate(header):
        values = [r[c] if c < len(r) else "" for r in body]
        try:
            numbers = np.array([float(v) if v != "" else np.nan for v in values], dtype=float)
        except ValueError:
            columns[name] = np.array(values, dtype=str)
            continue
        whole = all(v.lstrip("-").isdigit() for v in values) and len(values) > 0
        columns[name] = numbers.astype(np.int64) if whole else numbers
    return columns


def _load_run(folder: pathlib.Path) -> Dict[str, Any]:
    report_file = folder / "report.json"
    if not report_file.is_file():
        raise FileNotFoundError(f"'{folder}': no report.json (not a finished run folder)")
    run: Dict[str, Any] = {"kind": "run", "path": folder,
                           "report": json.loads(report_file.read_text(encoding="utf-8"))}
    field = _cmcsurf.read_field(folder)
    run["field_file"] = pathlib.Path(field["file"])
    run["fields"] = field["arrays"]
    run["phi"] = field["arrays"].get("phi")
    run["distance"] = field["arrays"].get("distance")
    run["metadata"] = field["metadata"]
    for name in ("history", "curvature_distribution", "curvature_histogram"):
        f = folder / f"{name}.csv"
        run[name] = _read_csv(f) if f.is_file() else None
    return run


def load(path: PathLike) -> Dict[str, Any]:
    """Reads a folder that ``cmcsurf run`` (or ``Result.save``) or ``cmcsurf sweep`` wrote.

    A run folder (report.json beside field.vti or field.pvti) gives ``kind`` "run", ``path``,
    ``report`` (report.json as a dict), ``phi`` (the (N, N, N) field), ``distance`` (the
    ``--distance-field`` array, else None), ``fields`` (every array of the field file),
    ``metadata`` (the field file's header), and ``history``, ``curvature_distribution`` and
    ``curvature_histogram`` as dicts of column arrays (None where the file is missing).
    A sweep folder (sweep.json) gives ``kind`` "sweep", ``path``, ``sweep`` (sweep.json),
    ``table`` (sweep.csv's columns, None if missing) and ``members``: a dict from each member
    folder's name to its run, as above, in name order.
    """
    folder = pathlib.Path(path)
    if not folder.is_dir():
        raise FileNotFoundError(f"'{folder}': not a folder (a run or sweep folder to load)")
    if (folder / "sweep.json").is_file():
        members: Dict[str, Dict[str, Any]] = {}
        for sub in sorted(p for p in folder.iterdir() if p.is_dir()):
            if (sub / "report.json").is_file():
                members[sub.name] = _load_run(sub)
        table = folder / "sweep.csv"
        return {"kind": "sweep", "path": folder,
                "sweep": json.loads((folder / "sweep.json").read_text(encoding="utf-8")),
                "table": _read_csv(table) if table.is_file() else None,
                "members": members}
    return _load_run(folder)


__all__: List[str] = ["load", "periodic_mesh", "signed_distance"]
