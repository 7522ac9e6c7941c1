"""Algorithm 2: the local solver.

Each iteration assembles every frame from the current edge vectors (Eq. 10),
fits the angular speeds to the assembled frames (Eq. 8) and re-solves every
edge's vector sequence (Eq. 9), until the assembled frames move less than the
tolerance (Eq. 11). The edge work runs on the compute backend in use
(:mod:`isotween.optimisation.backend`). Arrays are laid out with time last:
edges (E, m+1), vertices (n, m+1).
"""

import time

import numpy as np

from . import backend
from .assembly import FrameAssembler
from .problem import Result

__all__ = ["ASSEMBLY", "local_solve"]

ASSEMBLY = ("shared", "relative", "per-frame")
GROW = 2.0  # a solve whose first iterate folds stops once its iterates fold more than this many times as often


def local_solve(problem, *, assembly="shared", smooth=1.0, factorisation="auto", callback=None, folds=None):
    """Run Algorithm 2.

    Parameters
    ----------
    problem : Problem
        Shape, times, held frames, initial edges (overwritten: the solver
        reuses the array), centroids, scheme, absolute tolerance, max_iter
        (:class:`~isotween.optimisation.problem.Problem`).
    assembly : {'shared', 'relative', 'per-frame'}
        'per-frame' uses the paper's weights w = 1/|e_ij(t_k)| with a new
        factorisation per frame and iteration; 'shared' factorises once with
        w = 2 / (|e(0)| + |e(1)|) for all frames and iterations; 'relative'
        once with the square of that, so every edge's residual counts
        relative to its length (short edges, e.g. of a small copy that
        grows, are held as firmly as long ones).
    smooth : float
        Weight of the term that lets the velocity turn smoothly through an
        interior held frame (see :func:`~isotween.optimisation.edge_solve.solve_edges`).
    factorisation : {'auto', 'banded', 'cholmod', 'splu'}
        Factorisation of the shared Eq. (10) Laplacian (see `FrameAssembler`).
    callback : callable(iteration, energy, max_move), optional
    folds : callable(z) -> int, optional
        Counts the folds of every iterate's frames ``z`` (n, m+1) complex
        (e.g. flipped triangles over all frames). Where the first iterate has
        none, the solve stops before the first that has some and returns the
        one before it (its iteration the result's ``iterations``;
        ``info['stopped']``: ``{'iteration': it, 'of': the one refused}``);
        where the first folds, it stops at the first iterate with more than
        `GROW` times the first's folds (``info['spread']``: ``{'iteration':
        it, 'first': count, 'now': count}``): there the folds spread with
        every iteration, and a fold-free repair works on what is left.

    Returns
    -------
    Result
        ``z`` (n, m+1) complex; energy per iteration, iterations, converged,
        max_move and the timings of the two stages.
    """
    shape, t, fixed, edges = problem.shape, problem.times, problem.held, problem.edges
    e0 = edges[:, 0]
    norm = float(np.add.reduce(e0.real**2 + e0.imag**2))  # not BLAS: no threads
    norm = norm if norm > 0.0 else 1.0  # no edges (or all of zero length): energy 0, not 0 / 0
    free = problem.free
    centroids = problem.centroids[:, free]
    z = problem.z.copy()
    if assembly != "per-frame":
        weights = 2.0 / (np.abs(edges[:, 0]) + np.abs(edges[:, -1]))
        shared = FrameAssembler(shape, weights**2 if assembly == "relative" else weights, factorisation=factorisation)
    edge_pass = backend.current().edge_pass(shape.topology, t, problem.scheme, fixed, smooth)
    edge_pass.reuse(edges)
    energies, converged, move, info = [], False, np.inf, {}
    kept = None if folds is None else np.empty_like(z)  # the last iterate with no fold (one buffer, reused)
    first = 0  # the first iterate's folds
    timing = {"assemble": 0.0, "edges": 0.0}
    for it in range(1, problem.max_iter + 1):
        t0 = time.perf_counter()
        if assembly != "per-frame":
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
        if folds is not None:
            count = folds(z)
            if it == 1:
                first = count
            if not first and not count:
                np.copyto(kept, z)
            elif not first:  # the last iterate with no fold (the one before), and no further
                z, info = kept, {"stopped": {"iteration": it - 1, "of": it}}
                it -= 1
                break
            elif count > GROW * first:  # the folds spread: the iterations stop after this one
                info = {"spread": {"iteration": it, "first": first, "now": count}}
        t0 = time.perf_counter()
        if it > 1:
            move = step
        converged = move < problem.tol
        edges, energy = edge_pass(z, not (converged or info))  # Eqs. (8), (6) and, unless it stops, (9)
        energies.append(max(energy, 0.0) / norm)  # the expanded Eq. (6) can round below 0 at a rigid optimum
        timing["edges"] += time.perf_counter() - t0
        if callback is not None:
            callback(it, energies[-1], move)
        if converged or info:
            break
    edge_pass.close()
    return Result(z, energies, it, converged, move, timing, info)
