"""Solves: :func:`solve` (a surface and a material built in Python) and
:func:`solve_config` (a configuration file, exactly as ``viscoslide
solve``), both returning a :class:`Result`, isothermal or heated by the
contact's own friction (``heating=``, or a ``[heating]`` section; physics.md
section 14). The GIL is released during the solve; Ctrl-C stops it within a
fraction of a second (``KeyboardInterrupt``, nothing is written)."""

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
        self._summary: Optional[str] = None

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
        configuration, version and backend: the ``summary.json`` document.
        Each access gives a fresh copy: editing it changes neither the
        result nor what the next access returns."""
        if self._summary is None:
            self._summary = self._native.summary_json()
        return json.loads(self._summary)

    @property
    def convergence(self) -> Dict[str, Any]:
        """Iterations, matvecs, residual, load error and the residual and
        contact-set histories of the solve."""
        return json.loads(self._native.convergence_json())

    @property
    def backend(self) -> str:
        """Which executor ran the solve, and why."""
        return self._native.backend_line

    @property
    def heating(self) -> Optional[Dict[str, Any]]:
        """The heated solve's report (``summary["heating"]``, as
        ``viscoslide solve`` writes it), ``None`` for an isothermal solve:
        ``ambient_temperature`` ``T0`` and ``effective_temperature``
        ``T_eff`` [C]; ``temperature_rise`` [K] (``effective``: the
        dissipation-weighted rise ``Theta(T_eff)``, ``T_eff - T0`` to the
        ``tolerance``; ``peak_surface``, ``mean_contact``, ``background``
        of a periodic cell's block, else ``None``); ``chosen_branch`` and
        ``branches`` (every self-consistent temperature found in
        ``bracket``, coldest first, each with its ``temperature`` [C],
        ``rise`` [K], ``residual`` ``T0 + Theta(T) - T`` [K] and whether it
        is ``stable``); ``fixed_point_evaluations`` and
        ``evaluations`` (``Theta(T)`` at every temperature solved);
        ``heat_total_w`` against ``friction_power_w`` (the energy
        balance); ``isothermal_friction_coefficient`` (at ``T0``) and
        ``persson_friction_coefficient`` (Persson's at ``T_eff``);
        ``source``, ``closure``, ``conductivity``, ``diffusivity``,
        ``block_length``, ``peclet``, ``warnings`` and ``depth_profile``
        (the file :meth:`write` puts it in)."""
        text = self._native.heating_json()
        return None if text is None else json.loads(text)

    @property
    def temperature_rise(self) -> Optional[np.ndarray]:
        """The heated solve's surface temperature rise ``T - T0`` [K] at the
        cell centres, shape ``(nx, ny)``, axis 0 = x (``temperature.npy``
        of ``viscoslide solve``); ``None`` for an isothermal solve."""
        return self._native.temperature_rise

    @property
    def temperature_depth(self) -> Optional[Dict[str, np.ndarray]]:
        """The heated solve's rise against depth on a periodic cell
        (``temperature_depth.csv``): arrays ``depth`` [m], ``mean_rise``
        and ``max_rise`` [K] over the plane at that depth and
        ``mean_source`` [W/m^3] (the volume source of the layer holding
        it); ``None`` for an isothermal solve or a pad (solved at its
        surface only)."""
        rows = self._native.temperature_depth
        if rows is None:
            return None
        table = np.asarray(rows, dtype=float).reshape(-1, 4)
        return {name: table[:, k].copy() for k, name in enumerate(("depth", "mean_rise", "max_rise", "mean_source"))}

    def heat(
        self,
        conductivity: float,
        diffusivity: float,
        *,
        block_length: Optional[float] = None,
        source: Optional[str] = None,
        refined_layers: bool = False,
    ) -> Dict[str, Any]:
        """The heat of this solution (``viscoslide heat --from-run``;
        physics.md section 14) in a rubber of thermal ``conductivity``
        [W/(m K)] and ``diffusivity`` [m^2/s], without feedback on the
        friction.

        ``source`` is ``"volume"`` (the creep elements' dissipation on depth
        layers; periodic cells on a half-space only, their default) or
        ``"surface"`` (the work of the contact pressure as a surface flux;
        the default on a pad or a layer);
        ``refined_layers`` takes finer depth layers (depth integrals to
        about 5e-9 instead of 5e-5, the weighted rise to about 3e-4
        instead of 2e-3); ``block_length`` [m] adds a periodic
        cell's background heating over the block's passage. A heated
        solve's solution is at its effective temperature, and so is its
        heat. At rest (speed 0) nothing is dissipated: every rise is zero.
        Each of ``notes`` (what the rise leaves out or may overstate, such
        as a layer the heat reaches through, or the rest) is also warned
        about (``warnings.warn``), as ``viscoslide heat --from-run`` notes
        it. The GIL is released; Ctrl-C stops the volume source between
        its depth layers (``KeyboardInterrupt``).

        Returns the numbers of ``heat.json`` (``source``,
        ``effective_rise_k``, ``max_rise_k``, ``mean_rise_k``,
        ``background_rise_k``, ``heat_total_w``, ``friction_power_w``,
        ``energy_balance`` = heat over friction power minus 1, ``notes``,
        and the depth layers of a volume source) and ``temperature_rise``,
        the surface rise [K] at the cell centres, shape ``(nx, ny)``.
        """
        report, rise = self._native.heat(
            _checks.positive("conductivity", conductivity, "W/(m K)"),
            _checks.positive("diffusivity", diffusivity, "m^2/s"),
            None if block_length is None else _checks.positive("block_length", block_length, "m"),
            _checks.text("source", source, "'volume' or 'surface'"),
            _checks.flag("refined_layers", refined_layers),
        )
        doc = json.loads(report)
        doc["temperature_rise"] = rise
        for note in doc["notes"]:
            warnings.warn(note, stacklevel=2)
        return doc

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
        h = c.get("heating")
        heated = "" if h is None else f"heated to T_eff = {h['effective_temperature']:.6g} C, "
        return (
            f"Result({nx} x {ny}, {heated}friction_coefficient={self.friction_coefficient:.6g} "
            f"(dissipation {self.friction_coefficient_dissipation:.6g}), "
            f"contact_area_fraction={self.contact_area_fraction:.5g}, "
            f"{c['iterations']} iterations, residual {c['residual']:.2e}, backend {c['backend']})"
        )


def _layer(thickness: Optional[float], layer_base: str) -> Optional[str]:
    base = _checks.text("layer_base", layer_base, "'bonded' or 'frictionless'")
    if base not in ("bonded", "frictionless"):
        raise ValueError(f"layer_base must be 'bonded' or 'frictionless', got {base!r}")
    if thickness is None:
        if base != "bonded":
            raise ValueError(f"layer_base={base!r} needs thickness= (m): without one the solid is a half-space, which has no base")
        return None
    return json.dumps({"thickness": _checks.positive("thickness", thickness, "m"), "base": base})


def _heating(heating: Any) -> Optional[str]:
    """``heating`` (a mapping of ``[heating]`` keys) as the section's JSON;
    the keys and values are checked by the library as the command line
    checks ``[heating]`` (one line naming the key and value). A key whose
    value is ``None`` is left out (its default, as ``None`` is for every
    other argument). Here only what JSON cannot carry is refused: a key
    that is not a string, a value that is not a boolean, a string or a
    finite real number."""
    if heating is None:
        return None
    if not isinstance(heating, Mapping):
        raise TypeError(
            f"heating must be a dict of [heating] keys (conductivity, diffusivity, ...), got {type(heating).__name__}"
        )
    section: Dict[str, Any] = {}
    for key, value in heating.items():
        if not isinstance(key, str):
            raise TypeError(f"heating: a key is a [heating] key name such as 'conductivity', got {key!r}")
        if value is None:
            continue
        if isinstance(value, (bool, np.bool_)):
            section[key] = bool(value)
        elif isinstance(value, str):
            section[key] = value
        else:
            section[key] = _checks.number(f"heating[{key!r}]", value)
    return json.dumps(section)


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
    heating: Optional[Mapping[str, Any]] = None,
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
    heating : dict, optional
        Frictional heating and its feedback on the friction (the keys of
        ``[heating]``; physics.md section 14): ``conductivity`` [W/(m K)],
        ``diffusivity`` [m^2/s] or ``density`` [kg/m^3] and
        ``specific_heat`` [J/(kg K)], ``block_length`` [m] (the block's
        length along the sliding direction; periodic cells need it, pads
        refuse it), ``source`` (``"volume"``, periodic cells' default, or
        ``"surface"``), ``closure`` (``"effective"``), ``branch``
        (``"cold"``, default, or ``"hot"``), ``max_rise`` [K] (the bracket
        ``[T0, T0 + max_rise]`` searched, default 100), ``tolerance`` [K]
        (on ``|T0 + Theta(T) - T|``, default 1e-3) and ``enabled``
        (``False``: the isothermal solve); a key given as ``None`` takes
        its default, as if left out. Needs a material with WLF
        constants and ``temperature`` (the ambient ``T0``). The answer is
        the isothermal solve at the effective temperature ``T_eff = T0 +
        Theta(T_eff)`` (so ``mu_heated(v, T0) = mu(v, T_eff)``), with
        :attr:`Result.heating` (the report: ``T_eff``, the rises, every
        branch found, the evaluations, the isothermal friction at ``T0``,
        Persson's at ``T_eff``), :attr:`Result.temperature_rise` (the
        surface map) and :attr:`Result.temperature_depth`; ``summary``'s
        ``temperature`` and ``shift_factor`` are then ``T_eff``'s. The same numbers
        as ``viscoslide solve`` with the same ``[heating]``. Every key is
        checked before anything is solved (a ``ValueError`` naming the key
        and the value).
    progress : None, True or callable
        ``True`` shows a tqdm bar; a callable is called after every outer
        iteration with a dict (``iteration``, ``matvecs``, ``residual``,
        ``contact_cells``; in a heated solve also ``stage``, the
        evaluation the iteration belongs to, e.g. ``"heated: evaluation 2
        at 17.0246 C: isothermal solve"``). Ctrl-C stops a solve, a heated
        one's heat source too, within a depth layer's work.
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
        heating=heating,
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
    heating: Optional[Mapping[str, Any]] = None,
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
        _heating(heating),
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
    against its directory; an enabled ``[heating]`` section gives the
    heated solve (see ``heating`` of :func:`solve`).

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
