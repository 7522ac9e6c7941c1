"""Fold-free, nearly isometric morph: the convex morph refined by a barrier energy.

Every in-between frame is an embedding of a triangulated disc, as in method
'convex' (`isotween.baselines.convex`: each component completed to a disc
inside a fixed 32-gon, its exterior and holes meshed compatibly), and then
made as isometric as the embedding allows:

1. Rest triangles at time t. Every face of the disc gets a rest triangle
   whose edge lengths are (1 - t)|e(0)| + t|e(1)|: the lengths AIAP aims at
   (``edge_length_deviation`` zero; docs/how-it-works.md). A convex
   combination of two valid length triples satisfies the triangle inequality, so the rest
   triangle always exists.
2. Energy. The symmetric Dirichlet energy ``A (|J|^2 + |J^-1|^2)`` of each
   face's map from its rest triangle (Smith and Schaefer 2015, "Bijective
   parameterization with free boundaries"), weight 1 on the component's
   faces and ``SCAFFOLD`` on the completing faces (the scaffold of Jiang,
   Schaefer, Schaefer and Panozzo 2017, "Simplicial complex augmentation
   framework for bijective maps"): the scaffold may deform, never flip. The
   energy is infinite when a triangle degenerates.
3. Projected Newton (Teran et al. 2005: each face's Hessian with respect to
   its Jacobian projected to positive semi-definite), one sparse Cholesky-
   like solve (``splu``) per iteration, the 32-gon fixed.
4. Flip-preventing line search (Smith and Schaefer 2015, Sec. 4.1): the step
   is at most 0.9 of the first time at which a triangle's signed area (a
   quadratic in the step) reaches zero (`max_step`), then halved until the
   energy decreases enough (Armijo). Every iterate is therefore an
   embedding of the disc: no triangle flips and no ring of a region
   crosses itself or another ring of the region, in any frame.
5. Start: whichever of the convex frame at t and the previous refined frame
   (an embedding of the same disc with the same boundary: warm start and
   temporal coherence) has the lower energy. Stop when an iteration lowers
   the energy above its minimum by less than ``TOL`` (relative), after
   ``MAX_ITER`` iterations, or when its share of the component's iteration
   budget is spent: ``WORK`` vertex-iterations, i.e. WORK / N Newton
   iterations for a disc of N vertices (what is left over the frames left;
   every frame gets at least one iteration, and its last iterate is an
   embedding). Only very large meshes reach the budget. The budget counts
   work, not seconds, so the result is the same on every machine.

The rigid motion of the convex morph (best rotation of the target onto the
source, interpolated, centroid on a straight line) is kept; the first and
last frames are the inputs exactly. ``info``: ``components`` (per component
``vertices``, ``faces``, ``rotation``, ``iterations``), ``iterations`` (all
Newton iterations).
"""

import numpy as np
from scipy.sparse import csc_matrix
from scipy.sparse.linalg import splu

from ..errors import MethodError, require
from ..optimisation.assembly import HAVE_CHOLMOD
from . import convex

__all__ = ["solve", "max_step", "SCAFFOLD", "MAX_ITER", "TOL", "WORK"]

SCAFFOLD = 1e-2  # weight of the completing (exterior and hole) faces against the region's
MAX_ITER = 20  # Newton iterations per frame at most
TOL = 1e-3  # stop when an iteration lowers the energy by less than this fraction
WORK = 2_000_000  # Newton iterations x disc vertices per component, shared out over its frames
ARMIJO = 1e-4


def solve(problem):
    """Frames of the refined fold-free morph.

    Parameters
    ----------
    problem : Problem
        Held at the first and the last frame; its shape a triangle mesh with
        every vertex in a face, no target triangle flipped against the source.

    Returns
    -------
    Result
        ``iterations``: Newton iterations of all frames; ``info``:
        ``components`` (per component ``vertices``, ``faces``, ``rotation``,
        ``iterations``).

    Raises
    ------
    MethodError
        As method 'convex' does (`isotween.baselines.convex.solve`).
    """
    result = convex.per_component(problem, "injective", _component)
    result.iterations = sum(c["iterations"] for c in result.info["components"])
    return result


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
    roots = np.where(np.isfinite(roots) & (roots > 0), roots, np.inf)
    return float(roots.min()) if roots.size else np.inf


