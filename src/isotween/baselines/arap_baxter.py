"""ARAP interpolation with consistent rotations (Baxter et al. 2008).

The same per-triangle blend and least-squares (normal-equation) solve as
:mod:`isotween.baselines.arap`, but the rotation angles are made consistent
first: a breadth-first traversal of the dual graph (triangles adjacent across
a shared side) gives every triangle the multiple of 2 pi that brings its angle
closest to its parent's. A shape curled by more than half a turn then unrolls
the way it came instead of letting some triangles spin backwards.
"""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order, connected_components

from . import arap

__all__ = ["solve", "propagate_angles"]


def propagate_angles(faces, theta, n_vertices):
    """Shift every triangle's angle by 2 pi k to within pi of its BFS parent's.

    Parameters
    ----------
    faces : (T, 3) int
    theta : (T,) float
        Angles in (-pi, pi].
    n_vertices : int

    Returns
    -------
    (T,) float
        Consistent angles; each dual-graph component keeps its root's (lowest
        triangle's) angle.
    """
    T = len(faces)
    sides = np.sort(np.c_[faces.ravel(), faces[:, [1, 2, 0]].ravel()], axis=1) @ [n_vertices, 1]
    tri = np.repeat(np.arange(T), 3)
    order = np.argsort(sides, kind="stable")
    same = sides[order[1:]] == sides[order[:-1]]  # a side shared by two triangles
    a, b = tri[order[:-1]][same], tri[order[1:]][same]
    dual = sp.csr_matrix((np.ones(len(a)), (a, b)), shape=(T, T))
    _, label = connected_components(dual, directed=False)
    parent = np.arange(T)
    for root in np.unique(label, return_index=True)[1]:  # one traversal per component
        nodes, pred = breadth_first_order(dual, root, directed=False, return_predecessors=True)
        parent[nodes[1:]] = pred[nodes[1:]]
    # k_child = k_parent + round((theta_parent - theta_child) / 2 pi): sum the
    # steps along every path to the root by pointer doubling
    k = np.round((theta[parent] - theta) / (2 * np.pi))
    up = parent
    while np.any(up != up[up]):
        k, up = k + k[up], up[up]
    return theta + 2 * np.pi * k


def solve(problem):
    """Frames of the consistent-rotation ARAP interpolation; see :func:`isotween.baselines.arap.solve`."""
    return arap.solve(problem, method="arap-baxter", propagate=propagate_angles)
