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
from scipy.sparse.linalg import splu

__all__ = ["incidence", "averaging", "centroid_path", "FrameAssembler"]


def incidence(edges, n):
    """(E, n) sparse D with (D z)_e = z_j - z_i for edge e = (i, j)."""
    E = len(edges)
    rows = np.repeat(np.arange(E), 2)
    vals = np.tile([-1.0, 1.0], E)
    return sp.csr_matrix((vals, (rows, edges.ravel())), shape=(E, n))


def averaging(components, n_components):
    """(C, n) sparse matrix: (A z)_c is the centroid of component c."""
    counts = np.bincount(components, minlength=n_components)
    n = len(components)
    return sp.csr_matrix((1.0 / counts[components], (components, np.arange(n))),
                         shape=(n_components, n))


def centroid_path(shape, z0, z1, t):
    """(C, len(t)) complex: every component's centroid blended linearly in t."""
    avg = averaging(shape.components, shape.n_components)
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

    def __init__(self, shape, weights=None):
        n = shape.n_vertices
        self.components, self.n_components = shape.components, shape.n_components
        self.anchors = np.unique(self.components, return_index=True)[1]  # (C,)
        self.free = np.setdiff1d(np.arange(n), self.anchors)
        self.n = n
        self.D_free = incidence(shape.edges, n)[:, self.free].tocsc()
        self.weights = np.ones(shape.n_edges) if weights is None else np.asarray(weights, float)
        self._lu = None
        if self.free.size:
            L = (self.D_free.T @ sp.diags(self.weights) @ self.D_free).tocsc()
            self._lu = splu(L, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        self._DtW = (self.D_free.T @ sp.diags(self.weights)).tocsr()
        self._avg = averaging(self.components, self.n_components)

    def solve_laplacian(self, b):
        """Apply L^{-1} to (n_free, k) complex right-hand sides."""
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
        z[self.free] = self.solve_laplacian(self._DtW @ e)
        return self.place(z, centroids)

    def gauge(self, z):
        """(n_free, F) complex: free vertices of (n, F) frames, anchors moved to 0."""
        return (z - z[self.anchors[self.components]])[self.free]

    def place(self, z, centroids):
        """Translate each component of (n, F) frames onto the (C, F) centroids."""
        return z + (centroids - self._avg @ z)[self.components]
