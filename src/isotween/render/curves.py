"""Cubic Bezier outlines of a sequence, with one segment structure for every frame.

Every path (a run of vertex indices, closed or open) is cut into pieces at its
*breaks*: the corners (vertices whose turning angle exceeds a threshold in any
frame), the ends of open paths, and extra joints chosen greedily so that one
cubic fits each piece within a tolerance in *every* frame at once. Since the
breaks are shared, frame ``k`` and frame ``k + 1`` have the same commands and
the curves themselves interpolate (SVG ``d`` animation, CSS ``path()``,
Lottie shape keyframes all need that).

A piece is fitted by least squares with chord-length parameters
(Schneider 1990) at its vertices and edge midpoints, its ends fixed on the
vertices; at a joint that is not a corner both neighbouring pieces share the
joint's tangent direction (central difference), so the outline stays smooth;
at a corner the inner control point is free. A piece of one edge is that
edge, a straight segment. The error is measured at the fitting parameters,
an upper bound on the distance from each vertex and edge midpoint to the
curve.
"""

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..geometry import bbox_diagonal

__all__ = ["CurvePath", "fit_curves", "curve_controls", "TOLERANCE", "CORNER"]

#: default tolerance, as a fraction of the diagonal of the drawing's bounding box
TOLERANCE = 1e-3
#: default corner threshold: turning angle in degrees
CORNER = 30.0

_RIDGE = 1e-9  # pulls an under-determined piece towards the straight segment


@dataclass(frozen=True)
class CurvePath:
    """The Bezier segment structure of one path.

    Attributes
    ----------
    indices : (k,) int array
        Vertex indices of the path, in order.
    closed : bool
    breaks : (S + 1,) int array
        Positions in ``indices`` where segments start and end, increasing;
        for a closed path the last equals the first plus ``k`` (it wraps).
    corner : (S + 1,) bool array
        Whether each break is a corner (or an end of an open path): the
        control points beside it are free, not tied to a shared tangent.
    """

    indices: np.ndarray
    closed: bool
    breaks: np.ndarray
    corner: np.ndarray

    @property
    def n_segments(self):
        """Number of cubic segments S."""
        return len(self.breaks) - 1

    @property
    def straight(self):
        """(S,) bool: segments of one edge, drawn as lines."""
        return np.diff(self.breaks) == 1

    def controls(self, frames):
        """Control points of every segment in every frame.

        Parameters
        ----------
        frames : (F, n, 2) float array

        Returns
        -------
        (F, S, 4, 2) float array
            ``P0, P1, P2, P3`` of each segment; ``P3`` of a segment is ``P0``
            of the next.
        """
        return curve_controls(self, frames)[0]


def _complex(frames):
    frames = np.asarray(frames, dtype=np.float64)
    return frames[..., 0] + 1j * frames[..., 1]


def _unit(z):
    a = np.abs(z)
    return np.where(a > 0, z / np.where(a > 0, a, 1.0), 0.0)


def _ring(z, indices, closed):
    """(F, k) complex points of a path, the first repeated at the end when closed."""
    pts = z[:, indices]
    return np.concatenate([pts, pts[:, :1]], axis=1) if closed else pts


def _turning(pts, closed):
    """(k,) largest turning angle (radians) at every vertex over all frames; ends of open paths: pi."""
    p = pts[:, :-1] if closed else pts
    k = p.shape[1]
    if k < 3:
        return np.full(k, np.pi)
    nxt = np.roll(p, -1, axis=1) - p
    prev = p - np.roll(p, 1, axis=1)
    ok = (np.abs(nxt) > 0) & (np.abs(prev) > 0)
    turn = np.where(ok, np.abs(np.angle(nxt * np.conj(prev))), 0.0).max(axis=0)
    if not closed:
        turn[[0, -1]] = np.pi
    return turn


def _tangents(pts, closed):
    """(F, k') unit tangent at every point of ``_ring`` (central differences)."""
    if closed:
        p = pts[:, :-1]
        t = _unit(np.roll(p, -1, axis=1) - np.roll(p, 1, axis=1))
        return np.concatenate([t, t[:, :1]], axis=1)
    t = np.empty_like(pts)
    t[:, 1:-1] = pts[:, 2:] - pts[:, :-2]
    t[:, 0] = pts[:, 1] - pts[:, 0]
    t[:, -1] = pts[:, -1] - pts[:, -2]
    return _unit(t)


