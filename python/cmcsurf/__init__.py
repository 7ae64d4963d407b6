"""Triply periodic constant-mean-curvature surfaces with NumPy arrays in and out.

The same C++ core as the ``cmcsurf`` command line: ``run`` is ``cmcsurf run``, ``sweep`` is
``cmcsurf sweep``, ``mesh`` is ``cmcsurf mesh``; ``relax`` and ``measure`` take your own field.
Every ``run`` option is a keyword argument with the command line's default, and bad values
raise ``ValueError`` (or ``TypeError`` for a wrong type) with the command line's message.

Fields are float64 NumPy arrays of shape (N, N, N) indexed ``phi[i, j, k]`` = the cell centred
at (x, y, z) = ((i + 1/2) / N, (j + 1/2) / N, (k + 1/2) / N) of the unit cell, i.e.
``numpy.meshgrid(x, y, z, indexing="ij")`` order; phase 1 is phi > 1/2. Arrays given to
``relax``, ``measure`` and ``mesh`` may be any real dtype and any strides: they are converted
once to float64 (a copy; your array is never changed) and refused when not cubic, when N is not
m 2^k (m in {1, 3, 5, 7}, N >= 8, the multigrid's grids) or when they hold NaN or infinity.

Solves release the GIL (other Python threads keep running), Ctrl-C stops a solve within one
time step with ``KeyboardInterrupt``, and ``progress`` is called with a dict per time step
(history.csv's columns, ``HISTORY_COLUMNS``; in a sweep also ``member``, e.g. ``"G_0.30"``).
"""

from __future__ import annotations

import inspect
import numbers
import operator
import os
import warnings
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, TypeVar, Union

import numpy as np

from . import _cmcsurf
from ._cmcsurf import Mesh, Result, SolverDiverged
from .analysis import load, periodic_mesh, signed_distance

__all__ = [
    "Mesh", "Result", "SolverDiverged", "initial_field", "measure", "mesh", "properties",
    "relax", "run", "scattering", "surfaces", "sweep", "__version__",
]
__all__ += ["volume_mesh", "HISTORY_COLUMNS"]
__all__ += ["morphometry", "scaffold"]
__all__ += ["load", "periodic_mesh", "signed_distance"]

__version__: str = _cmcsurf.version()
# history.csv's columns in its order (Result.history's keys, a progress dict's), from the
# library's table (schema/report_schema.h).
HISTORY_COLUMNS: List[str] = [c["name"] for c in _cmcsurf.report_schema()["history_columns"]]
__doc__ = (__doc__ or "").replace("``HISTORY_COLUMNS``",
                                  "``" + ", ".join(HISTORY_COLUMNS) + "``")

Progress = Optional[Callable[[Dict[str, Any]], Any]]

# The run options (the C++ run option table, model/run_schema.cpp): the keywords of run,
# relax and sweep with the command line's defaults. Their signatures are built from it below;
# None, the default of the options --fast or --paper chooses, lets the mode choose (the fast
# mode unless paper=True).
_RUN_OPTIONS: List[Dict[str, Any]] = _cmcsurf.run_options()
_TYPES = {"float": float, "int": int, "str": str, "bool": bool}
_P = inspect.Parameter


def _parameter(option: Dict[str, Any], kind: Any = _P.KEYWORD_ONLY,
               default: Any = _P.empty) -> inspect.Parameter:
    fast = option["fast"] or option["paper"]
    annotation = _TYPES[option["type"]]
    if default is _P.empty:
        default = None if fast else option["default"]
    return _P(option["key"], kind, default=default,
              annotation=Optional[annotation] if fast or default is None else annotation)


def _option(key: str) -> Dict[str, Any]:
    return next(o for o in _RUN_OPTIONS if o["key"] == key)


def _options_doc(keys: Sequence[str]) -> str:
    lines = ["", "Run options (as the command line's, `cmcsurf run --help`):", ""]
    for o in _RUN_OPTIONS:
        if o["key"] in keys:
            unit = f" [{o['unit']}]" if o["unit"] else ""
            accepted = f" (accepted: {o['accepted']})" if o["accepted"] else ""
            lines.append(f"    {o['key']}{unit}: {o['help']}{accepted}")
    return "\n".join(lines) + "\n"


_R = TypeVar("_R")
# The key under which a body finds the names of the arguments its caller gave (a resumed sweep
# compares those with the sweep it continues); no keyword can have this name.
_GIVEN = "-given"


