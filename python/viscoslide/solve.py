"""Solves: :func:`solve` (a surface and a material built in Python) and
:func:`solve_config` (a configuration file, exactly as ``viscoslide
solve``), both returning a :class:`Result`. The GIL is released during the
solve; Ctrl-C stops it within a fraction of a second (``KeyboardInterrupt``,
nothing is written)."""

from __future__ import annotations

import json
import os
import warnings
from typing import Any, Dict, Mapping, Optional

import numpy as np

from . import _checks, _native, _progress
from .material import Material
from .surface import Surface

FORMULATIONS = {"periodic": "periodic", "nonperiodic": "non_periodic", "non_periodic": "non_periodic"}


class Result:
    """The result of one solve.

    Fields are ``(nx, ny)`` float64 arrays with axis 0 = x = the sliding
    direction (as the ``.npy`` outputs of ``viscoslide solve``).
    """

    def __init__(self, native: "_native.Result"):
        """Wrap a native result; returned by :func:`solve`."""
        self._native = native
        self._summary: Optional[Dict[str, Any]] = None

    @property
    def friction_coefficient(self) -> float:
        """``mu = F_T / F_N`` from the work of the contact pressure (paper Eq. 9)."""
        return self._native.friction_coefficient

    @property
    def friction_coefficient_dissipation(self) -> float:
        """``mu`` from the dissipated power (paper Appendix A3-A4), an
        independent check of :attr:`friction_coefficient`."""
        return self._native.friction_coefficient_dissipation

    @property
    def contact_area_fraction(self) -> float:
        """Real contact area over the nominal area ``A / A0``."""
        return self._native.contact_area_fraction

    @property
    def approach(self) -> float:
        """Rigid approach (penetration) ``delta`` [m]."""
        return self._native.approach

    @property
    def pressure(self) -> np.ndarray:
        """Contact pressure [Pa], shape ``(nx, ny)``."""
        return self._native.pressure

    @property
    def gap(self) -> np.ndarray:
        """Gap between the surfaces [m], shape ``(nx, ny)``."""
        return self._native.gap

    @property
    def displacement(self) -> np.ndarray:
        """Normal surface displacement of the solid [m], shape ``(nx, ny)``."""
        return self._native.displacement

    @property
    def contact(self) -> np.ndarray:
        """1.0 where in contact, 0.0 elsewhere, shape ``(nx, ny)``."""
        return self._native.contact

    @property
    def summary(self) -> Dict[str, Any]:
        """Every scalar result, the convergence history, timings, seed, the
        configuration, version and backend: the ``summary.json`` document."""
        if self._summary is None:
            self._summary = json.loads(self._native.summary_json())
        return self._summary

    @property
    def convergence(self) -> Dict[str, Any]:
        """Iterations, matvecs, residual, load error and the residual and
        contact-set histories of the solve."""
        return json.loads(self._native.convergence_json())

    @property
    def backend(self) -> str:
        """Which executor ran the solve, and why."""
        return self._native.backend_line

    def analysis(self) -> Optional[Dict[str, Any]]:
        """The anisotropy analysis of the deformed surface and of the
        contact area (paper Section IV: ``gamma``, ``theta_p_deg``, ``m20``,
        ``m02``, ``m11``, ``lambda``, ellipse fits of ``C_chi``, contact
        spots): the ``analysis.json`` document; ``None`` if disabled."""
        text = self._native.analysis_json()
        return None if text is None else json.loads(text)

    def write(self, directory: "os.PathLike[str] | str") -> list:
        """Write summary.json, the maps (.npy, .png) and the analysis into
        ``directory``, as ``viscoslide solve --out``: all files or none.
        Returns the written paths."""
        return [str(p) for p in self._native.write(_checks.path("directory", directory))]

    def __repr__(self) -> str:
        nx, ny = self._native.grid
        c = self.summary
        return (
            f"Result({nx} x {ny}, friction_coefficient={self.friction_coefficient:.6g} "
            f"(dissipation {self.friction_coefficient_dissipation:.6g}), "
            f"contact_area_fraction={self.contact_area_fraction:.5g}, "
            f"{c['iterations']} iterations, residual {c['residual']:.2e}, backend {c['backend']})"
        )


