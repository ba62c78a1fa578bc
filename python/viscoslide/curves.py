"""Many solves and the analytic references: :func:`sweep` and
:func:`friction_curve` (friction and contact area against speed and load),
:func:`persson` (Persson's theory for the same surface, material and
pressure) and :func:`kernel_table` (the influence coefficients)."""

from __future__ import annotations

import itertools
import json
import warnings
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple

import numpy as np

from . import _checks, _native, _progress
from .material import Material
from .solve import _check, _layer, _loading, solve
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

#: The config keys :func:`sweep` can vary (``vary=``) and the argument of
#: :func:`solve` each sets; ``surface.generate.*`` keys of a generated
#: surface regenerate it (:meth:`Surface.generate`).
VARY_KEYS = {
    "loading.temperature": "temperature",
    "loading.direction_deg": "direction_deg",
    "layer.thickness": "thickness",
    "layer.base": "layer_base",
    "solver.formulation": "formulation",
    "solver.tolerance": "tolerance",
    "solver.max_iterations": "max_iterations",
    "solver.max_matvecs": "max_matvecs",
    "solver.cascade_levels": "cascade_levels",
    "solver.mesh": "mesh",
    "solver.precision": "precision",
}

#: Arguments of ``VARY_KEYS`` that take a number, and a whole number.
_NUMBER_ARGS = ("temperature", "direction_deg", "thickness", "tolerance")
_COUNT_ARGS = ("max_iterations", "max_matvecs", "cascade_levels")

#: Keys the axes of :func:`sweep` set themselves.
_AXIS_KEYS = ("loading.speed", "loading.xi", "loading.normal_load", "loading.mean_pressure", "loading.approach")


def _frame(columns: Dict[str, np.ndarray], as_frame: bool) -> Any:
    if not as_frame:
        return columns
    try:
        import pandas
    except ImportError:
        raise ImportError("as_frame=True needs pandas (pip install pandas)") from None
    return pandas.DataFrame(columns)


def _axis(name: str, values: Any) -> Optional[np.ndarray]:
    if values is None:
        return None
    arr = _checks.real_array(name, np.atleast_1d(np.asarray(values)), 1)
    if arr.size == 0:
        raise ValueError(f"{name} is empty: give at least one value")
    return arr


def _vary_axes(vary: Any, surf: Surface, options: Dict[str, Any]) -> list:
    """``vary`` checked: ``[(key, values), ...]`` in key order, as the
    command line's ``[sweep.vary]`` (one line per refusal)."""
    if vary is None:
        return []
    if not isinstance(vary, Mapping):
        raise ValueError(f"vary must be a dict of config key -> list of values, got {type(vary).__name__}")
    axes = []
    for key in sorted(vary):
        values = vary[key]
        if not isinstance(key, str) or "." not in key:
            raise ValueError(f"vary {key!r}: expected a dotted config key such as 'loading.temperature'")
        if key in _AXIS_KEYS:
            raise ValueError(f"vary {key!r} is an axis of sweep already (speed, xi, normal_load, mean_pressure)")
        if key.startswith("surface.generate."):
            section = surf.section
            if section is None or section.get("generate") is None:
                raise ValueError(f"vary {key!r} needs a generated surface (Surface.generate or Surface.self_affine)")
        elif key not in VARY_KEYS:
            raise ValueError(
                f"vary {key!r}: unknown key; sweep varies {', '.join(sorted(VARY_KEYS))} and surface.generate.* "
                "(any key of a configuration file: viscoslide sweep with [sweep.vary])"
            )
        elif VARY_KEYS[key] in options:
            raise ValueError(f"vary {key!r} and the argument {VARY_KEYS[key]} both set it: give one")
        if isinstance(values, (str, bytes)) or not isinstance(values, (Sequence, np.ndarray)):
            values = [values]
        values = list(values)
        if not values:
            raise ValueError(f"vary {key!r} is empty: give at least one value")
        values = [v.item() if isinstance(v, np.generic) else v for v in values]
        arg = VARY_KEYS.get(key)
        if arg in _NUMBER_ARGS:
            values = [_checks.number(key, v) for v in values]
        elif arg in _COUNT_ARGS:
            values = [_checks.count(key, v) for v in values]
        for i, v in enumerate(values):
            if any(_same_value(v, w) for w in values[:i]):
                raise ValueError(f"vary {key!r} lists {v!r} twice: give each value once")
        axes.append((key, values))
    combos = 1
    for _, values in axes:
        combos *= len(values)
    if combos > MAX_VARY_COMBINATIONS:
        sizes = " x ".join(str(len(v)) for _, v in axes)
        raise ValueError(
            f"vary makes {sizes} = {combos} combinations, above the limit of {MAX_VARY_COMBINATIONS}; "
            "split the sweep into several"
        )
    return axes


