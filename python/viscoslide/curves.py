"""Many solves and the analytic references: :func:`sweep` and
:func:`friction_curve` (friction and contact area against speed and load),
:func:`persson` (Persson's theory for the same surface, material and
pressure) and :func:`kernel_table` (the influence coefficients)."""

from __future__ import annotations

import inspect
import json
import warnings
from collections.abc import Iterator
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from . import _checks, _native, _progress
from .material import Material
from .solve import Result, _layer, _loading, _native_args, _warned
from .surface import Surface

#: Columns of :func:`sweep`, in order.
COLUMNS = (
    "speed",
    "xi",
    "normal_load",
    "friction_coefficient",
    "friction_coefficient_dissipation",
    "contact_area_fraction",
    "approach",
    "max_pressure",
    "iterations",
    "matvecs",
    "residual",
    "persson_friction_coefficient",
    "persson_contact_area_fraction",
    "temperature",
    "shift_factor",
)

#: Columns of :func:`sweep` added when it heats (``heating=`` or a varied
#: ``heating.*`` key): from each point's heating report (``NaN`` for a
#: point solved isothermally, ``"heating.enabled" = False``);
#: ``temperature_rise`` is the effective rise ``Theta(T_eff)``.
HEATING_COLUMNS = (
    "effective_temperature",
    "temperature_rise",
    "peak_surface_rise",
    "isothermal_friction_coefficient",
    "branches",
    "fixed_point_evaluations",
)


def _heating_row(heating: Optional[Dict[str, Any]]) -> Dict[str, Any]:
    """The :data:`HEATING_COLUMNS` of one point's heating report."""
    if heating is None:
        return {c: None for c in HEATING_COLUMNS}
    return {
        "effective_temperature": heating["effective_temperature"],
        "temperature_rise": heating["temperature_rise"]["effective"],
        "peak_surface_rise": heating["temperature_rise"]["peak_surface"],
        "isothermal_friction_coefficient": heating["isothermal_friction_coefficient"],
        "branches": len(heating["branches"]),
        "fixed_point_evaluations": heating["fixed_point_evaluations"],
    }

def _frame(columns: Dict[str, np.ndarray], as_frame: Any) -> Any:
    if not _checks.flag("as_frame", as_frame):
        return columns
    try:
        import pandas
    except ImportError:
        raise ImportError("as_frame=True needs pandas (pip install pandas)") from None
    return pandas.DataFrame(columns)


def _axis(name: str, values: Any) -> Optional[np.ndarray]:
    if values is None:
        return None
    arr = np.asarray(_checks.reals(name, values), dtype=float)
    if arr.size == 0:
        raise ValueError(f"{name} is empty: give at least one value")
    return arr


def _vary_lists(vary: Any) -> List[Tuple[str, list]]:
    """``vary`` as ``[(key, values), ...]`` for the sweep planner (which
    checks the keys and values as ``[sweep.vary]``): a number or string is
    a list of one, numpy values are Python's."""
    if vary is None:
        return []
    if not isinstance(vary, Mapping):
        raise TypeError(f"vary must be a dict of config key -> list of values, got {type(vary).__name__}")
    lists = []
    for key, values in vary.items():
        if not isinstance(key, str):
            raise TypeError(f"vary {key!r}: a key is a dotted config key such as 'loading.temperature'")
        if isinstance(values, Iterator):
            values = list(values)  # a generator: its values, once
        elif isinstance(values, (str, bytes)) or not isinstance(values, (Sequence, np.ndarray)):
            values = [values]
        lists.append((key, [v.item() if isinstance(v, np.generic) else v for v in values]))
    return lists


def _set_by(sections: Tuple[str, str, Optional[str], Optional[str]], options: Mapping[str, Any]) -> Dict[str, str]:
    """The config keys that the arguments in ``options`` set, each with its
    argument: the keys of the sections are named as the arguments of
    :func:`solve` (``layer.base`` is ``layer_base``, ``heating.*`` is
    ``heating``)."""
    given = {}
    for section, text in zip(("loading", "solver", "layer", "heating"), sections):
        for key in json.loads(text or "{}"):
            if section == "heating":
                arg = "heating"
            elif (section, key) == ("layer", "base"):
                arg = "layer_base"
            else:
                arg = key
            if options.get(arg) is not None:
                given[f"{section}.{key}"] = arg
    return given


