"""Checks on the numbers a user gives the engine: finite, in range, whole where they count.

Every setting that comes from a person (a text field, a slider, a command-line flag) goes
through one of these before it reaches arithmetic, so that NaN, infinity or a negative count
gives a :class:`VoodooError` that names the setting, never a NaN result or a traceback.
"""

from __future__ import annotations

import math
from numbers import Integral, Real

import numpy as np

from .errors import VoodooError


def _describe(low, high, low_open: bool, high_open: bool) -> str:
    if low is not None and high is not None:
        left = "above" if low_open else "at least"
        right = "below" if high_open else "at most"
        return f"{left} {low:g} and {right} {high:g}"
    if low is not None:
        return f"{'above' if low_open else 'at least'} {low:g}"
    if high is not None:
        return f"{'below' if high_open else 'at most'} {high:g}"
    return ""


def finite(
    value,
    what: str,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """``value`` as a finite float within bounds.

    Parameters
    ----------
    value : real number
    what : str
        The setting's name, for the message ("the maximum triangle area").
    low, high : float, optional
        Bounds, inclusive unless ``low_open`` / ``high_open``.

    Raises
    ------
    VoodooError
        When the value is not a real number, is NaN or infinite, or is out of bounds.
    """
    if isinstance(value, bool) or not isinstance(value, Real | np.floating | np.integer):
        raise VoodooError(f"{what.capitalize()} must be a number; got {value!r}.")
    v = float(value)
    bounds = _describe(low, high, low_open, high_open)
    if not math.isfinite(v):
        need = f"a finite number {bounds}" if bounds else "a finite number"
        raise VoodooError(f"{what.capitalize()} is {v}; it must be {need}.")
    too_low = low is not None and (v <= low if low_open else v < low)
    too_high = high is not None and (v >= high if high_open else v > high)
    if too_low or too_high:
        raise VoodooError(f"{what.capitalize()} is {v:g}; it must be {bounds}.")
    return v


def whole(value, what: str, low: int | None = None, high: int | None = None) -> int:
    """``value`` as an int within inclusive bounds; a float must be a whole number.

    Raises
    ------
    VoodooError
        When the value is not a whole number (NaN, infinity, 2.5, text) or is out of bounds.
    """
    if isinstance(value, bool):
        raise VoodooError(f"{what.capitalize()} must be a whole number; got {value!r}.")
    if not isinstance(value, Integral | np.integer):
        v = finite(value, what)
        if v != int(v):
            raise VoodooError(f"{what.capitalize()} must be a whole number; got {v:g}.")
        value = int(v)
    v = int(value)
    if (low is not None and v < low) or (high is not None and v > high):
        bounds = _describe(low, high, False, False)
        raise VoodooError(f"{what.capitalize()} is {v}; it must be {bounds}.")
    return v


def finite_array(values, what: str, shape: tuple | None = None) -> np.ndarray:
    """``values`` as a float64 array with no NaN or infinity (and the given shape).

    ``shape`` may hold None for an axis of any length.

    Raises
    ------
    VoodooError
    """
    try:
        a = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise VoodooError(f"{what.capitalize()} must be numbers.") from None
    if shape is not None and (
        a.ndim != len(shape)
        or any(s is not None and s != n for s, n in zip(shape, a.shape, strict=True))
    ):
        want = "x".join("n" if s is None else str(s) for s in shape)
        raise VoodooError(f"{what.capitalize()} must be {want} numbers; got shape {a.shape}.")
    if not np.isfinite(a).all():
        raise VoodooError(f"{what.capitalize()} has NaN or infinite values.")
    return a
