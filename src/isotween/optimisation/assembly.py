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

__all__ = ["incidence", "component_centroids", "centroid_path", "FrameAssembler"]


def incidence(edges, n):
    """(E, n) sparse D with (D z)_e = z_j - z_i for edge e = (i, j)."""
    E = len(edges)
    rows = np.repeat(np.arange(E), 2)
    vals = np.tile([-1.0, 1.0], E)
    return sp.csr_matrix((vals, (rows, edges.ravel())), shape=(E, n))


def component_centroids(z, components, n_components):
    """(..., C) complex centroid of every component of (..., n) complex frames."""
    counts = np.bincount(components, minlength=n_components)
    avg = sp.csr_matrix(
        (1.0 / counts[components], (components, np.arange(len(components)))),
        shape=(n_components, len(components)),
    )
    return (avg @ z.reshape(-1, z.shape[-1]).T).T.reshape(z.shape[:-1] + (n_components,))


def centroid_path(shape, z0, z1, t):
    """(len(t), C) complex: every component's centroid blended linearly in t."""
    c0 = component_centroids(z0, shape.components, shape.n_components)
    c1 = component_centroids(z1, shape.components, shape.n_components)
    t = np.asarray(t)[:, None]
    return (1 - t) * c0 + t * c1


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
        centroids : (F, C) complex
            Where each component's centroid must be in every frame.

        Returns
        -------
        (F, n) complex vertex positions.
        """
        F = e.shape[1]
        z = np.zeros((F, self.n), dtype=complex)
        z[:, self.free] = self.solve_laplacian(self._DtW @ e).T
        return self.place(z, centroids)

    def gauge(self, z):
        """(F, n_free) complex: free vertices of (F, n) frames, anchors moved to 0."""
        return (z - z[:, self.anchors[self.components]])[:, self.free]

    def place(self, z, centroids):
        """Translate each component of (F, n) frames onto the given centroids."""
        shift = centroids - component_centroids(z, self.components, self.n_components)
        return z + shift[:, self.components]