#: The most ``vary`` combinations :func:`sweep` takes (as ``[sweep.vary]``).
MAX_VARY_COMBINATIONS = 10_000


def _same_value(a: Any, b: Any) -> bool:
    """Whether two values of one ``vary`` list are the same setting
    (numbers by value, booleans never equal to numbers)."""
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    return a == b


def _vary_point(surf: Surface, combo: Dict[str, Any]) -> Tuple[Surface, Dict[str, Any]]:
    """The surface and :func:`solve` arguments of one ``vary`` combination."""
    kwargs = {VARY_KEYS[k]: v for k, v in combo.items() if k in VARY_KEYS}
    generate = {k[len("surface.generate.") :]: v for k, v in combo.items() if k.startswith("surface.generate.")}
    if generate:
        keys = dict(surf.section["generate"])
        for k in generate:
            if k not in keys and k not in _GENERATE_KEYS:
                raise ValueError(f"vary 'surface.generate.{k}': unknown key of [surface.generate]")
        # q1 and scales exclude each other, as rms_height and rms_slope do.
        for a, b in (("q1", "scales"), ("scales", "q1"), ("rms_slope", "rms_height"), ("rms_height", "rms_slope")):
            if a in generate:
                keys.pop(b, None)
        keys.update(generate)
        surf = Surface.generate(**keys)
    return surf, kwargs