def _signature(leading: Sequence[inspect.Parameter], scopes: Sequence[str],
               trailing: Sequence[inspect.Parameter], returns: Any,
               defaults: Optional[Dict[str, Any]] = None,
               ) -> Callable[[Callable[[Dict[str, Any]], _R]], Callable[..., _R]]:
    """Gives the decorated body(arguments) the signature leading, then the run options of
    `scopes` not among leading (keyword-only, table order, `defaults` overriding the table's),
    then trailing; calls bind as that signature does and pass every argument, defaults
    applied."""
    named = {p.name for p in leading} | {p.name for p in trailing}
    options = [_parameter(o, default=(defaults or {}).get(o["key"], _P.empty))
               for o in _RUN_OPTIONS if o["scope"] in scopes and o["key"] not in named]
    sig = inspect.Signature(list(leading) + options + list(trailing), return_annotation=returns)

    def decorate(body: Callable[[Dict[str, Any]], _R]) -> Callable[..., _R]:
        def call(*args: Any, **kwargs: Any) -> _R:
            try:
                bound = sig.bind(*args, **kwargs)
            except TypeError as e:
                raise TypeError(f"{body.__name__}() {e}") from None
            given = set(bound.arguments)
            bound.apply_defaults()
            arguments = dict(bound.arguments)
            arguments[_GIVEN] = given
            return body(arguments)

        call.__name__ = call.__qualname__ = body.__name__
        call.__module__ = body.__module__
        call.__doc__ = (body.__doc__ or "") + _options_doc(list(sig.parameters))
        call.__signature__ = sig  # type: ignore[attr-defined]
        return call

    return decorate


def _run_options(values: Dict[str, Any], scopes: Sequence[str]) -> Dict[str, Any]:
    """The arguments that are run options of `scopes` (the rest are the function's own)."""
    return {o["key"]: values[o["key"]] for o in _RUN_OPTIONS
            if o["scope"] in scopes and o["key"] in values}


_SOLVER = ("solver",)
_THREADS = _P("threads", _P.KEYWORD_ONLY, default=0, annotation=int)
_PROGRESS = _P("progress", _P.KEYWORD_ONLY, default=None, annotation=Progress)
# The --properties stage of run and sweep (``run --properties-*``), handled beside the run options
_PROPERTIES = [
    _P("properties", _P.KEYWORD_ONLY, default=False, annotation=bool),
    _P("properties_nodal", _P.KEYWORD_ONLY, default=False, annotation=bool),
    _P("properties_solid", _P.KEYWORD_ONLY, default="network", annotation=str),
    _P("properties_porosity", _P.KEYWORD_ONLY, default=None,
       annotation=Union[None, float, Sequence[float]]),
    _P("properties_thickness", _P.KEYWORD_ONLY, default=None, annotation=Optional[float]),
    _P("properties_grid_check", _P.KEYWORD_ONLY, default=False, annotation=bool),
]


# sweep()'s folder (``cmcsurf sweep --out``, ``--resume``, ``--force`` and its output options).
_SWEEP_FOLDER = [
    _P("out", _P.KEYWORD_ONLY, default=None, annotation=Optional[Union[str, os.PathLike]]),
    _P("resume", _P.KEYWORD_ONLY, default=False, annotation=Union[bool, str, os.PathLike]),
    _P("force", _P.KEYWORD_ONLY, default=False, annotation=bool),
    _P("float32", _P.KEYWORD_ONLY, default=False, annotation=bool),
    _P("preview", _P.KEYWORD_ONLY, default=True, annotation=bool),
    _P("report", _P.KEYWORD_ONLY, default=True, annotation=bool),
    _P("plot", _P.KEYWORD_ONLY, default=True, annotation=bool),
    _P("plot_diffuse", _P.KEYWORD_ONLY, default=False, annotation=bool),
    _P("checkpoint_every", _P.KEYWORD_ONLY, default=_cmcsurf.default_checkpoint_every(),
       annotation=float),
]
_SWEEP_OUTPUTS = ("float32", "preview", "report", "plot", "plot_diffuse", "checkpoint_every")


def _properties_stage(properties: bool, nodal: bool, solid: str,
                      porosity: Union[None, float, Sequence[float]], thickness: Optional[float],
                      grid_check: bool) -> Optional[Dict[str, Any]]:
    """The --properties stage's options (``run --properties-*``), or None when it is off: any
    properties_* argument turns it on, as on the command line. A porosity is a ramp of one."""
    if not (properties or nodal or grid_check or solid != "network" or porosity is not None
            or thickness is not None):
        return None
    if porosity is not None and not isinstance(porosity, (list, tuple, np.ndarray)):
        porosity = [porosity]
    return {"solid": solid, "porosity": porosity, "thickness": thickness, "nodal": nodal,
            "grid_check": grid_check}


def _stage_of(a: Dict[str, Any]) -> Optional[Dict[str, Any]]:
    return _properties_stage(a["properties"], a["properties_nodal"], a["properties_solid"],
                             a["properties_porosity"], a["properties_thickness"],
                             a["properties_grid_check"])


def surfaces() -> List[Dict[str, Any]]:
    """The built-in surfaces, as ``cmcsurf surfaces`` lists them.

    Each is a dict with ``name`` (what ``surface=`` takes), ``nodal`` (a trigonometric nodal
    approximation, relaxed by steps 1-6 of the paper's Section 4.4), ``balanced`` (both phases
    congruent; None for non-nodal ones) and ``description``. A user formula
    ``"expr:<muParser formula in x, y, z in [0, 2 pi)>"`` is accepted as well.
    """
    return _cmcsurf.surfaces()


