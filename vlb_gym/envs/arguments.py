"""Checks of environment constructor arguments: the right type (an int is not a bool, a real is
finite) and a range, raising ``TypeError`` or ``ValueError`` with the argument's name."""

from __future__ import annotations

import math
import numbers


def integer(name: str, value: object, low: int, high: int | None = None) -> int:
    """``value`` as an int, if it is an integer (not a bool) in ``[low, high]``."""
    if not isinstance(value, numbers.Integral) or isinstance(value, bool):
        raise TypeError(f"{name} must be an integer (got {value!r})")
    _in_range(name, value, low, high)
    return int(value)


def real(name: str, value: object, low: float, high: float | None = None) -> float:
    """``value`` as a float, if it is a finite number (not a bool) in ``[low, high]``."""
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        raise TypeError(f"{name} must be a number (got {value!r})")
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite (got {value!r})")
    _in_range(name, value, low, high)
    return float(value)


def _in_range(name: str, value: float, low: float, high: float | None) -> None:
    if not low <= value <= (math.inf if high is None else high):
        bounds = f">= {low}" + ("" if high is None else f" and <= {high}")
        raise ValueError(f"{name} must be {bounds} (got {value!r})")
