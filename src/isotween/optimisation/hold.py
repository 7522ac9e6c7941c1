"""Paths that stay put between the two drawings, held on their straight way in the in-betweens.

AIAP places the vertices of every frame from its edge vectors by the least
squares of Eq. (10), ``L z = D^T W e`` with ``L = D^T W D`` (the local
solver's frozen weights ``w_ij = 2 / (|e_ij(0)| + |e_ij(1)|)``). Where a path of the
drawing hardly moves from one end to the other (every vertex by less than
`HOLD` of the diagonal: an outline icon and its filled variant share the
outline, two emoji their face), the same least squares with those vertices
held on the straight way between their ends changes the other vertices of
their components by the discrete harmonic extension of the change at the held
ones, ``L_ff dz_f = -L_fh dz_h``. Without it the free outline bulges while
the hole inside it closes, as the in-betweens spread the hole's growth over
the whole region.
"""

import numpy as np

__all__ = ["HOLD", "still_vertices", "hold"]

#: a path whose vertices all move less than this share of the diagonal between the ends is held
HOLD = 0.01


def still_vertices(shape, z0, z1, diagonal, tol=HOLD):
    """Vertices of the paths that move less than ``tol * diagonal`` between the ends.

    Parameters
    ----------
    shape : Shape
        Its ``paths`` are the candidates (each whole or not at all).
    z0, z1 : (n,) complex
        The two ends.
    diagonal : float
    tol : float

    Returns
    -------
    (h,) int
        Sorted vertex indices (empty where no path stays put).
    """
    move = np.abs(z1 - z0)
    still = [idx for idx, _ in shape.paths or () if len(idx) and move[idx].max() < tol * diagonal]
    return np.unique(np.concatenate(still)) if still else np.zeros(0, dtype=np.int64)


def hold(shape, z, times, held):
    """Frames ``z`` with the vertices ``held`` on their straight way and the rest of their components following.

    Parameters
    ----------
    shape : Shape
        Connectivity (its edge incidence ``topology.D``).
    z : (n, F) complex
        Vertex positions of every frame; the first and last are kept (and
        weight the edges as the local solver does).
    times : (F,) float
        Frame times (the straight way is linear in time).
    held : (h,) int
        Vertices to hold (`still_vertices`).

    Returns
    -------
    (n, F) complex
        The frames; components without a held vertex are unchanged.
    """
    from scipy.sparse.linalg import splu

    top = shape.topology
    s = (np.asarray(times, float) - times[0]) / (times[-1] - times[0])
    line = z[held, :1] * (1 - s) + z[held, -1:] * s  # (h, F)
    mask = np.zeros(top.n, dtype=bool)
    mask[held] = True
    free = np.flatnonzero(np.isin(top.components, top.components[held]) & ~mask)
    out = z.copy()
    out[held] = line
    if free.size:
        e = top.D @ z[:, [0, -1]]
        w = 2.0 / np.maximum(np.abs(e).sum(axis=1), 1e-300)  # the frozen weights of Algorithm 2
        L = (top.D.T @ top.D.multiply(w[:, None])).tocsr()  # Eq. (10)'s Laplacian
        rhs = -(L[free][:, held] @ (line - z[held]))  # (f, F)
        lu = splu(L[free][:, free].tocsc())  # a held vertex in every component: positive definite
        dz = lu.solve(np.ascontiguousarray(np.c_[rhs.real, rhs.imag]))
        out[free] += dz[:, :z.shape[1]] + 1j * dz[:, z.shape[1]:]
    return out
