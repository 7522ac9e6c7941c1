"""Problems of shapes held at key frames: the one builder every entry point uses.

Every :class:`~isotween.optimisation.problem.Problem` is made by
:func:`held_problem`. :func:`keyed_problem` adds the initial edges and the
centroid paths of key shapes: two shapes held at the first and last frame
(:func:`isotween.interpolate`, the baselines of :func:`isotween.baselines.run`)
are the two-key case of :func:`isotween.interpolate_keyframes`. Shape transfer
and sequence editing build theirs from the edges of Eq. (15) and solve it by
:func:`assemble`. The option checks shared by the entry points are here too.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._validate import check_choice, check_int, check_number
from .errors import ParameterError, ShapeError
from .initialisation import INITIALISERS, edge_vector_init, linear_init
from .optimisation.assembly import FrameAssembler, assembler_for, centroid_path
from .optimisation.problem import Problem, Result, bbox_diagonal

if TYPE_CHECKING:
    from collections.abc import Sequence as Seq

    from .shape import Shape

__all__ = ["assemble", "check_choice", "check_movable", "check_stopping", "held_problem", "keyed_problem"]


def check_movable(shape, name="source"):
    """Refuse a shape with no edge: there is nothing to keep isometric.

    Raises
    ------
    ShapeError
        Naming ``name`` and its vertex count.
    """
    if shape.n_edges == 0:
        what = "no vertices" if shape.n_vertices == 0 else f"{shape.n_vertices} vertex(es) but no edges"
        raise ShapeError(f"{name} has {what}; interpolation needs at least one edge (two vertices joined)")


def check_stopping(tol, max_iter):
    """Refuse a ``tol`` that is not a finite positive number or a ``max_iter`` below 1."""
    check_number("tol", tol)
    check_int("max_iter", max_iter, 1)


def held_problem(shape: Shape, t: np.ndarray, idx: np.ndarray, zk: np.ndarray, *, centroids: np.ndarray,
                 edges: np.ndarray | None = None, scheme: str = "midpoint", tol: float = 0.0,
                 max_iter: int = 0) -> Problem:
    """The problem of frames ``t`` of ``shape`` with ``zk[:, j]`` held at frame ``idx[j]``.

    Parameters
    ----------
    shape : Shape
        Connectivity (edges, components).
    t : (F,) float
        Frame times (kept, not copied).
    idx : (K,) int
        Strictly increasing frame index of every held frame, K >= 1.
    zk : (n, K) complex
        Positions of the held frames.
    centroids : (C, F) complex
        Every component's centroid in every frame.
    edges : (E, F) complex, optional
        Initial edge vectors, exact on the held frames; None for methods
        that start from the held positions alone.
    scheme : {'midpoint', 'paper'}
    tol : float
        Absolute Eq. (11) tolerance of iterative solvers.
    max_iter : int
        0 for a problem whose edges are final (see :func:`assemble`).

    Returns
    -------
    Problem
        ``z`` is zero outside the held frames.

    Raises
    ------
    ParameterError
        ``idx`` is empty, out of range or not increasing.
    """
    idx = np.asarray(idx)
    F = len(t)
    if idx.ndim != 1 or not idx.size or idx[0] < 0 or idx[-1] >= F or np.any(np.diff(idx) <= 0):
        raise ParameterError(f"held frames must be increasing indices in 0..{F - 1}, got {idx.tolist()}")
    z = np.zeros((shape.n_vertices, F), dtype=complex)
    z[:, idx] = zk
    held = np.zeros(F, dtype=bool)
    held[idx] = True
    return Problem(shape, t, held, z, edges, centroids, scheme, tol, max_iter)


def keyed_problem(shapes: Seq[Shape], t: np.ndarray, idx: np.ndarray, *, init: str | None, scheme: str,
                  tol: float, max_iter: int, diagonal: float | None = None) -> Problem:
    """The problem of frames ``t`` with ``shapes[j]`` held at frame ``idx[j]``.

    Parameters
    ----------
    shapes : list of K >= 2 Shape
        Compatible; the first gives the connectivity.
    t : (F,) float
        Frame times; ``t[idx]`` are the keyframe times, ``idx[0] = 0`` and
        ``idx[-1] = F - 1``.
    idx : (K,) int
        Strictly increasing frame index of every keyframe.
    init : {'edge', 'linear'} or None
        Initial edges per segment: Eqs. (12)-(13) or the linear blend; None
        for none (methods that blend the key positions: the baselines).
    scheme : {'midpoint', 'paper'}
    tol : float
        Eq. (11) relative to ``diagonal``.
    max_iter : int
    diagonal : float, optional
        Bounding-box diagonal of all keyframes together (computed when not given).

    Returns
    -------
    Problem
        Centroids blended linearly for two keyframes, along a natural cubic
        spline through the keyframes' centroids for more.
    """
    if init is not None:
        check_choice("init", init, INITIALISERS)
    base, K = shapes[0], len(shapes)
    zk = np.stack([s.z for s in shapes], axis=1)  # (n, K)
    if diagonal is None:
        diagonal = bbox_diagonal(*(s.vertices for s in shapes))
    edges = None
    if init is not None:
        ek = [base.edge_vectors(zk[:, j]) for j in range(K)]

        def segment(j):  # Eq. (13) (or linear) from key j to key j + 1
            a, b = idx[j], idx[j + 1]
            u = (t[a : b + 1] - t[a]) / (t[b] - t[a])
            if init == "edge":
                return edge_vector_init(base, ek[j], ek[j + 1], u)
            return linear_init(base, zk[:, j], zk[:, j + 1], u)

        if K == 2 and idx[0] == 0 and idx[1] == len(t) - 1:
            edges = segment(0)  # the whole range: no copy of the (E, F) edges
        else:
            edges = np.empty((base.n_edges, len(t)), dtype=complex)
            for j in range(K - 1):
                edges[:, idx[j] : idx[j + 1] + 1] = segment(j)
    if K == 2:
        centroids = centroid_path(base, zk[:, 0], zk[:, 1], t, turn=True)
    else:
        from scipy.interpolate import CubicSpline  # imported here: scipy.interpolate takes 0.3 s

        key_t = t[idx]
        centroids = CubicSpline(key_t, (base.topology.avg @ zk).T, bc_type="natural")(t).T
    return held_problem(base, t, idx, zk, centroids=centroids, edges=edges, scheme=scheme, tol=tol * diagonal,
                        max_iter=max_iter)


def assemble(problem: Problem, weights: np.ndarray, owner: object = None) -> Result:
    """Solve a problem whose edges are final: Eq. (10) at every free frame.

    Shape transfer and sequence editing find their edge vectors in closed
    form (Eq. 15); the positions follow from one factorisation of the
    weighted Laplacian for all free frames, each component's centroid put
    where ``problem.centroids`` says. The held frames are kept bit for bit.

    Parameters
    ----------
    problem : Problem
        With ``edges``; its ``z`` is filled in and returned.
    weights : (E,) float
        w_ij of Eq. (10).
    owner : object, optional
        Keeps the factorisation for the next solve with the same shape and
        weights (`optimisation.assembly.assembler_for`), e.g. the sequence
        that is edited again and again.

    Returns
    -------
    Result
        ``z`` is ``problem.z``; no iterations.

    Raises
    ------
    ParameterError
        The problem has no edges.
    """
    if problem.edges is None:
        raise ParameterError("assembling frames needs the problem's edges; this problem has none")
    free = problem.free
    if not problem.held.all():
        asm = FrameAssembler(problem.shape, weights) if owner is None else assembler_for(owner, problem.shape, weights)
        problem.z[:, free] = asm.positions(problem.edges[:, free], problem.centroids[:, free])  # Eq. (10)
    return Result(problem.z)
