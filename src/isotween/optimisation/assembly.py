"""Eq. (10): vertex positions of a frame from (possibly incompatible) edge vectors.

    min_z  sum_(i,j) w_ij |z_j - z_i - e_ij|^2

is a weighted Laplace equation. Its solution is unique up to one translation per
connected component: we pin one anchor vertex per component during the solve,
then move each component so that its centroid follows the linear blend of the
two inputs' centroids (docs/how-it-works.md). The Laplacian is factorised once and
reused for every frame and every iteration (all frames are right-hand sides of
one solve).

Three factorisations, chosen by size (benchmarks/RESULTS.md, Performance):

- 'banded': numba's banded Cholesky in reverse Cuthill-McKee order; costs
  n b^2, so it is used up to bandwidth b = 128 (on the 100k-vertex bar,
  b = 100, 101 frames: 3.40 s against CHOLMOD's 5.39 s at load ~1.3);
- 'cholmod': CHOLMOD's supernodal Cholesky with a fill-reducing ordering
  (scikit-sparse, ``pip install isotween[large]``); the symbolic analysis is
  kept per connectivity, so a new set of weights costs only the numeric
  factorisation;
- 'splu': scipy's SuperLU (always available).
"""

import importlib.util
import weakref

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..errors import MissingDependencyError, ParameterError, require
from . import backend

__all__ = ["centroid_path", "FrameAssembler", "FACTORISATIONS", "HAVE_CHOLMOD"]

FACTORISATIONS = ("auto", "banded", "cholmod", "splu")

#: scikit-sparse is installed (imported on the first CHOLMOD factorisation)
HAVE_CHOLMOD = importlib.util.find_spec("sksparse") is not None

#: Topology -> CHOLMOD symbolic factor (ordering and supernodes) of its free-vertex Laplacian
_ANALYSIS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def centroid_path(shape, z0, z1, t):
    """(C, len(t)) complex: every component's centroid blended linearly in t."""
    top = shape.topology
    c0, c1 = top.centroids(z0)[:, None], top.centroids(z1)[:, None]
    return c0 + np.asarray(t)[None, :] * (c1 - c0)


