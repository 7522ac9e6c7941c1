"""Contour correspondence: two sets of outlines resampled to common point counts.

Each ring is resampled uniformly in arc length. A closed ring of the target
starts where it best matches the source ring, in the better of its two
orientations. The matching cost of a start ``u`` (arc length along the target
ring) and an orientation is the sum of squared distances between the source
samples ``x`` and the target samples ``y(u)``, both centred on their centroid
and scaled to unit norm (optionally also rotated onto each other)::

    cost(u) = min_a || x^ - a y^(u) ||^2,   a = 1, or a = e^{i phi} with ``rotation=True``

which is ``2 - 2 Re <x^, y^(u)>`` (or ``2 - 2 |<x^, y^(u)>|``). The correlation
``<x^, y^(u)>`` at all starts on a fine uniform grid comes from one FFT per
grid offset (cyclic cross-correlation); the best grid start is then refined
over the target vertices within one grid step of it, so a target that is a
re-started copy of the source matches exactly.
"""

from __future__ import annotations

import numbers
from typing import TYPE_CHECKING

import numpy as np

from ..errors import IncompatibleShapesError, ParameterError, ShapeError
from ..geometry import ring_orientation
from ..shape import Shape

if TYPE_CHECKING:
    from typing import Any

__all__ = ["resample"]


def resample(source_rings: Any, target_rings: Any, points: int | list[int] | None = None, closed: Any = None,
             corners: float | None = None, rotation: bool = False,
             keep_turn: bool = False) -> tuple[Shape, Shape]:
    """Resample two sets of rings to a compatible pair of outline shapes.

    Parameters
    ----------
    source_rings, target_rings : Shape, (k, 2) array_like, or list of (k_i, 2) array_like
        Outlines. A Shape contributes its ``paths`` (closed rings and open
        polylines, as read from SVG or made by `Shape.from_polygon`). Rings
        are paired in order: ring i of the source with ring i of the target.
    points : int or list of int, optional
        Total number of vertices of each output shape, shared among the rings
        in proportion to their length (the mean of the source's and the
        target's length shares; at least 3 per closed ring, 2 per open one);
        or the count of every ring. Default: the larger total vertex count
        of the inputs.
    closed : bool or list of bool, optional
        Whether each ring is closed. Default: from the Shape's paths, and
        closed for arrays.
    corners : float, optional
        Turning angle in degrees from which a vertex is a corner. Each corner
        replaces the nearest sample of its ring (one corner per sample at
        most), so sharp corners stay sharp. Default: no corners.
    rotation : bool
        Also factor out a rotation in the matching cost (a rotated copy of a
        ring matches itself at the right start). Default: only centroid and
        scale.
    keep_turn : bool
        Traverse every closed target ring in the turning direction of its
        source ring (never a mirror image), as compatible meshes need.
        Default: the better matching of the two directions.

    Returns
    -------
    source, target : Shape
        Outline shapes with the same vertex count, edges and paths; vertex 0
        of each source ring stays at the source ring's first point. Each keeps
        the ``y_down`` of its input Shape.

    Raises
    ------
    ShapeError
        A ring with too few distinct points, zero length, or non-finite
        coordinates (naming the shape and ring).
    IncompatibleShapesError
        Different ring counts, or a ring closed in one shape and open in the other.
    ParameterError
        ``points`` too small for the rings, or another bad option.

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    >>> theta = np.linspace(0, 2 * np.pi, 30, endpoint=False)
    >>> circle = np.c_[np.cos(theta), np.sin(theta)]
    >>> source, target = isotween.resample(square, circle, points=40)
    >>> source.n_vertices, target.n_vertices, bool(np.array_equal(source.edges, target.edges))
    (40, 40, True)
    """
    src = _rings(source_rings, closed, "source")
    tgt = _rings(target_rings, closed, "target")
    if len(src) != len(tgt):
        raise IncompatibleShapesError(
            f"the source has {len(src)} ring(s) but the target has {len(tgt)}; rings are paired "
            "in order, so both need the same number"
        )
    for r, ((_, cs), (_, ct)) in enumerate(zip(src, tgt, strict=False)):
        if cs != ct:
            raise IncompatibleShapesError(
                f"ring {r} is {'closed' if cs else 'open'} in the source but "
                f"{'closed' if ct else 'open'} in the target"
            )
    if corners is not None and not (isinstance(corners, numbers.Real) and 0 < corners < 180):
        raise ParameterError(f"corners must be an angle in degrees between 0 and 180, got {corners!r}")
    counts = _counts(points, src, tgt)
    out_s, out_t = [], []
    for (a, c), (b, _), n in zip(src, tgt, counts, strict=False):
        sa, sb = _Ring(a, c), _Ring(b, c)
        x = sa.at(sa.grid(0.0, n), corners)
        u, reverse = _best_start(x, sb, rotation, keep_turn)
        ring = sb.reversed() if reverse else sb
        out_s.append(x)
        out_t.append(ring.at(ring.grid(u, n), corners))
    closed_flags = [c for _, c in src]
    return (_shape(out_s, closed_flags, getattr(source_rings, "y_down", False)),
            _shape(out_t, closed_flags, getattr(target_rings, "y_down", False)))