@_signature([_parameter(_option(k), _P.POSITIONAL_OR_KEYWORD)
            for k in ("surface", "volume_fraction", "grid", "epsilon")],
            ("surface", "initial", "grid", "solver"), [*_PROPERTIES, _THREADS, _PROGRESS], Result)
def run(arguments: Dict[str, Any]) -> Result:
    """One CMC surface, exactly as ``cmcsurf run`` computes it (same defaults, same report).

    Nodal surfaces (P, D, G, ..., ``expr:``) go through Section 4.4's steps 1-6 at
    ``volume_fraction`` and, with ``constrain="volume"``, the mass corrections that hold the
    sharp volume fraction of phi > 1/2 at it; ``sphere``, ``cube`` and ``noise`` are relaxed
    directly. The fast mode is the default (``--fast``: it chooses the options whose default
    is None where they are None; the grid is 128); ``paper=True`` is ``--paper``, the
    paper-faithful algorithm at 64^3 unless ``grid`` is given. ``threads``: OpenMP threads for
    this call (0: OMP_NUM_THREADS or all cores). ``progress``: called with a dict after every
    time step.

    ``properties=True`` is ``--properties``: the effective stiffness and conductivities of the
    network of phase 1 (``properties_solid="sheet"`` with ``properties_porosity`` or
    ``properties_thickness`` in unit cells: the wall around the surface; a sequence of
    porosities is a ramp, ``report["properties_ramp"]``), with
    ``properties_nodal`` the nodal twin(s) beside it and ``properties_grid_check`` the
    ``properties_*_error`` keys from N/2; the report gets the command line's keys
    (``properties``, ``properties_*``, ``properties_seconds``; docs/properties.md). Any
    ``properties_*`` argument turns the stage on.

    Returns a :class:`Result`: ``.phi`` (N, N, N) float64 (read-only), ``.report`` (the dict of
    report.json), ``.history`` (a dict of NumPy columns, history.csv's), ``.save(dir)``.
    Raises ValueError / TypeError on bad arguments, SolverDiverged if the run diverges,
    KeyboardInterrupt on Ctrl-C.
    """
    a = arguments
    options = _run_options(a, ("surface", "initial", "grid", "solver"))
    stage = _stage_of(a)
    if stage is not None:  # refused before the solve, as the command line does
        _cmcsurf.check_properties_stage(stage, a["surface"], a["grid"])
    result = _cmcsurf.run(options, a["threads"], a["progress"])
    if stage is not None:
        _cmcsurf.properties_stage([result], stage, a["threads"])
    return result


@_signature([_P("phi", _P.POSITIONAL_OR_KEYWORD, annotation=Any),
             _P("volume_fraction", _P.POSITIONAL_OR_KEYWORD, default=None,
                annotation=Optional[float]),
             _parameter(_option("epsilon"), _P.POSITIONAL_OR_KEYWORD),
             _P("algorithm", _P.KEYWORD_ONLY, default="cmc", annotation=str)],
            _SOLVER,
            [_P("surface", _P.KEYWORD_ONLY, default=None, annotation=Optional[str]),
             _THREADS, _PROGRESS], Result,
            defaults={"prerelax_steps": 0})  # documented below: step 3 off for a given field
def relax(arguments: Dict[str, Any]) -> Result:
    """Relax your own field ``phi`` (an (N, N, N) array, e.g. a segmented tomography volume with
    0/1 phases or a simulation snapshot) to the CMC surface of its phase 1 = {phi > 1/2}.

    ``algorithm="cmc"`` (default): the paper's Section 4.4 from phi instead of a nodal formula,
    exactly as ``run`` does it (truncation to [0, 1], ``prerelax_steps`` steps at
    ``prerelax_epsilon_factor`` epsilon, the threshold whose mean is ``volume_fraction``, the
    shift to that mean, the relaxation at ``epsilon`` and, with ``constrain="volume"``, the mass
    corrections until the sharp volume fraction of phi > 1/2 is ``volume_fraction``).
    ``volume_fraction=None`` takes phi's own (the sharp volume fraction of phi > 1/2).
    Unlike ``run``, ``prerelax_steps`` defaults to 0: the steps at a 5 times wider interface
    smooth a nodal formula's kinks, but they can dissolve the fine structure of a segmented
    field. With ``prerelax_steps=5`` (run's default) this is run's algorithm:
    ``relax(initial_field("G", N), 0.5, prerelax_steps=5, surface="G")`` is
    ``run("G", 0.5, N)`` bit for bit.

    ``algorithm="direct"``: the Cahn-Hilliard relaxation at ``epsilon`` from phi as it is until
    the stop rule; the mass (mean of phi) is conserved, ``volume_fraction`` must be None. This
    is how ``run`` relaxes sphere, cube and noise: ``relax(initial_field("noise", N),
    algorithm="direct")`` is ``run("noise", grid=N)``.

    ``surface`` labels the report (default ``"field"``); a nodal name (e.g. "G") also adds the
    comparison with that nodal surface to the quality keys. ``coarse_levels`` must be 0 or None:
    there is no coarser version of a given field. Other options as in :func:`run`.
    """
    a = arguments
    options = _run_options(a, _SOLVER)
    options["surface"] = a["surface"]
    return _cmcsurf.relax(a["phi"], a["volume_fraction"], a["algorithm"], options, a["threads"],
                          a["progress"])


