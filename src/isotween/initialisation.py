"""Initial guesses for the edge vectors of every frame (Sec. 4.3)."""

import numpy as np

from .optimisation import accelerated

__all__ = ["INITIALISERS", "edge_rotations", "edge_vector_init", "linear_init"]

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
    if shape.n_edges == 0:
        return s, theta
    # k_child = k_parent + round((theta_parent - theta_child) / 2 pi), summed
    # along every path to the root of the breadth-first tree
    top = shape.topology
    k = top.path_sums(np.round((theta[top.parent] - theta) / (2 * np.pi)))
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
    if accelerated.ENABLED:
        return accelerated.edge_init(shape.topology, e0, e1, np.asarray(t, dtype=float))
    s, theta = edge_rotations(shape, e0, e1)
    t = np.asarray(t, dtype=float)
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


def linear_init(shape, z0, z1, t):
    """Edge vectors of the linear blend of vertex positions: (E, F) complex."""
    t = np.asarray(t)[None, :]
    return shape.edge_vectors(z0)[:, None] * (1 - t) + shape.edge_vectors(z1)[:, None] * t