#: Keys of ``[surface.generate]`` (checked by the library when generating).
_GENERATE_KEYS = ("n", "ny", "length", "hurst", "scales", "q1", "ql", "rolloff_q0", "rms_slope", "rms_height", "seed")


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
    number or a 1-D array; ``options`` are those of :func:`solve`
    (``formulation``, ``thickness``, ``backend``, ``tolerance``,
    ``temperature``, ...). ``vary`` maps config keys to lists of values,
    as ``[sweep.vary]`` of ``viscoslide sweep``: ``{"loading.temperature":
    [7.0, 17.0, 27.0]}``, ``"layer.thickness"``, ``"surface.generate.q1"``
    (of a generated surface), and the other keys of :data:`VARY_KEYS`;
    each combination is crossed with the speeds and loads and each key is a
    column of the result. ``progress=True`` shows a tqdm bar over points;
    a callable gets a dict per finished point (``point``, ``points`` and
    the point's columns).

    Returns a dict of 1-D arrays (:data:`COLUMNS` and the varied keys), or
    a pandas DataFrame with ``as_frame=True``. With ``temperature`` (or
    ``vary={"loading.temperature": ...}``) the ``temperature`` and
    ``shift_factor`` columns give ``a_T``: ``mu(v, T) = mu(a_T v, T_ref)``.
    """
    surf = Surface.coerce(surface)
    speeds = _axis("speed", speed)
    xis = _axis("xi", xi)
    loads = _axis("normal_load", normal_load)
    pressures = _axis("mean_pressure", mean_pressure)
    if (speeds is None) == (xis is None):
        raise ValueError("give exactly one of speed (m/s) and xi (v tau / L)")
    if (loads is None) == (pressures is None):
        raise ValueError("give exactly one of normal_load (N) and mean_pressure (Pa)")
    if "progress" in options or "speed" in options:
        raise ValueError("progress and speed are arguments of sweep itself")
    sliding_key, sliding = ("speed", speeds) if speeds is not None else ("xi", xis)
    load_key, load = ("normal_load", loads) if loads is not None else ("mean_pressure", pressures)
    axes = _vary_axes(vary, surf, options)
    combos = [dict(zip([k for k, _ in axes], c)) for c in itertools.product(*[v for _, v in axes])]
    # Every point is checked before the first solve: its surface, its
    # arguments and its problem, built as the solve builds it (a refused
    # sweep solves nothing).
    prepared = [_vary_point(surf, c) for c in combos]
    grid = [(p, f, v) for p in range(len(combos)) for f in load for v in sliding]
    for p, f, v in grid:
        s_p, kwargs = prepared[p]
        _check(s_p, material, **{sliding_key: float(v), load_key: float(f)}, **kwargs, **options)
    keys = [k for k, _ in axes]
    rows: Dict[str, list] = {c: [] for c in (*COLUMNS, *keys)}
    with _progress.points(progress, len(grid)) as callback:
        for k, (p, f, v) in enumerate(grid):
            s_p, kwargs = prepared[p]
            result = solve(s_p, material, **{sliding_key: float(v), load_key: float(f)}, **kwargs, **options)
            s = result.summary
            row = {c: s.get(c) for c in COLUMNS}
            row["normal_load"] = s["normal_load"]
            row.update(combos[p])
            for c in rows:
                rows[c].append(np.nan if row[c] is None else row[c])
            if callback is not None:
                callback({"point": k + 1, "points": len(grid), **row})
    columns = {c: np.asarray(v, dtype=float) for c, v in rows.items() if c not in keys}
    for c in keys:
        columns[c] = np.asarray(rows[c])
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
    shifts the material by its WLF factor as in :func:`solve`."""
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
    else ``None``). A PSD whose rms slope differs from the map's real-space
    rms slope by more than 20 % is warned about (``warnings.warn``).
    """
    surf = Surface.coerce(surface, fill_missing=fill_missing, detrend=detrend, window=window)
    v = _axis("speeds", speeds)
    loading = _loading(0.0, None, normal_load, mean_pressure, None, None, temperature)
    mu, area, g, kind, sigma0, report, shift = _native.persson(
        surf._native, material._native, json.dumps(loading), v.tolist()
    )
    map_psd = None if report is None else json.loads(report)
    temperature_c, a_t = (None, None) if shift is None else shift
    if map_psd is not None and map_psd.get("warning"):
        warnings.warn(map_psd["warning"], stacklevel=2)
    columns: Dict[str, Any] = {
        "speed": v,
        "friction_coefficient": mu,
        "contact_area_fraction": area,
        "g_q1": g,
    }
    if as_frame:
        frame = _frame(columns, True)
        frame.attrs.update(psd=kind, nominal_pressure=sigma0, map_psd=map_psd, temperature=temperature_c, shift_factor=a_t)
        return frame
    columns.update(
        psd=kind, nominal_pressure=sigma0, map_psd=map_psd, temperature=temperature_c, shift_factor=a_t
    )
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
) -> np.ndarray:
    """Influence coefficients of the sliding kernel (paper Eq. 4-6): the
    surface displacement [m] of cell ``(i, j)`` under unit pressure [Pa] on
    cell ``(0, 0)``, for cells of side ``cell_size`` [m] along x and
    ``cell_size_y`` along y (default ``cell_size``: square; rectangular
    cells are a scan's non-square pixels) and every offset of an
    ``nx x ny`` grid; with ``derivative=True`` the cell-averaged ``dK/dx``
    [1/Pa] of the friction stencil.

    Returns an array of shape ``(2 nx - 1, 2 ny - 1)``; offset ``(i, j)``
    is at index ``(i + nx - 1, j + ny - 1)``.
    """
    n = _checks.count("nx", nx)
    m = n if ny is None else _checks.count("ny", ny)
    return _native.kernel_table(
        material._native,
        n,
        m,
        _checks.positive("cell_size", cell_size, "m"),
        _checks.number("speed", speed),
        _checks.number("direction_deg", direction_deg),
        _layer(thickness, layer_base),
        bool(derivative),
        None if cell_size_y is None else _checks.positive("cell_size_y", cell_size_y, "m"),
    )
