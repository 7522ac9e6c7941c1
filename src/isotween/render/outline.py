"""The outline of a triangle mesh: its boundary loops (numpy only)."""

import numpy as np

__all__ = ["mesh_boundary", "edge_chains"]


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


def edge_chains(edges):
    """Few open walks that pass along every edge once (a path cover of the edge graph).

    Walks start at vertices of odd degree first (each such vertex must end
    one; the dead ends before the others), so a graph whose vertices all have even degree is covered by
    closed walks, written open (the first vertex repeated at the end).

    Parameters
    ----------
    edges : (E, 2) int array

    Returns
    -------
    list of (k,) int64 array
        Vertex indices of every walk (k >= 2); together they hold every
        edge exactly once.

    Examples
    --------
    >>> [w.tolist() for w in edge_chains([[0, 1], [1, 2], [2, 0], [2, 3]])]
    [[3, 2, 0, 1, 2]]
    """
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    if not len(edges):
        return []
    adjacent = {}
    for k, (i, j) in enumerate(edges.tolist()):
        adjacent.setdefault(i, []).append((j, k))
        adjacent.setdefault(j, []).append((i, k))
    used = np.zeros(len(edges), dtype=bool)
    degree = np.bincount(edges.ravel())
    odd = np.flatnonzero(degree % 2 == 1)
    starts = np.concatenate([odd[np.argsort(degree[odd], kind="stable")],  # dead ends first
                             np.flatnonzero((degree > 0) & (degree % 2 == 0))])
    walks = []
    for start in starts.tolist():
        while True:
            walk, v = [start], start
            while True:
                nbrs = adjacent[v]
                while nbrs and used[nbrs[-1][1]]:
                    nbrs.pop()
                if not nbrs:
                    break
                w, k = nbrs.pop()
                used[k] = True
                walk.append(w)
                v = w
            if len(walk) < 2:
                break
            walks.append(np.asarray(walk, dtype=np.int64))
    return walks
