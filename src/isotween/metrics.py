"""Distortion metrics of a shape sequence (definitions: docs/how-it-works.md, Metric definitions).

Every function takes a :class:`~isotween.Sequence`. ``reduce`` picks the
summary: 'max' or 'mean' over all frames and elements, or None for per-frame
values (an (F,) array).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, overload

import numpy as np

from .errors import ParameterError
from .geometry import bbox_diagonal, orient, ring_areas, segment_distance
from .optimisation.schemes import SCHEMES
from .optimisation.schemes import isometric_energy as _energy
from .paint import half_widths, out_of_sight

if TYPE_CHECKING:
    from .sequence import Sequence

__all__ = ["isometric_energy", "edge_length_deviation", "area_deviation", "flipped", "flipped_faces",
           "symmetry_error", "report", "loop_areas", "outline_crossings",
           "outline_edges", "crossing_pairs", "crossing_edges", "path_crossings", "new_crossings", "edge_paths"]


def isometric_energy(seq: Sequence, scheme: str | None = None) -> float:
    """Eq. (6) with the sequence's scheme (or ``scheme``), over ``sum |e(0)|^2``.

    For the paper scheme the forward and reverse samplings are averaged.

    Examples
    --------
    >>> import isotween
    >>> from isotween import metrics
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> bool(metrics.isometric_energy(isotween.interpolate(bar, bar.rotate(1.0), frames=5)) < 1e-12)
    True
    >>> round(metrics.isometric_energy(isotween.interpolate(bar, bar.scale(2.0), frames=3)), 9)
    1.0
    """
    scheme = scheme or (seq.scheme if seq.scheme in SCHEMES else "midpoint")
    return _energy(seq.edge_vectors().T, np.diff(seq.times), scheme)


def _reduce(values, per_frame, reduce):
    """values: (F, k) deviations; per_frame: how to fold one frame."""
    if reduce is None:
        return per_frame(values, axis=1) if values.shape[1] else np.zeros(len(values))
    if values.size == 0:
        return float("nan")
    if reduce == "max":
        return float(values.max())
    if reduce == "mean":
        return float(values.mean())
    raise ParameterError(f"unknown reduce {reduce!r}; choose 'max', 'mean' or None")


def _blend(first, last, t):
    """Linear blend of the end values at times ``t``, over the sequence's own time span.

    A slice of a sequence thus blends between its own first and last frames.
    """
    t = ((t - t[0]) / (t[-1] - t[0]))[:, None] if len(t) > 1 else np.zeros((len(t), 1))
    return (1 - t) * first[None] + t * last[None]


@overload
def edge_length_deviation(seq: Sequence, reduce: str = "max") -> float: ...
@overload
def edge_length_deviation(seq: Sequence, reduce: None) -> np.ndarray: ...
def edge_length_deviation(seq: Sequence, reduce: str | None = "max") -> float | np.ndarray:
    """``| |e(t_k)| / ((1 - t_k)|e(0)| + t_k|e(1)|) - 1 |`` over edges and frames.

    Examples
    --------
    >>> import isotween
    >>> from isotween import metrics
    >>> bar = isotween.Shape.from_polyline([[-1, 0], [1, 0]])
    >>> squash = isotween.Sequence([[[-1, 0], [1, 0]], [[-0.25, 0], [0.25, 0]], [[-1, 0], [1, 0]]], bar)
    >>> metrics.edge_length_deviation(squash), metrics.edge_length_deviation(squash, reduce=None).tolist()
    (0.75, [0.0, 0.75, 0.0])
    """
    L = np.abs(seq.edge_vectors())
    blend = _blend(L[0], L[-1], seq.times)
    # an edge of zero blended length (an item collapsed at an end frame) deviates by nothing there
    with np.errstate(divide="ignore", invalid="ignore"):
        dev = np.where(blend > 0, np.abs(L / np.where(blend > 0, blend, 1.0) - 1.0), 0.0)
    return _reduce(dev, np.max, reduce)


def loop_areas(seq: Sequence) -> np.ndarray:
    """(F, k) signed areas of the sequence's faces, or of its closed paths.

    Examples
    --------
    >>> import isotween
    >>> from isotween import metrics
    >>> square = isotween.Shape.from_polygon([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> metrics.loop_areas(isotween.Sequence([square.vertices, square.scale(2).vertices], square)).tolist()
    [[1.0], [4.0]]
    """
    shape = seq.shape
    if shape.faces is not None and len(shape.faces):
        return shape.face_areas(seq.frames)
    loops = [p for p, closed in (shape.paths or []) if closed]
    if not loops:
        return np.zeros((len(seq), 0))
    return ring_areas(seq.z, loops)


@overload
def area_deviation(seq: Sequence, reduce: str = "max") -> float: ...
@overload
def area_deviation(seq: Sequence, reduce: None) -> np.ndarray: ...
def area_deviation(seq: Sequence, reduce: str | None = "max") -> float | np.ndarray:
    """Relative deviation of every face's (or closed loop's) signed area from the linear blend of its two end areas.

    Examples
    --------
    >>> import isotween
    >>> from isotween import metrics
    >>> square = isotween.Shape.from_polygon([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> frames = [square.vertices, square.scale([1, 0.5]).vertices, square.vertices]
    >>> metrics.area_deviation(isotween.Sequence(frames, square))
    0.5
    """
    A = loop_areas(seq)
    blend = _blend(A[0], A[-1], seq.times) if A.shape[1] else A
    scale = np.maximum(np.abs(blend), 1e-300)
    return _reduce(np.abs(A - blend) / scale, np.max, reduce)


def flipped(seq: Sequence) -> np.ndarray:
    """(F, faces) bool: the one definition of a flipped face.

    A face is flipped in a frame when its signed area has the other sign than
    in the source: the shape's own vertices, frame 0 unless an end frame was
    changed after solving (`pipeline.collapse_vanishing` collapses a hole
    one drawing lacks to a point, which may turn triangles around it over
    there); a face of zero area in the source or in frame 0 (a piece
    collapsed to a point there) never counts.

    Examples
    --------
    >>> import isotween
    >>> from isotween import metrics
    >>> tri = isotween.Shape.from_mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])
    >>> frames = [tri.vertices, tri.scale([1, -1]).vertices, tri.vertices]
    >>> metrics.flipped(isotween.Sequence(frames, tri)).tolist()
    [[False], [True], [False]]
    """
    A = seq.shape.face_areas(seq.frames)
    if not A.size:
        return np.zeros((len(seq.frames), 0), bool)
    source = seq.shape.face_areas()
    return (np.sign(A) != np.sign(source)) & (source != 0) & (A[:1] != 0)


@overload
def flipped_faces(seq: Sequence, reduce: str = "sum") -> int: ...
@overload
def flipped_faces(seq: Sequence, reduce: None) -> np.ndarray: ...
def flipped_faces(seq: Sequence, reduce: str | None = "sum") -> int | np.ndarray:
    """Faces whose signed area has the other sign than in the source (`flipped`).

    reduce : 'sum' (over the intermediate frames), 'max' (the largest count in
    one frame) or None (per-frame counts, (F,) int).

    Examples
    --------
    >>> import isotween
    >>> from isotween import metrics
    >>> tri = isotween.Shape.from_mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])
    >>> frames = [tri.vertices, tri.scale([1, -1]).vertices, tri.vertices]
    >>> metrics.flipped_faces(isotween.Sequence(frames, tri))
    1
    """
    counts = flipped(seq).sum(axis=1)
    if reduce is None:
        return counts
    inner = counts[1:-1]
    if reduce == "sum":
        return int(inner.sum())
    if reduce == "max":
        return int(inner.max(initial=0))
    raise ParameterError(f"unknown reduce {reduce!r}; choose 'sum', 'max' or None")


def _boundary_edges(shape):
    """(B, 2) edges of the drawn outline: the paths' edges, else the mesh boundary, else all."""
    if shape.paths:
        return np.vstack([np.column_stack([p, np.roll(p, -1)] if closed else [p[:-1], p[1:]])
                          for p, closed in shape.paths if len(p) > 1])
    if shape.faces is not None and len(shape.faces):
        sides = np.sort(shape.faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        key, count = np.unique(sides, axis=0, return_counts=True)
        return key[count == 1]
    return shape.edges


def crossing_pairs(z, edges, group=None):
    """Number of pairs of ``edges`` that cross properly at positions ``z`` (n,) complex (in one ``group``).

    See `crossing_edges`, which names them.
    """
    return len(crossing_edges(z, edges, group)[0])


def crossing_edges(z, edges, group=None, seen=None, touch=False):
    """The pairs of ``edges`` that cross properly at positions ``z``, in one frame or in each of several.

    Candidate pairs come from a sweep over x (intervals sorted by their left
    end; the frames side by side); edges that share a vertex, or have an end
    at the same place, are never counted, and touching or collinear overlaps
    are not crossings. With ``touch``, the pairs that meet at all: those that
    touch, overlap or have an end at the same place count too (not those
    that share a vertex).

    Parameters
    ----------
    z : (n,) or (F, n) complex
        Vertex positions, in one frame or per frame.
    edges : (B, 2) int
    group : (B,) int, optional
        Only pairs within one group count.
    seen : (F, B) bool, optional
        The edges drawn in each frame (default all).
    touch : bool
        Count the pairs that meet, not only those that cross.

    Returns
    -------
    i, j : (C,) int arrays
        Rows of ``edges``: edge ``i[c]`` crosses (meets) edge ``j[c]``.
    frame : (C,) int array
        Only for (F, n) ``z``: the frame of each crossing.
    """
    frames = np.atleast_2d(z)
    F, B = len(frames), len(edges)
    f, e = (np.repeat(np.arange(F), B), np.tile(np.arange(B), F)) if seen is None else np.nonzero(seen)
    a, b = frames[f, edges[e, 0]], frames[f, edges[e, 1]]
    real = a != b  # an edge of length 0 crosses nothing
    f, e, a, b = f[real], e[real], a[real], b[real]
    lo, hi = np.minimum(a.real, b.real), np.maximum(a.real, b.real)
    if F > 1 and len(lo):  # frames side by side: no interval of one frame reaches into the next
        shift = f * (2.0 * (hi.max() - lo.min()) + 1.0)
        lo, hi = lo + shift, hi + shift
    order = np.argsort(lo, kind="stable")
    end = np.searchsorted(lo[order], hi[order], side="right")
    n = len(order)
    counts = np.maximum(end - np.arange(1, n + 1), 0)
    total = int(counts.sum())
    first = np.repeat(np.arange(n), counts)
    second = first + 1 + np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
    i, j = order[first], order[second]
    ylo, yhi = np.minimum(a.imag, b.imag), np.maximum(a.imag, b.imag)
    keep = (ylo[i] <= yhi[j]) & (ylo[j] <= yhi[i])
    if group is not None:
        keep &= group[e[i]] == group[e[j]]
    i, j = i[keep], j[keep]
    # edges that share a vertex, or an end at the same place, only touch
    ei, ej = edges[e[i]], edges[e[j]]
    pi, pj = np.c_[a[i], b[i]], np.c_[a[j], b[j]]
    keep = np.all(ei[:, :, None] != ej[:, None, :], axis=(1, 2))
    if not touch:
        keep &= np.all(pi[:, :, None] != pj[:, None, :], axis=(1, 2))
    i, j = i[keep], j[keep]
    d1, d2 = orient(a[i], b[i], a[j]), orient(a[i], b[i], b[j])
    d3, d4 = orient(a[j], b[j], a[i]), orient(a[j], b[j], b[i])
    cross = (d1 * d2 <= 0) & (d3 * d4 <= 0) if touch else (d1 * d2 < 0) & (d3 * d4 < 0)
    i, j = i[cross], j[cross]
    return (e[i], e[j]) if np.ndim(z) == 1 else (e[i], e[j], f[i])


def outline_crossings(seq, scope="all", visible=False):
    """(F,) int: pairs of outline edges that cross each other, per frame.

    Outline edges are those of the shape's paths (rings and polylines; for a
    mesh without paths, its boundary edges). Edges that share a vertex never
    count; two edges count when they cross properly (not when they only touch).

    scope : {'all', 'region'}
        'all': every pair of outline edges; 'region': only pairs within one
        filled region (its outer ring and holes) or within one path outside
        the regions, i.e. self-intersections of each item, not overlaps of
        separate items.
    visible : bool
        Leave out, in each frame, the paths drawn with opacity 0 there
        (`isotween.paint.out_of_sight`: a piece that has faded out, or not
        yet in); they cannot be seen to cross anything.
    """
    edges, group = outline_edges(seq.shape, scope)
    if not len(edges):
        return np.zeros(len(seq), dtype=np.int64)
    gone = out_of_sight(seq) if visible and seq.shape.paths else None
    seen = None if gone is None or not gone.any() else ~gone[:, edge_paths(seq.shape)]
    _, _, frame = crossing_edges(seq.z, edges, group, seen=seen)
    return np.bincount(frame, minlength=len(seq)).astype(np.int64)


def path_crossings(shape, z, hidden=None, new=False, reach=None):
    """Every crossing of two outline edges in frames ``z``, as the frame and the two edges' paths.

    Parameters
    ----------
    shape : Shape
        With paths.
    z : (F, n) complex
        Vertex positions per frame.
    hidden : (F, P) bool, optional
        Paths left out in each frame (`isotween.paint.out_of_sight`).
    new : bool
        Leave out the crossings between two paths (or within one) that cross
        in the first or last frame, or pass through each other at a vertex
        there (a vertex on the other's edge, its neighbours on either side, as
        the strokes of a plus resampled can; not a T, nor a V's tip on a line):
        those the end drawings have themselves.
    reach : (P,) float, optional
        With ``new``: an open path's end that lies within ``reach`` of another
        path in the first and the last frame meets it there (a T: a lock's
        shackle on its body); where that end lies within ``reach`` of the
        other path's edge it crosses, the crossing is left out too (it lies
        under the stroke, of half width ``reach``: `isotween.paint.half_widths`).

    Returns
    -------
    frame, p, q : (C,) int arrays
        Crossing ``c`` is in frame ``frame[c]``, between an edge of path ``p[c]``
        and one of path ``q[c]`` (``p <= q``; the same path: it crosses itself).
    """
    edges, _ = outline_edges(shape, "all")
    path_of = edge_paths(shape)
    i, j, frame = crossing_edges(z, edges, seen=None if hidden is None else ~hidden[:, path_of])
    p, q = np.minimum(path_of[i], path_of[j]), np.maximum(path_of[i], path_of[j])
    if new:
        end = (frame == 0) | (frame == len(z) - 1)
        pair = p * len(shape.paths) + q
        met = _met(shape, z[[0, -1]], edges, path_of, None if hidden is None else hidden[[0, -1]])
        keep = ~np.isin(pair, np.r_[pair[end], met])
        if reach is not None:
            keep &= ~_at_joints(shape, z, edges, path_of, i, j, frame, np.asarray(reach, dtype=np.float64))
        frame, p, q = frame[keep], p[keep], q[keep]
    return frame, p, q


def _at_joints(shape, z, edges, path_of, i, j, frame, reach):
    """(C,) bool: crossings of edges ``i``, ``j`` in frames ``frame`` at an open path's end that meets the other path.

    The end lies within ``reach`` (of its path) of the other path in the
    first and the last frame, and of the other edge in the crossing's frame.
    """
    out = np.zeros(len(i), dtype=bool)
    owner = np.full(z.shape[1], -1)  # the open path each end vertex ends
    for k, (idx, closed) in enumerate(shape.paths):
        if not closed and len(idx) > 1 and reach[k] > 0:
            owner[[idx[0], idx[-1]]] = k
    tips = np.flatnonzero(owner >= 0)
    if not len(i) or not len(tips):
        return out
    # which paths each end meets in the first and the last frame: (T, P) bool
    ends = z[[0, -1]]
    gap = segment_distance(ends[:, tips, None], ends[:, None, edges[:, 0]], ends[:, None, edges[:, 1]])
    least = np.full((2, len(shape.paths), len(tips)), np.inf)
    for end in (0, 1):
        np.minimum.at(least[end], path_of, gap[end].T)
    meets = (least.max(axis=0) <= reach[owner[tips]]).T
    row = np.full(z.shape[1], -1)
    row[tips] = np.arange(len(tips))
    for x, y in ((i, j), (j, i)):
        for col in (0, 1):
            v, p, q = edges[x, col], path_of[x], path_of[y]
            at = owner[v] == p
            close = segment_distance(z[frame, v], z[frame, edges[y, 0]], z[frame, edges[y, 1]]) <= reach[p]
            out |= at & close & meets[np.maximum(row[v], 0), q]
    return out


def _met(shape, z, edges, path_of, hidden):
    """Pairs ``p * P + q`` of two paths that pass through each other at a point they share in frames ``z`` (F, n).

    A vertex of one path on the other (a plus's upright resampled with a
    vertex on the bar) is a crossing that `crossing_edges` does not see:
    there the two arms of one path lie on either side of the other's (the
    four arms round the point alternate). A path that ends on another (a T)
    or touches it from one side (a V's tip on a line) only meets it.
    """
    i, j, f = crossing_edges(z, edges, seen=None if hidden is None else ~hidden[:, path_of], touch=True)
    n = len(z[0])
    before, after = np.full(n, -1), np.full(n, -1)
    for idx, closed in shape.paths:
        idx = np.asarray(idx)
        before[idx], after[idx] = np.roll(idx, 1), np.roll(idx, -1)
        if not closed and len(idx):
            before[idx[0]], after[idx[-1]] = -1, -1
    scale = max(float(np.ptp(z.real) + np.ptp(z.imag)), 1e-300)
    through = np.zeros(len(i), dtype=bool)
    for x, y in ((i, j), (j, i)):
        a, b = z[f, edges[y, 0]], z[f, edges[y, 1]]
        for end in (0, 1):
            v = edges[x, end]
            pt = z[f, v]
            t = np.clip(((pt - a) * np.conj(b - a)).real / np.maximum(np.abs(b - a) ** 2, 1e-300), 0.0, 1.0)
            on = np.abs(a + t * (b - a) - pt) <= 1e-9 * scale
            # the other path's arms there: its edge's two ends, or at its vertex, that vertex's neighbours
            w = np.where(t <= 0.5, edges[y, 0], edges[y, 1])
            at = np.minimum(t, 1 - t) <= 1e-9
            q1 = np.where(at, before[w], edges[y, 0])
            q2 = np.where(at, after[w], edges[y, 1])
            ok = on & (before[v] >= 0) & (after[v] >= 0) & (q1 >= 0) & (q2 >= 0)
            arms = [z[f, np.maximum(k, 0)] - pt for k in (q1, q2, before[v], after[v])]
            turn = [np.angle(u / np.where(arms[0] != 0, arms[0], 1)) % (2 * np.pi) for u in arms[1:]]
            # the arms of v's path on either side of the other's two arms: exactly one within the angle q1 -> q2
            through |= ok & ((turn[1] < turn[0]) != (turn[2] < turn[0])) & (turn[1] > 0) & (turn[2] > 0)
    p, q = np.minimum(path_of[i], path_of[j]), np.maximum(path_of[i], path_of[j])
    return (p * len(shape.paths) + q)[(p != q) & through]


def new_crossings(seq, visible=True):
    """(F,) int: crossings per frame between two paths (or within one) that do not cross in the first or last frame.

    What `outline_crossings` counts, less the crossings the end drawings have
    themselves (two strokes of an 'x' cross in every frame of its morph, as
    do two that pass through each other at a vertex at an end), and those
    under a stroke's end where it meets another path at an end (a T:
    `path_crossings` with ``reach``, half the stroke's width).
    A shape without paths: `outline_crossings`.
    """
    if not seq.shape.paths:
        return outline_crossings(seq, visible=visible)
    frame, _, _ = path_crossings(seq.shape, seq.z, out_of_sight(seq) if visible else None, new=True,
                                 reach=half_widths(seq))
    return np.bincount(frame, minlength=len(seq)).astype(np.int64)


def outline_edges(shape, scope="all"):
    """The outline edges (B, 2) of `outline_crossings` and their groups ((B,) int, or None for 'all')."""
    if scope not in ("all", "region"):
        raise ParameterError(f"unknown scope {scope!r}; choose 'all' or 'region'")
    edges = _boundary_edges(shape)
    group = None
    if scope == "region" and shape.paths and len(edges):
        owner = np.arange(len(shape.paths))
        for r, ring_ids in enumerate(shape.regions or []):
            owner[ring_ids] = len(shape.paths) + r
        group = owner[edge_paths(shape)]
    return edges, group


def edge_paths(shape):
    """(B,) int: the path of every outline edge of a shape with paths, in the order of `outline_edges`."""
    drawn = [k for k, (p, _) in enumerate(shape.paths) if len(p) > 1]
    return np.repeat(np.array(drawn, dtype=np.int64),
                     [len(shape.paths[k][0]) - (0 if shape.paths[k][1] else 1) for k in drawn])


def symmetry_error(seq: Sequence, backward: Sequence | None = None) -> float:
    """Max distance between frame k of A->B and frame m-k of B->A over the bounding-box diagonal.

    ``backward`` is recomputed with the same options when not given.

    Examples
    --------
    >>> import isotween
    >>> from isotween import metrics
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    >>> bool(metrics.symmetry_error(isotween.interpolate(bar, bar.rotate(2.0), frames=5)) < 1e-6)
    True
    """
    if backward is None:
        from .interpolate import interpolate

        options = dict(seq.info.get("options", {}))
        options.pop("frames", None)
        times = options.pop("times", None)
        if times is not None:
            options["times"] = 1.0 - np.asarray(times)[::-1]
        backward = interpolate(seq[-1], seq[0], frames=len(seq), **options)
    if len(backward) != len(seq):
        raise ParameterError(f"sequences differ in length: {len(seq)} and {len(backward)}")
    diag = bbox_diagonal(seq.frames[0], seq.frames[-1])
    return float(np.max(np.linalg.norm(seq.frames - backward.frames[::-1], axis=-1)) / diag)


def report(seq: Sequence, symmetry: bool = False) -> dict:
    """Every metric of ``seq`` as a dict of floats (symmetry error on request: it costs a second interpolation).

    Examples
    --------
    >>> import isotween
    >>> from isotween import metrics
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    >>> r = metrics.report(isotween.interpolate(bar, bar.rotate(2.0), frames=5))
    >>> r["flipped_faces"], r["edge_length_deviation"] < 1e-9
    (0, True)
    """
    if len(getattr(seq, "frames", ())) < 1:
        raise ParameterError("metrics.report needs a sequence of at least one frame, got an empty one")
    out = {
        "isometric_energy": isometric_energy(seq),
        "edge_length_deviation": edge_length_deviation(seq, "max"),
        "edge_length_deviation_mean": edge_length_deviation(seq, "mean"),
        "area_deviation": area_deviation(seq, "max"),
        "area_deviation_mean": area_deviation(seq, "mean"),
        "flipped_faces": flipped_faces(seq, "sum"),
        "flipped_faces_max_frame": flipped_faces(seq, "max"),
        "iterations": seq.iterations,
        "converged": bool(seq.converged),
        "seconds": float(seq.timings.get("total", float("nan"))),
    }
    if symmetry:
        out["symmetry_error"] = symmetry_error(seq)
    return out
