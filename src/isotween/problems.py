"""Solve problems of shapes held at key frames, shared by `interpolate` and `interpolate_keyframes`.

Two shapes held at the first and last frame (:func:`isotween.interpolate`) are
the two-key case of :func:`isotween.interpolate_keyframes`; both build their
:class:`~isotween.optimisation.problem.Problem` with :func:`keyed_problem` and
check their options with the functions here.
"""

from __future__ import annotations

import numbers
from typing import TYPE_CHECKING

import numpy as np

from .errors import ParameterError, ShapeError
from .initialisation import INITIALISERS, edge_vector_init, linear_init
from .optimisation.assembly import centroid_path
from .optimisation.problem import Problem

if TYPE_CHECKING:
    from collections.abc import Sequence as Seq

    from .shape import Shape

__all__ = ["check_choice", "check_movable", "check_stopping", "keyed_problem"]


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
    if isinstance(tol, bool) or not (isinstance(tol, numbers.Real) and np.isfinite(tol) and tol > 0):
        raise ParameterError(f"tol must be a positive number, got {tol!r}")
    if isinstance(max_iter, bool) or not (isinstance(max_iter, numbers.Integral) and max_iter >= 1):
        raise ParameterError(f"max_iter must be an integer >= 1, got {max_iter!r}")


def check_choice(name, value, choices):
    """Refuse a ``value`` of option ``name`` that is not one of ``choices``."""
    if value not in choices:
        raise ParameterError(f"unknown {name} {value!r}; choose one of {', '.join(choices)}")


def keyed_problem(shapes: Seq[Shape], t: np.ndarray, idx: np.ndarray, *, init: str, scheme: str,
                  tol: float, max_iter: int, diagonal: float) -> Problem:
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
    init : {'edge', 'linear'}
        Initial edges per segment: Eqs. (12)-(13) or the linear blend.
    scheme : {'midpoint', 'paper'}
    tol : float
        Eq. (11) relative to ``diagonal``.
    max_iter : int
    diagonal : float
        Bounding-box diagonal of all keyframes together.

    Returns
    -------
    Problem
        Centroids blended linearly for two keyframes, along a natural cubic
        spline through the keyframes' centroids for more.
    """
    check_choice("init", init, INITIALISERS)
    base, K = shapes[0], len(shapes)
    zk = np.stack([s.z for s in shapes], axis=1)  # (n, K)
    ek = [base.edge_vectors(zk[:, j]) for j in range(K)]
    edges = np.empty((base.n_edges, len(t)), dtype=complex)
    for j in range(K - 1):  # Eq. (13) (or linear) per segment
        a, b = idx[j], idx[j + 1]
        u = (t[a : b + 1] - t[a]) / (t[b] - t[a])
        if init == "edge":
            edges[:, a : b + 1] = edge_vector_init(base, ek[j], ek[j + 1], u)
        else:
            edges[:, a : b + 1] = linear_init(base, zk[:, j], zk[:, j + 1], u)
    if K == 2:
        centroids = centroid_path(base, zk[:, 0], zk[:, 1], t)
    else:
        from scipy.interpolate import CubicSpline  # imported here: scipy.interpolate takes 0.3 s

        key_t = t[idx]
        centroids = CubicSpline(key_t, (base.topology.avg @ zk).T, bc_type="natural")(t).T
    z = np.zeros((base.n_vertices, len(t)), dtype=complex)
    z[:, idx] = zk
    held = np.zeros(len(t), dtype=bool)
    held[idx] = True
    return Problem(base, t, held, z, edges, centroids, scheme, tol * diagonal, max_iter)