def initial_field(
    surface: str = "G",
    grid: int = 64,
    epsilon: float = 0.01,
    *,
    radius: float = 0.25,
    seed: int = 1,
) -> np.ndarray:
    """Step 1's field phi^0 of ``surface`` on the N^3 grid (the nodal formula of Eqs. 7-9 for
    nodal surfaces, the tanh-profile ball of ``radius`` for sphere, ...), read-only float64,
    indexed [i, j, k] as everywhere in this package."""
    return _cmcsurf.initial_field(
        {"surface": surface, "grid": grid, "epsilon": epsilon, "radius": radius, "seed": seed})


def measure(
    phi: Any, epsilon: float = 0.01, *, surface: Optional[str] = None, threads: int = 0
) -> Dict[str, Any]:
    """The measures of any field, with report.json's keys and estimators: ``area``,
    ``mean_curvature`` (sharp, of the phi = 1/2 surface, with ``area_error`` and
    ``mean_curvature_error``), ``volume_fraction``, ``mass``, ``energy``, the diffuse-layer
    ones (``area_diffuse``, ...) and the CMC-quality keys (``mean_curvature_std``, ...).
    ``epsilon`` is the interface parameter of the diffuse and energy measures (checked as
    ``run``'s). With a nodal ``surface`` the ``nodal_*`` keys compare with that nodal surface at
    phi's volume fraction (None otherwise)."""
    return _cmcsurf.measure(phi, {"epsilon": epsilon, "surface": surface}, threads)


@_signature([_P("surfaces", _P.POSITIONAL_OR_KEYWORD, default=("P", "D", "G"),
                annotation=Union[str, Sequence[str]]),
             _P("volume_fractions", _P.POSITIONAL_OR_KEYWORD, default="0.25:0.75:0.05",
                annotation=Union[str, Sequence[float]]),
             _parameter(_option("grid"), _P.POSITIONAL_OR_KEYWORD),
             _parameter(_option("epsilon"), _P.POSITIONAL_OR_KEYWORD),
             _P("continuation", _P.KEYWORD_ONLY, default=False, annotation=bool)],
            ("grid", "solver"), [*_PROPERTIES, *_SWEEP_FOLDER, _THREADS, _PROGRESS],
            Tuple[List[Result], Dict[str, np.ndarray]])
def sweep(arguments: Dict[str, Any]) -> Tuple[List[Result], Dict[str, np.ndarray]]:
    """Families of CMC surfaces over volume fraction (Fig. 11), as ``cmcsurf sweep``.

    ``surfaces``: nodal surfaces, a sequence or the command line's "P,D,G".
    ``volume_fractions``: a sequence, or "start:stop:step" (stop included) / "a,b,c".
    ``continuation``: start each member from the previous member's field.

    ``progress`` dicts carry ``member``, the member's name (``"G_0.30"``) as its folder in a
    ``cmcsurf sweep`` folder is named.

    Returns ``(results, table)``: one :class:`Result` per member (surfaces outermost; each
    ``.report`` is the member's report.json, with ``member`` and ``started_from``), and the
    table of sweep.csv as a dict of columns (float64 arrays for numbers, None as NaN; object
    arrays for strings and booleans).
    ``properties``, ``properties_*``: ``run``'s, for every member (sweep.csv's
    ``properties_*`` columns in the table).

    ``out``: also write the sweep's folder, as ``cmcsurf sweep --out`` does and with the same
    library code (member folders, sweep.csv, sweep.json, families.png/.svg, gallery.png,
    report.html; with ``properties`` the properties chart); ``force``, ``float32``,
    ``preview``, ``report``, ``plot``, ``plot_diffuse`` and ``checkpoint_every`` (seconds) are
    the command's ``--force``, ``--float32``, ``--no-preview``, ``--no-report``, ``--no-plot``,
    ``--plot-diffuse`` and ``--checkpoint-every``.
    Each Result's ``.report`` is then its report.json as written (with ``write_seconds``).
    Ctrl-C (or an exception raised by ``progress``) stops the member within a step and leaves
    its checkpoint, as a signal stops the command line's sweep; the exception is raised.
    ``resume=True`` (with ``out``) or ``resume=DIR`` continues such a folder as ``cmcsurf sweep
    --resume DIR`` does, the command line's or this function's: complete members are kept,
    an interrupted one goes on from its checkpoint. Arguments given must agree with sweep.json
    (ValueError names the first that differs); those not given take its values. A resumed
    sweep's ``results`` hold the members run by this call; the table has every member.
    Errors the command line reports with exit 2 raise ValueError, others RuntimeError.
    """
    a = arguments
    given = a[_GIVEN]
    resume = a["resume"]
    if resume is not False and resume is not True:  # a folder
        if a["out"] is not None and os.fspath(a["out"]) != os.fspath(resume):
            raise ValueError(f"out {os.fspath(a['out'])}: a resumed sweep writes into its own "
                             f"folder, resume {os.fspath(resume)}")
        out: Any = resume
        resuming = True
    else:
        out = a["out"]
        resuming = bool(resume)
        if resuming and out is None:
            raise ValueError("resume=True: give the folder, out=DIR (or resume=DIR)")
    if out is None:
        for key in ("force", *_SWEEP_OUTPUTS):
            if key in given:
                raise TypeError(f"sweep() {key}: only with out= (the folder it describes)")
    stage = _stage_of(a)
    properties_given = any(k.startswith("properties") for k in given)
    if stage is not None:  # refused before the solves (the checks do not depend on the surface)
        _cmcsurf.check_properties_stage(stage, "G", a["grid"])
    run_options = _run_options(a, ("grid", "solver"))
    if out is None:
        results, columns = _cmcsurf.sweep(a["surfaces"], a["volume_fractions"],
                                          a["continuation"], run_options, a["threads"],
                                          a["progress"])
        if stage is not None:
            columns = _cmcsurf.properties_stage(results, stage, a["threads"])
        reports = [r.report for r in results]
    else:
        # Not given: None, so that a resume takes sweep.json's value.
        folder = {k: (a[k] if k in given or not resuming else None) for k in _SWEEP_OUTPUTS}
        folder.update(dir=os.fspath(out), resume=resuming, force=a["force"])
        if resuming and not properties_given:
            stage = None
        results, reports, columns = _cmcsurf.sweep_folder(
            a["surfaces"], a["volume_fractions"], a["continuation"], run_options, folder, stage,
            sorted(given), a["threads"], a["progress"])
    table: Dict[str, np.ndarray] = {}
    for key in columns:
        values = [r.get(key) for r in reports]
        numeric = all(v is None or (isinstance(v, (int, float)) and not isinstance(v, bool))
                      for v in values)
        table[key] = (np.array([np.nan if v is None else v for v in values], dtype=float)
                      if numeric else np.array(values, dtype=object))
    return results, table


