"""Easing of the time parameter: where the frames of a sequence fall in [0, 1]."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .errors import ParameterError

if TYPE_CHECKING:
    from collections.abc import Callable

__all__ = ["EASINGS", "eased_times", "frame_times"]

EASINGS = {
    "linear": lambda s: s,
    "ease-in": lambda s: s * s,
    "ease-out": lambda s: s * (2.0 - s),
    "ease-in-out": lambda s: s * s * (3.0 - 2.0 * s),
}


def eased_times(frames: int, easing: str | Callable[[np.ndarray], np.ndarray] = "linear") -> np.ndarray:
    """Times t_k = u(k / (frames - 1)) of every frame, spaced by an easing curve.

    (`isotween.times.frame_times` checks given times or makes uniform ones.)

    Parameters
    ----------
    frames : int
    easing : str or callable
        One of :data:`EASINGS` or a monotone curve u: [0, 1] -> [0, 1] with
        u(0) = 0 and u(1) = 1, applied elementwise to an array.

    Returns
    -------
    (frames,) float array, strictly increasing from 0 to 1.

    Examples
    --------
    >>> from isotween.easing import eased_times
    >>> eased_times(5, "ease-in").tolist()
    [0.0, 0.0625, 0.25, 0.5625, 1.0]
    """
    curve = EASINGS.get(easing) if isinstance(easing, str) else easing
    if curve is None or not callable(curve):
        raise ParameterError(f"unknown easing {easing!r}; choose one of {', '.join(EASINGS)} or pass a function")
    s = np.linspace(0.0, 1.0, int(frames))
    t = np.asarray(curve(s), dtype=float)
    if t.shape != s.shape or not np.all(np.isfinite(t)):
        raise ParameterError("the easing curve must map an array of times to finite times")
    if abs(t[0]) > 1e-12 or abs(t[-1] - 1.0) > 1e-12 or np.any(np.diff(t) <= 0):
        raise ParameterError("the easing curve must increase strictly from u(0) = 0 to u(1) = 1")
    t[0], t[-1] = 0.0, 1.0
    return t


def frame_times(frames: int, easing: str | Callable[[np.ndarray], np.ndarray] = "linear") -> np.ndarray:
    """Deprecated name of `eased_times` (it clashed with `isotween.times.frame_times`, which differs)."""
    import warnings

    warnings.warn("isotween.easing.frame_times is deprecated; call isotween.easing.eased_times",
                  DeprecationWarning, stacklevel=2)
    return eased_times(frames, easing)
