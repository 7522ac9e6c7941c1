"""Planar polygon primitives shared by the readers and the correspondence: ring areas, winding numbers, fill regions.

Rings are closed vertex loops (the closing edge implied), as ``(k,)`` complex
arrays or ``(k, 2)`` float arrays as each function says. This module imports
only numpy, so a reader (`isotween.io.svg`) can use it without loading the
correspondence.
"""

import numpy as np

__all__ = ["ring_area", "winding_numbers", "fill_regions"]


def ring_area(z):
    """Signed shoelace area of closed rings: (k,) complex -> float."""
    return 0.5 * float(np.sum((np.conj(z) * np.roll(z, -1)).imag))


#: most (point, edge) pairs whose crossing `winding_numbers` tests at once (bounds its memory: ~100 B a pair)
WINDING_CHUNK = 1 << 20


def winding_numbers(points, rings, sparse=False):
    """(m, R) winding number of every closed ring around every point.

    Only the (point, edge) pairs whose edge spans the point's height can
    cross the ray to the right of the point: with the points sorted by y,
    each edge's pairs are one range found by binary search, and the pairs
    are tested in chunks of at most `WINDING_CHUNK`, so memory follows the
    pairs that can cross (plus the nonzero results), never points x edges.

    Parameters
    ----------
    points : (m, 2) array
    rings : list of (k_r, 2) arrays
        Closed rings (the closing edge implied).
    sparse : bool
        Return a ``scipy.sparse.csr_array`` (only nonzero winding numbers
        stored) instead of a dense array.

    Returns
    -------
    (m, R) int64 array, or csr_array with ``sparse``
    """
    from scipy.sparse import coo_array

    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    m, n_rings = len(points), len(rings)
    a = np.vstack(rings) if n_rings else np.zeros((0, 2))
    b = np.vstack([np.roll(r, -1, axis=0) for r in rings]) if n_rings else np.zeros((0, 2))
    owner = np.repeat(np.arange(n_rings), [len(r) for r in rings])
    order = np.argsort(points[:, 1], kind="stable")
    ys = points[order, 1]
    upward = a[:, 1] <= b[:, 1]
    # an edge crosses the height of the points with min(ay, by) <= py < max(ay, by)
    start = np.searchsorted(ys, np.minimum(a[:, 1], b[:, 1]), side="left")
    count = np.searchsorted(ys, np.maximum(a[:, 1], b[:, 1]), side="left") - start
    ends = np.cumsum(count)
    rows, cols, vals = [], [], []
    first = 0
    while first < len(count):
        last = max(int(np.searchsorted(ends, (ends[first - 1] if first else 0) + WINDING_CHUNK, side="right")),
                   first + 1)
        edge = np.repeat(np.arange(first, last), count[first:last])
        if edge.size:
            offset = np.arange(edge.size) - np.repeat(np.cumsum(count[first:last]) - count[first:last],
                                                      count[first:last])
            point = order[start[edge] + offset]
            ax, ay, bx, by = a[edge, 0], a[edge, 1], b[edge, 0], b[edge, 1]
            px, py = points[point, 0], points[point, 1]
            cross = (bx - ax) * (py - ay) - (px - ax) * (by - ay)
            w = np.where(upward[edge], (cross > 0).astype(np.int64), -(cross < 0).astype(np.int64))
            hit = w != 0
            key = point[hit].astype(np.int64) * max(n_rings, 1) + owner[edge[hit]]
            key, inverse = np.unique(key, return_inverse=True)
            total = np.bincount(inverse, weights=w[hit], minlength=len(key)).astype(np.int64)
            rows.append(key // max(n_rings, 1))
            cols.append(key % max(n_rings, 1))
            vals.append(total)
        first = last
    cat = (lambda parts: np.concatenate(parts) if parts else np.zeros(0, np.int64))  # noqa: E731
    out = coo_array((cat(vals), (cat(rows), cat(cols))), shape=(m, n_rings)).tocsr()
    out.eliminate_zeros()
    return out if sparse else out.toarray()


def fill_regions(rings, rule="evenodd"):
    """Regions of rings filled together under a fill rule.

    Each ring's winding number just outside it (the sum over the other rings
    at one of its points) and just inside it (plus its own orientation) says
    whether it bounds the fill: from unfilled outside to filled inside it is
    an outer ring, the other way round a hole of the smallest outer ring
    around it. A ring with the fill on both sides (or neither) bounds nothing.

    Parameters
    ----------
    rings : list of (k_r, 2) arrays
    rule : {'nonzero', 'evenodd'}

    Returns
    -------
    regions : list of list of int
        Outer ring first, then its holes (indices into ``rings``).
    outline : set of int
        Rings that bound no filled region.
    """
    filled = (lambda w: w % 2 == 1) if rule == "evenodd" else (lambda w: w != 0)
    probes = np.array([r[0] for r in rings])
    w = winding_numbers(probes, rings, sparse=True)  # mostly zeros: many small rings are side by side
    signed = np.array([ring_area(r[:, 0] + 1j * r[:, 1]) for r in rings])
    outside = np.asarray(w.sum(axis=1)).ravel() - w.diagonal()
    inside = outside + np.sign(signed).astype(np.int64)
    is_outer = ~filled(outside) & filled(inside)
    is_hole = filled(outside) & ~filled(inside)
    outers = np.flatnonzero(is_outer)
    area = np.abs(signed)
    regions = {int(o): [int(o)] for o in outers}
    outline = set(np.flatnonzero(~is_outer & ~is_hole).tolist())
    for h in np.flatnonzero(is_hole):
        row = w[[h]].toarray().ravel()
        around = outers[(row[outers] != 0) & (area[outers] > area[h])]
        if around.size:
            regions[int(around[np.argmin(area[around])])].append(int(h))
        else:
            outline.add(int(h))
    return list(regions.values()), outline