def _bernstein(u):
    v = 1.0 - u
    return np.stack([v ** 3, 3 * v * v * u, 3 * v * u * u, u ** 3], axis=-1)


def _fit(q, t0, t1):
    """Least-squares cubic through a run of points in every frame.

    Parameters
    ----------
    q : (F, m) complex array
        Points of the piece, m >= 2; the ends are kept.
    t0, t1 : (F,) complex array or None
        Unit tangent at the start and at the end (pointing forward), or None
        for a free control point.

    Returns
    -------
    ctrl : (F, 4) complex array
    err : (F,) float array
        Largest distance between a vertex or edge midpoint and the curve at
        its chord-length parameter.
    """
    f, m = q.shape
    p0, p3 = q[:, 0], q[:, -1]
    chord = p3 - p0
    straight = np.stack([p0, p0 + chord / 3, p3 - chord / 3, p3], axis=1)
    if m == 2:
        return straight, np.zeros(f)
    seg = np.abs(np.diff(q, axis=1))  # (F, m-1)
    cum = np.concatenate([np.zeros((f, 1)), np.cumsum(seg, axis=1)], axis=1)
    total = cum[:, -1:]
    u = np.where(total > 0, cum / np.where(total > 0, total, 1.0), np.linspace(0, 1, m))
    uu = np.concatenate([u, 0.5 * (u[:, 1:] + u[:, :-1])], axis=1)  # (F, M)
    target = np.concatenate([q, 0.5 * (q[:, 1:] + q[:, :-1])], axis=1)
    b = _bernstein(uu)  # (F, M, 4)
    cols, defaults = [], []
    length = np.abs(chord) / 3
    if t0 is None:
        cols += [b[..., 1] + 0j, 1j * b[..., 1]]
        defaults += [straight[:, 1].real, straight[:, 1].imag]
        base1 = 0.0
    else:
        cols.append(b[..., 1] * t0[:, None])
        defaults.append(length)
        base1 = b[..., 1] * p0[:, None]
    if t1 is None:
        cols += [b[..., 2] + 0j, 1j * b[..., 2]]
        defaults += [straight[:, 2].real, straight[:, 2].imag]
        base2 = 0.0
    else:
        cols.append(-b[..., 2] * t1[:, None])
        defaults.append(length)
        base2 = b[..., 2] * p3[:, None]
    a = np.stack(cols, axis=-1)  # (F, M, U) complex
    x0 = np.stack(defaults, axis=-1)  # (F, U)
    rhs = target - b[..., 0] * p0[:, None] - b[..., 3] * p3[:, None] - base1 - base2
    rhs = rhs - np.einsum("fmu,fu->fm", a, x0)  # solve for the change from the straight segment
    ar = np.concatenate([a.real, a.imag], axis=1)  # (F, 2M, U)
    br = np.concatenate([rhs.real, rhs.imag], axis=1)
    ata = np.einsum("fmu,fmv->fuv", ar, ar) + _RIDGE * np.eye(ar.shape[2])
    atb = np.einsum("fmu,fm->fu", ar, br)
    x = x0 + np.linalg.solve(ata, atb[..., None])[..., 0]
    j = 0
    if t0 is None:
        p1 = x[:, 0] + 1j * x[:, 1]
        j = 2
    else:
        p1 = p0 + x[:, 0] * t0
        j = 1
    p2 = x[:, j] + 1j * x[:, j + 1] if t1 is None else p3 - x[:, j] * t1
    ctrl = np.stack([p0, p1, p2, p3], axis=1)
    err = np.abs(np.einsum("fmc,fc->fm", b, ctrl) - target).max(axis=1)
    return ctrl, err


def _piece(pts, tan, corner, s, e):
    """Fit of ring positions ``s..e`` (inclusive) with the tangents their breaks call for."""
    return _fit(pts[:, s:e + 1], None if corner[s] else tan[:, s], None if corner[e] else tan[:, e])


def _greedy(pts, tan, corner, start, stop, tol):
    """Breaks between two corners: each piece as long as it fits within ``tol`` in every frame."""
    breaks = [start]
    s = start
    while s < stop:
        def ok(e, s=s):
            return bool(_piece(pts, tan, corner, s, e)[1].max() <= tol)

        if ok(stop):
            breaks.append(stop)
            break
        good, step = s + 1, 2
        while s + step < stop and ok(s + step):
            good, step = s + step, step * 2
        bad = min(s + step, stop)
        while bad - good > 1:  # binary search for the longest piece that fits
            mid = (good + bad) // 2
            good, bad = (mid, bad) if ok(mid) else (good, mid)
        breaks.append(good)
        s = good
    return breaks