def _cross(u, v):
    return (np.conj(u) * v).imag


def _component(zs, zt, f, t):
    """(F, n) complex frames of one component; see `interpolate`."""
    d = convex.disc(zs, zt, f)
    convex_frame = convex.ConvexFrames(d)
    energy = _Energy(d)
    budget = max(len(t) - 2, WORK // len(d.ws))  # Newton iterations for all the frames
    out = np.empty((len(t), len(zs)), dtype=complex)
    z = d.ws
    iterations = 0
    for k, tk in enumerate(t):
        if k == 0 or k == len(t) - 1:
            out[k] = convex.place(d, (d.ws if k == 0 else d.wa)[:d.n], tk)
            continue
        energy.rest(tk)
        z0 = convex_frame(tk)
        if energy(z0) < energy(z):
            z = z0
        share = max(1, (budget - iterations) // (len(t) - 1 - k))
        z, used = _minimise(energy, z, min(MAX_ITER, share))
        iterations += used
        out[k] = convex.place(d, z[:d.n], tk)
    return out, {"vertices": len(d.ws), "faces": len(d.faces), "rotation": d.theta, "iterations": iterations}


def _minimise(energy, z, limit):
    """Projected Newton with the flip-preventing line search; every iterate an embedding.

    At most ``limit`` iterations.
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
        if drop < TOL * (e - energy.least):  # TOL: of the energy above
            return z, it + 1  # its minimum (every face isometric)
    return z, limit


class _Energy:
    """Symmetric Dirichlet energy of the disc against rest triangles at one time (steps 1-2)."""

    def __init__(self, d):
        areas = convex._areas(d.ws, d.faces)
        f = np.where((areas < 0)[:, None], d.faces[:, ::-1], d.faces)  # all counter-clockwise
        if np.any(areas == 0) or np.any(convex._areas(d.wa, f) <= 0):
            raise MethodError("the completed disc has a degenerate triangle or one flipped in the target")
        self.faces = f
        self.n_vertices = N = len(d.ws)
        self.weight = np.where(np.arange(len(f)) < d.n_region, 1.0, SCAFFOLD)
        # edge lengths (0-1, 1-2, 2-0) at both ends
        self._ls = np.abs(d.ws[np.roll(f, -1, axis=1)] - d.ws[f])
        self._la = np.abs(d.wa[np.roll(f, -1, axis=1)] - d.wa[f])
        fixed = np.zeros(N, dtype=bool)
        fixed[d.boundary] = True
        self.free = np.flatnonzero(~fixed)
        index = np.full(N, -1)
        index[self.free] = np.arange(len(self.free))
        m = len(self.free)
        dof = np.c_[index[f], np.where(index[f] >= 0, index[f] + m, -1)]  # (K, 6): x0 x1 x2 y0 y1 y2
        rows = np.broadcast_to(dof[:, :, None], (len(f), 6, 6))
        cols = np.broadcast_to(dof[:, None, :], (len(f), 6, 6))
        self._keep = (rows >= 0) & (cols >= 0)
        # the Hessian's fixed pattern: entry -> its slot among the sorted (row, column) pairs
        key, self._slot = np.unique(rows[self._keep] * (2 * m) + cols[self._keep], return_inverse=True)
        self._indices = key % (2 * m)
        self._indptr = np.searchsorted(key // (2 * m), np.arange(2 * m + 1))
        self._dof = dof
        self._size = 2 * m
        self._symbolic = None

    def solve(self, H, b):
        """``H^-1 b`` for a positive definite ``H`` of `derivatives`: CHOLMOD (symbolic analysis once) or SuperLU."""
        if HAVE_CHOLMOD:
            cholmod = require("sksparse.cholmod", "large")
            if self._symbolic is None:
                self._symbolic = cholmod.analyze(H, mode="supernodal", ordering_method="amd")
            try:
                return self._symbolic.cholesky(H)(b)
            except cholmod.CholmodNotPositiveDefiniteError:
                pass
        # a symmetric pattern: minimum degree on H + H^T, pivots on the diagonal
        try:
            lu = splu(H, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        except RuntimeError as exc:  # exactly singular
            raise MethodError(f"the Newton system of the completed disc cannot be solved ({exc})") from None
        return lu.solve(b)

    def rest(self, tk):
        """Set the rest triangles of time ``tk``: edge lengths blended linearly."""
        L = (1 - tk) * self._ls + tk * self._la
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
        return float(np.sum(self._area * norm * (1 + 1 / det ** 2)))

    def derivatives(self, z):
        """Gradient (2m,) and projected Hessian (2m, 2m) sparse over the free coordinates (x then y)."""
        J = self._jacobian(z)
        det = J[:, 0] * J[:, 3] - J[:, 1] * J[:, 2]
        norm = np.einsum("ki,ki->k", J, J)
        gd = np.c_[J[:, 3], -J[:, 2], -J[:, 1], J[:, 0]]  # d det / d J
        inv2, inv3 = det ** -2, det ** -3
        w = self._area
        grad = w[:, None] * (2 * J * (1 + inv2)[:, None] - 2 * (norm * inv3)[:, None] * gd)
        Hdet = np.array([[0, 0, 0, 1], [0, 0, -1, 0], [0, -1, 0, 0], [1, 0, 0, 0]], float)
        H = (2 * (1 + inv2))[:, None, None] * np.eye(4)
        H = H - (4 * inv3)[:, None, None] * (J[:, :, None] * gd[:, None, :] + gd[:, :, None] * J[:, None, :])
        H = H + (6 * norm * inv2 * inv2)[:, None, None] * gd[:, :, None] * gd[:, None, :]
        H = H - (2 * norm * inv3)[:, None, None] * Hdet
        # projected to positive semi-definite (Smith, de Goes and Kim 2019, "Analytic eigensystems for
        # isotropic distortion energies"): with singular values s1 >= s2 > 0 the scaling and flip
        # eigenvalues 2 + 6 / s^4 and 2 + 2 (s1^2 + s1 s2 + s2^2) / (s1 s2)^3 are positive; only the
        # twist's, 2 - 2 (s1^2 - s1 s2 + s2^2) / (s1 s2)^3, can be negative. Its eigenvector is
        # the polar rotation of J turned by a right angle, over sqrt(2).
        conf = 0.5 * ((J[:, 0] + J[:, 3]) + 1j * (J[:, 2] - J[:, 1]))  # J z = conf z + anti conj(z)
        anti = 0.5 * ((J[:, 0] - J[:, 3]) + 1j * (J[:, 2] + J[:, 1]))
        s1, s2 = np.abs(conf) + np.abs(anti), np.abs(conf) - np.abs(anti)
        twist = 2 - 2 * (s1 * s1 - s1 * s2 + s2 * s2) / (s1 * s2) ** 3
        r = 1j * conf / np.abs(conf)
        vec = np.c_[r.real, -r.imag, r.imag, r.real] / np.sqrt(2)
        H = H + np.maximum(-twist, 0)[:, None, None] * vec[:, :, None] * vec[:, None, :]
        H = H * w[:, None, None]
        # back to the six coordinates (x0 x1 x2 y0 y1 y2): D = blockdiag(G, G)
        K = len(w)
        D = np.zeros((K, 4, 6))
        D[:, :2, :3] = self._G
        D[:, 2:, 3:] = self._G
        H6 = np.matmul(D.transpose(0, 2, 1), np.matmul(H, D))
        g6 = np.einsum("kai,ka->ki", D, grad)
        keep = self._dof >= 0
        g = np.bincount(self._dof[keep], weights=g6[keep], minlength=self._size)
        data = np.bincount(self._slot, weights=H6[self._keep], minlength=len(self._indices))
        A = csc_matrix((data, self._indices, self._indptr), shape=(self._size,) * 2)  # symmetric: CSR = CSC
        return g, A
