"""Keyframe reduction: keep a tick only where easing between its neighbours does not reproduce it.

Every animated output (Lottie, SMIL, CSS, Web Animations) interpolates a
property between two keys as ``a + y(u) (b - a)``, ``u`` the elapsed fraction
of the interval and ``y`` a cubic Bezier easing with handles ``(x1, y1)`` and
``(x2, y2)``. With ``x1 = 1/3`` and ``x2 = 2/3`` the easing's x is ``u``
itself, so ``y(u) = 3 (1-u)^2 u y1 + 3 (1-u) u^2 y2 + u^3`` is linear in the
two unknowns: a least-squares fit per interval. Greedily, each interval is
made as long as the eased blend stays within every track's tolerance at the
ticks it skips.
"""

import numpy as np

from ..errors import ParameterError

__all__ = ["reduce_keys", "ease", "LINEAR", "X1", "X2", "TOLERANCE"]

#: default tolerance of the keys, as a fraction of the drawing's diagonal (looser than the curves': a
#: skipped tick is on screen for 1 / fps seconds; tests/test_lottie.py's pixel bound holds with room)
TOLERANCE = 2.5e-3
#: x of the two easing handles (the easing's x is then the elapsed fraction)
X1, X2 = 1.0 / 3.0, 2.0 / 3.0
#: (y1, y2) of a linear easing
LINEAR = (1.0 / 3.0, 2.0 / 3.0)
_RIDGE = 1e-10


def ease(u, y1, y2):
    """Eased fraction ``y(u)`` of the handles ``(X1, y1)``, ``(X2, y2)``.

    Parameters
    ----------
    u : (m,) float array
        Elapsed fractions in [0, 1].
    y1, y2 : float

    Returns
    -------
    (m,) float array
    """
    v = 1.0 - u
    return 3 * v * v * u * y1 + 3 * v * u * u * y2 + u ** 3


def _fit_ease(u, s, unit):
    """(y1, y2) whose easing best matches the fractions ``s`` at ``u`` (pulled towards linear)."""
    v = 1.0 - u
    a = np.stack([3 * v * v * u, 3 * v * u * u], axis=1)  # (m, 2)
    rhs = s - u ** 3 - a @ np.array(LINEAR)
    y = np.array(LINEAR) + np.linalg.solve(a.T @ a + _RIDGE * np.eye(2), a.T @ rhs)
    if unit:  # SMIL keySplines: handles inside the unit square
        y = np.clip(y, 0.0, 1.0)
    return float(y[0]), float(y[1])


def _within(tracks, a, b, times, unit):
    """The easing of interval ``a..b`` if it reproduces every tick in between, else None."""
    u = (times[a + 1:b] - times[a]) / (times[b] - times[a])  # (m,)
    starts = [v[a] for v, _, _ in tracks]
    spans = [v[b] - v[a] for v, _, _ in tracks]
    inner = [v[a + 1:b] - v[a] for v, _, _ in tracks]  # (m, D) each
    # one fraction per tick for all tracks: the projection on the change, each track scaled by its tolerance
    num = sum((x @ d) / tol ** 2 for x, d, (_, tol, _) in zip(inner, spans, tracks, strict=True))
    den = sum((d @ d) / tol ** 2 for d, (_, tol, _) in zip(spans, tracks, strict=True))
    s = num / den if den > 0 else np.zeros(len(u))
    y1, y2 = _fit_ease(u, s, unit) if den > 0 else LINEAR
    y = ease(u, y1, y2)[:, None]
    for start, d, (v, tol, points) in zip(starts, spans, tracks, strict=True):
        miss = start + y * d - v[a + 1:b]
        err = np.linalg.norm(miss.reshape(len(u), -1, 2), axis=2) if points else np.abs(miss)
        if err.size and err.max() > tol:
            return None
    return y1, y2


def reduce_keys(times, tracks, unit=False, reduce=True):
    """Ticks that must stay keyframes, and the easing of every interval.

    Parameters
    ----------
    times : (P,) float array
        Time of every tick, increasing.
    tracks : list of ((P, D) float array, float, bool)
        Values at every tick, their tolerance, and whether the columns are
        2-D points (tolerance on the distance) rather than numbers (on each
        value). All tracks share the keys and the easing.
    unit : bool
        Keep the easing handles in the unit square (SMIL ``keySplines``).
    reduce : bool
        False: every tick is a key, every easing linear.

    Returns
    -------
    keys : (K,) int array
        Indices of the kept ticks; the first and the last always.
    eases : (K - 1, 2) float array
        ``(y1, y2)`` of the easing from each key to the next.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 1, 11)
    >>> keys, eases = reduce_keys(t, [(np.c_[t ** 2, 0 * t], 1e-6, True)])
    >>> keys.tolist(), np.round(eases, 6).tolist()
    ([0, 10], [[0.0, 0.333333]])
    """
    times = np.asarray(times, dtype=np.float64)
    p = len(times)
    if p and np.any(np.diff(times) <= 0):
        raise ParameterError("key times must increase")
    tracks = [(np.asarray(v, dtype=np.float64).reshape(p, -1), float(tol), bool(points)) for v, tol, points in tracks]
    if any(tol <= 0 for _, tol, _ in tracks):
        raise ParameterError("every track needs a positive tolerance")
    if p <= 2 or not reduce:
        return np.arange(p), np.tile(LINEAR, (max(p - 1, 0), 1))
    keys, eases, a = [0], [], 0
    while a < p - 1:
        b, best = a + 1, LINEAR
        while b + 1 < p:
            found = _within(tracks, a, b + 1, times, unit)
            if found is None:
                break
            b, best = b + 1, found
        keys.append(b)
        eases.append(best if b > a + 1 else LINEAR)
        a = b
    return np.asarray(keys, dtype=np.int64), np.asarray(eases, dtype=np.float64)
