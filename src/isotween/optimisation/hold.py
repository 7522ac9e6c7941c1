"""Paths that stay put between the two drawings, and holes that close inside them, held on their straight way.

AIAP places the vertices of every frame from its edge vectors by the least
squares of Eq. (10), ``L z = D^T W e`` with ``L = D^T W D`` (the local
solver's frozen weights ``w_ij = 2 / (|e_ij(0)| + |e_ij(1)|)``). Where a
path of the drawing stays put between the ends (within `HOLD` of the
diagonal: an outline icon and its filled variant share the outline, two
emoji their face), or, in a piece where one does, is at one end a copy of
itself at the other, moved and scaled but not turned nor bent (a hole that
closes, shrinking into a small copy of itself), the same least
squares with its vertices held on the straight way between their ends, on
which the path stays such a copy, changes the other vertices of their
components by the discrete harmonic extension of the change at the held
ones, ``L_ff dz_f = -L_fh dz_h``. Without it the free outline bulges while
the hole inside it closes (the in-betweens spread the hole's growth over the
whole region), and the closing hole's small round corners stay round while
the rest of it shrinks, standing out as ears.
"""

import numpy as np

__all__ = ["HOLD", "still_vertices", "Hold"]

#: a path stays put where it moves less than this share of the diagonal (a copy: is that near a moved, scaled copy)
HOLD = 0.01


def still_vertices(shape, z0, z1, diagonal, tol=HOLD):
    """Vertices of the paths that stay put, and of those that are moved and scaled copies where something stays.

    A path stays put where every vertex moves less than ``tol * diagonal``
    between the ends; a path whose target is within that of the best copy
    ``c1 + s (z0 - c0)`` of its source (centroids ``c``, a scale ``s >= 0``
    by least squares: moved and scaled, not turned nor bent) is held too
    where a path of the same piece (component) stays put: a hole closing
    inside an outline that stays. (Alone, a large hole held shrinking while
    the region round it changes makes the region fold more.)

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
    still, copies = [], []
    for idx, _ in shape.paths or ():
        if len(idx) < 2:
            continue
        if np.abs(z1[idx] - z0[idx]).max() < tol * diagonal:
            still.append(idx)
            continue
        a, b = z0[idx] - z0[idx].mean(), z1[idx] - z1[idx].mean()
        s = max(float(np.vdot(a, b).real / max(np.vdot(a, a).real, 1e-300)), 0.0)
        if np.abs(b - s * a).max() < tol * diagonal:
            copies.append(idx)
    if not still:
        return np.zeros(0, dtype=np.int64)
    pieces = shape.topology.components
    kept = set(np.unique(pieces[np.concatenate(still)]).tolist())
    return np.unique(np.concatenate(still + [idx for idx in copies if pieces[idx[0]] in kept]))


class Hold:
    """Frames with the vertices ``held`` on their straight way and the rest of their components following.

    The Laplacian of the held vertices' components is factorised once; every
    call applies it to other frames of the same two ends (AIAP's iterations).

    Parameters
    ----------
    shape : Shape
        Connectivity (its edge incidence ``topology.D``).
    z0, z1 : (n,) complex
        The two ends (they weight the edges as the local solver does).
    held : (h,) int
        Vertices to hold (`still_vertices`): on their straight way, a path
        whose ends are copies of each other stays such a copy.
    """

    def __init__(self, shape, z0, z1, held):
        from scipy.sparse.linalg import splu

        top = shape.topology
        self.held = held
        mask = np.zeros(top.n, dtype=bool)
        mask[held] = True
        self.free = free = np.flatnonzero(np.isin(top.components, top.components[held]) & ~mask)
        if free.size:
            w = 2.0 / np.maximum(np.abs(top.D @ z0) + np.abs(top.D @ z1), 1e-300)  # the frozen weights of Alg. 2
            L = (top.D.T @ top.D.multiply(w[:, None])).tocsr()  # Eq. (10)'s Laplacian
            self._coupling = L[free][:, held]
            self._lu = splu(L[free][:, free].tocsc())  # a held vertex in every component: positive definite

    def __call__(self, z, times):
        """The frames ``z`` (n, F) complex at ``times`` (F,) held; the first and last are kept.

        Returns
        -------
        (n, F) complex
            The frames; components without a held vertex are unchanged.
        """
        held, free = self.held, self.free
        s = (np.asarray(times, float) - times[0]) / (times[-1] - times[0])
        line = z[held, :1] * (1 - s) + z[held, -1:] * s  # (h, F)
        out = z.copy()
        out[held] = line
        if free.size:
            rhs = -(self._coupling @ (line - z[held]))  # (f, F)
            dz = self._lu.solve(np.ascontiguousarray(np.c_[rhs.real, rhs.imag]))
            out[free] += dz[:, :z.shape[1]] + 1j * dz[:, z.shape[1]:]
        return out