class FrameAssembler:
    """Reusable factorisation of the Eq. (10) Laplacian.

    Parameters
    ----------
    shape : Shape
        Connectivity (edges, components).
    weights : (E,) float array, optional
        w_ij; default 1 (the combinatorial Laplacian).
    factorisation : {'auto', 'banded', 'cholmod', 'splu'}
        'auto': banded up to bandwidth `BANDED` (with numba), else CHOLMOD
        from `CHOLMOD_SIZE` free vertices on (with scikit-sparse), else splu.

    Attributes
    ----------
    anchors : (C,) int array
        The pinned vertex of every component (its lowest index).
    free : (n_free,) int array
        Vertices solved for (all but the anchors).
    D_free : (E, n_free) sparse
        Incidence restricted to the free vertices.
    method : str
        The factorisation in use: 'banded', 'cholmod' or 'splu'.
    """

    #: with numba, a banded factorisation (reverse Cuthill-McKee order) up to this bandwidth
    BANDED = 128
    #: with scikit-sparse and a larger bandwidth (or no numba), CHOLMOD from this many free vertices
    CHOLMOD_SIZE = 20_000

    def __init__(self, shape, weights=None, factorisation="auto"):
        if factorisation not in FACTORISATIONS:
            raise ParameterError(f"unknown factorisation {factorisation!r}; choose one of "
                                 f"{', '.join(FACTORISATIONS)}")
        top = self._top = shape.topology
        self.n, self.components, self.n_components = top.n, top.components, top.n_components
        self.anchors, self.free, self.D_free = top.anchors, top.free, top.D_free
        self.weights = np.ones(top.n_edges) if weights is None else np.asarray(weights, float)
        self._factor = self._band = None
        nf = self.free.size
        method, self._forced = factorisation, factorisation != "auto"
        self._backend = backend.current()
        if method == "auto":
            if nf and self._backend.banded and top.band_pattern[1] <= self.BANDED:
                method = "banded"
            else:
                method = "cholmod" if HAVE_CHOLMOD and nf >= self.CHOLMOD_SIZE else "splu"
        if method == "banded":
            if not self._backend.banded:
                raise ParameterError("the banded factorisation needs the numba backend: pip install 'isotween[fast]'")
            if nf:
                rows, bw, edge, sign, position, Dt = top.band_pattern
                band = np.bincount(position, sign * self.weights[edge], minlength=(bw + 1) * nf)
                band = band.reshape(nf, bw + 1)
                if self._backend.band_cholesky(band):
                    self._band = (band, Dt.indptr, Dt.indices, Dt.data * self.weights[Dt.indices], rows,
                                  top.anchors, top.components, top.inv_count)
                    self.method = method
                    return
            method = "splu"  # not positive definite (zero weights): LU still solves it
        self.method = method
        self._factorise()

    def _factorise(self):
        """Factorise the free-vertex Laplacian with CHOLMOD or scipy's sparse LU."""
        top, nf = self._top, self.free.size
        Dt = top.D_free_T
        self._DtW = sp.csr_matrix((Dt.data * self.weights[Dt.indices], Dt.indices, Dt.indptr),
                                  shape=Dt.shape)
        if nf == 0:
            self._factor = np.zeros_like
            return
        edge, sign, slot, indices, indptr = top.laplacian_pattern
        data = np.bincount(slot, sign * self.weights[edge], minlength=len(indices))
        L = sp.csc_matrix((data, indices, indptr), shape=(nf, nf))
        if self.method == "cholmod":
            try:
                self._factor = _cholmod(top, L)
            except MissingDependencyError:
                if self._forced:
                    raise
            if self._factor is not None:
                return
            self.method = "splu"  # scikit-sparse unusable, or L not positive definite: LU solves it
        self._factor = splu(L, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True}).solve

    def solve_laplacian(self, b):
        """Apply L^{-1} to (n_free, k) complex right-hand sides."""
        if self._factor is None:
            self._factorise()
        # L is real: solve for the interleaved real and imaginary parts at once
        x = self._factor(np.ascontiguousarray(b, dtype=complex).view(np.float64))
        return np.ascontiguousarray(x).view(complex)

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
        if self._band is not None:
            z = np.zeros((self.n, e.shape[1]), dtype=complex)
            self._backend.banded_positions(z, e, centroids, *self._band)
            return z
        if self._factor is None:
            self._factorise()
        F = e.shape[1]
        if self.method == "cholmod":  # no two (n, F) arrays beyond the solve's at any time
            free = self._cholmod_positions(e)
            z = np.zeros((self.n, F), dtype=complex)
            z[self.free] = free
            del free
            return self.place(z, centroids)
        z = np.zeros((self.n, F), dtype=complex)
        rhs = self._DtW @ e
        step = max(1, (4 << 20) // (16 * max(self.free.size, 1)))  # blocks of <= 4 MiB
        for c in range(0, F, step):
            z[self.free, c : c + step] = self.solve_laplacian(rhs[:, c : c + step])
        return self.place(z, centroids)

    def _cholmod_positions(self, e):
        """(n_free, F) complex: L^{-1} D^T W e for all frames in one CHOLMOD solve.

        The right-hand sides are built a few frames at a time straight into one
        Fortran-ordered real array (real parts of every frame, then imaginary
        parts), the layout CHOLMOD solves without copying; ``e`` may be a
        column slice (no (E, F) copy of it is made).
        """
        nf, F = self.free.size, e.shape[1]
        rhs = np.empty((nf, 2 * F), order="F")
        step = max(1, (64 << 20) // (16 * e.shape[0]))  # (E, step) copies of <= 64 MiB
        for c in range(0, F, step):
            d = min(F, c + step)
            block = self._DtW @ np.ascontiguousarray(e[:, c:d])
            rhs[:, c:d], rhs[:, F + c : F + d] = block.real, block.imag
        x = self._factor(rhs)
        del rhs
        out = np.empty((nf, F), dtype=complex)
        out.real, out.imag = x[:, :F], x[:, F:]
        return out

    def update(self, z, frames, e, centroids):
        """Eq. (10) into ``z[:, frames]``; returns the largest vertex move (Eq. 11).

        Parameters
        ----------
        z : (n, F) complex, C-ordered
        frames : slice or (k,) int array
            Columns of ``z`` to replace.
        e : (E, k) complex
            Edge vectors of those frames.
        centroids : (C, k) complex
        """
        if self._band is not None and isinstance(frames, slice):  # z[:, frames] is a view
            return self._backend.banded_positions(z[:, frames], e, centroids, *self._band)
        new = self.positions(e, centroids)
        old = z[:, frames]
        old -= new
        move = float(np.sqrt(np.max(old.real**2 + old.imag**2, initial=0.0)))
        z[:, frames] = new
        return move

    def gauge(self, z):
        """(n_free, F) complex: free vertices of (n, F) frames, anchors moved to 0."""
        return (z - z[self.anchors[self.components]])[self.free]

    def place(self, z, centroids):
        """Translate each component of (n, F) frames onto the (C, F) centroids (in place)."""
        shift = centroids - self._top.centroids(z)
        z += shift if self.n_components == 1 else shift[self.components]
        return z


def _cholmod(top, L):
    """Solve function of a CHOLMOD factor of the symmetric matrix ``L`` (None unless it is positive definite).

    The symbolic analysis (fill-reducing ordering, supernodes) is computed once per ``top``.
    """
    cholmod = require("sksparse.cholmod", "large")
    symbolic = _ANALYSIS.get(top)
    if symbolic is None:
        # AMD, not METIS: on the 1M-vertex bar (one run, load ~2) analysis 0.8 s vs 11.6 s,
        # factor plus two 102-column solves 28.5 s vs 29.6 s
        symbolic = _ANALYSIS[top] = cholmod.analyze(L, mode="supernodal", ordering_method="amd")
    try:
        factor = symbolic.cholesky(L)
    except cholmod.CholmodNotPositiveDefiniteError:
        return None
    return factor