def _layer(thickness: Optional[float], layer_base: str) -> Optional[str]:
    base = _checks.text("layer_base", layer_base, "'bonded' or 'frictionless'")
    if base not in ("bonded", "frictionless"):
        raise ValueError(f"layer_base must be 'bonded' or 'frictionless', got {base!r}")
    if thickness is None:
        return None
    return json.dumps({"thickness": _checks.positive("thickness", thickness, "m"), "base": base})


def _loading(
    speed: Any,
    xi: Any,
    normal_load: Any,
    mean_pressure: Any,
    approach: Any,
    direction_deg: Any,
    temperature: Any = None,
) -> Dict[str, Any]:
    return _checks.drop_none(
        {
            "temperature": _checks.optional("temperature", temperature),
            "speed": _checks.optional("speed", speed),
            "xi": _checks.optional("xi", xi),
            "normal_load": _checks.optional("normal_load", normal_load),
            "mean_pressure": _checks.optional("mean_pressure", mean_pressure),
            "approach": _checks.optional("approach", approach),
            "direction_deg": _checks.optional("direction_deg", direction_deg),
        }
    )


def _solver(
    surface: Surface,
    formulation: str,
    tolerance: Any,
    max_iterations: Any,
    max_matvecs: Any,
    cascade_levels: Any,
    mesh: Optional[str],
    precision: Optional[str] = None,
) -> Dict[str, Any]:
    _checks.text("formulation", formulation, "'auto', 'periodic' or 'nonperiodic'")
    _checks.text("mesh", mesh, "'uniform' or 'adaptive'")
    _checks.text("precision", precision, "'f64' or 'mixed'")
    if formulation == "auto":
        form = "periodic" if surface.periodic else "non_periodic"
    elif formulation in FORMULATIONS:
        form = FORMULATIONS[formulation]
    else:
        raise ValueError(f"formulation {formulation!r}: expected 'auto', 'periodic' or 'nonperiodic'")
    if precision is not None and precision not in ("f64", "mixed"):
        raise ValueError(f"precision {precision!r}: expected 'f64' or 'mixed'")
    return _checks.drop_none(
        {
            "formulation": form,
            "tolerance": _checks.number("tolerance", tolerance),
            "max_iterations": None if max_iterations is None else _checks.count("max_iterations", max_iterations),
            "max_matvecs": None if max_matvecs is None else _checks.count("max_matvecs", max_matvecs),
            "cascade_levels": None if cascade_levels is None else _checks.count("cascade_levels", cascade_levels),
            "mesh": mesh,
            "precision": precision,
        }
    )


