"""Intrinsic interpolation of polygons and polylines (Sederberg et al. 1993).

Every ring or chain of ``shape.paths`` is described by its edge lengths, the
turning angle at every interior vertex and the direction of its first edge.
Lengths and turning angles are blended linearly (the first edge's direction
along the shorter way round); edge vectors follow by accumulating the turning
angles. A closed ring then generally fails to close: the edge lengths are
changed as little as possible (least squares, each length weighted by how much
it changes between the inputs, Sederberg's tolerance rule) so that the edge
vectors sum to zero. Turning angles are never changed. Each path's vertex
centroid moves linearly.
"""

import numpy as np

from ..errors import MethodError
from ..optimisation.problem import Result

__all__ = ["solve", "path_edges", "close_ring"]


def _check_paths(shape):
    paths = shape.paths or []
    if not paths:
        raise MethodError(
            "method 'intrinsic' needs polygons or polylines (shape.paths, as made by "
            "Shape.from_polygon / from_polyline or read from .svg / .json with paths); "
            f"this shape is an edge soup or mesh with {shape.n_edges} edges and no paths"
        )
    covered = np.bincount(np.concatenate([p for p, _ in paths]), minlength=shape.n_vertices)
    if np.any(covered != 1):
        v = int(np.flatnonzero(covered != 1)[0])
        raise MethodError(
            f"method 'intrinsic' needs paths that visit every vertex exactly once; "
            f"vertex {v} is on {covered[v]} path(s)"
        )
    return paths


def path_edges(z, idx, closed):
    """(F, k) complex edge vectors of one path in every frame.

    Parameters
    ----------
    z : (F, n) complex
    idx : (k,) int
        Path vertices in order.
    closed : bool
        Ring (the closing edge is last) or chain.
    """
    p = z[:, idx]
    return (np.roll(p, -1, axis=1) - p) if closed else np.diff(p, axis=1)


def close_ring(lengths, directions, weights):
    """Least change of the edge lengths that closes a ring (Sederberg et al.).

    min sum_i (dL_i)^2 / w_i subject to sum_i (L_i + dL_i) u_i = 0.

    Parameters
    ----------
    lengths : (F, k) float
    directions : (F, k) complex
        Unit edge directions u_i.
    weights : (k,) float
        w_i > 0; a length with a small weight barely changes.

    Returns
    -------
    (F, k) float corrected lengths.
    """
    gap = np.sum(lengths * directions, axis=1)  # (F,) closure error
    U = np.stack([directions.real, directions.imag], axis=1)  # (F, 2, k)
    M = np.einsum("fak,k,fbk->fab", U, weights, U)
    lam = np.linalg.solve(M, -np.stack([gap.real, gap.imag], axis=1)[..., None])[..., 0]
    return lengths + weights * np.einsum("fak,fa->fk", U, lam)


def solve(problem):
    """Frames of the intrinsic interpolation between the problem's first and last frame.

    Parameters
    ----------
    problem : Problem
        Of a shape with paths, held at the first and the last frame.

    Returns
    -------
    Result
        ``z`` (n, F) complex; ``info['closure_correction']``: largest
        relative length change made to close a ring.
    """
    source = problem.shape
    paths = _check_paths(source)
    t = np.asarray(problem.times, dtype=float)[:, None]
    ends = np.stack(problem.ends())
    out = np.empty((len(t), source.n_vertices), dtype=complex)
    worst = 0.0
    for idx, closed in paths:  # loop over rings, vectorised over their vertices and frames
        e0, e1 = path_edges(ends, idx, closed)  # no zero lengths (check_compatible)
        L = (1 - t) * np.abs(e0) + t * np.abs(e1)  # (F, k)
        turn0, turn1 = np.angle(e0[1:] / e0[:-1]), np.angle(e1[1:] / e1[:-1])  # in (-pi, pi]
        first = np.angle(e0[0]) + t * np.angle(e1[0] / e0[0])  # (F, 1), shorter way round
        phi = np.concatenate([first, first + np.cumsum((1 - t) * turn0 + t * turn1, axis=1)], axis=1)
        u = np.exp(1j * phi)
        if closed:
            change = np.abs(np.abs(e1) - np.abs(e0))
            weights = np.maximum(change, 1e-4 * max(change.max(), np.abs(e0).mean())) ** 2
            corrected = close_ring(L, u, weights)
            worst = max(worst, float(np.max(np.abs(corrected / L - 1))))
            L = corrected
        d = L * u
        p = np.concatenate([np.zeros((len(t), 1)), np.cumsum(d[:, : len(idx) - 1], axis=1)], axis=1)
        centre = (1 - t) * ends[0, idx].mean() + t * ends[1, idx].mean()
        out[:, idx] = p - p.mean(axis=1, keepdims=True) + centre
    return Result(out.T, info={"closure_correction": worst})
