"""Eq. (10): vertex positions of a frame from (possibly incompatible) edge vectors.

    min_z  sum_(i,j) w_ij |z_j - z_i - e_ij|^2

is a weighted Laplace equation. Its solution is unique up to one translation per
connected component: we pin one anchor vertex per component during the solve,
then move each component so that its centroid follows the linear blend of the
two inputs' centroids (docs/how-it-works.md). The Laplacian is factorised once and
reused for every frame and every iteration (all frames are right-hand sides of
one solve).

Three factorisations, chosen by size (benchmarks/RESULTS.md, Performance):

- 'banded': a banded Cholesky factor in reverse Cuthill-McKee order (LAPACK),
  solved by numba kernels on blocks of bandwidth rows with BLAS; costs n b^2
  to factorise and n b per frame to solve, so it is used up to bandwidth
  b = 192 (101 frames: on the 100k-vertex bar, b = 100, 2.1-2.8 s against
  CHOLMOD's 5.1 s; at b = 180, 51 frames, 3.4-4.3 s against 4.4-4.5 s; at
  b = 250 CHOLMOD wins, 5.8 s against 6.4 s);
- 'cholmod': CHOLMOD's supernodal Cholesky with a fill-reducing ordering
  (scikit-sparse, ``pip install isotween[large]``); the symbolic analysis is
  kept per connectivity, so a new set of weights costs only the numeric
  factorisation. One solve takes every frame's real and imaginary parts as
  columns; the right-hand sides are read from the frames' edge vectors in
  place and the solution is written into the frames a block of rows at a
  time, so the only (n, F)-sized arrays are the solve's own;
- 'splu': scipy's SuperLU (always available).
"""

import importlib.util
import weakref

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..errors import MissingDependencyError, ParameterError, require
from . import backend

__all__ = ["centroid_path", "FrameAssembler", "assembler_for", "FACTORISATIONS", "HAVE_CHOLMOD"]

#: owner (e.g. a Sequence) -> (shape, weights, FrameAssembler) of its last factorisation (kept out of the owner,
#: so that it still copies and pickles; dropped with it)
_OWNED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()

FACTORISATIONS = ("auto", "banded", "cholmod", "splu")

#: scikit-sparse is installed (imported on the first CHOLMOD factorisation)
HAVE_CHOLMOD = importlib.util.find_spec("sksparse") is not None

#: Topology -> CHOLMOD symbolic factor (ordering and supernodes) of its free-vertex Laplacian
_ANALYSIS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


#: components follow the drawing's turn when its similarity fit leaves less than this (relative RMS)
TURN_FIT = 0.1