def solve(
    surface: Any,
    material: Material,
    *,
    speed: Optional[float] = None,
    xi: Optional[float] = None,
    normal_load: Optional[float] = None,
    mean_pressure: Optional[float] = None,
    approach: Optional[float] = None,
    direction_deg: Optional[float] = None,
    temperature: Optional[float] = None,
    formulation: str = "auto",
    thickness: Optional[float] = None,
    layer_base: str = "bonded",
    backend: Optional[str] = None,
    tolerance: float = 1e-8,
    max_iterations: Optional[int] = None,
    max_matvecs: Optional[int] = None,
    cascade_levels: Optional[int] = None,
    mesh: Optional[str] = None,
    precision: Optional[str] = None,
    progress: Any = None,
    fill_missing: Optional[bool] = None,
    detrend: Optional[str] = None,
    window: Optional[str] = None,
) -> Result:
    """Solve the steady sliding contact of ``surface`` on ``material``.

    Parameters
    ----------
    surface : Surface or topography-like
        The rigid rough surface (a :class:`Surface`, or any object with
        ``heights()`` and ``physical_sizes`` such as a SurfaceTopography
        ``Topography``).
    material : Material
        The viscoelastic solid.
    speed, xi : float
        Sliding speed [m/s], or ``xi = v tau / L`` for a single-relaxation
        material; exactly one.
    normal_load, mean_pressure, approach : float
        Normal load [N], nominal pressure [Pa] (times the map's area), or a
        prescribed rigid approach [m]; exactly one.
    direction_deg : float, optional
        Sliding direction, degrees from +x (default 0).
    temperature : float, optional
        Temperature [C] of the isothermal solve (``[loading] temperature``):
        every creep time is scaled by the WLF shift factor ``a_T``, so
        ``mu(v, T) = mu(a_T v, T_ref)`` (physics.md section 12). Needs a
        material with WLF constants (``wlf=`` of :meth:`Material.sls` and
        the other constructors' ``[material] wlf`` key, or a material.toml
        fitted with ``--wlf``); ``summary`` states ``temperature`` and
        ``shift_factor``. Only inside the WLF validity range
        ``|log10 a_T| <= 50`` (``T >= T_ref - C2 * 50 / (|C1| + 50)``,
        above the pole ``T_ref - C2``); outside it a ``ValueError`` names
        the temperature and the bound.
    formulation : str
        ``"nonperiodic"`` (a finite pad, the paper's), ``"periodic"`` (one
        period of a periodic surface), or ``"auto"``: periodic for a
        surface marked periodic (a periodic SurfaceTopography topography,
        ``Surface.from_array(..., periodic=True)``), else non-periodic.
    thickness : float, optional
        Thickness [m] of a viscoelastic layer on a rigid base
        (``layer_base`` ``"bonded"`` or ``"frictionless"``); default a half-space.
    backend : str, optional
        ``"auto"`` (a hardware GPU when one exists, else the CPU), ``"cpu"``
        or ``"gpu"``; default ``VISCOSLIDE_BACKEND``, else ``"auto"``.
    tolerance : float
        Relative complementarity residual to reach (default 1e-8).
    max_iterations, max_matvecs, cascade_levels : int, optional
        Solver controls (``[solver]`` keys).
    mesh : str, optional
        ``"uniform"`` (default) or ``"adaptive"``.
    precision : str, optional
        ``"f64"`` (default) or ``"mixed"``: f32 spectra and transforms for
        the inner Krylov products with every restart's residual, the gap
        and the contact decisions in f64 (``[solver] precision``; physics.md
        section 13); ``summary["precision"]`` states it.
    progress : None, True or callable
        ``True`` shows a tqdm bar; a callable is called after every outer
        iteration with a dict (``iteration``, ``matvecs``, ``residual``,
        ``contact_cells``).
    fill_missing, detrend, window : optional
        How a topography-like ``surface`` is prepared (see
        :meth:`Surface.from_array`: missing points, the polynomial removed,
        default ``"plane"`` unless periodic, and the PSD window of Persson's
        theory beside the solve, default ``"hann"``).

    The solution's warnings (``summary["warnings"]``) are also issued with
    ``warnings.warn``.

    Returns
    -------
    Result

    Raises
    ------
    ValueError
        Bad input, named.
    ConvergenceError
        The iteration did not converge; it carries the residual history.
    KeyboardInterrupt
        Ctrl-C during the solve.
    """
    args = _native_args(
        surface,
        material,
        speed=speed,
        xi=xi,
        normal_load=normal_load,
        mean_pressure=mean_pressure,
        approach=approach,
        direction_deg=direction_deg,
        temperature=temperature,
        formulation=formulation,
        thickness=thickness,
        layer_base=layer_base,
        backend=backend,
        tolerance=tolerance,
        max_iterations=max_iterations,
        max_matvecs=max_matvecs,
        cascade_levels=cascade_levels,
        mesh=mesh,
        precision=precision,
        fill_missing=fill_missing,
        detrend=detrend,
        window=window,
    )
    with _progress.iterations(progress) as callback:
        native = _native.solve(*args, callback)
    return _warned(Result(native))


