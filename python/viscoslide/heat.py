"""Frictional heating's heat problem: :func:`surface_temperature`, the
steady surface temperature rise of a rubber half-space sliding past a
surface heat flux map (physics.md section 14)."""

from __future__ import annotations

import warnings
from typing import Any, Optional

import numpy as np

from . import _checks, _native


def _flux(value: Any) -> np.ndarray:
    """``value`` as a C-contiguous float64 2-D array of finite values; a
    masked array's masked points are refused as such (a flux has no
    missing cells: 0 where no heat enters)."""
    value = _checks.unmasked(
        "flux", value, "; a flux has a value in every cell: fill them (flux.filled(0.0) where no heat enters)"
    )
    try:
        arr = np.asarray(value)
    except Exception as e:  # ragged lists and the like
        raise ValueError(f"flux must be an array of real numbers: {e}") from None
    if arr.dtype.kind not in "fiu" or arr.ndim != 2:
        # The common refusals (complex, strings, wrong rank) in their words.
        return _checks.real_array("flux", arr, 2)
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    if arr.size == 0:
        raise ValueError(f"flux is empty (shape {arr.shape}): give at least one cell")
    finite = np.isfinite(arr)
    if not finite.all():
        bad = int(arr.size - np.count_nonzero(finite))
        first = tuple(int(i) for i in np.argwhere(~finite)[0])
        raise ValueError(
            f"flux has {bad} non-finite value(s) (NaN or inf), the first at index {first}; "
            "every value must be finite (0 where no heat enters)"
        )
    return arr


def surface_temperature(
    flux: Any,
    cell_size: float,
    speed: float,
    conductivity: float,
    diffusivity: float,
    periodic: bool = False,
    block_length: Optional[float] = None,
    direction_deg: float = 0.0,
    cell_size_y: Optional[float] = None,
) -> np.ndarray:
    """The steady surface temperature rise ``T - T0`` [K] of a rubber
    half-space sliding at ``speed`` [m/s] along ``direction_deg`` (degrees
    from +x) past the surface heat flux ``flux`` [W/m^2], one value per
    cell of ``cell_size`` x ``cell_size_y`` [m] (default square; axis 0 =
    x), for a rubber of thermal ``conductivity`` [W/(m K)] and
    ``diffusivity`` [m^2/s].

    By default the cells are a pad on an unbounded half-space (the moving
    point source integrated over each cell). With ``periodic=True`` they are
    one period of a periodic cell, whose mean rise has no steady state: the
    array then has zero mean unless ``block_length`` [m], the length of the
    sliding block along the sliding direction, is given, in which case the
    block's background heating over a passage, ``(4/3) qbar sqrt(kappa t_c
    / pi) / lam`` with ``t_c = block_length / speed``, is added. Where the
    passage is too short for the cell (the depth ``L / (2 pi)`` of its
    longest period ``L`` above 0.3 of ``sqrt(kappa t_c)``: the background
    formula and the steady rise of the modes constant along the sliding
    direction then overstate what one passage reaches), a warning says so
    (``warnings.warn``), as ``viscoslide heat`` notes it.

    Returns an array of the shape of ``flux``: the rise at the cell centres.
    """
    q = _flux(flux)
    periodic = _checks.flag("periodic", periodic)
    if block_length is not None and not periodic:
        raise ValueError(
            "block_length is the periodic cell's (its background heating); pass periodic=True or drop block_length"
        )
    rise, notes = _native.surface_temperature(
        q,
        _checks.positive("cell_size", cell_size, "m"),
        _checks.positive("speed", speed, "m/s"),
        _checks.positive("conductivity", conductivity, "W/(m K)"),
        _checks.positive("diffusivity", diffusivity, "m^2/s"),
        periodic,
        None if block_length is None else _checks.positive("block_length", block_length, "m"),
        _checks.number("direction_deg", direction_deg),
        None if cell_size_y is None else _checks.positive("cell_size_y", cell_size_y, "m"),
    )
    if block_length is not None:
        # Without a block the one note is the zero mean, stated above.
        for note in notes:
            warnings.warn(note, stacklevel=2)
    return rise
