"""Initial guesses for the edge vectors of every frame (Sec. 4.3)."""

import numpy as np

__all__ = ["INITIALISERS", "edge_rotations", "edge_vector_init", "linear_init"]

INITIALISERS = ("edge", "linear")


def edge_vector_init(shape, e0, e1, t):
    """Eq. (13): e(t) = (1 - t + t s) R(t theta) e(0), for every edge and time.

    Angles as `edge_rotations` finds them; computed by the backend in use
    (:mod:`isotween.optimisation.backend`).

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

    t = np.asarray(t, dtype=float)
    if not shape.n_faces:
        return backend.current().edge_init(shape.topology, e0, e1, t)
    s, theta = edge_rotations(shape, e0, e1)
    return backend.current().edge_frames(e0, s, theta, t)


def edge_rotations(shape, e0, e1):
    """Eq. (12) with compatible angles: per-edge scale and rotation angle.

    Each edge's angle theta in (-pi, pi] is then shifted by multiples of 2 pi
    so that neighbours agree. On a triangle mesh the triangles decide
    (Baxter et al.'s propagation, Sec. 4.3): every triangle's rotation (the
    polar angle of its affine map from source to target, defined even where
    the map shears an edge half round) is propagated across shared sides
    along a breadth-first tree of the triangles, so that a child never
    differs from its parent by more than pi, and every edge of a triangle
    takes the turn nearest its triangle's. Edges in no triangle (polylines)
    follow a breadth-first traversal of the graph whose nodes are edges,
    adjacent when they share a vertex. One traversal per connected
    component, rooted at its lowest-numbered triangle (edge).

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

    s, theta = reference.edge_angles(shape.topology, e0, e1)
    if shape.n_faces:
        edge, sign, twin = _face_edges(shape)
        u0, v0 = sign[:, 0] * e0[edge[:, 0]], -sign[:, 2] * e0[edge[:, 2]]  # sides a->b and a->c
        u1, v1 = sign[:, 0] * e1[edge[:, 0]], -sign[:, 2] * e1[edge[:, 2]]
        # the face's map z -> p z + q conj(z) from source to target sides; its rotation is arg p
        det = u0 * np.conj(v0) - v0 * np.conj(u0)
        p = (u1 * np.conj(v0) - v1 * np.conj(u0)) / det
        q = (v1 * u0 - u1 * v0) / det
        kept = np.abs(p) > np.abs(q)  # a face turned over has no rotation: its sides follow the edge tree
        phi = _unwrapped(np.angle(p), _face_tree(twin, kept))
        raw = np.angle(np.asarray(e1) / np.asarray(e0))
        ref = np.full(shape.n_edges, np.nan)
        ref[edge[kept].ravel()] = np.repeat(phi[kept], 3)
        meshed = ~np.isnan(ref)
        theta[meshed] = raw[meshed] + 2 * np.pi * np.round((ref[meshed] - raw[meshed]) / (2 * np.pi))
    return s, theta


def _face_edges(shape):
    """Every face's sides a-b, b-c, c-a as edges of the shape, and their twins.

    Returns
    -------
    edge : (F, 3) int
        The edge index of every side.
    sign : (F, 3) float
        +1 where the edge runs along the side, -1 against it.
    twin : (3F,) int
        Every side's twin in the neighbouring face (`geometry.edge_table`), -1 on the boundary.
    """
    from .geometry import edge_table, face_sides

    top = shape.topology
    faces = np.asarray(shape.faces, dtype=np.int64)
    edge, sign = face_sides(faces, np.c_[top.first, top.second])
    return edge.reshape(-1, 3), sign.reshape(-1, 3), edge_table(faces)[4]


def _face_tree(twin, kept):
    """(F,) parent of every face in a breadth-first tree of ``kept`` faces adjacent across a side.

    ``twin`` (3F,) is every side's twin side (`_face_edges`). One root per
    connected component of the kept faces, its lowest face, all joined to a
    virtual root node that the traversal starts from; roots and faces not
    kept are their own parents.
    """
    import scipy.sparse as sp
    from scipy.sparse.csgraph import breadth_first_order, connected_components

    F = len(kept)
    side = np.flatnonzero(twin >= 0)
    u, v = side // 3, twin[side] // 3
    both = kept[u] & kept[v]
    adjacency = sp.coo_matrix((np.ones(int(both.sum())), (u[both], v[both])), shape=(F, F))
    first = np.unique(connected_components(adjacency, directed=False)[1], return_index=True)[1]
    rows, cols = np.r_[adjacency.row, np.full(len(first), F)], np.r_[adjacency.col, first]
    g = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(F + 1, F + 1))
    _, pred = breadth_first_order(g, F, directed=False, return_predecessors=True)
    pred = pred[:F]
    return np.where(pred == F, np.arange(F), pred)


def _unwrapped(angle, parent):
    """``angle`` (F,) shifted by whole turns so that no child differs from its tree parent by more than pi."""
    k = np.round((angle[parent] - angle) / (2 * np.pi))  # turns relative to the parent; 0 at the roots
    up = parent.copy()
    while not np.array_equal(up, up[up]):  # pointer doubling: k sums the turns along the path to the root
        k = k + k[up]
        up = up[up]
    k = k + k[up] * (up != np.arange(len(up)))
    return angle + 2 * np.pi * k


def linear_init(shape, z0, z1, t):
    """Edge vectors of the linear blend of vertex positions: (E, F) complex."""
    t = np.asarray(t)[None, :]
    return shape.edge_vectors(z0)[:, None] * (1 - t) + shape.edge_vectors(z1)[:, None] * t
