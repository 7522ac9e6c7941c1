"""Initial guesses for the edge vectors of every frame (Sec. 4.3)."""

import numpy as np

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
    if shape.n_edges == 0:
        ratio = np.asarray(e1) / np.asarray(e0)
        return np.abs(ratio), np.angle(ratio)
    from .optimisation import reference

    return reference.edge_angles(shape.topology, e0, e1)


def edge_vector_init(shape, e0, e1, t):
    """Eq. (13): e(t) = (1 - t + t s) R(t theta) e(0), for every edge and time.

    Computed by the backend in use (:mod:`isotween.optimisation.backend`).

    Parameters
    ----------
    shape : Shape
    e0, e1 : (E,) complex
    t : (F,) float

    Returns
    -------
    (E, F) complex
    """
    from .optimisation import backend  # the solver's kernels: imported by the first solve, not by the CLI's options

    return backend.current().edge_init(shape.topology, e0, e1, np.asarray(t, dtype=float))


def linear_init(shape, z0, z1, t):
    """Edge vectors of the linear blend of vertex positions: (E, F) complex."""
    t = np.asarray(t)[None, :]
    return shape.edge_vectors(z0)[:, None] * (1 - t) + shape.edge_vectors(z1)[:, None] * t
