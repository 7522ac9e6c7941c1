"""The numpy / scipy reference of the hot loops (the numba twins are in `accelerated`).

- :func:`edge_angles`, :func:`edge_frames`: Eqs. (12)-(13), the initial edges.
- :class:`EdgePass`: one iteration's edge work of Algorithm 2: the edge
  vectors of the assembled frames, the angular speeds (Eq. 8), the energy
  (Eq. 6) and the new edge vectors (Eq. 9), over blocks of edges on threads.

:mod:`isotween.optimisation.backend` picks between these and the kernels.
"""

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from .edge_solve import solve_edges
from .schemes import normal_equations, step_angle

__all__ = ["edge_angles", "edge_frames", "EdgePass", "EdgeBlocks", "face_derivatives"]


def edge_angles(top, e0, e1):
    """Eq. (12) with angles propagated along ``top``'s edge tree: (s, theta), each (E,) float.

    :func:`isotween.initialisation.edge_rotations` on a Topology (see there).
    """
    ratio = e1 / e0
    s, theta = np.abs(ratio), np.angle(ratio)
    if len(ratio) == 0:
        return s, theta
    # k_child = k_parent + round((theta_parent - theta_child) / 2 pi), summed
    # along every path to the root of the breadth-first tree
    k = top.path_sums(np.round((theta[top.parent] - theta) / (2 * np.pi)))
    return s, theta + 2 * np.pi * k


def edge_frames(e0, s, theta, t):
    """Eq. (13): e(t) = (1 - t + t s) R(t theta) e(0) for every edge and time.

    Parameters
    ----------
    e0 : (E,) complex
    s, theta : (E,) float
        From :func:`edge_angles`.
    t : (F,) float

    Returns
    -------
    (E, F) complex
    """
    h = np.diff(t)
    if len(h) and h.max() - h.min() <= 1e-12 * h[0]:
        # uniform times: R(t_k theta) = R(h theta)^k, one complex exp per edge
        rot = np.empty((len(theta), len(t)), dtype=complex)
        rot[:, 0] = 1.0
        rot[:, 1:] = np.exp(1j * h[0] * theta)[:, None]
        rot = np.cumprod(rot, axis=1)
    else:
        phase = t[None, :] * theta[:, None]
        rot = np.cos(phase) + 1j * np.sin(phase)
    return (1 - t + t * s[:, None]) * rot * e0[:, None]


class EdgePass:
    """Eqs. (8), (6), (9) for every edge, over blocks of edges.

    Parameters
    ----------
    top : Topology
    t : (F,) float
    scheme : {'midpoint', 'paper'}
    fixed : (F,) bool
        Held frames.
    smooth : float
        Weight of the term that lets the velocity turn smoothly through an
        interior held frame (see :func:`~isotween.optimisation.edge_solve.solve_edges`).
    """

    def __init__(self, top, t, scheme, fixed, smooth):
        self.h, self.scheme, self.fixed, self.smooth = np.diff(t), scheme, fixed, smooth
        self.keys = np.flatnonzero(fixed[1:-1]) + 1
        self.blocks = EdgeBlocks(top.D, len(t))

    def reuse(self, edges):
        """No-op: the blocks write into arrays of their own."""

    def __call__(self, z, solve):
        """Edge work on the frames ``z`` (n, F) complex.

        Returns
        -------
        edges : (E, F) complex
            New edge vectors (Eq. 9) if ``solve``, else unspecified.
        energy : float
            Eq. (6) of the edge vectors of ``z``, not yet divided by sum |e(0)|^2.
        """
        h, fixed, smooth, keys, scheme = self.h, self.fixed, self.smooth, self.keys, self.scheme

        def work(rows, D_rows, out):
            e = D_rows @ z
            diag, lower, energy = normal_equations(e, h, scheme)  # Eq. (8), Eq. (6)
            if solve:
                couplings = [(k, _turn(e, k), smooth / h[k]) for k in keys] if smooth else []
                out[rows] = solve_edges(e, diag, lower, fixed, couplings)  # Eq. (9)
            return energy

        return self.blocks.map(work)

    def close(self):
        """Stop the threads."""
        self.blocks.close()


def _turn(e, k):
    """(E,) unit complex: per-step rotation of every edge around frame k."""
    omega = step_angle(e[:, k - 1] + e[:, k], 2 * (e[:, k] - e[:, k - 1]))
    omega += step_angle(e[:, k] + e[:, k + 1], 2 * (e[:, k + 1] - e[:, k]))
    return np.exp(0.5j * omega)


class EdgeBlocks:
    """Runs a per-edge computation over blocks of edges, on several threads.

    Blocks stay below glibc's mmap threshold (so their temporaries reuse heap
    memory instead of faulting fresh pages in) and numpy releases the GIL in
    the elementwise work, so two blocks run at once on two cores.
    """

    BYTES = 4 << 20

    def __init__(self, D, frames):
        E = D.shape[0]
        step = max(1, self.BYTES // (16 * frames))
        self.rows = [slice(i, min(i + step, E)) for i in range(0, E, step)] or [slice(0, 0)]
        self.D = [D[r] for r in self.rows] if len(self.rows) > 1 else [D]
        self.shape = (E, frames)
        self._out = np.empty(self.shape, dtype=complex)
        self._spare = np.empty(self.shape, dtype=complex)
        workers = min(len(self.rows), os.cpu_count() or 1, 4)
        self.pool = ThreadPoolExecutor(workers) if workers > 1 else None

    def map(self, work):
        """work(rows, D_rows, out) -> energy; returns (out, total energy)."""
        out, self._spare = self._spare, self._out
        self._out = out
        args = list(zip(self.rows, self.D, strict=False))
        if self.pool is None:
            energies = [work(r, d, out) for r, d in args]
        else:
            energies = list(self.pool.map(lambda a: work(a[0], a[1], out), args))
        return out, float(sum(energies))

    def close(self):
        """Stop the threads."""
        if self.pool is not None:
            self.pool.shutdown()


def face_derivatives(z, faces, G, w):
    """Gradient and projected Hessian of the symmetric Dirichlet energy of every face, in its six coordinates.

    The energy of face k is ``w_k (|J_k|^2 + |J_k^-1|^2)``, ``J_k`` its map's
    Jacobian from the rest triangle (`isotween.optimisation.barrier`).

    Parameters
    ----------
    z : (N,) complex
        Positions; every face positive.
    faces : (K, 3) int
    G : (K, 2, 3) float
        Rows of J = G (x0, x1, x2) (and the same for y).
    w : (K,) float
        Weights (rest areas).

    Returns
    -------
    g6 : (K, 6) float
        Gradient over (x0 x1 x2 y0 y1 y2).
    H6 : (K, 6, 6) float
        Hessian projected to positive semi-definite, same order.
    """
    p = z[faces]
    J = np.c_[np.einsum("kij,kj->ki", G, p.real), np.einsum("kij,kj->ki", G, p.imag)]  # rows of J = G (x0, x1, x2)
    det = J[:, 0] * J[:, 3] - J[:, 1] * J[:, 2]
    norm = np.einsum("ki,ki->k", J, J)
    gd = np.c_[J[:, 3], -J[:, 2], -J[:, 1], J[:, 0]]  # d det / d J
    inv2, inv3 = det ** -2, det ** -3
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
    D[:, :2, :3] = G
    D[:, 2:, 3:] = G
    H6 = np.matmul(D.transpose(0, 2, 1), np.matmul(H, D))
    g6 = np.einsum("kai,ka->ki", D, grad)
    return g6, H6
