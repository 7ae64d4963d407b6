# Type stubs of the compiled module (python/src/module.cpp); use the cmcsurf package's functions.
from os import PathLike
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

class SolverDiverged(RuntimeError): ...

class Result:
    """A run's result: immutable, the same numbers as the command line's run folder."""
    @property
    def phi(self) -> npt.NDArray[np.float64]:
        """The final field, (N, N, N) float64, read-only, indexed [i, j, k] (x, y, z)."""
    @property
    def report(self) -> Dict[str, Any]:
        """report.json of the run, as a dict."""
    @property
    def history(self) -> Dict[str, np.ndarray]:
        """history.csv's columns: step, stage, time, area, d_area, d_phi, energy, mass,
        vcycles, residual, elapsed, dt (int64 / float64 / str arrays), one row per time step."""
    def save(self, dir: Union[str, PathLike[str]], float32: bool = False,
             preview: bool = True) -> Any:
        """Writes the run folder as `cmcsurf run --out dir --no-report` does: history.csv,
        curvature_histogram.csv, field.vti (float32: single precision), preview.png (unless
        preview=False; report.json then gains preview_seconds) and report.json last. The
        interactive report.html: `cmcsurf report dir`. Returns the pathlib.Path of dir."""

class Mesh:
    """A triangle mesh in output units."""
    @property
    def vertices(self) -> npt.NDArray[np.float64]: ...
    @property
    def faces(self) -> npt.NDArray[np.int64]: ...
    @property
    def report(self) -> Dict[str, Any]: ...
    def save(self, path: Union[str, PathLike[str]], format: str = "") -> Any:
        """Writes the mesh (stl, ply, obj, 3mf; from the extension unless format is given) and
        path.json, as `cmcsurf mesh --out path` does; returns the pathlib.Path."""

def version() -> str: ...
def surfaces() -> List[Dict[str, Any]]: ...
def default_options() -> Dict[str, Any]: ...
def run(options: Dict[str, Any], threads: int,
        progress: Optional[Callable[[Dict[str, Any]], Any]]) -> Result: ...
def relax(phi: Any, volume_fraction: Optional[float], algorithm: str, options: Dict[str, Any],
          threads: int,
          progress: Optional[Callable[[Dict[str, Any]], Any]]) -> Result: ...
def initial_field(options: Dict[str, Any]) -> npt.NDArray[np.float64]: ...
def measure(phi: Any, epsilon: float, surface: Optional[str], threads: int) -> Dict[str, Any]: ...
def sweep(surfaces: str, fractions: str, continuation: bool, options: Dict[str, Any],
          threads: int, progress: Optional[Callable[[Dict[str, Any]], Any]]
          ) -> Tuple[List[Result], List[str]]: ...
def mesh(source: Any, tile: str, cell_size: float, units: str, solid: str, other_phase: bool,
         thickness: float, threads: int) -> Mesh: ...