def mesh(
    source: Union[Result, Any],
    tile: Union[int, Tuple[int, int, int]] = (1, 1, 1),
    solid: str = "surface",
    thickness: Optional[float] = None,
    cell_size: float = 1.0,
    units: str = "mm",
    *,
    other_phase: bool = False,
    keep_fragments: bool = False,
    accept_topology_change: bool = False,
    threads: int = 0,
) -> Mesh:
    """A watertight scaffold mesh of a :class:`Result` or an (N, N, N) field, as
    ``cmcsurf mesh``: ``solid`` "surface" (the phi = 1/2 interface), "network" (the region
    phi > 1/2, capped at the box; ``other_phase`` for phi < 1/2) or "sheet" (a wall of
    ``thickness`` output units around the interface), ``tile`` unit cells along x, y, z, each
    ``cell_size`` ``units`` wide. ``keep_fragments`` (``--keep-fragments``): solids keep the
    pieces the box cuts off (by default they are removed; ``.report["topology"]`` says how
    many, their volume and whether they were removed); removing more than 1e-3 of the box (a
    solid in pieces) raises RuntimeError. A :class:`Result` whose member's Euler characteristic
    differs from its family's (``report["topology_changed"]``) raises RuntimeError unless
    ``accept_topology_change``.

    Returns a :class:`Mesh`: ``.vertices`` (n, 3) float64 (x, y, z along the field's axes i, j,
    k), ``.faces`` (m, 3) int64 (counter-clockwise seen from outside), ``.report`` (the dict of
    FILE.json: counts, area, volume, Euler characteristic, checks) and ``.save(path)`` for
    .stl/.ply/.obj/.3mf (format from the extension unless ``format=`` is given).
    """
    if isinstance(tile, (int, np.integer)) and not isinstance(tile, bool):
        tile_spec = str(int(tile))
    else:
        try:
            whole = all(isinstance(t, (int, np.integer)) and not isinstance(t, bool)
                        for t in tile)
            parts = [int(t) for t in tile] if whole else None
        except TypeError:
            parts = None
        if parts is None or len(parts) != 3:
            raise TypeError(f"tile: got {tile!r}; accepted: an int A or three ints (A, B, C)")
        tile_spec = "x".join(str(t) for t in parts)
    options = {"tile": tile_spec, "cell_size": cell_size, "units": units, "solid": solid,
               "thickness": thickness, "other_phase": other_phase,
               "keep_fragments": keep_fragments,
               "accept_topology_change": accept_topology_change}
    return _cmcsurf.mesh(source, options, threads)