#: The keyword arguments of :func:`solve` that :func:`sweep` and
#: :func:`friction_curve` pass on to every point.
_SOLVE_OPTIONS = frozenset(inspect.signature(_native_args).parameters) - {
    "surface",
    "material",
    "speed",
    "xi",
    "normal_load",
    "mean_pressure",
}


def _check_options(function: str, options: Mapping[str, Any]) -> None:
    """A keyword argument that is no option of :func:`solve` is a
    TypeError naming ``function`` and the argument, as Python names one."""
    for key in options:
        if key not in _SOLVE_OPTIONS:
            hint = "; the speeds are its argument speeds" if (function, key) == ("friction_curve", "speed") else ""
            raise TypeError(f"{function}() got an unexpected keyword argument {key!r}{hint}")


def _key_column(values: list) -> np.ndarray:
    """The column of a varied key, one entry per point: the values as numpy
    makes them, but an object array when they are lists or dicts (a
    ``creep_spectrum``'s rows, ``wlf``'s three numbers), which numpy would
    otherwise stack into more dimensions or refuse."""
    if any(isinstance(v, (list, tuple, dict)) for v in values):
        column = np.empty(len(values), dtype=object)
        for k, v in enumerate(values):
            column[k] = v
        return column
    return np.asarray(values)


def _point_note(k: int, count: int, point: Dict[str, Any], sliding_key: str, load_key: str) -> str:
    """The sweep point a failed solve belongs to, by its settings."""
    parts = [f"{sliding_key} = {v}" for v in point["speed"].values()]
    if point.get("normal_load") is not None:
        parts.append(f"{load_key} = {point['normal_load']}")
    parts += [f"{key} = {value}" for key, value in point.get("vary", {}).items()]
    return f"in sweep point {k + 1} of {count} ({', '.join(parts)})"