# ---------------------------------------------------------------------- rings
class _Ring:
    """A ring (closed) or polyline (open) parameterised by arc length.

    Parameters
    ----------
    z : (k,) complex array
        Distinct consecutive points.
    closed : bool
    """

    def __init__(self, z, closed):
        self.z, self.closed = z, closed
        self.knots = np.append(z, z[0]) if closed else z
        self.cum = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(self.knots)))])
        self.length = float(self.cum[-1])

    def reversed(self):
        """The same ring traversed backwards from the same first point."""
        return _Ring(np.roll(self.z[::-1], 1) if self.closed else self.z[::-1], self.closed)

    def grid(self, start, n):
        """(n,) arc positions: uniform from ``start`` around a ring, end to end on a polyline."""
        if self.closed:
            return np.mod(start + self.length * np.arange(n) / n, self.length)
        return np.linspace(0.0, self.length, n)

    def at(self, s, corners=None):
        """Complex points at arc positions ``s`` (any shape).

        With ``corners`` (degrees), the sample nearest each corner moves onto it.
        """
        s = np.array(s, dtype=np.float64)
        if corners is not None:
            s = self._snap(s, corners)
        return np.interp(s, self.cum, self.knots.real) + 1j * np.interp(s, self.cum, self.knots.imag)

    def _snap(self, s, corners):
        d = np.diff(self.knots)
        if self.closed:
            turn = np.angle(d / np.roll(d, 1))  # at vertex i, between edges i-1 and i
            where = self.cum[:-1]
        else:
            turn = np.angle(d[1:] / d[:-1])
            where = self.cum[1:-1]
        pos = where[np.abs(turn) >= np.deg2rad(corners)]
        if not pos.size:
            return s
        gap = np.abs(pos[:, None] - s[None, :])
        if self.closed:
            gap = np.minimum(gap, self.length - gap)
        nearest = np.argmin(gap, axis=1)
        slot, first = np.unique(nearest, return_index=True)
        s[slot] = pos[first]
        return s


def _rings(obj, closed, name):
    """[(z (k,) complex, closed bool)] of a Shape, an array or a list of arrays."""
    if isinstance(obj, Shape):
        if not obj.paths:
            raise ShapeError(f"the {name} shape has no outline paths (rings or polylines) to resample")
        rings = [obj.vertices[idx] for idx, _ in obj.paths]
        flags = [c for _, c in obj.paths]
    else:
        if isinstance(obj, np.ndarray) and obj.ndim == 2 or (len(obj) and np.ndim(obj[0]) == 1):
            obj = [obj]
        rings = list(obj)
        flags = [True] * len(rings)
    if not rings:
        raise ShapeError(f"the {name} has no rings")
    if closed is not None:
        flags = [bool(closed)] * len(rings) if np.ndim(closed) == 0 else [bool(c) for c in closed]
        if len(flags) != len(rings):
            raise ParameterError(f"closed has {len(flags)} value(s) but the {name} has {len(rings)} ring(s)")
    out = []
    for r, (ring, c) in enumerate(zip(rings, flags, strict=False)):
        p = np.asarray(ring, dtype=np.float64)
        if p.ndim != 2 or p.shape[1] != 2:
            raise ShapeError(f"{name} ring {r} must be an array of shape (k, 2), got {p.shape}")
        bad = np.flatnonzero(~np.all(np.isfinite(p), axis=1))
        if bad.size:
            raise ShapeError(f"{name} ring {r} point {bad[0]} has a non-finite coordinate")
        z = p[:, 0] + 1j * p[:, 1]
        keep = np.ones(len(z), dtype=bool)
        keep[1:] = z[1:] != z[:-1]
        z = z[keep]
        if c and len(z) > 1 and z[-1] == z[0]:
            z = z[:-1]
        need = 3 if c else 2
        if len(z) < need:
            raise ShapeError(
                f"{name} ring {r} has {len(z)} distinct point(s); a "
                f"{'closed ring' if c else 'polyline'} needs at least {need}"
            )
        out.append((z, c))
    return out


#: peak bytes per resampled point and shape (arc positions, complex points, the Shape's arrays):
#: measured 385 for one million points of a pair
POINT_BYTES = 400


def check_points(points, shapes=2, what="resampling"):
    """Refuse (`ResourceError`) ``points`` per shape that would not fit in memory, before any allocation."""
    from ..resources import check_memory

    check_memory(POINT_BYTES * float(points) * shapes, f"{what} {shapes} shapes to {points} points",
                 advice="use fewer points")