def volume_mesh(
    source: Union[Result, Any],
    out: str,
    solid: str = "network",
    *,
    porosity: Optional[float] = None,
    thickness: Optional[float] = None,
    tile: Union[int, Tuple[int, int, int]] = (1, 1, 1),
    cell_size: float = 1.0,
    units: str = "mm",
    size: Optional[float] = None,
    size_min: Optional[float] = None,
    size_max: Optional[float] = None,
    facet_distance: Optional[float] = None,
    cut: str = "flat",
    format: str = "",
    threads: int = 0,
) -> Dict[str, Any]:
    """A periodic tetrahedral mesh of the network or sheet solid of a :class:`Result` or an
    (N, N, N) field, written to ``out`` (.msh/.inp/.vtu/.xdmf, or ``format``) with out.json, as
    ``cmcsurf volume-mesh`` (docs/volume_mesh.md): the nodes on the periodic cut are paired
    with their images one period away. Options and ranges as the command's; returns the dict
    of out.json. ValueError names a bad option.
    """
    if isinstance(tile, (int, np.integer)) and not isinstance(tile, bool):
        tile_spec = str(int(tile))
    elif isinstance(tile, (tuple, list)) and len(tile) == 3:
        tile_spec = "x".join(str(int(t)) for t in tile)
    else:
        raise TypeError(f"tile: got {tile!r}; accepted: an int A or three ints (A, B, C)")
    options = {"solid": solid, "porosity": porosity, "thickness": thickness, "tile": tile_spec,
               "cell_size": cell_size, "units": units, "size": size, "size_min": size_min,
               "size_max": size_max, "facet_distance": facet_distance, "cut": cut,
               "format": format}
    return _cmcsurf.volume_mesh(source, str(out), options, threads)


def properties(
    source: Union[Result, Any],
    solid: str = "network",
    *,
    phase: int = 1,
    porosity: Optional[float] = None,
    thickness: Optional[float] = None,
    material: Optional[Tuple[float, float]] = None,
    compare_nodal: bool = False,
    grid_check: bool = False,
    only: Union[str, Tuple[str, ...]] = ("elastic", "conductivity", "flow"),
    tolerance: float = 1e-5,
    cell_size: float = 1.0,
    units: str = "cell",
    surface: Optional[str] = None,
    flow_rate: Optional[float] = None,
    flow_area: Optional[float] = None,
    velocity: Optional[float] = None,
    viscosity: Optional[float] = None,
    threads: int = 0,
) -> Dict[str, Any]:
    """Effective stiffness and conductivities of a :class:`Result`'s (or an (N, N, N) field's)
    network or sheet solid, as ``cmcsurf properties``: returns the dict of its FILE.json
    (``stiffness_voigt`` normalised by E_s, ``youngs_modulus``, ``shear_modulus``,
    ``poisson_ratio``, ``bulk_modulus``, ``zener_ratio``, ``conductivity_solid``,
    ``conductivity_pore``, ``tortuosity_pore``, ``hashin_shtrikman_upper``,
    ``fraction_of_bound``, ...; docs/properties.md). ``solid`` "network" (phase ``phase``) or
    "sheet" (a wall of ``thickness`` in ``units`` of ``cell_size`` per cell, or at
    ``porosity``); ``material`` (E_GPa, nu) adds the moduli in GPa; ``compare_nodal`` adds the
    nodal part at the same porosity (``surface`` names the formula for a plain array);
    ``grid_check`` adds ``*_error`` keys from N/2. Flow (in ``only`` by default):
    ``permeability`` (cell_size^2; ``permeability_m2`` when ``units`` is physical),
    ``hydraulic_tortuosity``, ``specific_surface``, ``kozeny_carman_constant``,
    ``wall_shear_stress`` (flow along z), ``wall_shear_stress_per_axis`` and
    ``wall_shear_stress_axis_mean`` (flow along x, y, z and their mean); with ``flow_rate``
    (mL/min through ``flow_area`` in units^2) or ``velocity`` (mm/s) and ``viscosity`` (mPa s,
    water at 37 C by default) also ``wall_shear_stress_mpa`` (and its ``_per_axis``,
    ``_axis_mean``), ``pressure_drop_pa_per_m`` and ``pressure_drop_pa_per_m_per_axis``.
    """
    options: Dict[str, Any] = {"solid": solid, "phase": phase, "porosity": porosity,
                               "thickness": thickness, "compare_nodal": compare_nodal,
                               "grid_check": grid_check, "only": only, "tolerance": tolerance,
                               "cell_size": cell_size, "units": units, "surface": surface,
                               "flow_rate": flow_rate, "flow_area": flow_area,
                               "velocity": velocity, "viscosity": viscosity}
    if material is not None:
        try:
            e, nu = material
        except (TypeError, ValueError):
            raise TypeError(f"material: got {material!r}; accepted: (E_GPa, nu)") from None
        options["youngs_modulus_gpa"] = e
        options["poisson_ratio"] = nu
    return _cmcsurf.properties(source, options, threads)


