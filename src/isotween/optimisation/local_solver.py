"""Algorithm 2: the local solver.

Each iteration assembles every frame from the current edge vectors (Eq. 10),
fits the angular speeds to the assembled frames (Eq. 8) and re-solves every
edge's vector sequence (Eq. 9), until the assembled frames move less than the
tolerance (Eq. 11). Arrays are laid out with time last: edges (E, m+1),
vertices (n, m+1).
"""

import os
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from . import accelerated
from .assembly import FrameAssembler
from .edge_solve import solve_edges
from .schemes import normal_equations, step_angle

__all__ = ["ASSEMBLY", "local_solve"]

ASSEMBLY = ("shared", "per-frame")


def local_solve(shape, z, t, edges, centroids, scheme, tol, max_iter, assembly="shared",
                callback=None, fixed=None, smooth=1.0, factorisation="auto", overwrite_edges=False):
    """Run Algorithm 2.

    Parameters
    ----------
    shape : Shape
    z : (n, m+1) complex
        Vertex positions; the fixed frames (the inputs) are read from it.
    t : (m+1,) float
        Frame times, t[0] = 0 and t[-1] = 1.
    edges : (E, m+1) complex
        Initial edge vectors (Eq. 13 or linear); fixed frames' must be exact.
    centroids : (C, m+1) complex
        Centroid of every component in every frame (docs/how-it-works.md, centroid translation).
    scheme : {'midpoint', 'paper'}
    tol : float
        Absolute tolerance of Eq. (11) (tau times the bounding-box diagonal).
    max_iter : int
    assembly : {'shared', 'per-frame'}
        'per-frame' uses the paper's weights w = 1/|e_ij(t_k)| with a new
        factorisation per frame and iteration; 'shared' factorises once with
        w = 2 / (|e(0)| + |e(1)|) for all frames and iterations.
    callback : callable(iteration, energy, max_move), optional
    fixed : (m+1,) bool array, optional
        Frames held (keyframes); default the first and the last.
    smooth : float
        Weight of the term that lets the velocity turn smoothly through an
        interior fixed frame (see :func:`solve_edges`).
    factorisation : {'auto', 'banded', 'cholmod', 'splu'}
        Factorisation of the shared Eq. (10) Laplacian (see `FrameAssembler`).
    overwrite_edges : bool
        Let the solver reuse ``edges`` for its new edge vectors (saves one
        (E, m+1) array; the caller's ``edges`` is then overwritten).

    Returns
    -------
    z : (n, m+1) complex
        Vertex positions of every frame.
    info : dict
        energy (list), iterations, converged, max_move, timings.
    """
    h = t[1:] - t[:-1]
    e0 = edges[:, 0]
    norm = float(np.add.reduce(e0.real**2 + e0.imag**2))  # not BLAS: no threads
    norm = norm if norm > 0.0 else 1.0  # no edges (or all of zero length): energy 0, not 0 / 0
    if fixed is None:
        fixed = np.zeros(len(t), dtype=bool)
        fixed[[0, -1]] = True
        free, keys = slice(1, len(t) - 1), np.zeros(0, dtype=np.int64)
    else:
        free = np.flatnonzero(~fixed)
        if free.size and free[-1] - free[0] + 1 == free.size:
            free = slice(free[0], free[-1] + 1)  # a view, not a copy, of the frames
        keys = np.flatnonzero(fixed[1:-1]) + 1
    centroids = centroids[:, free]
    z = z.copy()
    if assembly == "shared":
        shared = FrameAssembler(shape, 2.0 / (np.abs(edges[:, 0]) + np.abs(edges[:, -1])),
                                factorisation=factorisation)
    top = shape.topology
    # the numba kernel covers the default case: midpoint scheme, only the ends held
    fused = accelerated.ENABLED and scheme == "midpoint" and fixed[0] and fixed[-1] and not keys.size
    if fused:
        inv_h = 1.0 / h
        reuse = overwrite_edges and edges.dtype == complex and edges.flags.c_contiguous
        out = edges if reuse else np.empty(edges.shape, dtype=complex)
    else:
        blocks = _EdgeBlocks(top.D, len(t))
    energies, converged, move = [], False, np.inf
    timing = {"assemble": 0.0, "edges": 0.0}
    for it in range(1, max_iter + 1):
        t0 = time.perf_counter()
        if assembly == "shared":
            step = shared.update(z, free, edges[:, free], centroids)  # Eq. (10), Eq. (11)
        else:  # Eq. (10) with the paper's per-frame weights
            new = np.empty_like(z[:, free])
            for i, k in enumerate(np.arange(len(t))[free]):
                length = np.abs(edges[:, k])
                a = FrameAssembler(shape, 1.0 / np.maximum(length, 1e-9 * length.max()))
                new[:, i] = a.positions(edges[:, k : k + 1], centroids[:, i : i + 1])[:, 0]
            step = float(np.max(np.abs(new - z[:, free]), initial=0.0))  # Eq. (11)
            z[:, free] = new
        timing["assemble"] += time.perf_counter() - t0
        t0 = time.perf_counter()
        if it > 1:
            move = step
        converged = move < tol

        def work(rows, D_rows, out, converged=converged):
            e = D_rows @ z
            diag, lower, energy = normal_equations(e, h, scheme)  # Eq. (8), Eq. (6)
            if not converged:
                couplings = [(k, _turn(e, k), smooth / h[k]) for k in keys] if smooth else []
                out[rows] = solve_edges(e, diag, lower, fixed, couplings)  # Eq. (9)
            return energy

        if fused:  # the same as `work` on all edges at once
            energy = accelerated.midpoint_edge_pass(z, top.first, top.second, inv_h, not converged, out)
            edges = out
        else:
            edges, energy = blocks.map(work)
        energies.append(max(energy, 0.0) / norm)  # the expanded Eq. (6) can round below 0 at a rigid optimum
        timing["edges"] += time.perf_counter() - t0
        if callback is not None:
            callback(it, energies[-1], move)
        if converged:
            break
    if not fused:
        blocks.close()
    return z, {"energy": energies, "iterations": it, "converged": converged,
               "max_move": move, "timings": timing}


def _turn(e, k):
    """(E,) unit complex: per-step rotation of every edge around frame k."""
    omega = step_angle(e[:, k - 1] + e[:, k], 2 * (e[:, k] - e[:, k - 1]))
    omega += step_angle(e[:, k] + e[:, k + 1], 2 * (e[:, k + 1] - e[:, k]))
    return np.exp(0.5j * omega)


class _EdgeBlocks:
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
        if self.pool is not None:
            self.pool.shutdown()
