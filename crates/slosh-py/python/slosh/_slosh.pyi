"""Type stubs of ``slosh._slosh``, the compiled part of the package (Rust, pyo3)."""

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

class ScriptError(Exception):
    """An error in a case script or in the parameters given to it.

    ``file`` is the script; ``line`` and ``column`` (1-based) say where the script is at
    fault, and are None for an error without a place (an unknown parameter, say)."""

    file: str
    line: Optional[int]
    column: Optional[int]

class Record:
    """A ground-acceleration record: uniform samples in m/s²."""

    @property
    def t(self) -> npt.NDArray[np.float64]:
        """Sample times (s)."""
    @property
    def accel(self) -> npt.NDArray[np.float64]:
        """Ground acceleration (m/s²), a copy of the samples."""
    @property
    def dt(self) -> float:
        """Sample interval (s)."""
    @property
    def pga(self) -> float:
        """Peak ground acceleration max |a| (m/s²)."""
    @property
    def source(self) -> str:
        """The file the record was read from."""
    @property
    def format(self) -> str:
        """The file layout: "PEER AT2", "K-NET ASCII" or "plain text"."""
    @property
    def units(self) -> str:
        """The units of the file's values ("g", "gal", "m/s2"), converted to m/s²."""
    @property
    def processing_log(self) -> List[str]:
        """Every operation applied since reading, in order."""
    def scale_to_pga(self, pga: float) -> "Record":
        """Scales the record in place to the peak |a| ``pga`` (m/s²); returns it."""
    def spectrum(
        self, periods: Sequence[float], damping: float = 0.05
    ) -> npt.NDArray[np.float64]:
        """Pseudo-acceleration response spectrum S_a (m/s²) at the natural periods
        ``periods`` (s) for the damping ratio ``damping`` (fraction of critical)."""
    def __len__(self) -> int: ...

def run_case(
    script: str,
    out: str,
    sets: List[str],
    threads: Optional[int] = None,
    progress: bool = False,
    plots: bool = True,
    checkpoint_every: Optional[str] = None,
) -> Optional[str]:
    """Runs ``script`` into the folder ``out`` as ``slosh run SCRIPT --out OUT --set S...``;
    None when the run completed, else its error (the folder holds what was written)."""

def list_params(script: str) -> List[Dict[str, Any]]:
    """The script's parameters: name, type, default, unit, description."""

def theory_ron(
    shape: str,
    size: float,
    depth: float,
    tank_height: Optional[float] = None,
    pga: Optional[float] = None,
    sa: Optional[float] = None,
    amplitude: Optional[float] = None,
    omega: Optional[float] = None,
    gravity: float = 9.81,
) -> str:
    """The report of ``slosh theory SHAPE ... --ron`` as RON text."""

def load_record(
    path: str,
    format: Optional[str] = None,
    units: Optional[str] = None,
    dt: Optional[float] = None,
) -> Record:
    """Reads a record as a script's ``load_record`` does."""

def read_csv_columns(path: str) -> Tuple[List[str], List[npt.NDArray[np.float64]]]:
    """A numeric CSV table with one header line: its names and float64 columns."""

def rect_sine_elevation(
    width: float,
    depth: float,
    amplitude: float,
    omega: float,
    t: List[float],
    x: float = 0.0,
    modes: int = 10,
    gravity: float = 9.81,
) -> npt.NDArray[np.float64]:
    """Linear theory's η (m) at x in a rectangular tank under x_g = −A sin ωt from rest."""
