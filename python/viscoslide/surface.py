"""Surfaces: height maps on grids of cells (axis 0 = x = the
sliding direction), generated, read from a file in any format the engine
reads, given as an array, or taken from any object with ``heights()`` and
``physical_sizes`` (a SurfaceTopography ``Topography``).

A map read from a file or given as values is a scan unless marked
periodic: its mean plane is removed before solving and before any PSD
(``detrend="plane"``; ``"none"``, ``"mean"``, ``"quadratic"``) and its
PSDs use the Hann window (``window="hann"``), the rule of the engine
(``[surface] detrend``/``window``/``periodic``). Generated surfaces are
taken as they are. Missing points (NaN, masked) are an error unless
``fill_missing=True`` fills them by harmonic interpolation."""

from __future__ import annotations

import json
import math
import os
import warnings
from typing import Any, Dict, Optional, Tuple

import numpy as np

from . import _checks
from . import _native


#: What ``detrend`` and ``window`` take (for messages; the values are
#: checked by the engine).
_DETREND = "'none', 'mean', 'plane' or 'quadratic'"
_WINDOW = "'none', 'hann' or 'blackman_harris'"


def _plain(key: str, value: Any) -> Any:
    """``value`` as JSON takes it: numpy scalars (and 0-d arrays) as Python
    numbers (a ``np.int64`` count, a ``np.float32`` length), dicts and
    lists item by item; a number JSON cannot carry (NaN, inf, a whole
    number beyond 64 bits) is a ValueError and anything else that is not a
    number, string or bool a TypeError, naming ``key``
    (``anisotropy.ratio``)."""
    if isinstance(value, np.generic) or (isinstance(value, np.ndarray) and value.ndim == 0):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"{key} must be finite, got {value}")
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > _checks.COUNT_MAX:
        digits = len(str(abs(value)))
        raise ValueError(
            f"{key} is out of the range of a 64-bit whole number (magnitudes up to 2**63 - 1), "
            f"got a whole number of {digits} digits"
        )
    if isinstance(value, dict):
        return {k: _plain(f"{key}.{k}", v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(key, v) for v in value]
    if value is None or isinstance(value, (bool, int, float, str, os.PathLike)):
        return value
    raise TypeError(f"{key} must be a number or a string, got {type(value).__name__}")


class Surface:
    """A rigid rough surface: heights [m] at cell centres on a grid of
    ``dx x dy`` cells (rectangular where the pixels are).

    Build one with :meth:`self_affine`, :meth:`generate`, :meth:`from_file`,
    :meth:`from_array` or :meth:`from_topography`; anywhere a surface is
    expected, a SurfaceTopography ``Topography`` (any object with
    ``heights()`` and ``physical_sizes``) is accepted as well.
    """

    def __init__(self, native: "_native.Surface", periodic: bool = False):
        """Wrap a native surface; use the class methods instead."""
        self._native = native
        #: Whether the map is one period of a periodic surface
        #: (``formulation="auto"`` then solves the periodic problem).
        self.periodic = periodic

    @classmethod
    def self_affine(
        cls,
        n: int,
        length: float,
        hurst: float,
        *,
        scales: Optional[float] = None,
        q1: Optional[float] = None,
        rms_height: Optional[float] = None,
        rms_slope: Optional[float] = None,
        seed: int = 0,
        ny: Optional[int] = None,
        ql: Optional[float] = None,
        rolloff_q0: Optional[float] = None,
        anisotropy: Optional[Tuple[float, float]] = None,
    ) -> "Surface":
        """A self-affine random surface (physics.md section 8), the same as
        a ``[surface.generate]`` section with these keys gives.

        Parameters
        ----------
        n : int
            Cells along x (and along y unless ``ny`` is given).
        length : float
            Side along x [m].
        hurst : float
            Hurst exponent ``0 < H <= 1``.
        scales, q1 : float
            Upper cut-off: ``q1 = scales * q_L``, or ``q1`` [1/m]; one of the two.
        rms_height, rms_slope : float
            Amplitude: rms height [m] or rms slope; one of the two.
        seed : int
            Seed of the random phases (the same seed gives the same Fourier
            modes at every resolution).
        ql, rolloff_q0 : float, optional
            Lower cut-off and roll-off wavenumbers [1/m].
        anisotropy : (ratio, angle_deg), optional
            Stretch factor and its direction.
        """
        keys: Dict[str, Any] = {
            "n": _checks.count("n", n, 2),
            "ny": None if ny is None else _checks.count("ny", ny, 2),
            "length": _checks.number("length", length),
            "hurst": _checks.number("hurst", hurst),
            "scales": _checks.optional("scales", scales),
            "q1": _checks.optional("q1", q1),
            "rms_height": _checks.optional("rms_height", rms_height),
            "rms_slope": _checks.optional("rms_slope", rms_slope),
            "seed": _checks.count("seed", seed, 0),
            "ql": _checks.optional("ql", ql),
            "rolloff_q0": _checks.optional("rolloff_q0", rolloff_q0),
        }
        if anisotropy is not None:
            if not isinstance(anisotropy, (tuple, list)) or len(anisotropy) != 2:
                raise ValueError(f"anisotropy must be (ratio, angle_deg), got {anisotropy!r}")
            ratio, angle = anisotropy
            keys["anisotropy"] = {
                "ratio": _checks.number("anisotropy ratio", ratio),
                "angle_deg": _checks.number("anisotropy angle_deg", angle),
            }
        return cls.generate(**keys)

    @classmethod
    def generate(cls, **keys: Any) -> "Surface":
        """A surface from the keys of a ``[surface.generate]`` section
        (``n``, ``length``, ``hurst``, ``scales``, ``rms_slope``, ``seed``,
        ..., or ``psd`` with a ``q, C`` CSV path for a surface following a
        tabulated PSD). Unknown keys are refused by name. An ``anisotropy``
        stretch whose rms-slope ratio the grid does not hold within 10 % is
        warned about (``warnings.warn``), as ``viscoslide surface generate``
        and a solve on it warn."""
        section = {key: _plain(key, value) for key, value in _checks.drop_none(keys).items()}
        if "psd" in section:
            section["psd"] = os.path.abspath(_checks.path("psd", section["psd"]))
        native = _native.Surface.generate(json.dumps(section), os.getcwd())
        # A stretch the grid cannot hold (the surface is made, and warned).
        for w in native.generation_warnings():
            warnings.warn(w, stacklevel=2)
        return cls(native)

    @classmethod
    def from_file(
        cls,
        path: "os.PathLike[str] | str",
        length: Optional[float] = None,
        *,
        length_y: Optional[float] = None,
        format: Optional[str] = None,
        fill_missing: bool = False,
        detrend: Optional[str] = None,
        window: Optional[str] = None,
        periodic: bool = False,
    ) -> "Surface":
        """A surface read from ``path``: ``.x3p``, ``.gwy`` (sizes from the
        file), ``.npy`` or a text matrix (``length`` [m] along x needed),
        or a text matrix with a size header as SurfaceTopography's
        ``to_matrix`` writes it (rows along y; sides and height unit from
        the header, which ``length``/``length_y`` must agree with).

        ``format`` (``"x3p"``, ``"gwy"``, ``"npy"``, ``"text"``) overrides the
        extension; ``fill_missing`` fills missing points by harmonic
        interpolation (otherwise they are an error); ``detrend`` (default
        ``"plane"``, ``"none"`` when ``periodic``) is removed before solving
        and before any PSD, whose ``window`` defaults to ``"hann"``
        (``"none"`` when ``periodic``).
        """
        path = _checks.path("path", path)
        if not os.path.exists(path):
            raise FileNotFoundError(f"{path}: no such file")
        native = _native.Surface.from_file(
            path,
            None if length is None else _checks.positive("length", length, "m"),
            None if length_y is None else _checks.positive("length_y", length_y, "m"),
            _checks.text("format", format, "'x3p', 'gwy', 'npy' or 'text'"),
            _checks.flag("fill_missing", fill_missing),
            _checks.text("detrend", detrend, _DETREND),
            _checks.text("window", window, _WINDOW),
            _checks.flag("periodic", periodic),
        )
        return cls(native, periodic=bool(periodic))

    @classmethod
    def from_array(
        cls,
        heights: Any,
        length: float,
        *,
        length_y: Optional[float] = None,
        periodic: bool = False,
        fill_missing: bool = False,
        detrend: Optional[str] = None,
        window: Optional[str] = None,
    ) -> "Surface":
        """A surface from a 2-D array of heights [m] (axis 0 = x), any real
        dtype and memory order; ``length`` [m] is the side along x and
        ``length_y`` the side along y (default: square cells). Cells are
        ``length / nx`` by ``length_y / ny``: rectangular pixels are solved
        on their own grid (Love's rectangle, physics.md section 11).

        NaN and the masked points of a numpy masked array are missing: an
        error unless ``fill_missing`` (harmonic interpolation). Unless
        ``periodic``, the map is a scan: ``detrend`` (default ``"plane"``)
        is removed and its PSDs use ``window`` (default ``"hann"``); a
        periodic map is taken as it is (defaults ``"none"``)."""
        fill = _checks.flag("fill_missing", fill_missing)
        periodic = _checks.flag("periodic", periodic)
        _checks.text("detrend", detrend, _DETREND)
        _checks.text("window", window, _WINDOW)
        h = _checks.real_array("heights", heights, 2, allow_nan=fill)
        lx = _checks.positive("length", length, "m")
        nx, ny = h.shape
        if nx < 2 or ny < 2:
            raise ValueError(f"heights needs at least 2 x 2 cells, got shape {h.shape}")
        ly = None
        if length_y is not None:
            ly = _checks.positive("length_y", length_y, "m")
            if math.isclose(lx / nx, ly / ny, rel_tol=1e-9):
                ly = None
        native = _native.Surface.from_array(h, lx, ly, detrend, window, periodic, fill)
        return cls(native, periodic=periodic)

    @classmethod
    def from_topography(
        cls,
        topography: Any,
        *,
        fill_missing: bool = False,
        detrend: Optional[str] = None,
        window: Optional[str] = None,
    ) -> "Surface":
        """A surface from any object with ``heights()`` (a 2-D array, axis 0
        = x) and ``physical_sizes`` (``(Lx, Ly)`` in m), such as a
        SurfaceTopography ``Topography``; its ``is_periodic`` flag, if it has
        one, is kept (a periodic map is taken as it is, any other is
        detrended, see :meth:`from_array`). A topography in other units is
        converted with its ``to_unit("m")``; its missing (masked) points are
        an error unless ``fill_missing``."""
        _checks.flag("fill_missing", fill_missing)
        unit = getattr(topography, "unit", None)
        if unit is None:
            warnings.warn(
                "the topography carries no unit: its heights and physical_sizes are taken as metres",
                stacklevel=2,
            )
        elif unit != "m":
            if not callable(getattr(topography, "to_unit", None)):
                raise ValueError(f"the topography's unit is {unit!r}; heights and sizes must be in m")
            topography = topography.to_unit("m")
        heights = topography.heights()
        if isinstance(heights, np.ma.MaskedArray):
            masked = int(np.ma.count_masked(heights))
            if masked and not fill_missing:
                raise ValueError(
                    f"the topography's heights have {masked} masked (missing) points; "
                    "pass fill_missing=True to fill them by harmonic interpolation"
                )
            # Kept masked: from_array checks its dtype (a boolean, complex
            # or string map is refused, not cast) and marks the points NaN.
            h = heights
        else:
            if getattr(topography, "has_undefined_data", False) and not fill_missing:
                raise ValueError(
                    "the topography has undefined (missing) points; "
                    "pass fill_missing=True to fill them by harmonic interpolation"
                )
            try:
                h = np.asarray(heights)
            except Exception as e:  # ragged lists and the like
                raise ValueError(f"the topography's heights() must be an array of real numbers: {e}") from None
        if h.ndim != 2:
            raise ValueError(f"the topography's heights() must be 2-dimensional (a map, not a line scan), got shape {h.shape}")
        sizes = topography.physical_sizes
        try:
            lx, ly = (float(s) for s in sizes)
        except (TypeError, ValueError):
            raise ValueError(f"physical_sizes must be (Lx, Ly) in m, got {sizes!r}") from None
        periodic = bool(getattr(topography, "is_periodic", False))
        return cls.from_array(
            h, lx, length_y=ly, periodic=periodic, fill_missing=fill_missing, detrend=detrend, window=window
        )

    @classmethod
    def coerce(
        cls,
        value: Any,
        *,
        fill_missing: Optional[bool] = None,
        detrend: Optional[str] = None,
        window: Optional[str] = None,
    ) -> "Surface":
        """``value`` if it is a :class:`Surface`, else a surface from a
        topography-like object (:meth:`from_topography` with
        ``fill_missing``, ``detrend`` and ``window``). A :class:`Surface` was
        prepared when it was built: giving the three keys with one is an
        error."""
        _checks.optional_flag("fill_missing", fill_missing)
        _checks.text("detrend", detrend, _DETREND)
        _checks.text("window", window, _WINDOW)
        if isinstance(value, Surface):
            given = [k for k, v in (("fill_missing", fill_missing), ("detrend", detrend), ("window", window)) if v is not None]
            if given:
                raise ValueError(
                    f"{', '.join(given)} apply when a surface is built (Surface.from_array, from_file, "
                    "from_topography); this Surface was prepared already"
                )
            return value
        if callable(getattr(value, "heights", None)) and hasattr(value, "physical_sizes"):
            return cls.from_topography(value, fill_missing=bool(fill_missing), detrend=detrend, window=window)
        raise TypeError(
            f"expected a viscoslide.Surface or an object with heights() and physical_sizes, got {type(value).__name__}"
        )

    @property
    def heights(self) -> np.ndarray:
        """Heights [m], shape ``(nx, ny)``."""
        return self._native.heights

    @property
    def shape(self) -> Tuple[int, int]:
        """``(nx, ny)``."""
        return self._native.shape

    @property
    def cell_size(self) -> float:
        """Side of a cell along x [m] (see :attr:`cell_sizes`)."""
        return self._native.cell_size

    @property
    def cell_sizes(self) -> Tuple[float, float]:
        """Sides of a cell ``(dx, dy)`` [m]; equal for square cells."""
        return self._native.cell_sizes

    @property
    def physical_sizes(self) -> Tuple[float, float]:
        """``(Lx, Ly)`` [m]."""
        return self._native.lengths

    @property
    def seed(self) -> Optional[int]:
        """Seed of a generated surface, else ``None``."""
        return self._native.seed

    @property
    def section(self) -> Optional[Dict[str, Any]]:
        """The ``[surface]`` configuration section that makes this surface
        (``None`` for heights given as an array)."""
        text = self._native.section_json()
        return None if text is None else json.loads(text)

    @property
    def preprocessing(self) -> Optional[Dict[str, Any]]:
        """How the map was prepared (``periodic``, ``detrend``, ``window``),
        ``None`` for a generated surface (taken as it is)."""
        text = self._native.preprocessing_json()
        return None if text is None else json.loads(text)

    def psd(self, window: Optional[str] = None) -> Tuple[np.ndarray, np.ndarray]:
        """Radially averaged PSD ``(q [1/m], C [m^4])`` with
        ``<h^2> = 2 pi Int q C dq``; ``window`` is ``"none"`` (periodic maps),
        ``"hann"`` or ``"blackman_harris"`` (measured, non-periodic maps);
        default: the map's own (``"hann"`` for a scan, ``"none"`` for a
        periodic or generated map)."""
        q, c, _ = self._native.psd(_checks.text("window", window, _WINDOW))
        return q, c

    def stats(self, window: Optional[str] = None) -> Dict[str, Any]:
        """Statistics of the map (rms height, slope and curvature from the
        PSD and from the map, ...), as ``viscoslide surface stats``; the
        window defaults to the map's own (see :meth:`psd`). A PSD whose rms
        slope differs from the real-space rms slope by more than 20 % is
        warned about (``warnings`` key and ``warnings.warn``)."""
        doc = json.loads(self._native.stats_json(_checks.text("window", window, _WINDOW)))
        for w in doc.get("warnings", []):
            warnings.warn(w, stacklevel=2)
        return doc

    def __repr__(self) -> str:
        nx, ny = self.shape
        lx, ly = self.physical_sizes
        rms = float(np.std(self.heights))
        return f"Surface({nx} x {ny} cells, {lx:.4g} m x {ly:.4g} m, rms height {rms:.4g} m)"