def centroid_path(shape, z0, z1, t, turn=False):
    """(C, len(t)) complex: every component's centroid path from frame ``z0`` to ``z1``.

    Blended linearly in t; or, with ``turn`` and several components that move
    together (the least-squares similarity ``z -> a z + b`` of all vertices
    leaves an RMS residual below `TURN_FIT` of the target's RMS spread),
    carried by that motion, interpolated about its fixed point (``|a|^t`` and
    ``t arg a``), plus the linear blend of what it leaves over. A drawing
    whose pieces turn together then turns as a whole (a rigid turn exactly),
    instead of its pieces' centroids cutting straight across.
    """
    top = shape.topology
    c0, c1 = top.centroids(z0)[:, None], top.centroids(z1)[:, None]
    t = np.asarray(t)[None, :]
    if not turn or len(c0) < 2:
        return c0 + t * (c1 - c0)
    m0, m1 = z0.mean(), z1.mean()
    d0 = z0 - m0
    a = np.vdot(d0, z1 - m1) / max(np.vdot(d0, d0).real, 1e-300)
    b = m1 - a * m0
    spread = np.sqrt(np.mean(np.abs(z1 - m1) ** 2))
    if not np.isfinite(a) or abs(a) == 0 or np.sqrt(np.mean(np.abs(z1 - a * z0 - b) ** 2)) > TURN_FIT * spread:
        return c0 + t * (c1 - c0)
    # the similarity at time t about its fixed point: c0 + g(t) (a c0 + b - c0), g = (a^t - 1) / (a - 1)
    log_a = np.log(abs(a)) + 1j * np.angle(a)
    g = t if abs(log_a) < 1e-9 else (np.exp(t * log_a) - 1) / (a - 1)
    moved = c0 + g * (a * c0 + b - c0)
    return moved + t * (c1 - (a * c0 + b))


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
    BANDED = 192
    #: with scikit-sparse and a larger bandwidth (or no numba), CHOLMOD from this many free vertices
    CHOLMOD_SIZE = 20_000
    #: the CHOLMOD path's passes over the vertices work on blocks of rows of at most this size
    #: (below glibc's mmap threshold, so the blocks reuse heap memory)
    BLOCK_BYTES = 4 << 20

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
        self._DtW_rows, self._rhs = {}, None
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
        if self.method == "cholmod":
            z = np.empty((self.n, F), dtype=complex)
            self._cholmod_into(z, slice(None), e, centroids, measure=False)
            return z
        z = np.zeros((self.n, F), dtype=complex)
        rhs = self._DtW @ e
        step = max(1, (4 << 20) // (16 * max(self.free.size, 1)))  # blocks of <= 4 MiB
        for c in range(0, F, step):
            z[self.free, c : c + step] = self.solve_laplacian(rhs[:, c : c + step])
        return self.place(z, centroids)

    def _cholmod_rhs(self, e):
        """(n_free, 2F) Fortran-ordered real: D^T W e, real and imaginary parts of every frame side by side.

        This is the layout CHOLMOD solves without copying. When ``e`` is a
        column slice of a C-ordered (E, F') array (the local solver's frames
        between the inputs), the sparse product reads that array's rows whole,
        a block of vertices at a time, so neither an (E, F) copy of ``e`` nor
        an (n_free, F') product is made.
        """
        nf, F = self.free.size, e.shape[1]
        rhs = self._rhs
        if rhs is None or rhs.shape != (nf, 2 * F):  # kept for the next iteration: no fresh pages to fault in
            rhs = self._rhs = np.empty((nf, 2 * F), order="F")
        whole, first = _parent_columns(e)
        if whole is None:  # blocks of frames copied contiguous, (E, step) copies of <= 64 MiB
            step = max(1, (64 << 20) // (16 * max(e.shape[0], 1)))
            for c in range(0, F, step):
                d = min(F, c + step)
                rhs[:, 2 * c : 2 * d] = self._DtW @ np.ascontiguousarray(e[:, c:d], dtype=complex).view(np.float64)
            return rhs
        real = whole.view(np.float64)
        cols = slice(2 * first, 2 * (first + F))
        for rows, DtW in self._DtW_blocks(real.shape[1]):
            rhs[rows] = (DtW @ real)[:, cols]
        return rhs

    def _row_blocks(self, width):
        """Slices of the free vertices whose (rows, width) float blocks stay below `BLOCK_BYTES`."""
        nf = self.free.size
        step = max(1, self.BLOCK_BYTES // (8 * max(width, 1)))
        return [slice(r, min(r + step, nf)) for r in range(0, nf, step)]

    def _DtW_blocks(self, width):
        """[(rows, DtW[rows])] over `_row_blocks` (kept per width)."""
        blocks = self._DtW_rows.get(width)
        if blocks is None:
            blocks = self._DtW_rows[width] = [(r, self._DtW[r]) for r in self._row_blocks(width)]
        return blocks

    def _cholmod_into(self, z, frames, e, centroids, measure=True):
        """Eq. (10) with CHOLMOD into ``z[:, frames]``: one solve for all frames, then one pass over the rows.

        The solution is translated onto the centroids and written into ``z``
        a block of rows at a time (with the largest move, Eq. 11, measured in
        the same pass), so no (n, F) array is made beyond the solve's.

        Returns
        -------
        float
            The largest vertex move (0.0 unless ``measure``).
        """
        F = e.shape[1]
        rhs = self._cholmod_rhs(e)
        x = self._factor(rhs)  # (n_free, 2F) Fortran-ordered, frames' real and imaginary parts side by side
        top = self._top
        # centroid of each component with its anchor at 0, then the translation onto `centroids`
        if self.n_components == 1:
            sums = np.add.reduce(x, axis=0)[None, :]
        else:
            comp = self.components[self.free]
            sums = np.stack([np.bincount(comp, x[:, j], minlength=self.n_components)
                             for j in range(2 * F)], axis=1)
        shift = centroids - np.ascontiguousarray(sums).view(complex) * top.inv_count[:, None]  # (C, F)
        move = _write_rows(z, self.anchors, frames, shift, measure)
        rows_of = self._free_rows()
        for rows in self._row_blocks(2 * F):
            new = np.ascontiguousarray(x[rows]).view(complex)
            new += shift if self.n_components == 1 else shift[self.components[self.free[rows]]]
            move = max(move, _write_rows(z, rows_of(rows), frames, new, measure))
        return move

    def _free_rows(self):
        """Map a slice of free-vertex positions to vertex rows: a slice when the free vertices are consecutive."""
        free = self.free
        if free.size and free[-1] - free[0] + 1 == free.size:
            return lambda rows: slice(free[0] + rows.start, free[0] + rows.stop)
        return lambda rows: free[rows]

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
        if self._factor is None:
            self._factorise()
        if self.method == "cholmod":
            return self._cholmod_into(z, frames, e, centroids)
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


def assembler_for(owner, shape, weights):
    """The `FrameAssembler` of ``shape`` and ``weights``, kept for ``owner`` until either changes.

    Repeated solves on one sequence (``Sequence.at``, edit after edit of the
    same morph) factorise Eq. (10) once. ``owner`` must be weakly referable
    and hashed by identity; the factorisation is dropped with it.
    """
    kept = _OWNED.get(owner)
    if kept is None or kept[0] is not shape or not np.array_equal(kept[1], weights):
        kept = _OWNED[owner] = (shape, np.array(weights, dtype=float), FrameAssembler(shape, weights))
    return kept[2]


def _parent_columns(e):
    """(whole, first): ``e`` is ``whole[:, first : first + F]`` in memory, ``whole`` a C-ordered (E, F') view.

    ``whole`` is ``e`` itself when it is C-ordered; otherwise a view of the
    contiguous array that owns ``e``'s memory, one row per row of ``e``.
    (None, 0) when there is no such view.
    """
    if e.ndim != 2 or e.dtype != complex:
        return None, 0
    if e.flags.c_contiguous:
        return e, 0
    root, (rows, cols), (s0, s1) = e.base, e.shape, e.strides
    if not isinstance(root, np.ndarray) or not root.flags.c_contiguous or s1 != 16 or s0 % 16 or s0 < 16 * cols:
        return None, 0
    start = e.__array_interface__["data"][0] - root.__array_interface__["data"][0]
    first = (start % s0) // 16
    begin = start - 16 * first
    if start % 16 or first + cols > s0 // 16 or begin < 0 or begin + rows * s0 > root.nbytes:
        return None, 0
    memory = root.reshape(-1).view(np.uint8)[begin : begin + rows * s0]
    return memory.view(complex).reshape(rows, s0 // 16), first


def _write_rows(z, rows, frames, new, measure):
    """``z[rows, frames] = new``; the largest |new - old| when ``measure`` (Eq. 11), else 0.0."""
    index = (rows, frames) if isinstance(frames, slice) else np.ix_(np.arange(z.shape[0])[rows], frames)
    move = 0.0
    if measure:
        d = z[index] - new
        move = float(np.sqrt(np.max(d.real**2 + d.imag**2, initial=0.0)))
    z[index] = new
    return move


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
