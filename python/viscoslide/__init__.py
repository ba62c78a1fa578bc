"""viscoslide: steady sliding contact of a rigid rough surface on a linear
viscoelastic solid (Carbone & Putignano, Phys. Rev. E 89, 032408, 2014),
with numpy arrays in and out.

>>> import viscoslide as vs
>>> rubber = vs.Material.sls(relaxed_modulus=10e6 / 3, glassy_modulus=10e6, creep_time=0.01)
>>> pad = vs.Surface.self_affine(64, 0.01, 0.8, scales=8, rms_slope=0.02, seed=1)
>>> result = vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3)
>>> result.friction_coefficient > 0
True

The API mirrors the engine's layers: :class:`Material`, :class:`Surface`,
:func:`solve` (and :func:`solve_config` for configuration files) giving a
:class:`Result`; :func:`sweep` and :func:`friction_curve` for many solves;
:func:`persson` for Persson's theory; :func:`magnification` for friction
and area against the cut-off ``q1``; :func:`kernel_table` for the
influence coefficients; :func:`surface_temperature` for the temperature
rise under a frictional heat flux map. ``heating=`` of :func:`solve`,
:func:`sweep` and :func:`friction_curve` heats the contact by its own
friction (:attr:`Result.heating`, :attr:`Result.temperature_rise`), and
:meth:`Result.heat` gives the heat of a solved contact. Errors: ``ValueError`` for bad input,
:class:`ConvergenceError` for a solve that did not converge.
"""

from ._native import VERSION as __version__
from .curves import COLUMNS, HEATING_COLUMNS, friction_curve, kernel_table, persson, sweep
from .errors import ConvergenceError
from .heat import surface_temperature
from .magnification import MAGNIFICATION_COLUMNS, magnification
from .material import Material
from .solve import Result, solve, solve_config
from .surface import Surface

__all__ = [
    "COLUMNS",
    "ConvergenceError",
    "HEATING_COLUMNS",
    "MAGNIFICATION_COLUMNS",
    "Material",
    "Result",
    "Surface",
    "__version__",
    "friction_curve",
    "kernel_table",
    "magnification",
    "persson",
    "solve",
    "solve_config",
    "surface_temperature",
    "sweep",
]
