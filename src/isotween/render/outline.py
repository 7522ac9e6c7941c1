"""The outline of a triangle mesh: its boundary loops (numpy only)."""

import numpy as np

__all__ = ["mesh_boundary"]


def mesh_boundary(faces):
    """Closed boundary loops of a triangle mesh.

    Boundary sides (those of one face only) keep their face's direction, so in
    a consistently oriented mesh they link up into directed loops.

    Parameters
    ----------
    faces : (F, 3) int array

    Returns
    -------
    list of (k,) int64 array
        Vertex indices of every loop (first vertex not repeated); empty when
        the boundary sides do not close into loops (an inconsistently
        oriented mesh), so that callers can fall back to the triangles.
    """
    faces = np.asarray(faces, dtype=np.int64)
    if not len(faces):
        return []
    sides = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    _, inverse, counts = np.unique(np.sort(sides, axis=1), axis=0, return_inverse=True, return_counts=True)
    boundary = sides[counts[inverse.ravel()] == 1]
    if not len(boundary):
        return []
    following = {}
    for i, j in boundary.tolist():
        following.setdefault(i, []).append(j)
    loops, used = [], 0
    for start in boundary[:, 0].tolist():
        if not following.get(start):
            continue
        loop, v = [start], following[start].pop()
        while v != start and following.get(v):
            loop.append(v)
            v = following[v].pop()
        if v != start:
            return []
        used += len(loop)
        loops.append(np.array(loop, dtype=np.int64))
    return loops if used == len(boundary) else []
