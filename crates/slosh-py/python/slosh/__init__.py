"""slosh: sloshing loads on liquid storage tanks by SPH, from Python.

Run a case script and read its results as numpy arrays::

    import slosh
    run = slosh.run("scripts/paper_2d_sloshing.rhai", duration=4.0, dx=0.02)
    t, eta = run.series["t"], run.series["eta_left"]
    print(run.summary["max_eta_left"], run.status)

A run is the one ``slosh run`` makes: the same script, the same ``--set`` rules for the
keyword arguments and, with ``out``, the same output folder (see the repository's
``docs/formats.md``).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any, Dict, List, Optional, Union

import numpy as np

from . import _ron, theory
from ._slosh import Record, ScriptError
from ._slosh import __version__ as __version__
from ._slosh import list_params as _list_params
from ._slosh import load_record as _load_record
from ._slosh import read_csv_columns as _read_csv_columns
from ._slosh import run_case as _run_case

__all__ = [
    "Record",
    "Run",
    "ScriptError",
    "SimulationError",
    "load_record",
    "params",
    "run",
    "theory",
]

PathLike = Union[str, "os.PathLike[str]"]


class SimulationError(RuntimeError):
    """A run that did not complete (the solver blew up, particles left the tank, the
    ground motion or ``post(run)`` failed, an output could not be written). ``run`` is the
    partial :class:`Run`: everything measured up to the failure."""

    def __init__(self, message: str, run: "Run") -> None:
        super().__init__(message)
        self.run = run


def _set_text(value: Any) -> str:
    """A keyword argument as the text of ``--set NAME=VALUE``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float, np.integer, np.floating)):
        return repr(value.item() if isinstance(value, np.generic) else value)
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    raise TypeError(
        f"a parameter value must be a number, a bool or a string, not {type(value).__name__}"
    )