def sweep(
    surface: Any,
    material: Material,
    *,
    speed: Any = None,
    xi: Any = None,
    normal_load: Any = None,
    mean_pressure: Any = None,
    vary: Optional[Mapping[str, Any]] = None,
    progress: Any = None,
    as_frame: bool = False,
    **options: Any,
) -> Any:
    """Solve every combination of the given speeds (or ``xi``) and loads
    (``normal_load`` [N] or ``mean_pressure`` [Pa]), one independent solve
    per point, ``vary`` values outermost, then loads, speeds inner.

    Each of ``speed``, ``xi``, ``normal_load``, ``mean_pressure`` may be a
    number or a 1-D sequence (an array, list, range or generator; a prescribed ``approach`` is refused: the
    sweep's axis is the load); ``options`` are those of :func:`solve`
    (``formulation``, ``thickness``, ``backend``, ``tolerance``,
    ``temperature``, ``heating``, ...). ``vary`` maps config keys to lists of values,
    as ``[sweep.vary]`` of ``viscoslide sweep``: ``{"loading.temperature":
    [7.0, 17.0, 27.0]}``, ``"layer.thickness"``, ``"solver.tolerance"``,
    ``"material.poisson"``, ``"surface.generate.q1"`` (of a surface made
    from a ``[surface]`` section: generated or read from a file; ``q1``
    replaces the surface's ``scales``, ``rms_slope`` its ``rms_height``
    and the other way round) and any other key of the ``[material]``,
    ``[surface]``, ``[loading]``, ``[solver]``, ``[layer]`` and
    ``[heating]`` sections (``{"heating.enabled": [False, True]}`` with
    ``heating=`` gives every speed isothermal and heated, as ``viscoslide
    sweep`` does).
    The points are planned by the command line's sweep planner: the same
    keys and values refused with the same messages, at most 10,000
    combinations, the same order (keys in name order, the last fastest);
    every point is built and checked before the first solve. A key that
    an argument in ``options`` sets too is refused. Each combination is
    crossed with the speeds and loads and each key is a column of the
    result. ``progress=True`` shows a tqdm bar over points; a callable
    gets a dict per finished point (``point``, ``points`` and the point's
    columns).

    Returns a dict of 1-D arrays (:data:`COLUMNS` and the varied keys; a
    key whose values are lists or dicts, such as ``material.wlf`` or
    ``material.creep_spectrum``, is an object array of one value per
    point), or a pandas DataFrame with ``as_frame=True``. With ``temperature`` (or
    ``vary={"loading.temperature": ...}``) the ``temperature`` and
    ``shift_factor`` columns give ``a_T``: ``mu(v, T) = mu(a_T v, T_ref)``.
    A heated sweep (``heating=``, see :func:`solve`, or a varied
    ``heating.*`` key) adds :data:`HEATING_COLUMNS`: ``effective_temperature``
    ``T_eff`` [C], ``temperature_rise`` ``Theta(T_eff)`` (``T_eff - T0`` to the tolerance) [K],
    ``peak_surface_rise`` [K], ``isothermal_friction_coefficient`` (at
    ``T0``), the number of ``branches`` found and
    ``fixed_point_evaluations``, ``NaN`` where a point is isothermal; at a
    heated point ``friction_coefficient`` is the heated friction,
    ``persson_friction_coefficient`` Persson's at ``T_eff`` and
    ``temperature``, ``shift_factor`` those of ``T_eff``.
    """
    _check_options("sweep", options)
    # A topography-like surface is prepared once, with solve's keys for it.
    surf = Surface.coerce(
        surface,
        fill_missing=options.pop("fill_missing", None),
        detrend=options.pop("detrend", None),
        window=options.pop("window", None),
    )
    _checks.flag("as_frame", as_frame)
    speeds = _axis("speed", speed)
    xis = _axis("xi", xi)
    loads = _axis("normal_load", normal_load)
    pressures = _axis("mean_pressure", mean_pressure)
    if (speeds is None) == (xis is None):
        raise ValueError("give exactly one of speed (m/s) and xi (v tau / L)")
    # The load as solve takes it: one of the three, and a sweep's axis is
    # a load (a prescribed approach would be dropped for it).
    if sum(v is not None for v in (loads, pressures, options.get("approach"))) > 1:
        raise ValueError("give only one of normal_load (N), mean_pressure (Pa) and approach (m)")
    if options.get("approach") is not None:
        raise ValueError("a sweep prescribes the load: give normal_load (N) or mean_pressure (Pa), not approach (m)")
    if loads is None and pressures is None:
        raise ValueError("give exactly one of normal_load (N) and mean_pressure (Pa)")
    if "progress" in options or "speed" in options:
        raise ValueError("progress and speed are arguments of sweep itself")
    sliding_key, sliding = ("speed", speeds) if speeds is not None else ("xi", xis)
    load_key, load = ("normal_load", loads) if loads is not None else ("mean_pressure", pressures)
    lists = _vary_lists(vary)
    args = _native_args(surf, material, **options)
    if args[4] is None and any(key.split(".")[0] == "layer" for key, _ in lists):
        # A varied layer key makes a layer on solve's default base.
        args = (*args[:4], json.dumps({"base": options.get("layer_base") or "bonded"}), *args[5:])
    given = _set_by(args[2:6], options)
    for key, _ in lists:
        if key in given:
            raise ValueError(f"vary {key!r} and the argument {given[key]} both set it: give one")
    # The library's sweep planner: keys, values, limit and point order as
    # `viscoslide sweep` plans them; every point is built and checked
    # before the first solve (a refused sweep solves nothing).
    plan = _native.SweepPlan(*args, sliding_key, sliding.tolist(), load_key, load.tolist(), lists)
    points = json.loads(plan.points_json())
    keys = sorted({k for p in points for k in p.get("vary", {})})
    heated = args[5] is not None or any(key.split(".")[0] == "heating" for key in keys)
    numeric = (*COLUMNS, *(HEATING_COLUMNS if heated else ()))
    rows: Dict[str, list] = {c: [] for c in (*numeric, *keys)}
    with _progress.points(progress, len(points)) as callback:
        for k, point in enumerate(points):
            try:
                solved = plan.solve(k, args[6])
            except Exception as e:
                if hasattr(e, "add_note"):  # Python 3.11 and later
                    e.add_note(_point_note(k, len(points), point, sliding_key, load_key))
                raise
            s = _warned(Result(solved)).summary
            row = {c: s.get(c) for c in COLUMNS}
            row["normal_load"] = s["normal_load"]
            if heated:
                row.update(_heating_row(s.get("heating")))
            row.update(point.get("vary", {}))
            for c in rows:
                rows[c].append(np.nan if row[c] is None else row[c])
            if callback is not None:
                callback({"point": k + 1, "points": len(points), **row})
    columns = {c: np.asarray(v, dtype=float) for c, v in rows.items() if c not in keys}
    for c in keys:
        columns[c] = _key_column(rows[c])
    for c in ("iterations", "matvecs"):
        columns[c] = columns[c].astype(np.int64)
    return _frame(columns, as_frame)


