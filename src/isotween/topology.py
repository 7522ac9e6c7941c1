"""Connectivity-only data of a shape.

Computed once and shared by every shape with the same connectivity
(``Shape.topology``; ``with_vertices`` keeps it).
"""

import functools

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order, reverse_cuthill_mckee

__all__ = ["Topology"]


class Topology:
    """Incidence, component averaging, anchors and the edge traversal tree.

    Parameters
    ----------
    edges : (E, 2) int array
    n : int
        Vertex count.
    components : (n,) int array
    n_components : int

    Attributes
    ----------
    first, second : (E,) int
        Edge end points, contiguous.
    D : (E, n) sparse csr
        Incidence: (D z)_e = z_j - z_i for edge e = (i, j).
    inv_count : (C,) float
        1 / vertex count of every component.
    avg : (C, n) sparse csr
        (avg z)_c = centroid of component c.
    anchors : (C,) int
        Lowest vertex of every component (pinned during Eq. 10 solves).
    free : (n_free,) int
        All other vertices.
    D_free : (E, n_free) sparse csc
        Incidence restricted to the free vertices.
    parent : (E,) int
        Parent of every edge in a breadth-first tree of the graph whose nodes
        are edges, adjacent when they share a vertex (roots are their own parent).
    tree_order : (E,) int
        The edges in breadth-first order (every parent before its children).
    ancestors : list of (E,) int arrays
        ``parent`` composed with itself 1, 2, 4, ... times (pointer doubling).
    """

    def __init__(self, edges, n, components, n_components):
        E = len(edges)
        self.edges, self.n, self.n_edges = edges, n, E
        self.first, self.second = np.ascontiguousarray(edges.T)  # e = z[second] - z[first]
        self.components, self.n_components = components, n_components
        rows = np.repeat(np.arange(E), 2)
        self.D = sp.csr_matrix((np.tile([-1.0, 1.0], E), (rows, edges.ravel())), shape=(E, n))
        counts = np.bincount(components, minlength=n_components)
        self.inv_count = 1.0 / counts
        self.avg = sp.csr_matrix((1.0 / counts[components], (components, np.arange(n))),
                                 shape=(n_components, n))
        self.anchors = np.unique(components, return_index=True)[1]
        self.free = np.setdiff1d(np.arange(n), self.anchors)
        self.D_free = self.D[:, self.free].tocsc()
        self.D_free_T = self.D_free.T.tocsr()
        self.parent, self.tree_order = _edge_tree(edges, n, components)
        self.ancestors = []
        up = self.parent
        while np.any(up != np.arange(E)):
            self.ancestors.append(up)
            if np.all(up[up] == up):
                break
            up = up[up]

    @functools.cached_property
    def laplacian_pattern(self):
        """Where every edge's weight goes in the Laplacian of the free vertices.

        Returns
        -------
        edge : (k,) int
            Edge of every contribution.
        sign : (k,) float
            +1 on the diagonal, -1 off it.
        slot : (k,) int
            Index into the compressed (CSC, row indices sorted) data array.
        indices, indptr : int arrays
            The CSC structure of the (n_free, n_free) matrix.
        """
        nf = self.free.size
        pos = -np.ones(self.n, dtype=np.int64)
        pos[self.free] = np.arange(nf)
        a, b = pos[self.edges[:, 0]], pos[self.edges[:, 1]]
        E = np.arange(self.n_edges)
        rows = np.concatenate([a, b, a, b])
        cols = np.concatenate([a, b, b, a])
        edge = np.concatenate([E, E, E, E])
        sign = np.concatenate([np.ones(2 * len(E)), -np.ones(2 * len(E))])
        keep = (rows >= 0) & (cols >= 0)
        rows, cols, edge, sign = rows[keep], cols[keep], edge[keep], sign[keep]
        linear, slot = np.unique(cols * nf + rows, return_inverse=True)  # column-major = CSC order
        col_of = linear // max(nf, 1)
        indptr = np.searchsorted(col_of, np.arange(nf + 1))
        indices = linear % max(nf, 1)
        return edge, sign, slot.ravel(), indices, indptr

    @functools.cached_property
    def band_pattern(self):
        """The free-vertex Laplacian in banded form (reverse Cuthill-McKee order).

        Returns
        -------
        rows : (n_free,) int
            Vertex of every banded row.
        bw : int
            Bandwidth in that order.
        edge, sign : (k,) int and float
            Every contribution to the lower band (as in ``laplacian_pattern``).
        position : (k,) int
            Its flat index in the (n_free, bw + 1) C-ordered band, band[j, i - j] = L[i, j].
        D_free_T : (n_free, E) sparse csr
            Incidence transposed, rows in banded order.
        """
        edge, sign, slot, indices, indptr = self.laplacian_pattern
        nf = self.free.size
        rows, cols = indices[slot], np.searchsorted(indptr, slot, side="right") - 1
        pattern = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(nf, nf))
        order = reverse_cuthill_mckee(pattern, symmetric_mode=True).astype(np.int64)
        rank = np.empty(nf, dtype=np.int64)
        rank[order] = np.arange(nf)
        i, j = rank[rows], rank[cols]
        lower = i >= j
        bw = int((i - j).max(initial=0))
        return (self.free[order], bw, edge[lower], sign[lower], j[lower] * (bw + 1) + (i - j)[lower],
                self.D_free_T[order].tocsr())

    def centroids(self, z):
        """(C,) or (C, F) complex: centroid of every component of (n,) or (n, F) positions."""
        if self.n_components == 1:
            return np.add.reduce(z, axis=0, keepdims=True) / self.n
        return self.avg @ z

    def path_sums(self, d):
        """(E,) sums of ``d`` over every edge's path to its tree root (root excluded)."""
        k = np.array(d, dtype=float)
        for up in self.ancestors:
            k += k[up] * (up != np.arange(len(up)))
        return k


def _edge_tree(edges, n, components):
    """Breadth-first tree over edges, one root (lowest edge) per component: (parent, order).

    Runs on the edge-vertex incidence graph (E edge nodes, n vertex nodes and a
    virtual root): every second level of it is a level of the graph of edges,
    which is never built (its size is quadratic in vertex degree).
    """
    E = len(edges)
    if E == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    root = E + n
    first = np.unique(components[edges[:, 0]], return_index=True)[1]
    rows = np.concatenate([np.arange(E), np.arange(E), np.full(len(first), root)])
    cols = np.concatenate([E + edges[:, 0], E + edges[:, 1], first])
    g = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(root + 1, root + 1))
    nodes, pred = breadth_first_order(g, root, directed=False, return_predecessors=True)
    via = pred[:E]  # vertex node (or the root) each edge was reached through
    parent = np.where(via == root, np.arange(E), pred[np.minimum(via, root)])
    return parent, nodes[nodes < E].astype(np.int64)
