"""The geometry kernel: planar polygon and triangle-mesh primitives, vectorised numpy.

Every signed area, orientation, bounding-box diagonal, boundary loop, edge
table, corner angle, mean-value weight and convex (Tutte) map in the package
is computed here; the rest of the package imports these functions rather than
writing the formulas again (``tests/test_geometry.py`` scans the sources for a
second shoelace).

Points are ``(N,)`` complex arrays or ``(N, 2)`` float arrays (the functions
taking ``points`` accept either); rings are closed vertex loops with the
closing edge implied; faces are ``(K, 3)`` integer arrays of vertex indices,
counter-clockwise when their signed area is positive. At module level this
imports only numpy (scipy is imported by the functions that need it), so a
reader (`isotween.io.svg`) can use it without loading the solver.
"""

import numpy as np

from .errors import ShapeError

__all__ = [
    "as_complex", "orient", "segment_distance", "ring_area", "ring_areas", "ring_orientation", "ring_centroid",
    "triangle_areas",
    "triangle_angles", "affine_maps", "bbox_diagonal", "edge_keys", "edge_table", "face_sides", "boundary_loops",
    "mean_value_weights",
    "mean_value_laplacian", "cotangent_laplacian", "convex_map", "winding_numbers", "fill_regions", "MAX_TRIANGLES",
]

MAX_TRIANGLES = 2_000_000
"""Meshes above this many triangles are refused before meshing (the overlay and quality steps hold copies)."""


def as_complex(points):
    """Points as complex numbers.

    Parameters
    ----------
    points : (N,) complex or (N, 2) float array

    Returns
    -------
    (N,) complex array
        ``points`` itself when it is already complex.

    Examples
    --------
    >>> as_complex(np.array([[1.0, 2.0]]))
    array([1.+2.j])
    """
    p = np.asarray(points)
    if np.iscomplexobj(p) or p.ndim < 2:
        return p
    return p[..., 0] + 1j * p[..., 1]


def ring_area(ring):
    """Signed shoelace area of a closed ring, positive counter-clockwise.

    Parameters
    ----------
    ring : (k,) complex or (k, 2) float array

    Returns
    -------
    float

    Notes
    -----
    Float points are summed as ``x * y' - x' * y`` in real arithmetic,
    complex ones as ``Im(conj(z) z')``: the two can differ in the last bit,
    which decides the sign of a flat ring (see `triangle_areas`).

    Examples
    --------
    >>> ring_area(np.array([0, 1, 1 + 1j, 1j]))
    1.0
    >>> ring_area(np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]]))
    -0.5
    """
    v = np.asarray(ring)
    if not np.iscomplexobj(v) and v.ndim == 2 and v.shape[-1] == 2:
        x, y = v[:, 0], v[:, 1]
        return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    return 0.5 * float(np.sum((np.conj(v) * np.roll(v, -1)).imag))


def ring_areas(points, loops):
    """Signed shoelace areas of closed loops of vertex indices, frame by frame.

    Parameters
    ----------
    points : (..., N) complex array
        Positions, with any leading (frame) axes.
    loops : list of (k_r,) int arrays
        At least one loop.

    Returns
    -------
    (..., R) float array

    Examples
    --------
    >>> ring_areas(np.array([0, 1, 1 + 1j, 1j]), [np.array([0, 1, 2, 3]), np.array([3, 2, 1])]).tolist()
    [1.0, -0.5]
    """
    z = np.asarray(points)
    idx = np.concatenate(loops)
    nxt = np.concatenate([np.roll(p, -1) for p in loops])
    owner = np.repeat(np.arange(len(loops)), [len(p) for p in loops])
    cross = 0.5 * (z[..., idx].conj() * z[..., nxt]).imag  # shoelace terms
    out = np.zeros(z.shape[:-1] + (len(loops),))
    np.add.at(np.moveaxis(out, -1, 0), owner, np.moveaxis(cross, -1, 0))
    return out


def ring_orientation(ring):
    """Orientation of a closed ring: 1 counter-clockwise, -1 clockwise, 0 flat.

    Parameters
    ----------
    ring : (k,) complex or (k, 2) float array

    Returns
    -------
    int
    """
    return int(np.sign(ring_area(ring)))