def _counts(points, src, *others):
    """Points per ring: given, or the total shared in proportion to length (the mean of every shape's length shares)."""
    need = np.array([3 if c else 2 for _, c in src])
    if points is not None and np.ndim(points) == 1:
        counts = np.asarray(points)
        if len(counts) != len(src) or not np.issubdtype(counts.dtype, np.integer):
            raise ParameterError(f"points must be one integer or one per ring ({len(src)}), got {points!r}")
        low = np.flatnonzero(counts < need)
        if low.size:
            r = int(low[0])
            raise ParameterError(f"points for ring {r} is {counts[r]}; that ring needs at least {need[r]}")
        return counts.astype(np.int64)
    if points is None:
        points = max(sum(len(z) for z, _ in rings) for rings in (src, *others))
    if isinstance(points, bool) or not isinstance(points, numbers.Integral):
        raise ParameterError(f"points must be an integer, got {points!r}")
    check_points(points, 1 + len(others))
    if points < need.sum():
        raise ParameterError(f"points={points} is too few for {len(src)} ring(s); at least {need.sum()} needed")
    lengths = [np.array([_Ring(z, c).length for z, c in rings]) for rings in (src, *others)]
    for name, ls in zip(["source", "target"] + [f"shape {k}" for k in range(2, len(lengths))], lengths, strict=False):
        zero = np.flatnonzero(ls <= 0)
        if zero.size:
            raise ShapeError(f"{name} ring {zero[0]} has zero length")
    share = np.mean([ls / ls.sum() for ls in lengths], axis=0)
    # largest remainder, then rings below their minimum take from the largest ones
    raw = points * share
    counts = np.maximum(np.floor(raw).astype(np.int64), need)
    rest = points - counts.sum()
    if rest > 0:
        counts[np.argsort(np.floor(raw) - raw, kind="stable")[:rest]] += 1
    for _ in range(-rest):
        counts[np.argmax(np.where(counts > need, counts, -1))] -= 1
    return counts


def _shape(rings, closed, y_down):
    """One outline Shape of complex rings, paths in order."""
    return Shape.from_paths(rings, list(closed), y_down=y_down)


# ---------------------------------------------------------------------- matching
def _normalised(y):
    """Centred and scaled to unit norm along axis 0."""
    y = y - y.mean(axis=0)
    return y / np.maximum(np.linalg.norm(y, axis=0), 1e-300)


def _score(x, y, rotation):
    """Re <x, y> or |<x, y>| of normalised samples (higher is a better match)."""
    c = np.vdot(x, y) if y.ndim == 1 else x.conj() @ y
    return np.abs(c) if rotation else c.real


def _best_start(x, ring, rotation, keep_turn=False):
    """Start (arc length) and orientation of ``ring`` that best match samples ``x``.

    Parameters
    ----------
    x : (n,) complex array
        Source samples.
    ring : _Ring
    rotation : bool
    keep_turn : bool
        Only the direction that turns like ``x`` (closed rings).

    Returns
    -------
    start : float
        Arc length along the ring (in the chosen orientation) of its first sample.
    reverse : bool
    """
    n = len(x)
    xn = _normalised(x)
    both = (ring, ring.reversed())
    if not ring.closed:
        scores = [_score(xn, _normalised(r.at(r.grid(0.0, n))), rotation) for r in both]
        return 0.0, bool(scores[1] > scores[0])
    # grid of q * n starts; samples of start m = r + s q are Y[r + (s + i) q], i < n
    q = max(1, -(-max(4 * n, 2 * len(ring.z)) // n))
    spectrum = np.conj(np.fft.fft(xn))
    best = (-np.inf, 0.0, False)
    allowed = (False, True)
    if keep_turn:
        turn = ring_orientation(x)
        own = ring_orientation(ring.z)
        allowed = (bool(turn != own),)
    for reverse, r in zip((False, True), both, strict=False):
        if reverse not in allowed:
            continue
        grid = _normalised(r.at(r.length * np.arange(n * q) / (n * q)).reshape(n, q))
        corr = np.fft.ifft(spectrum[:, None] * np.fft.fft(grid, axis=0), axis=0)  # (n, q): shift s, offset
        score = np.abs(corr) if rotation else corr.real
        s, off = np.unravel_index(int(np.argmax(score)), score.shape)
        if score[s, off] > best[0]:
            best = (score[s, off], r.length * (s * q + off) / (n * q), reverse)
    _, start, reverse = best
    # refine over the ring's vertices within one grid step of the best grid start
    r = both[reverse]
    step = r.length / (n * q)
    gap = np.abs(r.cum[:-1] - start)
    near = r.cum[:-1][np.minimum(gap, r.length - gap) <= step * (1 + 1e-9)]
    starts = np.concatenate([[start], near])
    samples = r.at(np.mod(starts[None, :] + r.length * np.arange(n)[:, None] / n, r.length))
    scores = _score(xn, _normalised(samples), rotation)
    return float(starts[int(np.argmax(scores))] % r.length), reverse
