"""Frame times: the parameter t_k in [0, 1] of every frame of a sequence."""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._validate import check_int
from .errors import ParameterError

__all__ = ["frame_times", "uniform_times"]


def frame_times(frames: int, times: ArrayLike | None = None, *, per: str = "frame") -> NDArray[np.float64]:
    """Validated frame times, both inputs included.

    Parameters
    ----------
    frames : int
        Number of frames, at least 2 (the two inputs).
    times : (frames,) array_like of float, optional
        Strictly increasing times from exactly 0 to exactly 1; uniform when
        omitted.
    per : str
        What the times belong to, for the error messages ('frame',
        'keyframe').

    Returns
    -------
    (frames,) float64 array
        A new array (the caller may write into it).

    Raises
    ------
    ParameterError
        ``frames`` is not an integer >= 2, or ``times`` is not numbers, has
        the wrong length, is not finite, does not start at 0 and end at 1, or does not increase.

    Examples
    --------
    >>> from isotween.times import frame_times
    >>> frame_times(5)
    array([0.  , 0.25, 0.5 , 0.75, 1.  ])
    >>> frame_times(3, [0.0, 0.2, 1.0])
    array([0. , 0.2, 1. ])
    """
    check_int("frames", frames, 2, bound=">= 2 (both inputs included)")
    if times is None:
        return uniform_times(int(frames)).copy()
    try:
        t = np.asarray(times, dtype=np.float64)
    except (ValueError, TypeError):
        raise ParameterError(f"times must give one number per {per} ({frames}), got {times!r:.80}") from None
    if t.shape != (frames,):
        raise ParameterError(f"times must have one value per {per} ({frames}), got shape {t.shape}")
    if not np.all(np.isfinite(t)) or t[0] != 0.0 or t[-1] != 1.0 or np.any(np.diff(t) <= 0):
        raise ParameterError(f"{per} times must increase strictly from 0 to 1, got {t.tolist()!s:.80}")
    return t.copy()


@functools.lru_cache(maxsize=64)
def _uniform(frames: int) -> NDArray[np.float64]:
    t = np.linspace(0.0, 1.0, frames)
    t.flags.writeable = False
    return t


def uniform_times(frames: int) -> NDArray[np.float64]:
    """``frames`` evenly spaced times from 0 to 1 (a cached, read-only array).

    Parameters
    ----------
    frames : int
        Number of frames, at least 2.

    Returns
    -------
    (frames,) float64 array, read-only

    Examples
    --------
    >>> from isotween.times import uniform_times
    >>> uniform_times(3)
    array([0. , 0.5, 1. ])
    """
    return _uniform(int(frames))