def ring_centroid(ring):
    """Area centroid of a closed ring, or the vertex mean when the ring is flat.

    Parameters
    ----------
    ring : (k,) complex or (k, 2) float array

    Returns
    -------
    complex

    Examples
    --------
    >>> ring_centroid(np.array([0, 2, 2 + 2j, 2j]))
    (1+1j)
    """
    z = as_complex(ring)
    w = np.roll(z, -1)
    cross = (np.conj(z) * w).imag
    a = cross.sum()
    if abs(a) > 1e-12 * max(np.ptp(z.real), np.ptp(z.imag), 1e-300) ** 2:
        return complex(np.sum((z + w) * cross) / (3 * a))
    return complex(z.mean())


def orient(a, b, c):
    """Twice the signed area of triangles (a, b, c): > 0 when c lies left of a -> b.

    Parameters
    ----------
    a, b, c : (...) complex arrays
        Corner positions, broadcast together.

    Returns
    -------
    (...) float array

    Examples
    --------
    >>> float(orient(0, 1, 1j)), float(orient(0, 1, -1j))
    (1.0, -1.0)
    """
    return (np.conj(b - a) * (c - a)).imag


def segment_distance(p, a, b):
    """Distance from points ``p`` to segments ``a -> b``, all (...) complex arrays broadcast together.

    Examples
    --------
    >>> float(segment_distance(1 + 1j, 0, 2)), float(segment_distance(3, 0, 2))
    (1.0, 1.0)
    """
    d = b - a
    t = np.clip(((p - a) * np.conj(d)).real / np.maximum(np.abs(d) ** 2, 1e-300), 0.0, 1.0)
    return np.abs(a + t * d - p)


def triangle_areas(points, faces):
    """Signed areas of triangles, positive counter-clockwise.

    Parameters
    ----------
    points : (..., N) complex or (..., N, 2) float array
        Positions, with any leading (frame) axes.
    faces : (K, 3) int array

    Returns
    -------
    (..., K) float array

    Notes
    -----
    Float points are measured in real arithmetic, complex ones through
    `orient`; the two can differ in the last bit (numpy may fuse the complex
    product's multiply and add), which decides the sign of a sliver, so each
    caller keeps the form it was written with.

    Examples
    --------
    >>> triangle_areas(np.array([0, 1, 1j]), np.array([[0, 1, 2], [0, 2, 1]]))
    array([ 0.5, -0.5])
    >>> triangle_areas(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), np.array([[0, 1, 2]]))
    array([0.5])
    """
    v = np.asarray(points)
    if not np.iscomplexobj(v) and v.ndim >= 2 and v.shape[-1] == 2:
        a, b, c = (v[..., faces[:, i], :] for i in range(3))
        ab, ac = b - a, c - a
        return 0.5 * (ab[..., 0] * ac[..., 1] - ab[..., 1] * ac[..., 0])
    p = v[..., faces]
    return 0.5 * orient(p[..., 0], p[..., 1], p[..., 2])


def triangle_angles(points, faces):
    """Corner angles of triangles in radians (0 at a corner with a zero-length side).

    Parameters
    ----------
    points : (N,) complex or (N, 2) float array
    faces : (K, 3) int array

    Returns
    -------
    (K, 3) float array
        Column c is the angle at vertex ``faces[:, c]``.

    Examples
    --------
    >>> np.degrees(triangle_angles(np.array([0, 1, 1j]), np.array([[0, 1, 2]]))).round(6)
    array([[90., 45., 45.]])
    """
    p = as_complex(points)[faces]
    u = p[:, [1, 2, 0]] - p
    v = p[:, [2, 0, 1]] - p
    with np.errstate(divide="ignore", invalid="ignore"):
        ang = np.abs(np.angle(v / u))
    return np.where(np.isnan(ang), 0.0, ang)


