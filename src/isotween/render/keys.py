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

__all__ = ["reduce_keys", "key_counts", "split_by_keys", "ease", "LINEAR", "X1", "X2", "TOLERANCE"]

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


def key_counts(times, points, tolerance, unit=False, most=500):
    """How many keys `reduce_keys` keeps for each point's path alone.

    A point that turns about a pivot near it, or moves along a line, needs
    fewer keys than one that swings round on a long arm; items drawn
    together share their keys, so writers group them by these counts
    (`split_by_keys`).

    Parameters
    ----------
    times : (P,) float array
    points : (P, n, 2) float array
        Positions of ``n`` points at every tick.
    tolerance : float
    unit : bool
        As in `reduce_keys`.
    most : int
        Points reduced one by one at most; beyond, that many chosen with a
        fixed seed, and every other point takes the count of the nearest
        of them (first, middle and last tick).

    Returns
    -------
    (n,) int array

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 1, 9)
    >>> turn = np.array([0.0, 0.1, 1.0]) * np.exp(2j * t[:, None])  # radii 0, 0.1 and 1, by 2 radians
    >>> xy = np.stack([turn.real, turn.imag], axis=2)
    >>> key_counts(t, xy, 1e-2).tolist()
    [2, 4, 9]
    """
    points = np.asarray(points, dtype=np.float64)
    p, n = points.shape[:2]
    chosen = np.arange(n)
    if n > most:
        chosen = np.sort(np.random.default_rng(0).choice(n, size=most, replace=False))
    counts = np.array([len(reduce_keys(times, [(points[:, i], tolerance, True)], unit=unit)[0]) for i in chosen],
                      dtype=np.int64)
    if n <= most:
        return counts
    from scipy.spatial import cKDTree

    where = points[[0, p // 2, p - 1]].transpose(1, 0, 2).reshape(n, -1)
    return counts[cKDTree(where[chosen]).query(where)[1]]


def split_by_keys(counts, weights, overhead, most=8):
    """Split items into at most ``most`` groups, each drawn with its own keys, to write the fewest numbers.

    A group costs its largest key count times its weight (the numbers of
    one key), plus ``overhead`` (an element, its timing); groups are runs of
    the items sorted by count, chosen by dynamic programming.

    Parameters
    ----------
    counts : (m,) int array
        Keys each item needs alone (`key_counts`).
    weights : (m,) float array
        Numbers each item writes per key.
    overhead : float
        Cost of one more group, in numbers.
    most : int

    Returns
    -------
    (m,) int array
        Group of every item, 0 for the items that need the fewest keys.

    Examples
    --------
    >>> split_by_keys([2, 30, 2, 3], [100, 100, 100, 100], overhead=300).tolist()
    [0, 1, 0, 0]
    """
    counts = np.asarray(counts, dtype=np.int64)
    weights = np.asarray(weights, dtype=np.float64)
    if not len(counts):
        return np.zeros(0, dtype=np.int64)
    levels, level_of = np.unique(counts, return_inverse=True)
    cumulative = np.concatenate([[0.0], np.cumsum(np.bincount(level_of, weights, minlength=len(levels)))])
    n = len(levels)
    # best[g, j]: least cost of levels 0..j-1 in g groups; cut[g, j]: where the last group starts
    best = np.full((most + 1, n + 1), np.inf)
    cut = np.zeros((most + 1, n + 1), dtype=np.int64)
    best[0, 0] = 0.0
    for g in range(1, most + 1):
        for j in range(1, n + 1):
            i = np.arange(j)
            cost = best[g - 1, i] + levels[j - 1] * (cumulative[j] - cumulative[i]) + overhead
            k = int(np.argmin(cost))
            best[g, j], cut[g, j] = cost[k], k
    g, j = int(np.argmin(best[:, n])), n
    group_of_level = np.zeros(n, dtype=np.int64)
    while g > 0:
        i = cut[g, j]
        group_of_level[i:j] = g - 1
        g, j = g - 1, i
    return group_of_level[level_of]