def scattering(
    source: Union[Result, Any],
    density: str = "step",
    *,
    smax: int = 0,
    lattice: float = 1.0,
    peaks: Optional[Sequence[float]] = None,
    debye_waller: float = 0.0,
    peak_width: float = 0.0,
    peak_shape: str = "gaussian",
    absent_tol: float = 1e-6,
    index_tol: float = 0.01,
    threads: int = 0,
) -> Dict[str, Any]:
    """Structure factors of a :class:`Result` (or an (N, N, N) field), as ``cmcsurf
    scattering``: the dict of scattering.json (``space_group``, ``allowed``, ``absent``,
    ``indexing`` with ``peaks`` in 1/nm, ...; docs/science.md) with ``reflections`` (the
    columns of reflections.csv: h, k, l, s, multiplicity, intensity, amplitude, phase) and
    ``saxs`` (q, intensity of the powder pattern) as NumPy arrays. ``density``: "step",
    "bilayer:L" or "profile"; ``lattice`` a in nm.
    """
    options: Dict[str, Any] = {"density": density, "smax": smax, "lattice": lattice,
                               "peaks": peaks, "debye_waller": debye_waller,
                               "peak_width": peak_width, "peak_shape": peak_shape,
                               "absent_tol": absent_tol, "index_tol": index_tol}
    return _cmcsurf.scattering(source, options, threads)


# The scaffold's own options (driver/scaffold_run.cpp, the table `cmcsurf scaffold` reads):
# key, cli, help, type, default (None where the command line's is "" or none).
_SCAFFOLD_OPTIONS: List[Dict[str, Any]] = _cmcsurf.scaffold_options()
# Options a designer writes as numbers or tuples; the command line's text form is made here.
_RAMPS = ("porosity", "cell_size", "target_modulus", "target_permeability")
_PATHS = ("out", "shape", "cache")


def _number_text(key: str, v: Any) -> str:
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise TypeError(f"{key}: got {v!r} of type {type(v).__name__}; accepted: a real number")
    return repr(float(v))


def _scaffold_value(o: Dict[str, Any], v: Any) -> Any:
    """A keyword's value as the JSON value the option table takes (TypeError otherwise)."""
    key = o["key"]
    if key in _PATHS and isinstance(v, os.PathLike):
        v = os.fspath(v)
    if isinstance(v, str):
        if o["type"] != "str":
            raise TypeError(f"{key}: got {v!r} of type str; accepted: {o['type']}")
        return v
    if key in _RAMPS:  # V or (A, B)
        if isinstance(v, (tuple, list)) and len(v) == 2:
            return ":".join(_number_text(key, x) for x in v)
        return _number_text(key, v)
    if key == "size":  # A or (A, B, C)
        if isinstance(v, (tuple, list)) and len(v) == 3:
            return "x".join(_number_text(key, x) for x in v)
        return _number_text(key, v)
    if key == "material":  # E_GPa or (E_GPa, nu)
        if isinstance(v, (tuple, list)) and len(v) == 2:
            return ",".join(_number_text(key, x) for x in v)
        return _number_text(key, v)
    if o["type"] == "bool":
        if not isinstance(v, (bool, np.bool_)):
            raise TypeError(f"{key}: got {v!r} of type {type(v).__name__}; accepted: a bool")
        return bool(v)
    if o["type"] == "int":
        if isinstance(v, (bool, np.bool_)):
            raise TypeError(f"{key}: got {v!r}; accepted: an integer")
        try:
            return operator.index(v)
        except TypeError:
            raise TypeError(f"{key}: got {v!r} of type {type(v).__name__}; accepted: an "
                            f"integer") from None
    if o["type"] == "float":
        return float(_number_text(key, v))
    raise TypeError(f"{key}: got {v!r} of type {type(v).__name__}; accepted: a str")


def _scaffold_parameter(o: Dict[str, Any]) -> inspect.Parameter:
    default = o["default"]
    if default == "" or default is None:
        default = None
    elif o["key"] in _RAMPS:  # a number on the command line's text ("2")
        default = float(default)
    annotation = {"str": str, "float": float, "int": int, "bool": bool}[o["type"]]
    if o["key"] in _RAMPS:
        annotation = Union[str, float, Tuple[float, float]]  # type: ignore[assignment]
        if default is not None:
            return _P(o["key"], _P.KEYWORD_ONLY, default=default, annotation=annotation)
    elif o["key"] == "size":
        annotation = Union[str, float, Tuple[float, float, float]]  # type: ignore[assignment]
    elif o["key"] == "material":
        annotation = Union[str, float, Tuple[float, float]]  # type: ignore[assignment]
    elif o["key"] in _PATHS:
        annotation = Union[str, "os.PathLike[str]"]  # type: ignore[assignment]
    kind = _P.POSITIONAL_OR_KEYWORD if o["key"] == "out" else _P.KEYWORD_ONLY
    return _P(o["key"], kind, default=_P.empty if o["key"] == "out" else default,
              annotation=annotation if default is not None or o["key"] == "out"
              else Optional[annotation])


def _scaffold_doc() -> str:
    lines = ["", "Scaffold options (as the command line's, `cmcsurf scaffold --help`):", ""]
    for o in _SCAFFOLD_OPTIONS:
        lines.append(f"    {o['key']} ({o['cli']}): {o['help']}")
    return "\n".join(lines) + "\n"