def affine_maps(faces, z0, z1):
    """Per-triangle affine map ``A u = P u + Q conj(u)`` taking the sides of ``z0`` to those of ``z1``.

    ``P / |P|`` is the rotation closest to ``A`` (polar decomposition), and
    ``2 (|P - R|^2 + |Q|^2)`` is ``|A - R|_F^2`` for a rotation ``R``.

    Parameters
    ----------
    faces : (T, 3) int
    z0, z1 : (n,) complex
        Positions before and after; a triangle of zero area in ``z0`` gets
        infinite or undefined parts.

    Returns
    -------
    P, Q : (T,) complex

    Examples
    --------
    >>> P, Q = affine_maps(np.array([[0, 1, 2]]), np.array([0, 1, 1j]), 2j * np.array([0, 1, 1j]))
    >>> bool(P[0] == 2j and Q[0] == 0)  # a turn by 90 degrees, scaled by 2
    True
    """
    f = faces
    u1, u2 = (z0[f[:, k]] - z0[f[:, 0]] for k in (1, 2))
    v1, v2 = (z1[f[:, k]] - z1[f[:, 0]] for k in (1, 2))
    det = u1 * u2.conj() - u1.conj() * u2  # 2i x twice the signed area
    with np.errstate(divide="ignore", invalid="ignore"):
        return (v1 * u2.conj() - u1.conj() * v2) / det, (u1 * v2 - u2 * v1) / det


def bbox_diagonal(*points):
    """Length of the diagonal of the bounding box of all point arrays together.

    Parameters
    ----------
    *points : (n_i, 2) float or (n_i,) complex arrays
        At least one point in all.

    Returns
    -------
    float

    Examples
    --------
    >>> bbox_diagonal(np.array([[0.0, 0.0]]), np.array([[3.0, 4.0]]))
    5.0
    >>> bbox_diagonal(np.array([0, 3 + 4j]))
    5.0
    """
    both = np.concatenate([np.asarray(p) for p in points])
    if np.iscomplexobj(both):
        both = np.c_[both.real, both.imag]
    return float(np.hypot(*(both.max(axis=0) - both.min(axis=0))))


def edge_keys(a, b):
    """(m,) int64 key of every undirected edge between vertices ``a`` and ``b`` (m,): ``min * 2**32 + max``.

    Examples
    --------
    >>> int(edge_keys(np.array([3]), np.array([1]))[0]) == int(edge_keys(np.array([1]), np.array([3]))[0])
    True
    """
    a, b = np.asarray(a, dtype=np.int64), np.asarray(b, dtype=np.int64)
    return np.minimum(a, b) * (1 << 32) + np.maximum(a, b)


def edge_table(faces):
    """Directed half-edges of triangles and their twins.

    Parameters
    ----------
    faces : (K, 3) int array

    Returns
    -------
    a, b, c : (3K,) int arrays
        Half-edge ``h = 3 * face + corner`` runs from ``a[h]`` to ``b[h]``;
        ``c[h]`` is the vertex opposite it.
    key : (3K,) int64 array
        The undirected edge's key (`edge_keys`).
    twin : (3K,) int64 array
        The other half-edge of the same edge, -1 on the boundary.
    """
    a = faces.ravel()
    b = np.roll(faces, -1, axis=1).ravel()
    c = np.roll(faces, -2, axis=1).ravel()
    key = edge_keys(a, b)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    twin = np.full(len(a), -1, dtype=np.int64)
    same = np.flatnonzero(ks[1:] == ks[:-1])
    twin[order[same]] = order[same + 1]
    twin[order[same + 1]] = order[same]
    return a, b, c, key, twin


def face_sides(faces, edges):
    """Every triangle side a -> b (a-b, b-c, c-a) as one of ``edges`` and its direction along it.

    Parameters
    ----------
    faces : (T, 3) int
    edges : (E, 2) int
        Undirected edges, each side of every face among them.

    Returns
    -------
    edge : (3T,) int
        The edge of side ``3 * face + corner``.
    sign : (3T,) float
        +1 where the side runs along the edge (``edges[e, 0]`` to ``edges[e, 1]``), else -1.
    """
    faces, edges = np.asarray(faces, dtype=np.int64), np.asarray(edges, dtype=np.int64)
    a, b = faces.ravel(), np.roll(faces, -1, axis=1).ravel()
    key = edge_keys(edges[:, 0], edges[:, 1])
    order = np.argsort(key)
    edge = order[np.searchsorted(key[order], edge_keys(a, b))]
    return edge, np.where(edges[edge, 0] == a, 1.0, -1.0)


