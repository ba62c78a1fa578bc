"""Materials: linear viscoelastic solids described by a creep spectrum
(paper Eq. 2), built by the engine from the keys of a ``[material]``
configuration section, from a TOML file, or fitted to DMA data."""

from __future__ import annotations

import json
import math
import os
import warnings
from typing import Any, Dict, Optional, Sequence, Tuple

import numpy as np

from . import _checks
from . import _native


class Material:
    """A linear viscoelastic solid (creep spectrum and Poisson ratio).

    Build one with :meth:`sls`, :meth:`creep_spectrum`, :meth:`prony`,
    :meth:`from_toml` or :meth:`fit_dma`; keyword arguments are named as the
    keys of the ``[material]`` section of a configuration file (SI units).
    """

    def __init__(self, native: "_native.Material", fit_info: Optional[Dict[str, Any]] = None):
        """Wrap a native material; use the class methods instead."""
        self._native = native
        #: Quality of a DMA fit (:meth:`fit_dma`), else ``None``.
        self.fit_info = fit_info

    @classmethod
    def _from_section(cls, section: Dict[str, Any], base_dir: str = ".") -> "Material":
        return cls(_native.Material.from_section(json.dumps(_checks.drop_none(section)), base_dir))

    @classmethod
    def sls(
        cls,
        *,
        relaxed_modulus: float,
        glassy_modulus: float,
        creep_time: Optional[float] = None,
        relaxation_time: Optional[float] = None,
        poisson: float = 0.5,
        wlf: Optional[Tuple[float, float, float]] = None,
        wlf_range: Optional[Tuple[float, float]] = None,
        frequency_range: Optional[Tuple[float, float]] = None,
    ) -> "Material":
        """A standard linear solid (one creep time; the paper's material).

        Parameters
        ----------
        relaxed_modulus : float
            Zero-frequency modulus ``E0`` [Pa].
        glassy_modulus : float
            High-frequency modulus ``E_inf`` [Pa], larger than ``E0``.
        creep_time : float, optional
            Creep (retardation) time ``tau`` [s] of paper Eq. 2.
        relaxation_time : float, optional
            Stress-relaxation time ``tau E0 / E_inf`` [s]; give exactly one
            of ``creep_time`` and ``relaxation_time``.
        poisson : float
            Poisson ratio (default 0.5, incompressible).
        wlf : (C1, C2, T_ref), optional
            WLF constants (C2 in K, T_ref in C; ``[material] wlf``) that
            let a solve ask for another ``temperature``; the spectrum is
            the one at ``T_ref``.
        wlf_range : (lowest, highest), optional
            Temperatures [C] of the data the WLF constants were fitted to
            (``[material] wlf_range``): a solve beyond them warns that its
            shift is extrapolated.
        frequency_range : (lowest, highest), optional
            Angular frequencies [rad/s] of the data the spectrum was fitted
            to, at ``T_ref`` (``[material] frequency_range``): a solve that
            excites frequencies a decade beyond them warns.
        """
        return cls._from_section(
            {
                "model": "sls",
                "relaxed_modulus": _checks.number("relaxed_modulus", relaxed_modulus),
                "glassy_modulus": _checks.number("glassy_modulus", glassy_modulus),
                "creep_time": _checks.optional("creep_time", creep_time),
                "relaxation_time": _checks.optional("relaxation_time", relaxation_time),
                "poisson": _checks.number("poisson", poisson),
                "wlf": _wlf(wlf),
                "wlf_range": _pair("wlf_range", wlf_range, "(lowest, highest) in C"),
                "frequency_range": _pair("frequency_range", frequency_range, "(lowest, highest) in rad/s"),
            }
        )

    @classmethod
    def creep_spectrum(
        cls,
        times: Sequence[float],
        weights: Sequence[float],
        *,
        glassy_modulus: float,
        poisson: float = 0.5,
        wlf: Optional[Tuple[float, float, float]] = None,
        wlf_range: Optional[Tuple[float, float]] = None,
        frequency_range: Optional[Tuple[float, float]] = None,
    ) -> "Material":
        """A creep spectrum ``J(t) = 1/E_inf + sum_k C_k (1 - exp(-t/tau_k))``.

        Parameters
        ----------
        times : array of float
            Creep times ``tau_k`` [s].
        weights : array of float
            Compliances ``C_k`` [1/Pa], one per time.
        glassy_modulus : float
            ``E_inf`` [Pa].
        poisson : float
            Poisson ratio (default 0.5).
        wlf, wlf_range, frequency_range : optional
            WLF constants, the temperatures of their data and the data's
            frequencies, as for :meth:`sls`.
        """
        t = _checks.real_array("times", times, 1)
        w = _checks.real_array("weights", weights, 1)
        if t.shape != w.shape:
            raise ValueError(f"times and weights need one value each per term, got {t.size} and {w.size}")
        return cls._from_section(
            {
                "model": "creep_spectrum",
                "glassy_modulus": _checks.number("glassy_modulus", glassy_modulus),
                "creep_spectrum": [[float(c), float(tau)] for c, tau in zip(w, t)],
                "poisson": _checks.number("poisson", poisson),
                "wlf": _wlf(wlf),
                "wlf_range": _pair("wlf_range", wlf_range, "(lowest, highest) in C"),
                "frequency_range": _pair("frequency_range", frequency_range, "(lowest, highest) in rad/s"),
            }
        )

    @classmethod
    def prony(
        cls,
        moduli: Sequence[float],
        times: Sequence[float],
        *,
        relaxed_modulus: float,
        poisson: float = 0.5,
        wlf: Optional[Tuple[float, float, float]] = None,
        wlf_range: Optional[Tuple[float, float]] = None,
        frequency_range: Optional[Tuple[float, float]] = None,
    ) -> "Material":
        """A generalized Maxwell (Prony) series
        ``E(t) = E0 + sum_j E_j exp(-t/theta_j)``, converted exactly to a
        creep spectrum.

        Parameters
        ----------
        moduli : array of float
            ``E_j`` [Pa].
        times : array of float
            Relaxation times ``theta_j`` [s], one per modulus.
        relaxed_modulus : float
            ``E0`` [Pa].
        poisson : float
            Poisson ratio (default 0.5).
        wlf, wlf_range, frequency_range : optional
            WLF constants, the temperatures of their data and the data's
            frequencies, as for :meth:`sls`.
        """
        e = _checks.real_array("moduli", moduli, 1)
        t = _checks.real_array("times", times, 1)
        if t.shape != e.shape:
            raise ValueError(f"moduli and times need one value each per term, got {e.size} and {t.size}")
        return cls._from_section(
            {
                "model": "prony",
                "relaxed_modulus": _checks.number("relaxed_modulus", relaxed_modulus),
                "prony": [[float(m), float(theta)] for m, theta in zip(e, t)],
                "poisson": _checks.number("poisson", poisson),
                "wlf": _wlf(wlf),
                "wlf_range": _pair("wlf_range", wlf_range, "(lowest, highest) in C"),
                "frequency_range": _pair("frequency_range", frequency_range, "(lowest, highest) in rad/s"),
            }
        )

    @classmethod
    def from_toml(cls, path: "os.PathLike[str] | str") -> "Material":
        """The material of a TOML file: a configuration with a ``[material]``
        section (its relative paths resolved against the file's directory),
        or a ``material.toml`` written by ``viscoslide material fit``, read
        as ``model = "file"`` reads it (its ``section`` is that)."""
        path = _checks.path("path", path)
        if not os.path.exists(path):
            raise FileNotFoundError(f"{path}: no such file")
        return cls(_native.Material.from_toml(path))

    @classmethod
    def fit_dma(
        cls,
        frequency: Sequence[float],
        storage: Sequence[float],
        loss: Sequence[float],
        wlf: Optional[Tuple[float, float, float]] = None,
        temperature: Optional[float] = None,
        *,
        temperatures: Optional[Sequence[float]] = None,
        angular: bool = False,
        terms: int = 34,
        ratio: float = math.e,
        poisson: float = 0.5,
    ) -> "Material":
        """Fit a creep spectrum to DMA data (as ``viscoslide material fit``).

        Parameters
        ----------
        frequency : array of float
            Test frequencies, in Hz (or rad/s with ``angular=True``).
        storage, loss : array of float
            Storage and loss moduli ``E1``, ``E2`` [Pa].
        wlf : (C1, C2, T_ref), optional
            WLF constants that shift data at several ``temperatures`` [C]
            onto one master curve at ``temperature`` [C].
        temperature : float, optional
            Temperature of the master curve [C].
        temperatures : array of float, optional
            Test temperature of each point [C].
        terms, ratio : int, float
            Number of creep times and the ratio of consecutive ones
            (default 34 times in ratio e, as the paper).
        poisson : float
            Poisson ratio (default 0.5).

        The fit's quality (relative rms and maximum errors of E1 and E2) is
        in the returned material's ``fit_info``; so are its ``warnings``,
        each also raised (``warnings.warn``) as ``viscoslide material fit``
        prints them: data of several temperatures merged at one frequency,
        a fit whose rms relative error exceeds 10 %, and data that do not
        reach the rubbery or the glassy plateau (``E0`` or ``E_inf``
        extrapolated). With ``wlf`` and data at
        several ``temperatures``, their lowest and highest are the
        material's :attr:`wlf_range`, and the data's frequencies (shifted to
        ``temperature``) its :attr:`frequency_range`: solves beyond them
        warn.
        """
        f = _checks.real_array("frequency", frequency, 1)
        omega = f if _checks.flag("angular", angular) else 2.0 * math.pi * f
        temps = None if temperatures is None else _checks.real_array("temperatures", temperatures, 1).tolist()
        checked = _wlf(wlf)
        w = None if checked is None else (checked[0], checked[1], checked[2])
        native, info = _native.Material.fit_dma(
            omega.tolist(),
            _checks.real_array("storage", storage, 1).tolist(),
            _checks.real_array("loss", loss, 1).tolist(),
            temps,
            w,
            _checks.optional("temperature", temperature),
            _checks.count("terms", terms),
            _checks.number("ratio", ratio),
            _checks.number("poisson", poisson),
        )
        for note in info["warnings"]:
            warnings.warn(note, stacklevel=2)
        return cls(native, dict(info))

    def complex_modulus(self, omega: Any) -> np.ndarray:
        """``E(w) = E1 + i E2`` [Pa] at angular frequencies ``omega`` [rad/s]
        (a scalar or an array of any shape; the result has its shape). A
        masked point has no frequency: masked values are refused."""
        omega = _checks.unmasked("omega", omega, ": give only the frequencies to evaluate (.compressed())")
        w = np.asarray(omega)
        flat = _checks.real_array("omega", w.reshape(-1), 1)
        return _native.Material.complex_modulus(self._native, flat).reshape(w.shape)

    @property
    def relaxed_modulus(self) -> float:
        """Zero-frequency modulus ``E0`` [Pa]."""
        return self._native.relaxed_modulus

    @property
    def glassy_modulus(self) -> float:
        """High-frequency modulus ``E_inf`` [Pa]."""
        return self._native.glassy_modulus

    @property
    def wlf(self) -> Optional[Tuple[float, float, float]]:
        """WLF constants ``(C1, C2 [K], T_ref [C])``, or ``None``."""
        return self._native.wlf

    @property
    def wlf_range(self) -> Optional[Tuple[float, float]]:
        """Lowest and highest temperature [C] of the data the WLF constants
        were fitted to, or ``None`` where not recorded."""
        return self._native.wlf_range

    @property
    def frequency_range(self) -> Optional[Tuple[float, float]]:
        """Lowest and highest angular frequency [rad/s] of the data the
        spectrum was fitted to (at the temperature it describes), or
        ``None`` where not recorded."""
        return self._native.frequency_range

    @property
    def poisson(self) -> float:
        """Poisson ratio."""
        return self._native.poisson

    @property
    def creep_spectrum_terms(self) -> np.ndarray:
        """Creep spectrum as rows ``(C_k [1/Pa], tau_k [s])``."""
        return np.array(self._native.creep_spectrum, dtype=float).reshape(-1, 2)

    @property
    def section(self) -> Dict[str, Any]:
        """The ``[material]`` configuration section that builds this material
        at every temperature. A fit at a ``temperature`` other than its WLF
        constants' ``T_ref`` gives the constants referred to that
        temperature (``C2' = C2 + T - T_ref``, ``C1' = C1 C2 / C2'``: the
        same shift factors), since the fitted spectrum describes it."""
        return json.loads(self._native.section_json())

    def __repr__(self) -> str:
        terms = len(self._native.creep_spectrum)
        return (
            f"Material(E0={self.relaxed_modulus:.4g} Pa, E_inf={self.glassy_modulus:.4g} Pa, "
            f"{terms} creep term{'s' if terms != 1 else ''}, poisson={self.poisson:g})"
        )


def _wlf(wlf: Any) -> Optional[list]:
    """``(C1, C2, T_ref)`` checked as three numbers, or ``None``."""
    return _numbers("wlf", wlf, 3, "(C1, C2, T_ref)")


def _pair(name: str, value: Any, what: str) -> Optional[list]:
    """Two numbers, or ``None``."""
    return _numbers(name, value, 2, what)


def _numbers(name: str, value: Any, count: int, what: str) -> Optional[list]:
    """``value`` as ``count`` finite numbers, or ``None``; otherwise a
    ``ValueError`` naming ``name`` and ``what`` it must be."""
    if value is None:
        return None
    words = {2: "two", 3: "three"}[count]
    if not isinstance(value, (tuple, list, np.ndarray)) or len(value) != count:
        raise ValueError(f"{name} must be {what}, {words} numbers, got {value!r}")
    return [_checks.number(f"{name}[{i}]", v) for i, v in enumerate(value)]