def fit_curves(frames, paths, tolerance=None, corner=CORNER):
    """Bezier structure of every path, chosen once for all frames.

    Parameters
    ----------
    frames : (F, n, 2) float array
    paths : list of ((k,) int array, bool)
        Vertex indices of each path and whether it is closed.
    tolerance : float, optional
        Largest distance, in the frames' units, between the outline and its
        curves (at the vertices and edge midpoints); default `TOLERANCE`
        times the diagonal of the bounding box of all frames.
    corner : float
        Turning angle in degrees above which a vertex (in any frame) stays a
        corner.

    Returns
    -------
    list of CurvePath
        One per path, in order.

    Raises
    ------
    ParameterError
        A tolerance or corner angle that is not a positive finite number.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.exp(2j * np.pi * np.arange(64) / 64)
    >>> frames = np.stack([np.column_stack([a.real, a.imag]), np.column_stack([2 * a.real, a.imag])])
    >>> [c] = fit_curves(frames, [(np.arange(64), True)])
    >>> c.n_segments <= 8, c.controls(frames).shape[-2:]
    (True, (4, 2))
    """
    frames = np.asarray(frames, dtype=np.float64)
    if frames.ndim != 3 or frames.shape[-1] != 2:
        raise ParameterError(f"frames must have shape (F, n, 2), got {frames.shape}")
    if tolerance is None:
        flat = frames.reshape(-1, 2)
        tolerance = TOLERANCE * bbox_diagonal(flat) if len(flat) else TOLERANCE
    for name, value in (("tolerance", tolerance), ("corner", corner)):
        if not np.isfinite(value) or value <= 0:
            raise ParameterError(f"the curve {name} must be a positive number, got {value!r}")
    z = _complex(frames)
    limit = np.radians(corner)
    out = []
    for indices, closed in paths:
        indices = np.asarray(indices, dtype=np.int64)
        closed = bool(closed) and len(indices) >= 3
        k = len(indices)
        if k < 2:
            out.append(CurvePath(indices, closed, np.zeros(1, dtype=np.int64), np.ones(1, dtype=bool)))
            continue
        pts = _ring(z, indices, closed)
        tan = _tangents(pts, closed)
        sharp = _turning(pts, closed) > limit
        corners = np.flatnonzero(sharp)
        if closed:
            if not len(corners):  # a smooth loop: start anywhere, its start is a smooth joint
                corners = np.array([0])
            else:
                pts, tan = np.roll(pts[:, :-1], -corners[0], axis=1), np.roll(tan[:, :-1], -corners[0], axis=1)
                pts = np.concatenate([pts, pts[:, :1]], axis=1)
                tan = np.concatenate([tan, tan[:, :1]], axis=1)
                indices = np.roll(indices, -corners[0])
                sharp = np.roll(sharp, -corners[0])
                corners = corners - corners[0]
            stops = [*corners.tolist(), k]
            flags = np.append(sharp, sharp[0])
        else:
            stops = corners.tolist()
            flags = sharp
        breaks = [stops[0]]
        for a, b in zip(stops[:-1], stops[1:], strict=True):
            breaks += _greedy(pts, tan, flags, a, b, tolerance)[1:]
        breaks = np.asarray(breaks, dtype=np.int64)
        out.append(CurvePath(indices, closed, breaks, flags[breaks]))
    return out


def curve_controls(curve, frames):
    """Control points of a `CurvePath` in any frames, and the fitting error.

    Parameters
    ----------
    curve : CurvePath
    frames : (F, n, 2) float array

    Returns
    -------
    controls : (F, S, 4, 2) float array
    error : (F,) float array
        Largest distance from a vertex or edge midpoint to its segment.
    """
    z = _complex(frames)
    f, s = z.shape[0], curve.n_segments
    ctrl = np.zeros((f, s, 4), dtype=np.complex128)
    err = np.zeros(f)
    if s:
        pts = _ring(z, curve.indices, curve.closed)
        tan = _tangents(pts, curve.closed)
        flags = np.zeros(pts.shape[1], dtype=bool)
        flags[curve.breaks] = curve.corner
        for j, (a, b) in enumerate(zip(curve.breaks[:-1], curve.breaks[1:], strict=True)):
            ctrl[:, j], e = _piece(pts, tan, flags, int(a), int(b))
            err = np.maximum(err, e)
    return np.stack([ctrl.real, ctrl.imag], axis=-1), err
