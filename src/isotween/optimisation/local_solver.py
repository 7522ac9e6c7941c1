"""Algorithm 2: the local solver.

Each iteration assembles every frame from the current edge vectors (Eq. 10),
fits the angular speeds to the assembled frames (Eq. 8) and re-solves every
edge's vector sequence (Eq. 9), until the assembled frames move less than the
tolerance (Eq. 11).
"""

import time

import numpy as np

from .assembly import FrameAssembler, centroid_path
from .edge_solve import solve_edges
from .schemes import coefficients, isometric_energy

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
    frames : (m+1, n) complex
    info : dict
        energy (list), iterations, converged, max_move.
    """
    h = np.diff(t)
    E0, E1 = edges[:, 0], edges[:, -1]
    centroids = centroid_path(shape, z0, z1, t[1:-1])
    if assembly == "shared":
        shared = FrameAssembler(shape, 2.0 / (np.abs(E0) + np.abs(E1)))
    frames = np.empty((len(t), len(z0)), dtype=complex)
    frames[0], frames[-1] = z0, z1
    energies, prev, converged, move = [], None, False, np.inf
    timing = {"assemble": 0.0, "edges": 0.0}
    for it in range(1, max_iter + 1):
        t0 = time.perf_counter()
        if assembly == "shared":
            frames[1:-1] = shared.positions(edges[:, 1:-1], centroids)
        else:  # Eq. (10) with the paper's per-frame weights
            for k in range(1, len(t) - 1):
                a = FrameAssembler(shape, 1.0 / np.abs(edges[:, k]))
                frames[k] = a.positions(edges[:, k : k + 1], centroids[k - 1 : k])[0]
        timing["assemble"] += time.perf_counter() - t0
        e = shape.edge_vectors(frames).T
        energies.append(isometric_energy(e, h, scheme))
        if prev is not None:
            move = float(np.max(np.abs(frames[1:-1] - prev), initial=0.0))  # Eq. (11)
        if callback is not None:
            callback(it, energies[-1], move)
        if move < tol:
            converged = True
            break
        prev = frames[1:-1].copy()
        t0 = time.perf_counter()
        edges = solve_edges(e, h, coefficients(e, scheme))  # Eq. (8) then Eq. (9)
        timing["edges"] += time.perf_counter() - t0
    return frames, {"energy": energies, "iterations": it, "converged": converged,
                    "max_move": move, "timings": timing}
