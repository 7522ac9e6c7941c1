"""Algorithm 2: the local solver.

Each iteration assembles every frame from the current edge vectors (Eq. 10),
fits the angular speeds to the assembled frames (Eq. 8) and re-solves every
edge's vector sequence (Eq. 9), until the assembled frames move less than the
tolerance (Eq. 11). Arrays are laid out with time last: edges (E, m+1),
vertices (n, m+1).
"""

import time

import numpy as np

from .assembly import FrameAssembler, centroid_path, incidence
from .edge_solve import solve_edges
from .schemes import normal_equations

__all__ = ["ASSEMBLY", "local_solve"]

ASSEMBLY = ("shared", "per-frame")


def local_solve(shape, z0, z1, t, edges, scheme, tol, max_iter, assembly="shared", callback=None):
    """Run Algorithm 2.

    Parameters
    ----------
    shape : Shape
    z0, z1 : (n,) complex
        Source and target vertices.
    t : (m+1,) float
        Frame times, t[0] = 0 and t[-1] = 1.
    edges : (E, m+1) complex
        Initial edge vectors (Eq. 13 or linear); columns 0 and m are the inputs'.
    scheme : {'midpoint', 'paper'}
    tol : float
        Absolute tolerance of Eq. (11) (tau times the bounding-box diagonal).
    max_iter : int
    assembly : {'shared', 'per-frame'}
        'per-frame' uses the paper's weights w = 1/|e_ij(t_k)| with a new
        factorisation per frame and iteration; 'shared' factorises once with
        w = 2 / (|e(0)| + |e(1)|) for all frames and iterations.
    callback : callable(iteration, energy, max_move), optional

    Returns
    -------
    z : (n, m+1) complex
        Vertex positions of every frame.
    info : dict
        energy (list), iterations, converged, max_move, timings.
    """
    h = np.diff(t)
    D = incidence(shape.edges, shape.n_vertices)
    norm = float(np.sum(np.abs(edges[:, 0]) ** 2))
    centroids = centroid_path(shape, z0, z1, t[1:-1])
    if assembly == "shared":
        shared = FrameAssembler(shape, 2.0 / (np.abs(edges[:, 0]) + np.abs(edges[:, -1])))
    z = np.empty((len(z0), len(t)), dtype=complex)
    z[:, 0], z[:, -1] = z0, z1
    energies, prev, converged, move = [], None, False, np.inf
    timing = {"assemble": 0.0, "edges": 0.0}
    for it in range(1, max_iter + 1):
        t0 = time.perf_counter()
        if assembly == "shared":
            z[:, 1:-1] = shared.positions(edges[:, 1:-1], centroids)  # Eq. (10)
        else:  # Eq. (10) with the paper's per-frame weights
            for k in range(1, len(t) - 1):
                a = FrameAssembler(shape, 1.0 / np.abs(edges[:, k]))
                z[:, k] = a.positions(edges[:, k : k + 1], centroids[:, k - 1 : k])[:, 0]
        timing["assemble"] += time.perf_counter() - t0
        t0 = time.perf_counter()
        e = D @ z
        diag, lower, energy = normal_equations(e, h, scheme)  # Eq. (8), Eq. (6)
        energies.append(energy / norm)
        if prev is not None:
            move = float(np.sqrt(np.max(np.abs(z[:, 1:-1] - prev) ** 2, initial=0.0)))  # Eq. (11)
        if callback is not None:
            callback(it, energies[-1], move)
        if move < tol:
            converged = True
            timing["edges"] += time.perf_counter() - t0
            break
        prev = z[:, 1:-1].copy()
        edges = solve_edges(e, diag, lower)  # Eq. (9)
        timing["edges"] += time.perf_counter() - t0
    return z, {"energy": energies, "iterations": it, "converged": converged,
               "max_move": move, "timings": timing}