def _native_args(
    surface: Any,
    material: Material,
    *,
    speed: Optional[float] = None,
    xi: Optional[float] = None,
    normal_load: Optional[float] = None,
    mean_pressure: Optional[float] = None,
    approach: Optional[float] = None,
    direction_deg: Optional[float] = None,
    temperature: Optional[float] = None,
    formulation: str = "auto",
    thickness: Optional[float] = None,
    layer_base: str = "bonded",
    backend: Optional[str] = None,
    tolerance: float = 1e-8,
    max_iterations: Optional[int] = None,
    max_matvecs: Optional[int] = None,
    cascade_levels: Optional[int] = None,
    mesh: Optional[str] = None,
    precision: Optional[str] = None,
    fill_missing: Optional[bool] = None,
    detrend: Optional[str] = None,
    window: Optional[str] = None,
) -> tuple:
    """The arguments of the native solve of :func:`solve` (its arguments
    but ``progress``), checked as far as Python checks them."""
    surf = Surface.coerce(surface, fill_missing=fill_missing, detrend=detrend, window=window)
    if not isinstance(material, Material):
        raise TypeError(f"material must be a viscoslide.Material, got {type(material).__name__}")
    _checks.text("backend", backend, "'auto', 'cpu' or 'gpu'")
    loading = _loading(speed, xi, normal_load, mean_pressure, approach, direction_deg, temperature)
    solver = _solver(surf, formulation, tolerance, max_iterations, max_matvecs, cascade_levels, mesh, precision)
    return (
        surf._native,
        material._native,
        json.dumps(loading),
        json.dumps(solver),
        _layer(thickness, layer_base),
        backend,
    )


def _warned(result: Result) -> Result:
    """``result`` after its warnings are issued with ``warnings.warn``."""
    for w in result.summary.get("warnings", []):
        warnings.warn(w, stacklevel=3)
    return result


def _toml_value(value: Any, name: str = "set value") -> str:
    """A Python value as a TOML value for a ``--set`` override (``name``
    for messages: ``set 'loading.xi'``)."""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        x = _checks.number(name, value)
        return repr(x)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v, name) for v in value) + "]"
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{k} = {_toml_value(v, name)}" for k, v in value.items()) + "}"
    raise ValueError(f"{name}: cannot write {value!r} as a TOML value")


def _overrides(set: Any) -> list:
    """``set`` (a mapping ``{"section.key": value}``, one
    ``"section.key=value"`` string or a list of them) as the command line's
    ``--set`` arguments."""
    if set is None:
        return []
    if isinstance(set, Mapping):
        for key in set:
            if not isinstance(key, str):
                raise TypeError(f"set: a key is a 'section.key' string, got {key!r}")
        return [f"{key}={_toml_value(value, f'set {key!r}')}" for key, value in set.items()]
    items = [set] if isinstance(set, str) else set
    if not isinstance(items, (list, tuple)) or not all(isinstance(s, str) for s in items):
        raise TypeError(
            f"set must be a mapping {{'section.key': value}}, a 'section.key=value' string or a list of them, got {set!r}"
        )
    for item in items:
        if "=" not in item:
            raise ValueError(f"set {item!r}: expected 'section.key=value'")
    return list(items)


def solve_config(
    path: "os.PathLike[str] | str",
    set: "Optional[Mapping[str, Any] | str | Sequence[str]]" = None,
    backend: Optional[str] = None,
    progress: Any = None,
) -> Result:
    """Solve a configuration file as ``viscoslide solve`` does: the same
    problem, the same numbers (``summary`` equals the command's
    ``summary.json`` but for timings), relative paths in the file resolved
    against its directory.

    Parameters
    ----------
    path : path-like
        TOML configuration.
    set : mapping, str or list of str, optional
        Overrides by ``"section.key"``, e.g. ``{"loading.xi": 1e-3,
        "surface.generate.n": 512}``, or as the command's ``--set`` writes
        them: ``"loading.xi=1e-3"`` or a list of such strings.
    backend : str, optional
        ``"auto"``, ``"cpu"`` or ``"gpu"``; default ``VISCOSLIDE_BACKEND``,
        else ``"auto"`` (as the command line without ``--backend``).
    progress : None, True or callable
        As for :func:`solve`.
    """
    path = _checks.path("path", path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"{path}: no such file")
    overrides = _overrides(set)
    _checks.text("backend", backend, "'auto', 'cpu' or 'gpu'")
    with _progress.iterations(progress) as callback:
        native = _native.solve_config(path, overrides, backend, callback)
    return _warned(Result(native))
