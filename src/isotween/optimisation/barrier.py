"""Flip-free minimisation of the symmetric Dirichlet energy of a planar triangle mesh.

The energy ``A (|J|^2 + |J^-1|^2)`` of each face's map from a rest triangle
(Smith and Schaefer 2015, "Bijective parameterization with free boundaries")
is minimised over the free vertices by projected Newton (Teran et al. 2005;
the closed-form projection of Smith, de Goes and Kim 2019), one sparse
Cholesky (CHOLMOD) or LU solve per iteration, with a line search that never
passes 0.9 of the first step at which a triangle's signed area reaches zero
(`max_step`, Smith and Schaefer 2015, Sec. 4.1): every iterate keeps every
triangle positive. Used by the fold-free morph (`isotween.foldfree.injective`)
and by the compatible meshes' low-distortion map (`isotween.correspondence`).
"""

import numpy as np
from scipy.sparse import csc_matrix, diags
from scipy.sparse.linalg import splu

from ..errors import MethodError, require
from ..geometry import triangle_areas
from . import backend
from .assembly import HAVE_CHOLMOD

__all__ = ["SymmetricDirichlet", "minimise", "max_step", "face_steps", "triangle_areas", "TOL", "ARMIJO"]

TOL = 1e-3  # stop when an iteration lowers the energy by less than this fraction of its excess
ARMIJO = 1e-4
NEWTON_WORK = 30  # a face's Newton work, in the edge-frames of `backend.sized` (which picks numpy or numba)
_LU = {"diag_pivot_thresh": 0.0, "options": {"SymmetricMode": True}}  # SuperLU on a symmetric positive definite H
SUPERNODAL = 20_000  # unknowns from which CHOLMOD factorises supernodally; below, simplicial is faster (2x at 1,000)


def max_step(z, d, faces):
    """The first step ``s > 0`` at which a triangle of ``z + s d`` has zero signed area.

    Parameters
    ----------
    z : (N,) complex
        Positions; every face counter-clockwise (positive signed area).
    d : (N,) complex
        Search direction.
    faces : (K, 3) int

    Returns
    -------
    float
        ``inf`` when no triangle degenerates for any ``s > 0``.
    """
    steps = face_steps(z, d, faces)
    return float(steps.min()) if steps.size else np.inf


def face_steps(z, d, faces):
    """(K,) for every face, the first step ``s > 0`` at which it has zero signed area in ``z + s d`` (or inf)."""
    p0, p1, p2 = (z[faces[:, k]] for k in range(3))
    q0, q1, q2 = (d[faces[:, k]] for k in range(3))
    u, v, du, dv = p1 - p0, p2 - p0, q1 - q0, q2 - q0
    # twice the signed area: c + b s + a s^2
    a = _cross(du, dv)
    b = _cross(u, dv) + _cross(du, v)
    c = _cross(u, v)
    disc = b * b - 4 * a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.maximum(disc, 0))
        q = -0.5 * (b + np.where(b >= 0, root, -root))  # stable roots q / a and c / q
        r1, r2 = q / a, c / q
        linear = -c / b
    r1 = np.where((disc >= 0) & (a != 0), r1, np.inf)
    r2 = np.where((disc >= 0) & (q != 0), r2, np.inf)
    r1 = np.where(a == 0, np.where(b < 0, linear, np.inf), r1)
    roots = np.stack([r1, r2])
    return np.where(np.isfinite(roots) & (roots > 0), roots, np.inf).min(axis=0)


def _cross(u, v):
    return (np.conj(u) * v).imag


