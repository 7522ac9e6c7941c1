"""Checks of option values (counts, lengths, weights, choices): the one place that words their errors.

Beside `errors` at the bottom of the layers (it imports only `errors`), so
the model and every layer above can use it. Each check raises
`ParameterError` naming the option and the value given.
"""

from __future__ import annotations

import math
import numbers
from typing import TypeGuard

from .errors import ParameterError

__all__ = ["is_int", "check_int", "check_number", "check_choice"]


def is_int(value: object) -> TypeGuard[int]:
    """Whether ``value`` is an integer (numpy's too), not a bool.

    Examples
    --------
    >>> from isotween._validate import is_int
    >>> import numpy as np
    >>> is_int(3), is_int(np.int64(3)), is_int(True), is_int(3.0)
    (True, True, False, False)
    """
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def check_int(name: str, value, low: int = 1, high: int | None = None, *, bound: str | None = None) -> int:
    """``value`` as an int, or `ParameterError` unless it is an integer from ``low`` to ``high``.

    Parameters
    ----------
    name : str
        The option, as the message names it.
    value : object
    low, high : int, optional
        Inclusive bounds (``high=None``: none above).
    bound : str, optional
        How the message words the bounds (default ``'>= LOW'`` or
        ``'from LOW to HIGH'``).

    Examples
    --------
    >>> from isotween._validate import check_int
    >>> check_int("frames", 5, 2)
    5
    >>> check_int("frames", 1.5, 2)
    Traceback (most recent call last):
        ...
    isotween.errors.ParameterError: frames must be an integer >= 2, got 1.5
    """
    if not is_int(value) or value < low or (high is not None and value > high):
        if bound is None:
            bound = f">= {low}" if high is None else f"from {low} to {high}"
        raise ParameterError(f"{name} must be an integer {bound}, got {value!r}")
    return int(value)


def check_number(name: str, value, *, low: float = 0.0, strict: bool = True, bound: str | None = None) -> float:
    """``value`` as a float, or `ParameterError` unless it is a finite real number above ``low``.

    Parameters
    ----------
    name : str
    value : object
    low : float
    strict : bool
        ``value > low`` (True) or ``value >= low``.
    bound : str, optional
        How the message words what is wanted (default ``'a positive number'``
        for ``low=0, strict=True``, else ``'a finite number >= LOW'`` or
        ``'> LOW'``).

    Examples
    --------
    >>> from isotween._validate import check_number
    >>> check_number("tol", 1e-3)
    0.001
    >>> check_number("smooth", -1, strict=False)
    Traceback (most recent call last):
        ...
    isotween.errors.ParameterError: smooth must be a finite number >= 0, got -1
    """
    ok = not isinstance(value, bool) and isinstance(value, numbers.Real)
    if ok:
        v = float(value)
        ok = math.isfinite(v) and (v > low if strict else v >= low)
    if not ok:
        if bound is None:
            bound = ("a positive number" if strict and low == 0
                     else f"a finite number {'>' if strict else '>='} {low:g}")
        raise ParameterError(f"{name} must be {bound}, got {value!r}")
    return v


def check_choice(name: str, value, choices) -> None:
    """Refuse a ``value`` of option ``name`` that is not one of ``choices``.

    Examples
    --------
    >>> from isotween._validate import check_choice
    >>> check_choice("solver", "magic", ("local", "global"))
    Traceback (most recent call last):
        ...
    isotween.errors.ParameterError: unknown solver 'magic'; choose one of local, global
    """
    if value not in choices:
        raise ParameterError(f"unknown {name} {value!r}; choose one of {', '.join(choices)}")
