"""Magnification studies (physics.md section 12): friction and contact area
against the short-wavelength cut-off ``q1`` of a configuration's generated
surface, the boundary-element solution beside Persson's theory, exactly as
``viscoslide magnification`` computes them."""

from __future__ import annotations

import json
import os
import warnings
from typing import Any, Dict, Mapping, Optional, Sequence

import numpy as np

from . import _checks, _native
from .curves import _frame
from .solve import _overrides

#: Columns of :func:`magnification`, in order (one row per level and speed).
MAGNIFICATION_COLUMNS = (
    "speed",
    "q1",
    "n",
    "ny",
    "cells_per_shortest_wavelength",
    "rms_height",
    "rms_slope",
    "rms_slope_continuum",
    "friction_coefficient",
    "friction_coefficient_dissipation",
    "contact_area_fraction",
    "persson_friction_coefficient",
    "persson_contact_area_fraction",
    "matvecs",
    "iterations",
    "residual",
    "wall_time_s",
)


def magnification(
    config: "os.PathLike[str] | str",
    q1: Optional[Sequence[float]] = None,
    *,
    scales: Optional[Sequence[float]] = None,
    cells_per_wavelength: float = 4.0,
    speed: Optional[float] = None,
    speeds: Optional[Sequence[float]] = None,
    backend: Optional[str] = None,
    shard: Optional[str] = None,
    out: "os.PathLike[str] | str | None" = None,
    set: "Optional[Mapping[str, Any] | str | Sequence[str]]" = None,
    as_frame: bool = False,
) -> Any:
    """The magnification study of the configuration file ``config``, as
    ``viscoslide magnification``: the PSD of its ``[surface.generate]`` held
    fixed and cut at each level's ``q1`` [1/m] (or ``scales``, ``q1 = N
    q_L``), each level on the grid with ``cells_per_wavelength`` cells per
    shortest wavelength and the same seed; at ``speed`` or each of
    ``speeds`` [m/s] (default: the configuration's).

    With ``out`` the points are stored in that directory (a rerun resumes;
    ``shard="K/N"`` runs a subset) and ``magnification.json``, ``.csv`` and
    ``.png`` are written there when every point is done. ``set`` overrides
    configuration keys (the command's ``--set``): a mapping
    ``{"section.key": value}``, a ``"section.key=value"`` string or a list
    of them, as for :func:`solve_config`. Every argument is checked before
    anything is solved or written: numbers (a boolean, a string or NaN is
    a ``ValueError``), strings and paths (a ``TypeError``), each message
    naming the argument and the value.

    Returns a dict of 1-D arrays (:data:`MAGNIFICATION_COLUMNS`, one entry
    per level and speed, speeds outer), or a pandas DataFrame with
    ``as_frame=True`` (the study's ``warnings``, ``psd`` and
    ``nominal_pressure`` in ``attrs``); ``None`` when a shard leaves
    points of other shards missing. The study's warnings are also issued
    with ``warnings.warn``. Errors are the command's, as ``ValueError``.
    """
    path = _checks.path("config", config)
    if not os.path.exists(path):
        raise FileNotFoundError(f"{path}: no such file")
    if speed is not None and speeds is not None:
        raise ValueError("give at most one of speed (m/s) and speeds")
    if speed is not None:
        speed_list: Optional[list] = [_checks.number("speed", speed)]
    else:
        speed_list = None if speeds is None else _checks.reals("speeds", speeds)
    frame = _checks.flag("as_frame", as_frame)
    text = _native.magnification(
        path,
        _overrides(set),
        None if q1 is None else _checks.reals("q1", q1),
        None if scales is None else _checks.reals("scales", scales),
        _checks.number("cells_per_wavelength", cells_per_wavelength),
        speed_list,
        _checks.text("backend", backend, "'auto', 'cpu' or 'gpu'"),
        _checks.shard(shard),
        None if out is None else _checks.path("out", out),
    )
    if text is None:
        return None
    report = json.loads(text)
    for w in report["warnings"]:
        warnings.warn(w, stacklevel=2)
    levels = report["levels"]
    columns: Dict[str, np.ndarray] = {
        c: np.asarray([level[c] for level in levels], dtype=float) for c in MAGNIFICATION_COLUMNS
    }
    for c in ("n", "ny", "matvecs", "iterations"):
        columns[c] = columns[c].astype(np.int64)
    if frame:
        table = _frame(columns, True)
        table.attrs.update(
            warnings=report["warnings"],
            psd=report["psd"],
            nominal_pressure=report["nominal_pressure"],
        )
        return table
    return columns