def _pattern(dof, keep, m):
    """The fixed sparsity pattern of a Hessian over 2m unknowns (x of the m free vertices, then y).

    Parameters
    ----------
    dof : (K, 6) int
        Every face's unknowns x0 x1 x2 y0 y1 y2 (-1: a fixed vertex).
    keep : (K, 6, 6) bool
        The entries of the faces' 6 x 6 blocks between two unknowns.

    Returns
    -------
    slot : (P,) int
        Every kept entry's place among the pattern's nonzeros (CSR, columns sorted).
    indices : (Z,) int, indptr : (2m + 1,) int
    diagonal : (2m,) int or None
        The slots of the diagonal; None when a free vertex is in no face.
    """
    # one sort of the faces' vertex pairs, not of the four times as many entries: a row of vertex i holds
    # the x columns of the vertices that share a face with i (itself included), then their y columns
    v = dof[:, :3]
    both = (v[:, :, None] >= 0) & (v[:, None, :] >= 0)
    i, j = np.broadcast_to(v[:, :, None], both.shape)[both], np.broadcast_to(v[:, None, :], both.shape)[both]
    pair, at = np.unique(i * m + j, return_inverse=True)
    inverse = np.zeros(both.shape, dtype=np.int64)
    inverse[both] = at
    at = np.tile(inverse, (1, 2, 2))[keep]
    first, second = pair // m, pair % m
    deg = np.bincount(first, minlength=m)  # vertices beside i (i included)
    rank = np.arange(len(pair)) - np.r_[0, np.cumsum(deg)[:-1]][first]
    indptr = np.r_[0, np.cumsum(np.r_[2 * deg, 2 * deg])]
    rows = np.broadcast_to(dof[:, :, None], keep.shape)[keep]
    cols = np.broadcast_to(dof[:, None, :], keep.shape)[keep]
    slot = indptr[rows] + (cols >= m) * deg[first[at]] + rank[at]
    indices = np.empty(indptr[-1], dtype=np.int64)
    for half in (0, 1):  # the x rows, then the y rows
        base = indptr[half * m + first] + rank
        indices[base], indices[base + deg[first]] = second, second + m
    if np.any(deg == 0):
        return slot, indices, indptr, None
    own = rank[np.searchsorted(pair, np.arange(m) * (m + 1))]  # vertex i among its own neighbours
    diagonal = np.r_[indptr[:m] + own, indptr[m:2 * m] + deg + own]
    return slot, indices, indptr, diagonal


def minimise(energy, z, limit, tol=TOL):
    """Projected Newton with the flip-preventing line search; every iterate an embedding.

    Parameters
    ----------
    energy : SymmetricDirichlet
        With its rest triangles set (`SymmetricDirichlet.rest`).
    z : (N,) complex
        Start: every face positive.
    limit : int
        Newton iterations at most.
    tol : float
        Stop when an iteration lowers the energy above its least value by less than this fraction.

    Returns
    -------
    z : (N,) complex
        The last iterate (every face positive).
    iterations : int
    """
    e = energy(z)
    for it in range(limit):
        g, H = energy.derivatives(z)
        step = np.zeros_like(z)
        sol = energy.solve(H, -g)
        n = len(energy.free)
        step[energy.free] = sol[:n] + 1j * sol[n:]
        slope = float(g @ sol)
        if not slope < 0:
            return z, it
        s = min(1.0, 0.9 * max_step(z, step, energy.faces))
        while True:
            trial = z + s * step
            e_new = energy(trial)
            if e_new <= e + ARMIJO * s * slope:
                break
            s *= 0.5
            if s < 1e-12:
                return z, it + 1
        z, drop, e = trial, e - e_new, e_new
        if drop < tol * (e - energy.least):  # tol: of the energy above
            return z, it + 1  # its minimum (every face isometric)
    return z, limit


