"""Benchmark shapes with the vertex and edge counts of the paper's Table 1.

The paper's shapes are not public. Each case here is a triangulated bar
(two-row strips for the thin examples, a few rows for the larger ones) trimmed
to exactly the table's vertex count, with interior diagonals removed or chords
added until the edge count matches too, and bent by 180 degrees (the paper's
examples are bending characters and snakes).
"""

import numpy as np

from isotween import Shape
from isotween._heap import keep_heap

keep_heap()  # the malloc tuning the command line applies (opt-in for library users)

# name, vertices, edges, paper iterations (9/45/205 frames), paper seconds (AIAP), Kilian seconds
TABLE1 = [
    ("Fig. 1", 99, 211, (5, 3, 2), (0.205, 0.421, 0.842), (1.529, 18.783, 137.92)),
    ("Fig. 3", 108, 225, (2, 2, 2), (0.055, 0.234, 0.827), (0.643, 3.299, 42.407)),
    ("Fig. 7", 467, 1072, (2, 2, 2), (0.234, 0.998, 4.118), (3.931, 168.18, 1592.4)),
    ("Fig. 10", 272, 597, (2, 2, 2), (0.25, 0.562, 2.324), (1.592, 15.21, 294.4)),
    ("Fig. 8", 92, 198, (2, 2, 2), (0.103, 0.218, 0.759), (1.123, 16.344, 150.5)),
    ("Fig. 15", 20, 40, (3, 2, 2), (0.046, 0.104, 0.257), (0.327, 1.607, 6.155)),
]
FRAMES = (9, 45, 205)


def bar_with_counts(n_vertices, n_edges, rows=None):
    """A triangulated bar with exactly the given vertex and edge counts.

    Returns
    -------
    Shape
        Vertices on a grid of ``rows`` rows and unit spacing, lying along x.
    """
    rows = rows or (2 if n_edges < 2.6 * n_vertices else 4)
    cols = -(-n_vertices // rows)
    x, y = np.divmod(np.arange(n_vertices), rows)
    v = np.c_[x, y].astype(float)
    idx = -np.ones((cols, rows), dtype=int)
    idx.flat[:n_vertices] = np.arange(n_vertices)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    tri = np.vstack([np.c_[a, b, c], np.c_[a, c, d]])
    tri = tri[np.all(tri >= 0, axis=1)]
    edges = Shape(v, faces=tri).edges
    diagonal = (v[edges[:, 0], 0] != v[edges[:, 1], 0]) & (v[edges[:, 0], 1] != v[edges[:, 1], 1])
    if len(edges) > n_edges:  # drop diagonals, evenly spread
        drop = np.flatnonzero(diagonal)[:: 2][: len(edges) - n_edges]
        edges = np.delete(edges, drop, axis=0)
        tri = None
    if len(edges) < n_edges:  # add chords two columns apart along the rows
        i = np.arange(n_vertices)
        j = i + 2 * rows
        ok = j < n_vertices
        extra = np.c_[i[ok], j[ok]][: n_edges - len(edges)]
        edges = np.vstack([edges, extra])
    assert len(edges) == n_edges, (n_vertices, n_edges, len(edges))
    return Shape(v, edges, faces=tri if tri is not None and len(edges) == len(Shape(v, faces=tri).edges) else None)


def bent(shape, angle=np.pi):
    """The shape bent about its middle row into an arc of `angle` radians."""
    x, y = shape.vertices[:, 0], shape.vertices[:, 1]
    R = x.max() / angle
    r = R - (y - 0.5 * (y.min() + y.max()))
    return shape.with_vertices(np.c_[r * np.sin(x / R), R - r * np.cos(x / R)])


def table1_pair(n_vertices, n_edges):
    """(source, target) for one Table 1 row."""
    src = bar_with_counts(n_vertices, n_edges)
    return src, bent(src)


def mesh_pair(nx, ny, angle=np.pi):
    """A dense triangulated bar of nx x ny vertices and the same bar bent."""
    x, y = np.meshgrid(np.arange(nx, dtype=float), np.linspace(0, ny - 1, ny), indexing="ij")
    v = np.c_[x.ravel(), y.ravel()]
    idx = np.arange(nx * ny).reshape(nx, ny)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    src = Shape.from_mesh(v, np.vstack([np.c_[a, b, c], np.c_[a, c, d]]))
    return src, bent(src, angle)
