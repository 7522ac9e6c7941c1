"""Geodesic interpolation in shape space (Kilian et al. 2007), planar version.

Kilian et al. measure a deformation field X of a shape with vertices p by the
as-isometric-as-possible metric

    <X, X>_P = sum_(i,j) ((p_i - p_j) . (X_i - X_j))^2 + lambda <X, X>_L2,

which vanishes for isometric motions, and interpolate by a geodesic: the path
P_0, ..., P_m with both ends fixed that minimises the discrete path energy
sum_k <P_{k+1} - P_k, P_{k+1} - P_k> / h_k. As in their paper, the first term
uses the change of the squared edge length over a step,
e_k . (e_{k+1} - e_k) ~ (|e_{k+1}|^2 - |e_k|^2) / 2, so the energy minimised
here over all intermediate frames is exactly

    E = sum_k 1/h_k [ sum_edges ((|e_{k+1}|^2 - |e_k|^2) / (2 l_e))^2
                      + lambda (l / D)^2 sum_vertices |z_{k+1} - z_k|^2 ] / sum_edges |e(0)|^2,

with l_e = (|e(0)| + |e(1)|) / 2 making the first term a length change, l the
mean of the l_e and D the bounding-box diagonal of both inputs (so lambda
weighs displacements relative to the shape's size against length changes
relative to edge length, whatever the scale or resolution of the shape), and
the division making E dimensionless (reported as ``Sequence.energy``). The L2
term regularises the rigid and flexible motions that the isometric term cannot
see; since the first term ignores translation, each component's centroid moves
linearly at the optimum, as in AIAP. lambda = 0.01 by default: on the Fig. 3
pair of benchmarks/cases.py (9 frames) lambda = 1 and 0.1 left 8 % and 1.5 %
edge-length deviation, 0.01 left 0.3 % in 6 iterations.

Solved by Gauss-Newton over all intermediate vertex positions at once (one
sparse symmetric system per iteration; the L2 term keeps it positive
definite), starting from the linear blend, with a backtracking line search so
that E never increases, and stopped by the paper's Eq. (11) rule (no vertex
moves more than ``tol`` times the inputs' bounding-box diagonal: the
problem's absolute ``tol``).
"""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..optimisation.problem import Result, bbox_diagonal, pack

__all__ = ["solve", "PathEnergy"]

OPTIONS = ("callback", "regularisation")


