# Type stubs of the compiled module (python/src/module.cpp); use the cmcsurf package's functions.
from os import PathLike
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

class SolverDiverged(RuntimeError): ...

class Result:
    """A run's result: the field, report and history of one solve; immutable, the same numbers
    as the command line's run folder."""
    @property
    def phi(self) -> npt.NDArray[np.float64]:
        """The final field, (N, N, N) float64, read-only, indexed [i, j, k] (x, y, z)."""
    @property
    def report(self) -> Dict[str, Any]:
        """report.json of the run, as a dict: every key of the command line's report.json
        except preview_seconds, page_seconds and write_seconds (the preview, the page's meshes
        and the writes run in save(), whose report.json has them)."""
    @property
    def history(self) -> Dict[str, np.ndarray]:
        """history.csv's columns in its order (int64 / float64 / str arrays), one row per time
        step: the names, types and help are report_schema()["history_columns"]'s."""
    def save(self, dir: Union[str, PathLike[str]], float32: bool = False, preview: bool = True,
             report: bool = True, force: bool = False) -> Path:
        """Writes the run folder as `cmcsurf run --out dir` does: history.csv,
        curvature_histogram.csv, field.vti (float32: single precision), preview.png (unless
        preview=False, as --no-preview), report.json last (with preview_seconds) and
        report.html (unless report=False, as --no-report). Returns dir as a Path."""

class Mesh:
    """A watertight triangle mesh in output units (cell_size per unit cell); immutable."""
    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """(n, 3) float64, read-only: (x, y, z) along the field's axes i, j, k, times
        cell_size."""
    @property
    def faces(self) -> npt.NDArray[np.int64]:
        """(m, 3) int64, read-only: vertex indices, counter-clockwise seen from outside."""
    @property
    def report(self) -> Dict[str, Any]:
        """FILE.json of `cmcsurf mesh` as a dict: counts, area, volume, Euler characteristic,
        checks (closed, manifold), topology (fragments)."""
    def save(self, path: Union[str, PathLike[str]], format: str = "") -> Path:
        """Writes the mesh (stl, ply, obj, 3mf; from the extension unless format is given) and
        path.json (with source), as `cmcsurf mesh --out path` does; returns path as a Path."""

Progress = Optional[Callable[[Dict[str, Any]], Any]]

def version() -> str: ...
def surfaces() -> List[Dict[str, Any]]: ...
def default_options() -> Dict[str, Any]: ...
# The run option table (pipeline/run_schema.cpp), one dict per option: key, cli, scope
# (surface, initial, grid, solver), default, type (float, int, str, bool), unit, help,
# accepted, fast (whether --fast chooses it; the keyword's default is then None).
def run_options() -> List[Dict[str, Any]]: ...
# The report schema (schema/report_schema.cpp): report_keys (key, label, unit, help, format,
# page, error_key, timing, ...), history_columns (name, type, format, unit, help, timing),
# stages, sweep_leading_columns, families_table (key, header, format).
def report_schema() -> Dict[str, Any]: ...
def run(options: Dict[str, Any], threads: int, progress: Progress) -> Result: ...
def relax(phi: Any, volume_fraction: Optional[float], algorithm: str, options: Dict[str, Any],
          threads: int, progress: Progress) -> Result: ...
def initial_field(options: Dict[str, Any]) -> npt.NDArray[np.float64]: ...
def measure(phi: Any, options: Dict[str, Any], threads: int) -> Dict[str, Any]: ...
def sweep(surfaces: Union[str, Sequence[str]], fractions: Union[str, Sequence[float]],
          continuation: bool, options: Dict[str, Any], threads: int,
          progress: Progress) -> Tuple[List[Result], List[str]]: ...
# The sweep driver into folder["dir"] (resume, force, float32, preview, report, plot,
# plot_diffuse, checkpoint_every; None: sweep.json's or the default); returns (the Results
# run here, every member's report, sweep.csv's columns).
def default_checkpoint_every() -> float: ...  # --checkpoint-every's default, seconds
def sweep_folder(surfaces: Union[str, Sequence[str]], fractions: Union[str, Sequence[float]],
                 continuation: bool, options: Dict[str, Any], folder: Dict[str, Any],
                 stage: Optional[Dict[str, Any]], given: List[str], threads: int,
                 progress: Progress) -> Tuple[List[Result], List[Dict[str, Any]], List[str]]: ...
def mesh(source: Any, options: Dict[str, Any], threads: int) -> Mesh: ...
def properties(source: Any, options: Dict[str, Any], threads: int) -> Dict[str, Any]: ...
def volume_mesh(source: Any, out: str, options: Dict[str, Any],
                threads: int) -> Dict[str, Any]: ...
def check_properties_stage(options: Dict[str, Any], surface: str, grid: int) -> None: ...
def properties_stage(results: List[Result], options: Dict[str, Any],
                     threads: int) -> List[str]: ...
def scattering(source: Any, options: Dict[str, Any], threads: int) -> Dict[str, Any]: ...
# The scaffold's own option table (pipeline/scaffold_run.cpp), one dict per option: key, cli,
# help, type (str, float, int, bool), default (None: none).
def scaffold_options() -> List[Dict[str, Any]]: ...
# options: the scaffold options given, run_options: the run options given; returns
# (FILE.json, warnings) after writing the part (python/src/scaffold.cpp).
def scaffold(options: Dict[str, Any], run_options: Dict[str, Any], threads: int,
             progress: Optional[Callable[[str], Any]]) -> Tuple[Dict[str, Any], List[str]]: ...
def morphometry(source: Any, solid: str, porosity: float, thickness: float, cell_size: float,
                units: str, threads: int) -> Dict[str, Any]: ...
def periodic_mesh(phi: Any) -> Dict[str, Any]: ...
def signed_distance(phi: Any, epsilon: float) -> npt.NDArray[np.float64]: ...
def read_field(path: Any) -> Dict[str, Any]: ...