def friction_curve(
    surface: Any,
    material: Material,
    speeds: Any = None,
    *,
    xi: Any = None,
    normal_load: Optional[float] = None,
    mean_pressure: Optional[float] = None,
    progress: Any = None,
    as_frame: bool = False,
    **options: Any,
) -> Any:
    """Friction and contact area against speed at one load: :func:`sweep`
    over ``speeds`` [m/s] (or ``xi``) at ``normal_load`` [N] or
    ``mean_pressure`` [Pa]; ``temperature=`` [C] (among ``options``)
    shifts the material by its WLF factor as in :func:`solve`, and
    ``heating=`` (with ``temperature``, the ambient ``T0``) heats every
    point by its own friction, adding :data:`HEATING_COLUMNS`."""
    _check_options("friction_curve", {k: v for k, v in options.items() if k != "vary"})
    if speeds is not None and xi is None:
        # Checked here to be named as this function's argument.
        speeds = _axis("speeds", speeds)
    return sweep(
        surface,
        material,
        speed=speeds,
        xi=xi,
        normal_load=normal_load,
        mean_pressure=mean_pressure,
        progress=progress,
        as_frame=as_frame,
        **options,
    )


def persson(
    surface: Any,
    material: Material,
    speeds: Any,
    *,
    normal_load: Optional[float] = None,
    mean_pressure: Optional[float] = None,
    temperature: Optional[float] = None,
    as_frame: bool = False,
    fill_missing: Optional[bool] = None,
    detrend: Optional[str] = None,
    window: Optional[str] = None,
) -> Any:
    """Persson's theory of friction and contact area (physics.md section
    10) for ``surface``, ``material`` and the nominal pressure
    (``mean_pressure`` [Pa], or ``normal_load`` [N] over the map's area) at
    ``speeds`` [m/s]: the analytic reference beside the simulations.

    The PSD is the continuum self-affine PSD of a generated surface, the
    table of a surface synthesised from a PSD table (``psd`` key of
    :meth:`Surface.generate`), else the radial average of the map as the
    solve prepares it (a scan: detrended, Hann-windowed, over its trusted
    band; physics.md section 11). ``fill_missing``, ``detrend`` and
    ``window`` prepare a topography-like ``surface`` (see
    :meth:`Surface.from_array`). ``temperature`` [C] shifts the material
    by its WLF factor as :func:`solve` does (``mu(v, T) = mu(a_T v,
    T_ref)``). Returns a dict of arrays ``speed``,
    ``friction_coefficient``, ``contact_area_fraction``, ``g_q1`` and the
    scalars ``psd`` (which PSD), ``nominal_pressure`` [Pa], ``temperature``
    [C] and ``shift_factor`` (``a_T``; ``None`` without WLF constants) and ``map_psd``
    (for a map's radial average: preprocessing, band, rms-slope check;
    else ``None``), ``warnings`` and ``notes``. As ``viscoslide persson``
    warns (``warnings.warn`` and the ``warnings`` list): a PSD whose rms
    slope differs from the map's real-space rms slope by more than 20 %, a
    temperature beyond the material's WLF data, and speeds whose
    frequencies ``v q`` lie a decade beyond its frequency data; ``notes``
    say what the theory leaves out (a map's anisotropic slopes).
    """
    surf = Surface.coerce(surface, fill_missing=fill_missing, detrend=detrend, window=window)
    if not isinstance(material, Material):
        raise TypeError(f"material must be a viscoslide.Material, got {type(material).__name__}")
    _checks.flag("as_frame", as_frame)
    v = _axis("speeds", speeds)
    loading = _loading(0.0, None, normal_load, mean_pressure, None, None, temperature)
    if ("normal_load" in loading) == ("mean_pressure" in loading):
        # Named as this function's arguments (it takes no approach).
        raise ValueError("give exactly one of normal_load (N) and mean_pressure (Pa)")
    mu, area, g, kind, sigma0, report, shift, warned, notes = _native.persson(
        surf._native, material._native, json.dumps(loading), v.tolist()
    )
    map_psd = None if report is None else json.loads(report)
    temperature_c, a_t = (None, None) if shift is None else shift
    for w in warned:
        warnings.warn(w, stacklevel=2)
    columns: Dict[str, Any] = {
        "speed": v,
        "friction_coefficient": mu,
        "contact_area_fraction": area,
        "g_q1": g,
    }
    scalars = dict(
        psd=kind,
        nominal_pressure=sigma0,
        map_psd=map_psd,
        temperature=temperature_c,
        shift_factor=a_t,
        warnings=warned,
        notes=notes,
    )
    if as_frame:
        frame = _frame(columns, True)
        frame.attrs.update(scalars)
        return frame
    columns.update(scalars)
    return columns


