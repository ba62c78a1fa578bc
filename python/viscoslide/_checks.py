"""Checks and conversions of user input: every failure names the argument
and the value. A bad number (a boolean, a string, NaN, inf, out of range)
is a ValueError; a string, path or flag of the wrong type a TypeError."""

from __future__ import annotations

import decimal
import math
import numbers
import os
from collections.abc import Iterable, Mapping
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
        if allow_nan:
            # NaN passed: what is left is infinite, which no filling mends.
            raise ValueError(
                f"{name} has {bad} infinite value(s), the first at index {first}: "
                "only missing (NaN or masked) points are filled; replace or crop them"
            )
        hint = (
            "; pass fill_missing=True to fill missing (NaN or masked) points by harmonic interpolation, or crop them"
            if ndim == 2
            else ""
        )
        raise ValueError(f"{name} has {bad} non-finite value(s) (NaN or inf), the first at index {first}{hint}")
    return arr


def number(name: str, value: Any, allow_inf: bool = False) -> float:
    """A finite real number (``allow_inf``: or an infinite one, a limit
    the callee takes, such as the glassy speed)."""
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be a real number, got the boolean {value!r}")
    if isinstance(value, decimal.Decimal):
        # A real number that numbers.Real leaves out (read from a CSV file
        # or a database): taken rounded to a double, as a Fraction is.
        if value.is_snan():
            raise ValueError(f"{name} must be a number, got the signalling NaN {value!r}")
        value = float(value)
    if not isinstance(value, numbers.Real):
        if isinstance(value, numbers.Complex):
            raise ValueError(f"{name} must be real, got the complex number {value!r}")
        if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "fiu":
            value = value.item()
        else:
            raise ValueError(f"{name} must be a real number, got {value!r}")
    try:
        x = float(value)
    except OverflowError:
        # A whole number beyond a double (10**400): named, as any other
        # number out of range.
        digits = len(str(abs(int(value))))
        raise ValueError(
            f"{name} is out of the range of a float (magnitudes up to about 1.8e308), got a whole number of {digits} digits"
        ) from None
    if math.isnan(x) and allow_inf:
        raise ValueError(f"{name} must be a number (inf allowed), got {x}")
    if not math.isfinite(x) and not allow_inf:
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


def unmasked(name: str, value: Any, hint: str) -> Any:
    """``value`` with a masked array's data in place of the array, where
    nothing is masked; a masked point is a ValueError naming ``name``,
    the count and the first, then ``hint`` (what to give instead)."""
    if not isinstance(value, np.ma.MaskedArray):
        return value
    mask = np.ma.getmaskarray(value)
    if mask.any():
        first = tuple(int(i) for i in np.argwhere(mask)[0])
        raise ValueError(f"{name} has {int(np.count_nonzero(mask))} masked value(s), the first at index {first}{hint}")
    return np.ma.getdata(value)


def reals(name: str, value: Any) -> list:
    """A number or a 1-D sequence of numbers (a list, tuple, array, range
    or any other iterable such as a generator) as a list of finite floats;
    a boolean, a string or a non-finite value is refused, named by its
    position (``q1[0] must be finite, got nan``), and so are a set or a
    dict (no order) and masked values."""
    value = unmasked(name, value, ": give only the values to use (.compressed())")
    if isinstance(value, (set, frozenset, Mapping)):
        raise ValueError(
            f"{name} must be a number or a 1-D sequence of numbers (a list or an array), got a {type(value).__name__}"
        )
    if isinstance(value, Iterable) and not isinstance(value, (str, bytes, np.ndarray)):
        value = list(value)
    if isinstance(value, np.ndarray):
        if value.ndim > 1:
            raise ValueError(f"{name} must be a number or a 1-D sequence of numbers, got shape {value.shape}")
        if value.ndim == 0:
            return [number(name, value)]
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        return [number(f"{name}[{i}]", v) for i, v in enumerate(value)]
    return [number(name, value)]


def text(name: str, value: Any, expected: str) -> Optional[str]:
    """``None`` or a string (``expected`` says which, for the message)."""
    if value is None or isinstance(value, str):
        return value
    raise TypeError(f"{name} must be {expected}, got {value!r}")


def flag(name: str, value: Any) -> bool:
    """``True`` or ``False`` (numpy's booleans too)."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"{name} must be True or False, got {value!r}")


def optional_flag(name: str, value: Any) -> Optional[bool]:
    """``None``, ``True`` or ``False``."""
    return None if value is None else flag(name, value)


def path(name: str, value: Any) -> str:
    """A file system path (``str`` or ``os.PathLike``) as a string; an
    empty one (which names no file) is a ValueError."""
    if isinstance(value, (str, os.PathLike)):
        text = os.fspath(value)
        if isinstance(text, str):
            if text == "":
                raise ValueError(f"{name} is an empty path: give a file or directory name")
            return text
    raise TypeError(f"{name} must be a path (str or os.PathLike), got {value!r}")


def shard(value: Any) -> Optional[str]:
    """``None`` or a ``"K/N"`` string (checked as the command line's
    ``--shard``)."""
    return text("shard", value, "a string 'K/N' such as '0/4' (0 <= K < N)")
