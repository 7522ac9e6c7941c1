"""Initial guesses for the edge vectors of every frame (Sec. 4.3)."""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order

from .errors import ParameterError

__all__ = ["INITIALISERS", "edge_rotations", "edge_vector_init", "linear_init", "initial_edges"]

INITIALISERS = ("edge", "linear")


def edge_rotations(shape, e0, e1):
    """Eq. (12) with compatible angles: per-edge scale and rotation angle.

    Each edge's angle theta in (-pi, pi] is then shifted by multiples of 2 pi
    along a breadth-first traversal of the graph whose nodes are edges, adjacent
    when they share a vertex, so that a child never differs from its parent by
    more than pi (Baxter et al.'s propagation, Sec. 4.3). One traversal per
    connected component, rooted at its lowest-numbered edge.

    Parameters
    ----------
    shape : Shape
    e0, e1 : (E,) complex
        Source and target edge vectors.

    Returns
    -------
    s : (E,) float
        Scale factors |e1| / |e0|.
    theta : (E,) float
        Propagated rotation angles.
    """
    ratio = e1 / e0
    s, theta = np.abs(ratio), np.angle(ratio)
    E, n = shape.n_edges, shape.n_vertices
    if E == 0:
        return s, theta
    # Breadth-first search on the edge-vertex incidence graph (nodes: E edges, n
    # vertices, one virtual root). Every second level is a level of the graph
    # of edges; this avoids building that graph, quadratic in vertex degree.
    root = E + n
    comp_of_edge = shape.components[shape.edges[:, 0]]
    first = np.unique(comp_of_edge, return_index=True)[1]
    rows = np.concatenate([np.arange(E), np.arange(E), np.full(len(first), root)])
    cols = np.concatenate([E + shape.edges[:, 0], E + shape.edges[:, 1], first])
    g = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(root + 1, root + 1))
    _, pred = breadth_first_order(g, root, directed=False, return_predecessors=True)
    via = pred[:E]  # vertex node (or the root) each edge was reached through
    parent = np.where(via == root, np.arange(E), pred[np.minimum(via, root)])
    # k_child = k_parent + round((theta_parent - theta_child) / 2 pi): sum the
    # local jumps along every root path by pointer doubling (log depth steps)
    k = np.round((theta[parent] - theta) / (2 * np.pi))
    up = parent.copy()
    while np.any(up[up] != up):
        k += np.where(up != np.arange(E), k[up], 0.0)
        up = up[up]
    return s, theta + 2 * np.pi * k


def edge_vector_init(shape, e0, e1, t):
    """Eq. (13): e(t) = (1 - t + t s) R(t theta) e(0), for every edge and time.

    Parameters
    ----------
    shape : Shape
    e0, e1 : (E,) complex
    t : (F,) float

    Returns
    -------
    (E, F) complex
    """
    s, theta = edge_rotations(shape, e0, e1)
    t = np.asarray(t, dtype=float)
    h = np.diff(t)
    if len(h) and np.allclose(h, h[0], rtol=1e-12, atol=0):
        # uniform times: R(t_k theta) = R(h theta)^k, one complex exp per edge
        rot = np.empty((len(theta), len(t)), dtype=complex)
        rot[:, 0] = 1.0
        rot[:, 1:] = np.exp(1j * h[0] * theta)[:, None]
        rot = np.cumprod(rot, axis=1)
    else:
        phase = t[None, :] * theta[:, None]
        rot = np.cos(phase) + 1j * np.sin(phase)
    return (1 - t + t * s[:, None]) * rot * e0[:, None]


def linear_init(shape, z0, z1, t):
    """Edge vectors of the linear blend of vertex positions: (E, F) complex."""
    t = np.asarray(t)[None, :]
    return shape.edge_vectors(z0)[:, None] * (1 - t) + shape.edge_vectors(z1)[:, None] * t


def initial_edges(init, shape, z0, z1, t):
    """Dispatch on ``init`` ('edge' or 'linear'); returns (E, F) complex."""
    if init == "edge":
        return edge_vector_init(shape, shape.edge_vectors(z0), shape.edge_vectors(z1), t)
    if init == "linear":
        return linear_init(shape, z0, z1, t)
    raise ParameterError(f"unknown init {init!r}; choose one of {', '.join(INITIALISERS)}")
