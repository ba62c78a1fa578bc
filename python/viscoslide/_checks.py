"""Checks and conversions of user input: every failure is a ValueError
that names the argument and what is wrong with it."""

from __future__ import annotations

import math
import numbers
from typing import Any, Optional

import numpy as np


def real_array(name: str, value: Any, ndim: int, allow_nan: bool = False) -> np.ndarray:
    """``value`` as a C-contiguous float64 array of ``ndim`` dimensions.

    Any real dtype (float32, integers) and any memory order is accepted and
    converted; complex, object, boolean or string data, the wrong number of
    dimensions and non-finite values (NaN, inf) are refused. A numpy masked
    array has its masked points set to NaN (missing), whatever values lie
    under the mask. With ``allow_nan`` NaN (a missing point) passes; inf
    never does.
    """
    if isinstance(value, np.ma.MaskedArray):
        if value.dtype.kind in "fiu":
            value = np.ma.filled(value.astype(np.float64), np.nan)
        else:
            value = np.ma.getdata(value)
    try:
        arr = np.asarray(value)
    except Exception as e:  # ragged lists and the like
        raise ValueError(f"{name} must be an array of real numbers: {e}") from None
    if arr.dtype.kind == "c":
        raise ValueError(
            f"{name} must be real, got complex values (dtype {arr.dtype}); pass .real or abs() explicitly"
        )
    if arr.dtype.kind not in "fiu":
        raise ValueError(f"{name} must be an array of real numbers, got dtype {arr.dtype}")
    if arr.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-dimensional, got shape {arr.shape}")
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    finite = np.isfinite(arr) | (np.isnan(arr) if allow_nan else False)
    if not finite.all():
        bad = int(arr.size - np.count_nonzero(finite))
        first = tuple(int(i) for i in np.argwhere(~finite)[0])
        raise ValueError(
            f"{name} has {bad} non-finite value(s) (NaN or inf), the first at index {first}; "
            "pass fill_missing=True to fill missing (NaN or masked) points by harmonic interpolation, or crop them"
        )
    return arr


def number(name: str, value: Any) -> float:
    """A finite real number."""
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be a real number, got the boolean {value!r}")
    if not isinstance(value, numbers.Real):
        if isinstance(value, numbers.Complex):
            raise ValueError(f"{name} must be real, got the complex number {value!r}")
        if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "fiu":
            value = value.item()
        else:
            raise ValueError(f"{name} must be a real number, got {value!r}")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {x}")
    return x


def positive(name: str, value: Any, unit: str) -> float:
    """A finite number > 0."""
    x = number(name, value)
    if x <= 0:
        raise ValueError(f"{name} must be > 0 ({unit}), got {x}")
    return x


def optional(name: str, value: Any) -> Optional[float]:
    """``None`` or a finite real number."""
    return None if value is None else number(name, value)


def count(name: str, value: Any, minimum: int = 1) -> int:
    """A whole number >= ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{name} must be a whole number, got {value!r}")
    if int(value) < minimum:
        raise ValueError(f"{name} must be at least {minimum}, got {value}")
    if int(value) > COUNT_MAX:
        raise ValueError(f"{name} = {value} is too large: at most 2**63 - 1")
    return int(value)


#: The largest whole number the native module takes (a 64-bit count or seed).
COUNT_MAX = 2**63 - 1


def drop_none(d: dict) -> dict:
    """``d`` without its ``None`` values (absent config keys)."""
    return {k: v for k, v in d.items() if v is not None}