class PathEnergy:
    """Residuals, Jacobian and energy of a path with fixed end frames.

    Parameters
    ----------
    shape : Shape
        Connectivity.
    z0, z1 : (n,) complex
        End frames.
    t : (F,) float
        Frame times.
    regularisation : float
        lambda, relative weight of the L2 metric (module docstring).

    Notes
    -----
    Unknowns are the real and imaginary parts of the vertices of frames 1 to
    F - 2, frame-major: column ``2 ((k - 1) n + v) + c``.
    """

    def __init__(self, shape, z0, z1, t, regularisation):
        n, m = shape.n_vertices, len(t) - 1
        self.n, self.m, self.edges = n, m, shape.edges
        self.h = np.diff(t)
        e0, e1 = shape.edge_vectors(z0), shape.edge_vectors(z1)
        self.scale = float(np.sum(np.abs(e0) ** 2))
        # lambda relative to the shape's size: displacements in units of the
        # bounding-box diagonal against length changes in units of edge length
        mean_length = 0.5 * float(np.mean(np.abs(e0) + np.abs(e1)))
        diag = bbox_diagonal(*pack(np.c_[z0, z1]))
        self.lam = float(regularisation) * (mean_length / diag) ** 2
        # residual k, e: (|e_{k+1}|^2 - |e_k|^2) * w[k, e]
        self.w = 1.0 / (np.abs(e0) + np.abs(e1))[None, :] / np.sqrt(self.h)[:, None]  # (m, E)
        self.z0, self.z1 = z0, z1
        self._jacobian_pattern()
        # L2 term: lambda sum_k |z_{k+1} - z_k|^2 / h_k; its Hessian / 2 is a time
        # Laplacian (interior frames) times the identity on the 2n coordinates
        inv_h = 1.0 / self.h
        T = sp.diags([inv_h[:-1] + inv_h[1:], -inv_h[1:-1], -inv_h[1:-1]], [0, 1, -1], shape=(m - 1, m - 1))
        self.reg_hessian = self.lam * sp.kron(T, sp.identity(2 * n), format="csr")

    def _jacobian_pattern(self):
        """Rows and columns of the isometric Jacobian (fixed; data per iteration)."""
        n, m, E = self.n, self.m, len(self.edges)
        i, j = self.edges[:, 0], self.edges[:, 1]
        k = np.arange(m)[:, None]
        row = k * E + np.arange(E)[None, :]  # (m, E)
        rows, cols, self._slots = [], [], []
        # d r_ke / d z: +-2 e_{k+1} w at frame k+1, -+2 e_k w at frame k (vertex j: +, i: -)
        for frame, vertex, sign in ((k + 1, j, 1.0), (k + 1, i, -1.0), (k, j, 1.0), (k, i, -1.0)):
            frame, vertex = np.broadcast_arrays(frame, vertex[None, :])
            keep = (frame >= 1) & (frame <= m - 1)  # end frames are fixed
            base = 2 * ((frame[keep] - 1) * n + vertex[keep])
            rows += [row[keep], row[keep]]
            cols += [base, base + 1]
            self._slots.append((keep, sign))
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        marker = sp.csr_matrix((np.arange(1, len(rows) + 1, dtype=float), (rows, cols)),
                               shape=(m * E, 2 * n * (m - 1)))
        self._perm = marker.data.astype(np.int64) - 1
        self._J = marker

    def frames(self, x):
        """(F, n) complex frames of the unknown vector x."""
        inner = x.reshape(self.m - 1, self.n, 2)
        return np.vstack([self.z0[None], inner[..., 0] + 1j * inner[..., 1], self.z1[None]])

    def residuals(self, z):
        """Residuals of (F, n) complex frames.

        Returns
        -------
        r_iso : (m, E) float
        r_reg : (m, n) complex
            L2 residuals (real and imaginary parts are residuals).
        e : (F, E) complex
            Edge vectors.
        """
        e = z[:, self.edges[:, 1]] - z[:, self.edges[:, 0]]
        sq = e.real**2 + e.imag**2
        return (sq[1:] - sq[:-1]) * self.w, np.sqrt(self.lam / self.h)[:, None] * np.diff(z, axis=0), e

    def energy(self, z):
        """E of the module docstring for (F, n) complex frames."""
        r_iso, r_reg, _ = self.residuals(z)
        return float((np.sum(r_iso**2) + np.sum(r_reg.real**2 + r_reg.imag**2)) / self.scale)

    def step(self, x):
        """Gauss-Newton step: solve (J^T J) dx = -J^T r.

        Returns
        -------
        dx : (2 n (F - 2),) float
        slope : float
            Directional derivative of the unnormalised energy sum r^2 along dx.
        """
        z = self.frames(x)
        r_iso, _, e = self.residuals(z)
        g_up, g_lo = 2 * e[1:] * self.w, -2 * e[:-1] * self.w  # d r / d e at frames k+1 and k
        data = []
        for (keep, sign), g in zip(self._slots, (g_up, g_up, g_lo, g_lo), strict=False):
            gk = sign * g[keep]
            data += [gk.real, gk.imag]
        J = self._J
        J.data = np.concatenate(data)[self._perm]
        JT = J.T.tocsr()
        x_all = np.stack([z.real, z.imag], axis=-1)  # (F, n, 2)
        inv_h = 1.0 / self.h
        grad_reg = self.lam * ((x_all[1:-1] - x_all[:-2]) * inv_h[:-1, None, None]
                               - (x_all[2:] - x_all[1:-1]) * inv_h[1:, None, None]).ravel()
        grad = JT @ r_iso.ravel() + grad_reg  # half the gradient of sum r^2
        A = (JT @ J + self.reg_hessian).tocsc()
        dx = -splu(A, permc_spec="MMD_ATA").solve(grad)  # measured faster than MMD_AT_PLUS_A here
        return dx, 2.0 * float(grad @ dx)


def solve(problem, *, callback=None, regularisation=1e-2):
    """Frames of the shape-space geodesic between the problem's first and last frame.

    Parameters
    ----------
    problem : Problem
        Held at the first and the last frame. Its ``tol`` (Eq. 11: stop when
        no vertex moves more than that in one iteration) and ``max_iter``
        stop the iteration.
    callback : callable(iteration, energy, max_move), optional
    regularisation : float
        lambda, the relative weight of the L2 metric (module docstring).

    Returns
    -------
    Result
        ``z`` (n, F) complex, ``energy`` after every iteration,
        ``iterations``, ``converged``; ``info``: ``regularisation``,
        ``objective``, ``initial_energy`` (the linear blend's).
    """
    z0, z1 = problem.ends()
    t = np.asarray(problem.times, dtype=float)
    linear = (1 - t)[:, None] * z0[None] + t[:, None] * z1[None]
    energies = []
    info = {"regularisation": regularisation, "objective": "Kilian et al. 2007 path energy (module docstring)"}
    if len(t) == 2:
        info["initial_energy"] = 0.0
        return Result(linear.T, energy=energies, iterations=0, converged=True, info=info)
    path = PathEnergy(problem.shape, z0, z1, t, regularisation)
    inner = linear[1:-1]
    x = np.stack([inner.real, inner.imag], axis=-1).ravel()
    energy = path.energy(linear)
    info["initial_energy"] = energy
    converged, iterations = False, 0
    for it in range(1, problem.max_iter + 1):
        dx, slope = path.step(x)
        alpha = 1.0
        for _ in range(40):  # backtracking (Armijo): the energy never increases
            trial = path.energy(path.frames(x + alpha * dx))
            if trial <= energy + 1e-4 * alpha * slope / path.scale:
                break
            alpha *= 0.5
        else:
            converged = True  # no descent left at machine precision
            break
        x = x + alpha * dx
        energy = trial
        move = float(np.max(np.hypot(*(alpha * dx).reshape(-1, 2).T)))
        energies.append(energy)
        iterations = it
        if callback is not None:
            callback(it, energy, move)
        if move < problem.tol:  # Eq. (11)
            converged = True
            break
    return Result(path.frames(x).T, energy=energies, iterations=iterations, converged=converged, info=info)