_SCAFFOLD_KEYS = {o["key"] for o in _SCAFFOLD_OPTIONS}
# The run options `cmcsurf scaffold` takes: all but the surface's (it has its own --surface).
_SCAFFOLD_RUN_SCOPES = ("initial", "grid", "solver")
_SCAFFOLD_PROGRESS = _P("progress", _P.KEYWORD_ONLY, default=None,
                        annotation=Optional[Callable[[str], Any]])


def _scaffold_signature() -> inspect.Signature:
    leading = [_scaffold_parameter(o) for o in _SCAFFOLD_OPTIONS]
    named = {p.name for p in leading}
    runs = [_parameter(o) for o in _RUN_OPTIONS
            if o["scope"] in _SCAFFOLD_RUN_SCOPES and o["key"] not in named]
    return inspect.Signature(leading + runs + [_THREADS, _SCAFFOLD_PROGRESS],
                             return_annotation=Dict[str, Any])


_SCAFFOLD_SIGNATURE = _scaffold_signature()


def scaffold(*args: Any, **kwargs: Any) -> Dict[str, Any]:
    """A printable scaffold, exactly as ``cmcsurf scaffold``: every option of the command is a
    keyword (its long name with '-' -> '_', e.g. ``cell_size=2``, ``target_modulus=3``), with
    the command line's default, and the run options of ``run`` (``grid``, ``fast``, ...) are
    keywords too. Writes ``out`` (the mesh), ``out.json``, and unless ``no_page`` ``out.html``
    and ``out.png``; returns the dict of ``out.json`` (``porosity``, ``morphometry``,
    ``design``, ``properties``, ...; docs/scaffolds.md), the same numbers the command line
    writes. ``porosity`` and the targets take a number or a ramp ``(A, B)`` along ``axis``
    (``porosity`` also by depth in a ``shape``: ``grade_by="surface", grade_depth=D``),
    ``size`` a number or ``(A, B, C)``, ``material`` ``(E_GPa, nu)``. Members are cached as the
    command line caches them (``cache``). Warnings are issued as ``UserWarning``; ``progress``
    gets each line the command line prints while it works; the call releases the GIL and
    Ctrl-C stops it (KeyboardInterrupt, nothing written). A bad option raises ValueError
    (TypeError for a wrong type) with the command line's message; a part that cannot be made
    (a target out of reach, closed cells) raises RuntimeError and writes nothing.
    """
    try:
        bound = _SCAFFOLD_SIGNATURE.bind(*args, **kwargs)
    except TypeError as e:
        raise TypeError(f"scaffold() {e}") from None
    # Only the keywords given count, as only the options typed do on the command line (a
    # typed --cell-size lets no target solve it; a typed --grid is not with --resolution).
    given = {k: v for k, v in bound.arguments.items() if v is not None}
    bound.apply_defaults()
    options = {o["key"]: _scaffold_value(o, given[o["key"]]) for o in _SCAFFOLD_OPTIONS
               if o["key"] in given}
    run_options = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in given.items()
                   if k not in _SCAFFOLD_KEYS and k not in ("threads", "progress")}
    report, notes = _cmcsurf.scaffold(options, run_options, bound.arguments["threads"],
                                      bound.arguments["progress"])
    for note in notes:
        warnings.warn(note, UserWarning, stacklevel=2)
    return report


scaffold.__signature__ = _SCAFFOLD_SIGNATURE  # type: ignore[attr-defined]
scaffold.__doc__ = (scaffold.__doc__ or "") + _scaffold_doc() + _options_doc(
    [o["key"] for o in _RUN_OPTIONS if o["scope"] in _SCAFFOLD_RUN_SCOPES])


def morphometry(
    source: Union[Result, str, "os.PathLike[str]", Any],
    solid: str = "network",
    *,
    porosity: Optional[float] = None,
    thickness: Optional[float] = None,
    cell_size: float = 1.0,
    units: str = "mm",
    threads: int = 0,
) -> Dict[str, Any]:
    """Wall thickness, pore size and throat of one unit cell, as ``cmcsurf scaffold`` measures
    them (local thickness: the diameter of the largest ball inside the phase that holds each
    voxel, on the periodic cell): ``source`` a :class:`Result`, an (N, N, N) field or a run
    folder (or its field.vti); ``solid`` "network" (phase 1) or "sheet" (a wall around the
    phi = 1/2 surface at ``porosity`` or of ``thickness`` in ``units``); ``cell_size`` in
    ``units`` per cell. Returns ``wall_thickness`` and ``pore_size`` (mean, std, min, max, p5,
    p50, p95, histogram), ``throat`` (diameter along x, y, z and min), ``voxel``, ``method``.
    """
    if isinstance(source, Result):
        source = source.phi
    if isinstance(source, os.PathLike):
        source = os.fspath(source)
    if not isinstance(source, str):
        source = np.ascontiguousarray(source, dtype=np.float64)
    nan = float("nan")
    return _cmcsurf.morphometry(source, solid,
                                nan if porosity is None else float(porosity),
                                nan if thickness is None else float(thickness),
                                float(cell_size), units, int(threads))


def default_options() -> Dict[str, Any]:
    """The command line's defaults of every run option (report.json's ``parameters``)."""
    return _cmcsurf.default_options()

