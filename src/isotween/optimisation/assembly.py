"""Eq. (10): vertex positions of a frame from (possibly incompatible) edge vectors.

    min_z  sum_(i,j) w_ij |z_j - z_i - e_ij|^2

is a weighted Laplace equation. Its solution is unique up to one translation per
connected component: we pin one anchor vertex per component during the solve,
then move each component so that its centroid follows the linear blend of the
two inputs' centroids (SPEC.md, defect 5). The Laplacian is factorised once and
reused for every frame and every iteration (all frames are right-hand sides of
one solve).
"""

import numpy as np
import scipy.sparse as sp
from scipy.linalg import cho_factor, cho_solve
from scipy.sparse.linalg import splu

__all__ = ["centroid_path", "FrameAssembler"]


def centroid_path(shape, z0, z1, t):
    """(C, len(t)) complex: every component's centroid blended linearly in t."""
    avg = shape.topology.avg
    t = np.asarray(t)[None, :]
    return (1 - t) * (avg @ z0)[:, None] + t * (avg @ z1)[:, None]


class FrameAssembler:
    """Reusable factorisation of the Eq. (10) Laplacian.

    Parameters
    ----------
    shape : Shape
        Connectivity (edges, components).
    weights : (E,) float array, optional
        w_ij; default 1 (the combinatorial Laplacian).

    Attributes
    ----------
    anchors : (C,) int array
        The pinned vertex of every component (its lowest index).
    free : (n_free,) int array
        Vertices solved for (all but the anchors).
    D_free : (E, n_free) sparse
        Incidence restricted to the free vertices.
    """

    #: below this many free vertices the Laplacian is factorised densely
    DENSE = 160

    def __init__(self, shape, weights=None):
        top = shape.topology
        self.n, self.components, self.n_components = top.n, top.components, top.n_components
        self.anchors, self.free, self.D_free, self._avg = top.anchors, top.free, top.D_free, top.avg
        self.weights = np.ones(top.n_edges) if weights is None else np.asarray(weights, float)
        self._Dt = top.D_free_T
        self._lu = self._cho = None
        nf = self.free.size
        if nf == 0:
            return
        edge, sign, slot, indices, indptr, linear = top.laplacian_pattern
        data = np.bincount(slot, sign * self.weights[edge], minlength=len(indices))
        if nf <= self.DENSE:
            L = np.zeros(nf * nf)
            L[linear] = data
            self._cho = cho_factor(L.reshape(nf, nf), check_finite=False)
        else:
            L = sp.csc_matrix((data, indices, indptr), shape=(nf, nf))
            self._lu = splu(L, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})

    def solve_laplacian(self, b):
        """Apply L^{-1} to (n_free, k) complex right-hand sides."""
        if self._cho is not None:
            return cho_solve(self._cho, b, check_finite=False)
        if self._lu is None:
            return np.zeros_like(b)
        k = b.shape[1]
        x = self._lu.solve(np.ascontiguousarray(np.hstack([b.real, b.imag])))
        return x[:, :k] + 1j * x[:, k:]

    def positions(self, e, centroids):
        """Eq. (10) for several frames.

        Parameters
        ----------
        e : (E, F) complex
            Edge vectors of F frames.
        centroids : (C, F) complex
            Where each component's centroid must be in every frame.

        Returns
        -------
        (n, F) complex vertex positions.
        """
        z = np.zeros((self.n, e.shape[1]), dtype=complex)
        z[self.free] = self.solve_laplacian(self._Dt @ (self.weights[:, None] * e))
        return self.place(z, centroids)

    def gauge(self, z):
        """(n_free, F) complex: free vertices of (n, F) frames, anchors moved to 0."""
        return (z - z[self.anchors[self.components]])[self.free]

    def place(self, z, centroids):
        """Translate each component of (n, F) frames onto the (C, F) centroids."""
        return z + (centroids - self._avg @ z)[self.components]