class Run:
    """The results of a run, read from its output folder.

    Attributes:
        folder: the output folder (None when the run wrote into a temporary folder that is
            gone).
        series: ``series.csv`` as a dict of 1-D float64 arrays keyed by its column names
            (``t``, ``eta_left``, ``base_shear_x``, ...).
        units: the unit of each series column (``series_units.csv``).
        summary: ``summary.ron`` as a dict (numbers as float/int, structs and maps as
            dicts; ``parameters``, ``parts`` and ``post`` as dicts of name → value).
        impacts: the roof impacts, a list of dicts (Kurihara's and Malhotra's pressures
            beside the SPH peak).
        roof_pressure: the roof pressure map when the tank has a roof, else None: a dict
            with ``t`` (s, the rows), ``x`` (2D: the position along the roof, m; 3D, and a
            2D roof whose points share an x: the roof point index) and ``p`` (Pa, a 2-D array
            of shape (len(t), len(x))); with the index also ``points`` (``roof_points.csv``
            as a dict of columns).
        roof_load: the roof load from every step (``summary.ron``'s ``roof_load``) when the
            tank has a roof, else None: a dict with ``periods`` (the roof periods T_r, s),
            ``roof`` (``peak``, ``impulse``, ``design`` = F_eq at ``periods``, ``dlf``),
            ``sensors``, ``impacts`` and the impacts' spread (``impact_impulse``,
            ``impact_f_eq``: median, p84, max).
        roof_spectrum: the roof load spectrum (``roof_spectrum.csv``) as a dict of columns
            (``period``, ``roof_f_eq``, ``roof_dlf``, ``p_<sensor>_eq``, ...), else None.
        status: "completed", "failed" or "interrupted".
        error: the error message of a run that did not complete, else None.
    """

    def __init__(self, folder: PathLike, keep_folder: bool = True) -> None:
        folder = Path(folder)
        self.series: Dict[str, np.ndarray] = {}
        self.units: Dict[str, str] = {}
        series = folder / "series.csv"
        if series.exists():
            names, columns = _read_csv_columns(str(series))
            self.series = dict(zip(names, columns))
        units = folder / "series_units.csv"
        if units.exists():
            rows = units.read_text(encoding="utf-8").splitlines()[1:]
            self.units = dict(row.split(",", 1) for row in rows if "," in row)
        summary_file = folder / "summary.ron"
        self.summary: Dict[str, Any] = (
            _ron.loads(summary_file.read_text(encoding="utf-8")) if summary_file.exists() else {}
        )
        for key in ("parameters", "parts", "post"):
            value = self.summary.get(key)
            if isinstance(value, list):
                self.summary[key] = {name: v for name, v in value}
        self.impacts: List[Dict[str, Any]] = list(self.summary.get("impacts", []))
        self.status: str = self.summary.get("status", "failed")
        self.error: Optional[str] = self.summary.get("error")
        self.roof_pressure: Optional[Dict[str, Any]] = None
        roof = folder / "roof_pressure.csv"
        if roof.exists():
            names, columns = _read_csv_columns(str(roof))
            p = np.column_stack(columns[1:]) if len(columns) > 1 else np.zeros((0, 0))
            self.roof_pressure = {
                "t": columns[0],
                "x": np.array([float(n) for n in names[1:]]),
                "p": p,
            }
            points = folder / "roof_points.csv"
            if points.exists():
                names, columns = _read_csv_columns(str(points))
                self.roof_pressure["points"] = dict(zip(names, columns))
        self.roof_load: Optional[Dict[str, Any]] = self.summary.get("roof_load")
        self.roof_spectrum: Optional[Dict[str, np.ndarray]] = None
        spectrum = folder / "roof_spectrum.csv"
        if spectrum.exists():
            names, columns = _read_csv_columns(str(spectrum))
            self.roof_spectrum = dict(zip(names, columns))
        self.folder: Optional[Path] = folder if keep_folder else None

    @classmethod
    def load(cls, folder: PathLike) -> "Run":
        """Reads the output folder of a run made earlier (by ``slosh run`` or Python)."""
        if not (Path(folder) / "summary.ron").exists():
            raise FileNotFoundError(f"{folder} holds no summary.ron: not a slosh run folder")
        return cls(folder)

    def to_pandas(self) -> Any:
        """The series as a pandas DataFrame indexed by time ``t`` (needs pandas)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("Run.to_pandas needs pandas: pip install pandas") from e
        frame = pd.DataFrame(self.series)
        if "t" in frame:
            frame = frame.set_index("t")
        return frame

    def __repr__(self) -> str:
        rows = len(self.series.get("t", ()))
        return (
            f"Run(case={self.summary.get('case')!r}, status={self.status!r}, "
            f"{rows} rows, {len(self.series)} columns)"
        )


def run(
    script: PathLike,
    out: Optional[PathLike] = None,
    threads: Optional[int] = None,
    progress: bool = False,
    **params: Any,
) -> Run:
    """Runs the case script ``script`` and returns its :class:`Run`.

    Keyword arguments override the parameters the script declares with
    ``param(name, default)``, by the rules of ``slosh run --set name=value`` (a value is
    passed as its text: ``3`` is an integer, ``3.0`` a float, ``True`` the flag ``true``,
    any other string a string). With ``out`` the usual output folder is written there, the
    one ``slosh run SCRIPT --out OUT`` writes (plots and checkpoint included); without it the
    run goes into a temporary folder that is removed once its results are read.

    ``threads`` sets the worker threads of this run (default: all cores); ``progress``
    shows the progress bar on stderr. The GIL is released while the solver runs; Ctrl-C
    stops the run after its current step and raises ``KeyboardInterrupt``.

    Raises:
        ScriptError: the script or a parameter is wrong (with ``file``, ``line``, ``column``).
        SimulationError: the run did not complete; ``.run`` holds what it measured.
    """
    sets = [f"{name}={_set_text(value)}" for name, value in params.items()]
    script = os.fspath(script)
    if out is not None:
        out = os.fspath(out)
        error = _run_case(script, out, sets, threads, progress, True, "10m")
        return _finish(Run(out), error)
    with tempfile.TemporaryDirectory(prefix="slosh-run-") as tmp:
        folder = os.path.join(tmp, "run")
        error = _run_case(script, folder, sets, threads, progress, False, None)
        return _finish(Run(folder, keep_folder=False), error)


def _finish(result: Run, error: Optional[str]) -> Run:
    if error is None:
        return result
    if not result.summary:
        raise RuntimeError(error)
    raise SimulationError(error, result)


def params(script: PathLike) -> Dict[str, Dict[str, Any]]:
    """The parameters ``script`` declares, as ``slosh run SCRIPT --list-params`` lists them:
    name → dict with ``default``, ``type`` ("float", "int", "bool", "string"), ``unit`` and
    ``description`` (None when the script gives none)."""
    return {
        p["name"]: {k: v for k, v in p.items() if k != "name"}
        for p in _list_params(os.fspath(script))
    }


def load_record(
    path: PathLike,
    format: Optional[str] = None,
    units: Optional[str] = None,
    dt: Optional[float] = None,
) -> Record:
    """Reads a ground-acceleration record as a script's ``load_record`` does.

    ``format``: "at2" (PEER NGA, values in g), "knet" (K-NET / KiK-net ASCII, in gal) or
    "csv" (plain text: time and acceleration columns, or one acceleration column with
    ``dt`` in s); None follows the file's content and name. ``units`` ("g", "gal", "m/s2")
    is required for plain text. The record's ``t`` and ``accel`` are in s and m/s².
    """
    return _load_record(os.fspath(path), format, units, dt)