class SymmetricDirichlet:
    """Symmetric Dirichlet energy of a triangle mesh's positions against rest triangles.

    ``E(z) = sum_f weight_f A_f (|J_f|^2 + |J_f^-1|^2)`` with ``J_f`` the
    Jacobian of face f's map from its rest triangle (area ``A_f``) to its
    triangle in ``z``: at least ``4 sum weight_f A_f`` (`least`), reached by
    rotations; infinite when a triangle degenerates or flips.

    Parameters
    ----------
    start : (N,) complex
        Rest positions at time 0; their orientation of each face is the one kept.
    end : (N,) complex
        Positions at time 1 (every face positive in the orientation of
        ``start``); `rest` blends the edge lengths of both.
    faces : (K, 3) int
    fixed : (N,) bool
        Vertices that do not move.
    weight : (K,) float, optional
        Per-face weight (default 1).

    Raises
    ------
    MethodError
        A degenerate face in ``start``, or a face flipped or degenerate in ``end``.
    """

    def __init__(self, start, end, faces, fixed, weight=None):
        areas = triangle_areas(start, faces)
        f = np.where((areas < 0)[:, None], faces[:, ::-1], faces)  # all counter-clockwise
        if np.any(areas == 0) or np.any(triangle_areas(end, f) <= 0):
            raise MethodError("the mesh has a degenerate triangle or one flipped in the target")
        self.faces = f
        self.n_vertices = N = len(start)
        self.weight = np.ones(len(f)) if weight is None else np.asarray(weight, dtype=np.float64)
        self._backend = backend.for_size(NEWTON_WORK * len(f))
        # edge lengths (0-1, 1-2, 2-0) at both ends
        self._ls = np.abs(start[np.roll(f, -1, axis=1)] - start[f])
        self._la = np.abs(end[np.roll(f, -1, axis=1)] - end[f])
        self.free = np.flatnonzero(~np.asarray(fixed, dtype=bool))
        self.pull = None
        index = np.full(N, -1)
        index[self.free] = np.arange(len(self.free))
        self._index = index
        m = len(self.free)
        dof = np.c_[index[f], np.where(index[f] >= 0, index[f] + m, -1)]  # (K, 6): x0 x1 x2 y0 y1 y2
        self._keep = (dof[:, :, None] >= 0) & (dof[:, None, :] >= 0)
        self._slot, self._indices, self._indptr, self._diagonal = _pattern(dof, self._keep, m)
        self._dof = dof
        self._size = 2 * m
        self._symbolic = None
        self._order = None  # SuperLU's fill-reducing order of the first system (`_lu_solve`)

    def solve(self, H, b):
        """``H^-1 b`` for a positive definite ``H`` of `derivatives`: CHOLMOD (symbolic analysis once) or SuperLU."""
        if HAVE_CHOLMOD:
            cholmod = require("sksparse.cholmod", "large")
            if self._symbolic is None:
                mode = "supernodal" if H.shape[0] >= SUPERNODAL else "simplicial"
                self._symbolic = cholmod.analyze(H, mode=mode, ordering_method="amd")
            try:
                return self._symbolic.cholesky(H)(b)
            except cholmod.CholmodNotPositiveDefiniteError:
                pass
        try:
            return self._lu_solve(H, b)
        except RuntimeError as exc:  # exactly singular
            raise MethodError(f"the Newton system of the mesh cannot be solved ({exc})") from None

    def _lu_solve(self, H, b):
        """``H^-1 b`` by SuperLU; the fill-reducing order of the first system kept for later ones of its pattern.

        The first system is ordered by minimum degree on H + H^T (pivots on
        the diagonal: H is symmetric positive definite); later systems of the
        same sparsity pattern are permuted by that order and factorised in
        it (a third less time than ordering every Newton step afresh).
        """
        kept = self._order
        if kept is not None and np.array_equal(kept[0], H.indptr) and np.array_equal(kept[1], H.indices):
            p, take, indices, indptr = kept[2:]
            lu = splu(csc_matrix((H.data[take], indices, indptr), shape=H.shape), permc_spec="NATURAL", **_LU)
            x = np.empty_like(b)
            x[p] = lu.solve(b[p])
            return x
        lu = splu(H, permc_spec="MMD_AT_PLUS_A", **_LU)
        p = np.argsort(lu.perm_c)  # H[p][:, p] factorises with no reordering
        marks = csc_matrix((np.arange(1.0, H.nnz + 1), H.indices, H.indptr), shape=H.shape)[p][:, p].tocsc()
        marks.sort_indices()  # as SuperLU wants them (it would sort a copy's in place, out of step with ``take``)
        self._order = (H.indptr.copy(), H.indices.copy(), p, marks.data.astype(np.int64) - 1, marks.indices,
                       marks.indptr)
        return lu.solve(b)

    def rest(self, tk):
        """Set the rest triangles of time ``tk``: edge lengths blended linearly."""
        self.rest_lengths((1 - tk) * self._ls + tk * self._la)

    def rest_lengths(self, L):
        """Set the rest triangles from their side lengths ``L`` (K, 3): side j from corner j to corner j+1."""
        a, b, c = L[:, 0], L[:, 1], L[:, 2]
        x2 = (a * a + c * c - b * b) / (2 * a)
        y2 = np.sqrt(np.maximum(c * c - x2 * x2, (1e-12 * a) ** 2))
        self._area = self.weight * 0.5 * a * y2
        self.least = 4 * float(self._area.sum())  # |J|^2 + |J^-1|^2 >= 4, equal for rotations
        # J = X R^-1 with X = [p1 - p0, p2 - p0] and R = [[a, x2], [0, y2]]; rows of J = G (x0, x1, x2)
        r00, r01, r11 = 1 / a, -x2 / (a * y2), 1 / y2
        G = np.zeros((len(a), 2, 3))
        G[:, 0, 0], G[:, 0, 1] = -r00, r00
        G[:, 1, 0], G[:, 1, 1], G[:, 1, 2] = -(r01 + r11), r01, r11
        self._G = G

    def _jacobian(self, z):
        """(K, 4) row-major Jacobians of the faces' maps from their rest triangles."""
        p = z[self.faces]
        jx = np.einsum("kij,kj->ki", self._G, p.real)
        jy = np.einsum("kij,kj->ki", self._G, p.imag)
        return np.c_[jx, jy]

    def __call__(self, z):
        """The energy of positions ``z`` (N,) complex; ``inf`` when a triangle is not positive."""
        J = self._jacobian(z)
        det = J[:, 0] * J[:, 3] - J[:, 1] * J[:, 2]
        if np.any(det <= 0):
            return np.inf
        norm = np.einsum("ki,ki->k", J, J)
        e = float(np.sum(self._area * norm * (1 + 1 / det ** 2)))
        if self.pull is not None:
            idx, goal, lam = self.pull
            e += lam * float(np.sum(np.abs(z[idx] - goal) ** 2))
        return e

    def pull_towards(self, idx, goal, lam):
        """Add (or, with ``lam=0``, remove) the term ``lam sum |z[idx] - goal|^2``: free vertices pulled to places.

        Parameters
        ----------
        idx : (m,) int
            Free vertices.
        goal : (m,) complex
        lam : float
        """
        self.pull = (np.asarray(idx), np.asarray(goal), float(lam)) if lam else None

    def derivatives(self, z):
        """Gradient (2m,) and projected Hessian (2m, 2m) sparse over the free coordinates (x then y)."""
        g6, H6 = self._backend.face_derivatives(z, self.faces, self._G, self._area)
        keep = self._dof >= 0
        g = np.bincount(self._dof[keep], weights=g6[keep], minlength=self._size)
        data = np.bincount(self._slot, weights=H6[self._keep], minlength=len(self._indices))
        pulled = None
        if self.pull is not None:
            idx, goal, lam = self.pull
            slot = self._index[idx]
            r = z[idx] - goal
            g[slot] += 2 * lam * r.real
            g[slot + len(self.free)] += 2 * lam * r.imag
            pulled = np.r_[slot, slot + len(self.free)]
            if self._diagonal is not None:  # every free vertex has its diagonal entries
                np.add.at(data, self._diagonal[pulled], 2 * lam)
                pulled = None
        A = csc_matrix((data, self._indices, self._indptr), shape=(self._size,) * 2)  # symmetric: CSR = CSC
        if pulled is not None:
            diag = np.zeros(self._size)
            diag[pulled] = 2 * lam
            A = A + diags(diag, format="csc")
        return g, A