def kernel_table(
    material: Material,
    *,
    nx: int,
    cell_size: float,
    speed: float,
    ny: Optional[int] = None,
    direction_deg: float = 0.0,
    thickness: Optional[float] = None,
    layer_base: str = "bonded",
    derivative: bool = False,
    cell_size_y: Optional[float] = None,
    temperature: Optional[float] = None,
) -> np.ndarray:
    """Influence coefficients of the sliding kernel (paper Eq. 4-6): the
    surface displacement [m] of cell ``(i, j)`` under unit pressure [Pa] on
    cell ``(0, 0)``, for cells of side ``cell_size`` [m] along x and
    ``cell_size_y`` along y (default ``cell_size``: square; rectangular
    cells are a scan's non-square pixels) and every offset of an
    ``nx x ny`` grid; with ``derivative=True`` the cell-averaged ``dK/dx``
    [1/Pa] of the friction stencil.

    ``speed`` is ``>= 0``: ``0`` the relaxed limit, ``float("inf")`` the
    glassy one, as ``viscoslide kernel --speed inf``. The cells are checked
    as the command checks them: a layer below the bound of a cell is
    refused, one thinner than a cell is warned about (``warnings.warn``),
    and cells so far from a contact's scales that a coefficient is not
    finite are refused, naming the cell size.

    ``temperature`` [C] takes the material at that temperature: every creep
    time scaled by its WLF shift factor ``a_T`` (physics.md section 12;
    the material needs WLF constants), as ``viscoslide kernel`` applies
    ``[loading] temperature``; the coefficients are those at the speed
    ``a_T speed`` at the reference temperature.

    Returns an array of shape ``(2 nx - 1, 2 ny - 1)``; offset ``(i, j)``
    is at index ``(i + nx - 1, j + ny - 1)``.
    """
    if not isinstance(material, Material):
        raise TypeError(f"material must be a viscoslide.Material, got {type(material).__name__}")
    n = _checks.count("nx", nx)
    m = n if ny is None else _checks.count("ny", ny)
    table, warning = _native.kernel_table(
        material._native,
        n,
        m,
        _checks.positive("cell_size", cell_size, "m"),
        _checks.number("speed", speed, allow_inf=True),
        _checks.number("direction_deg", direction_deg),
        _layer(thickness, layer_base),
        _checks.flag("derivative", derivative),
        None if cell_size_y is None else _checks.positive("cell_size_y", cell_size_y, "m"),
        _checks.optional("temperature", temperature),
    )
    if warning is not None:
        warnings.warn(warning, stacklevel=2)
    return table
