"""Closed forms of ``slosh theory``: natural sloshing periods, Housner's (and the codes')
impulsive and convective masses and heights, convective base shear and the codes' wave
heights for a given spectral acceleration, freeboard, and the linear response to a sine.

Each function returns the report ``slosh theory SHAPE ... --ron`` prints, as a dict: the
same numbers, bit for bit.
"""

from __future__ import annotations

from typing import Any, Dict, Optional, Sequence

import numpy as np

from . import _ron
from ._slosh import rect_sine_elevation as _rect_sine_elevation
from ._slosh import theory_ron as _theory_ron

__all__ = ["rect", "cylinder", "rect_sine_elevation"]


def _report(
    shape: str,
    size: float,
    depth: float,
    tank_height: Optional[float],
    pga: Optional[float],
    sa: Optional[float],
    amplitude: Optional[float],
    omega: Optional[float],
    gravity: float,
) -> Dict[str, Any]:
    text = _theory_ron(shape, size, depth, tank_height, pga, sa, amplitude, omega, gravity)
    return _ron.loads(text)


def rect(
    width: float,
    depth: float,
    *,
    tank_height: Optional[float] = None,
    pga: Optional[float] = None,
    sa: Optional[float] = None,
    amplitude: Optional[float] = None,
    omega: Optional[float] = None,
    gravity: float = 9.81,
) -> Dict[str, Any]:
    """A rectangular tank (or 2D section) of inner width ``width`` = 2l (m) with ``depth``
    (m) of water: ``slosh theory rect --width W --depth H [...] --ron`` as a dict.

    ``tank_height`` (m) gives the freeboard check, ``pga`` (m/s²) the impulsive base shear,
    ``sa`` the convective spectral acceleration S_a(T_c) in g (the code wave heights and
    convective base shear), ``amplitude`` (m) with ``omega`` (rad/s) the linear response to
    the ground displacement A sin ωt. Keys: ``modes`` (omega rad/s, period s), ``masses``
    (impulsive/convective mass and height by source), ``wave_heights``, ``freeboard``, ...
    """
    return _report("rect", width, depth, tank_height, pga, sa, amplitude, omega, gravity)


def cylinder(
    radius: float,
    depth: float,
    *,
    tank_height: Optional[float] = None,
    pga: Optional[float] = None,
    sa: Optional[float] = None,
    amplitude: Optional[float] = None,
    omega: Optional[float] = None,
    gravity: float = 9.81,
) -> Dict[str, Any]:
    """An upright cylindrical tank of inner radius ``radius`` (m) with ``depth`` (m) of
    water: ``slosh theory cylinder --radius R --depth H [...] --ron`` as a dict (the options
    as in :func:`rect`)."""
    return _report("cylinder", radius, depth, tank_height, pga, sa, amplitude, omega, gravity)


def rect_sine_elevation(
    width: float,
    depth: float,
    amplitude: float,
    omega: float,
    t: Sequence[float],
    *,
    x: float = 0.0,
    modes: int = 10,
    gravity: float = 9.81,
) -> np.ndarray:
    """Linear potential theory's free-surface elevation η (m) in a rectangular tank (2D) of
    inner width ``width`` and liquid depth ``depth`` (m), at ``x`` (m from the left wall),
    under the ground displacement x_g = −A sin ωt started from rest (ground acceleration
    A ω² sin ωt: the paper's §3.1 excitation, ``amplitude`` = A in m, ``omega`` = ω in
    rad/s), at the times ``t`` (s since the excitation started; η = 0 before). Undamped
    modal sum over the first ``modes`` antisymmetric modes (Ibrahim 2005, ch. 2; Faltinsen &
    Timokha 2009, ch. 5), the reference of the validation suite's resonant case."""
    return _rect_sine_elevation(
        width, depth, amplitude, omega, [float(v) for v in t], x, modes, gravity
    )