def boundary_loops(faces, n):
    """Boundary loops of a consistently oriented triangle mesh, each in order.

    Parameters
    ----------
    faces : (K, 3) int array
        Counter-clockwise faces; the loops then run with the mesh on their left.
    n : int
        Number of vertices.

    Returns
    -------
    list of (k_i,) int arrays

    Raises
    ------
    ShapeError
        Two boundary loops meet at a vertex, or an edge has more than two faces.

    Examples
    --------
    >>> [loop.tolist() for loop in boundary_loops(np.array([[0, 1, 2], [0, 2, 3]]), 4)]
    [[0, 1, 2, 3]]
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    half = np.stack([faces, np.roll(faces, -1, axis=1)], axis=-1).reshape(-1, 2)
    key = half[:, 0] * n + half[:, 1]
    twin = half[:, 1] * n + half[:, 0]
    if len(np.unique(key)) < len(key):
        raise ShapeError("an edge is shared by more than two triangles (or two with the same orientation)")
    side = half[~np.isin(key, twin)]
    start, count = np.unique(side[:, 0], return_counts=True)
    if np.any(count > 1):
        raise ShapeError(f"two boundary loops meet at vertex {start[count > 1][0]}")
    # list ranking by pointer doubling: the steps from each loop's first vertex
    pos = np.full(n, -1)
    pos[start] = np.arange(len(start))
    succ = np.empty(len(start), dtype=np.int64)
    succ[pos[side[:, 0]]] = pos[side[:, 1]]
    _, label = connected_components(
        coo_matrix((np.ones(len(succ)), (np.arange(len(succ)), succ)), shape=(len(succ),) * 2), directed=False)
    _, root = np.unique(label, return_index=True)
    jump = np.empty_like(succ)
    jump[succ] = np.arange(len(succ))  # the predecessor
    jump[root] = root
    rank = np.ones(len(succ), dtype=np.int64)
    rank[root] = 0
    while np.any(jump != jump[jump]):
        rank += rank[jump]
        jump = jump[jump]
    order = np.lexsort((rank, label))
    return np.split(start[order], np.cumsum(np.bincount(label))[:-1])


def _mean_value_entries(z, faces):
    """Rows, columns and values of the mean-value weights w_ij (Floater 2003), duplicates not summed."""
    t = np.tan(triangle_angles(z, faces) / 2).ravel()
    i = faces.ravel()
    j = np.roll(faces, -1, axis=1).ravel()
    k = np.roll(faces, -2, axis=1).ravel()
    return np.r_[i, i], np.r_[j, k], np.r_[t / np.abs(z[j] - z[i]), t / np.abs(z[k] - z[i])]


def mean_value_weights(points, faces):
    """Normalised mean-value weights (Floater 2003): rows sum to 1 (0 for a vertex in no face).

    For the corner at vertex i of a triangle (i, j, k) with angle a,
    ``w_ij += tan(a/2) / |z_j - z_i|`` and ``w_ik += tan(a/2) / |z_k - z_i|``.
    An interior vertex is then the combination ``W @ z`` of its neighbours,
    exactly for every affine map of a planar mesh.

    Parameters
    ----------
    points : (N,) complex or (N, 2) float array
    faces : (K, 3) int array

    Returns
    -------
    (N, N) scipy.sparse.csr_matrix
    """
    from scipy.sparse import coo_matrix

    z = as_complex(points)
    N = len(z)
    rows, cols, w = _mean_value_entries(z, faces)
    total = np.bincount(rows, weights=w, minlength=N)
    total[total == 0] = 1
    return coo_matrix((w / total[rows], (rows, cols)), shape=(N, N)).tocsr()


def mean_value_laplacian(points, faces):
    """Mean-value Laplacian L with rows ``sum_j w_ij (z_j - z_i)`` (unnormalised weights).

    Parameters
    ----------
    points : (N,) complex or (N, 2) float array
    faces : (K, 3) int array

    Returns
    -------
    (N, N) scipy.sparse matrix
    """
    from scipy.sparse import coo_matrix

    z = as_complex(points)
    N = len(z)
    rows, cols, w = _mean_value_entries(z, faces)
    W = coo_matrix((w, (rows, cols)), shape=(N, N)).tocsr()
    return W - coo_matrix((np.asarray(W.sum(axis=1)).ravel(), (np.arange(N), np.arange(N))), shape=(N, N))


def cotangent_laplacian(points, faces):
    """Cotangent Laplacian ``D - W`` (symmetric, rows sum to 0).

    The angle at each corner weighs the side opposite it: ``w_jk += cot(a) / 2``.

    Parameters
    ----------
    points : (N,) complex or (N, 2) float array
    faces : (K, 3) int array

    Returns
    -------
    (N, N) scipy.sparse.csc_matrix
    """
    from scipy.sparse import coo_matrix

    p = as_complex(points)
    N = len(p)
    j, k = np.roll(faces, -1, axis=1), np.roll(faces, -2, axis=1)
    uv = (p[j] - p[faces]).conj() * (p[k] - p[faces])
    w, rows, cols = 0.5 * (uv.real / np.abs(uv.imag)).ravel(), j.ravel(), k.ravel()
    W = coo_matrix((np.r_[w, w], (np.r_[rows, cols], np.r_[cols, rows])), shape=(N, N)).tocsr()
    return (coo_matrix((np.asarray(W.sum(axis=1)).ravel(), (np.arange(N), np.arange(N))), shape=(N, N)) - W).tocsc()


def convex_map(points, faces, fixed, values):
    """Convex (Tutte) map with mean-value weights: ``values`` at ``fixed``, the rest solved.

    With the fixed vertices on a convex polygon in order, the map of a disc is
    an embedding (no triangle flipped).

    Parameters
    ----------
    points : (N,) complex or (N, 2) float array
        Positions that give the weights (from the shape of the triangles).
    faces : (K, 3) int array
    fixed : (B,) int array
    values : (B,) complex array

    Returns
    -------
    (N,) complex array
        Vertices in no face stay where they are.
    """
    from scipy.sparse.linalg import splu

    z = as_complex(points)
    out = z.astype(complex)
    out[fixed] = values
    free = np.setdiff1d(np.unique(faces), fixed)
    if len(free):
        L = mean_value_laplacian(z, faces).tocsr()
        rhs = -(L[free][:, fixed] @ values)
        lu = splu(L[free][:, free].tocsc())
        sol = lu.solve(np.c_[rhs.real, rhs.imag])
        out[free] = sol[:, 0] + 1j * sol[:, 1]
    return out


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


PROBES = 5  # points of each ring at which `fill_regions` asks which rings are around it


def fill_regions(rings, rule="evenodd"):
    """Regions of rings filled together under a fill rule.

    Each ring's winding number just outside it (the sum over the other rings,
    the median over `PROBES` of its vertices: rings that touch, as the parts
    of a cut shape do, do not mislead it) and just inside it (plus its own
    orientation) says whether it bounds the fill: from unfilled outside to filled inside it is
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
    # PROBES vertices of every ring (an odd number, spread along it): a vertex on another ring sees either side
    n = np.array([len(r) for r in rings])
    k = np.minimum(PROBES, n - (n % 2 == 0))
    ring_of = np.repeat(np.arange(len(rings)), k)
    at = np.arange(len(ring_of)) - np.repeat(np.cumsum(k) - k, k)
    probes = np.concatenate(rings)[np.repeat(np.cumsum(n) - n, k) + at * n[ring_of] // k[ring_of]]
    w = winding_numbers(probes, rings, sparse=True)  # mostly zeros: many small rings are side by side
    signed = np.array([ring_area(r[:, 0] + 1j * r[:, 1]) for r in rings])
    seen = np.asarray(w.sum(axis=1)).ravel() - np.asarray(w[np.arange(len(ring_of)), ring_of]).ravel()
    order = np.lexsort((seen, ring_of))
    median = order[np.cumsum(k) - k + k // 2]  # each ring's probe of median winding number
    outside, w = seen[median], w.tocsr()[median]
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
