"""Compatible meshes, stage 1: the rings checked, each polygon cut into a disc and triangulated, refined.

Part of `isotween.correspondence.compatible_mesh` (see its description).
"""

import numpy as np

from ..errors import IncompatibleShapesError, ShapeError
from ..geometry import edge_keys, edge_table, ring_area, segment_distance, triangle_angles, triangle_areas


# ---------------------------------------------------------------- validation
def _rings(rings, name):
    """List of (k,) complex arrays from a list of (k, 2) arrays."""
    if isinstance(rings, np.ndarray) and rings.ndim == 2:
        rings = [rings]
    out = []
    for r, ring in enumerate(rings):
        a = np.asarray(ring, dtype=np.float64)
        if a.ndim != 2 or a.shape[1] != 2:
            raise ShapeError(f"ring {r} of the {name} must be a (k, 2) array, got shape {a.shape}")
        if len(a) < 3:
            raise ShapeError(f"ring {r} of the {name} has {len(a)} vertices; a ring needs at least 3")
        bad = np.flatnonzero(~np.all(np.isfinite(a), axis=1))
        if bad.size:
            raise ShapeError(f"vertex {bad[0]} of ring {r} of the {name} is not finite: {a[bad[0]].tolist()}")
        out.append(a[:, 0] + 1j * a[:, 1])
    if not out:
        raise ShapeError(f"the {name} has no rings")
    return out


def _check_rings(rings, name):
    """Raise ShapeError naming ring and vertex unless the rings form a valid polygon with holes."""
    import shapely

    z = np.concatenate(rings)
    ring_of = np.repeat(np.arange(len(rings)), [len(r) for r in rings])
    local = np.concatenate([np.arange(len(r)) for r in rings])
    nxt = np.concatenate([np.roll(np.arange(len(r)), -1) for r in rings]) + np.repeat(
        np.r_[0, np.cumsum([len(r) for r in rings])[:-1]], [len(r) for r in rings])
    seg = np.stack([z, z[nxt]], axis=1)
    zero = np.flatnonzero(seg[:, 0] == seg[:, 1])
    if zero.size:
        i = zero[0]
        raise ShapeError(f"vertices {local[i]} and {local[nxt[i]]} of ring {ring_of[i]} of the {name} coincide")
    lines = shapely.linestrings(np.stack([seg.real, seg.imag], axis=-1))
    i, j = shapely.STRtree(lines).query(lines, predicate="intersects")
    keep = i < j
    i, j = i[keep], j[keep]
    adjacent = (nxt[i] == j) | (nxt[j] == i)
    d1, d2 = seg[i, 1] - seg[i, 0], seg[j, 1] - seg[j, 0]
    folded = adjacent & (np.abs((np.conj(d1) * d2).imag) <= 1e-15 * np.abs(d1) * np.abs(d2)) & (
        (np.conj(d1) * d2).real < 0)
    bad = np.flatnonzero(~adjacent | folded)
    if bad.size:
        a, b = i[bad[0]], j[bad[0]]
        p = shapely.intersection(lines[a], lines[b])
        x, y = shapely.get_coordinates(p)[0]
        raise ShapeError(
            f"the {name} outline touches or crosses itself at ({x:.6g}, {y:.6g}): edge {local[a]}-{local[nxt[a]]} "
            f"of ring {ring_of[a]} meets edge {local[b]}-{local[nxt[b]]} of ring {ring_of[b]}")
    polys = [shapely.Polygon(np.c_[r.real, r.imag]) for r in rings]
    for h in range(1, len(rings)):
        p = shapely.Point(rings[h][0].real, rings[h][0].imag)
        if not polys[0].contains(p):
            raise ShapeError(f"ring {h} of the {name} (a hole) lies outside ring 0, the outer boundary "
                             f"(its vertex 0 at ({p.x:.6g}, {p.y:.6g}))")
        for g in range(1, len(rings)):
            if g != h and polys[g].contains(p):
                raise ShapeError(f"ring {h} of the {name} (a hole) lies inside ring {g}, another hole")


def _orientation(src, tgt):
    """Per ring, the vertex order that makes the outer ring ccw and the holes cw."""
    order = []
    for r, (a, b) in enumerate(zip(src, tgt, strict=False)):
        sa, sb = np.sign(ring_area(a)), np.sign(ring_area(b))
        if sa != sb:
            raise IncompatibleShapesError(
                f"ring {r} runs {'counter-' if sa > 0 else ''}clockwise in the source but "
                f"{'counter-' if sb > 0 else ''}clockwise in the target: the correspondence mirrors it")
        want = 1 if r == 0 else -1
        idx = np.arange(len(a))
        order.append(idx if sa == want else idx[::-1].copy())
    return order


# ---------------------------------------------------------------- triangulation
def _keys(e):
    """(m,) int64 keys of undirected edges (m, 2)."""
    e = np.asarray(e, dtype=np.int64).reshape(-1, 2)
    return edge_keys(e[:, 0], e[:, 1])


def _scale2(z):
    return float(np.ptp(z.real) ** 2 + np.ptp(z.imag) ** 2)


def _min_angle(z, f):
    return float(np.degrees(triangle_angles(z, f).min())) if len(f) else 0.0


def _polygon(z, rings):
    import shapely

    xy = np.c_[z.real, z.imag]
    return shapely.Polygon(xy[rings[0]], [xy[r] for r in rings[1:]])


def _inside(z, poly, pairs):
    """(m,) whether each segment between vertices ``pairs`` (m, 2) lies inside the polygon.

    Inside means that it meets the polygon's boundary only at its two ends.
    """
    import shapely

    if not len(pairs):
        return np.zeros(0, dtype=bool)
    seg = shapely.linestrings(np.stack([np.c_[z[pairs[:, 0]].real, z[pairs[:, 0]].imag],
                                        np.c_[z[pairs[:, 1]].real, z[pairs[:, 1]].imag]], axis=1))
    # DE-9IM: the segment's interior meets the polygon's interior, neither its boundary nor outside
    ok = shapely.relate_pattern(poly, seg, "1**F**F**")
    # and passes no ring vertex closer than a rounding-proof margin (no sliver against the outline)
    pts = shapely.points(np.c_[z.real, z.imag])
    pi, si = shapely.STRtree(seg).query(pts, predicate="dwithin", distance=1e-9 * np.sqrt(_scale2(z)))
    near = (pi != pairs[si, 0]) & (pi != pairs[si, 1])
    ok[si[near]] = False
    return ok


def _triangulate(z, rings, constraints, fixed_keys, name):
    """Constrained Delaunay triangles (F, 3) of the polygon, ccw, with every constraint as an edge.

    Parameters
    ----------
    z : (K,) complex
        Ring vertices.
    rings : list of (k_r,) int arrays
    constraints : (m, 2) int array
        Segments between ring vertices that lie inside the polygon and do
        not cross each other (cuts and diagonals); the polygon is split along
        them and every piece triangulated on its own.
    fixed_keys : (m,) int64
        `_keys` of the constraints: Lawson flips (which remove the slivers
        that nearly collinear ring vertices can leave) keep them.
    """
    import shapely
    from shapely.ops import split

    xy = np.c_[z.real, z.imag]
    poly = _polygon(z, rings)
    pieces = [poly]
    if len(constraints):
        lines = shapely.MultiLineString(list(xy[np.asarray(constraints)]))
        pieces = list(split(poly, lines).geoms)
    try:
        tris = [g for p in pieces for g in shapely.constrained_delaunay_triangles(p).geoms]
    except shapely.errors.GEOSException as exc:  # e.g. rings that nearly touch: GEOS finds no ear to cut
        raise ShapeError(f"the {name} outline is too close to degenerate to triangulate ({exc})") from None
    coords = shapely.get_coordinates(tris).reshape(-1, 4, 2)[:, :3]
    q = (coords[..., 0] + 1j * coords[..., 1]).ravel()
    order = np.argsort(z)  # complex: by x, then y
    idx = np.minimum(np.searchsorted(z[order], q), len(z) - 1)
    found = z[order][idx] == q
    if not found.all():
        c = q[~found][0]
        raise ShapeError(f"the {name} outline is too close to degenerate to triangulate near "
                         f"({c.real:.6g}, {c.imag:.6g})")
    f = order[idx].reshape(-1, 3)
    a = triangle_areas(z, f)
    f[a < 0] = f[a < 0][:, ::-1]
    area = abs(ring_area(z[rings[0]])) - sum(abs(ring_area(z[r])) for r in rings[1:])
    if not np.isclose(np.abs(a).sum(), area, rtol=1e-9, atol=0):
        raise ShapeError(f"the {name} outline is too close to degenerate to triangulate")
    f = _lawson(z, f, fixed_keys, tiny=1e-13 * _scale2(z))
    thin = np.flatnonzero(triangle_areas(z, f) <= 1e-13 * _scale2(z))
    if thin.size:
        ring_of = np.concatenate([np.full(len(r), i) for i, r in enumerate(rings)])
        local = np.concatenate([np.arange(len(r)) for r in rings])
        v = np.sort(f[thin[0]])
        raise ShapeError(
            f"the {name} outline is too close to degenerate to triangulate: vertices "
            + ", ".join(f"{local[x]} of ring {ring_of[x]}" for x in v) + " are (nearly) collinear")
    return f


def _shared_diagonals(f_src, zt, poly_t, fixed):
    """(m, 2) interior edges of the source triangulation that are also diagonals of the target polygon.

    The edges kept cross none of each other in the target (nor the ``fixed`` segments (c, 2)).
    """
    import shapely

    a, b, _, key, twin = edge_table(f_src)
    h = np.flatnonzero((twin > np.arange(len(a))) & ~np.isin(key, _keys(fixed)))
    d = np.c_[a[h], b[h]]
    d = d[_inside(zt, poly_t, d)]
    if not len(d):
        return d
    allseg = np.r_[fixed.reshape(-1, 2), d]
    lines = shapely.linestrings(np.stack([np.c_[zt[allseg[:, 0]].real, zt[allseg[:, 0]].imag],
                                          np.c_[zt[allseg[:, 1]].real, zt[allseg[:, 1]].imag]], axis=1))
    i, j = shapely.STRtree(lines).query(lines, predicate="crosses")
    drop = np.zeros(len(allseg), dtype=bool)
    for u, v in zip(i, j, strict=True):  # crossings are rare (none for a polygon without holes)
        if u < v and not drop[u] and not drop[v]:
            drop[max(u, v)] = True
    return d[~drop[len(fixed):]]


def _cuts(zs, zt, rings, near=12):
    """Two cuts per hole, joining it to the outer ring or to a hole joined before.

    A cut is a segment between a vertex of the hole and a vertex of a joined
    ring that lies inside both polygons and crosses no other cut; no vertex
    ends two cuts, and the two cuts of a hole start a quarter of the hole
    apart. Holes are joined nearest first (summed cut length in both shapes).

    Returns
    -------
    list of (hole, (u1, v1), (u2, v2))
        In joining order; u on the joined ring, v on the hole; the first cut
        is opened to make the polygon a disc.
    """
    import shapely

    if len(rings) == 1:
        return []
    polys = [_polygon(z, rings) for z in (zs, zt)]
    for p in polys:
        shapely.prepare(p)
    joined = [0]
    chosen, used, taken = [], set(), [[], []]  # taken: lines of the chosen cuts in each shape
    known = {}  # (u, v) -> whether the segment lies inside both polygons, from every round so far
    while len(joined) < len(rings):
        best = None
        for h in (h for h in range(1, len(rings)) if h not in joined):
            base = np.concatenate([rings[j] for j in joined])
            picks = _hole_cuts(zs, zt, rings, h, base, polys, used, taken, near, known)
            if picks is None:  # every pair, not only the nearest
                picks = _hole_cuts(zs, zt, rings, h, base, polys, used, taken, len(base), known)
            if picks is not None and (best is None or picks[0] < best[0]):
                best = (picks[0], h, picks[1])
        if best is None:
            h = next(h for h in range(1, len(rings)) if h not in joined)
            raise ShapeError(
                f"ring {h} (a hole) has no two vertices that join the outer ring or another hole by straight "
                "cuts inside both the source and the target; resample the rings more finely")
        _, h, pair = best
        chosen.append((h, *pair))
        joined.append(h)
        for u, v in pair:
            used.update((u, v))
            for s, z in enumerate((zs, zt)):
                taken[s].append(shapely.linestrings(np.c_[z[[u, v]].real, z[[u, v]].imag]))
    return chosen


def _hole_cuts(zs, zt, rings, h, base, polys, used, taken, near, known):
    """The shortest two valid cuts from hole h to the vertices ``base``, or None.

    Returned as (summed length, ((u1, v1), (u2, v2))). ``known`` ((u, v) ->
    bool) holds the inside tests made before, and gets the new ones.
    """
    import shapely

    hole = rings[h]
    d = np.abs(zs[hole][:, None] - zs[base][None, :]) + np.abs(zt[hole][:, None] - zt[base][None, :])
    k = min(len(base), near)
    nearest = np.argpartition(d, k - 1, axis=1)[:, :k]
    hi = np.repeat(np.arange(len(hole)), k)
    bi = nearest.ravel()
    order = np.argsort(d[hi, bi], kind="stable")
    hi, bi = hi[order], bi[order]
    hv, bv = hole[hi], base[bi]
    cand = np.flatnonzero(~np.isin(bv, list(used)) & ~np.isin(hv, list(used)))
    inside = np.zeros(len(cand), dtype=bool)
    tested = 0  # the inside test (the costly part) runs on a growing prefix of the candidates, nearest first

    def valid(n):  # candidate n lies inside both polygons (the same cuts as testing every candidate at once)
        nonlocal tested
        while n >= tested:
            c = cand[tested:tested + max(64, tested)]
            seen = [known.get((u, v)) for u, v in zip(bv[c].tolist(), hv[c].tolist(), strict=True)]
            ok = np.array([s is None or s for s in seen], dtype=bool)
            new = np.array([s is None for s in seen], dtype=bool)
            for z, poly in zip((zs, zt), polys, strict=False):
                ok[ok & new] = _inside(z, poly, np.c_[bv[c[ok & new]], hv[c[ok & new]]])
            known.update(zip(zip(bv[c[new]].tolist(), hv[c[new]].tolist(), strict=True), ok[new].tolist(), strict=True))
            inside[tested:tested + len(c)] = ok
            tested += len(c)
        return inside[n]

    def clear(c, picks):
        """Cut c crosses no chosen cut (nor the picks) in either shape."""
        return not any(np.any(shapely.intersects(
            shapely.linestrings(np.c_[z[[bv[c], hv[c]]].real, z[[bv[c], hv[c]]].imag]),
            t + [shapely.linestrings(np.c_[z[[bv[p], hv[p]]].real, z[[bv[p], hv[p]]].imag]) for p in picks]))
            for z, t in zip((zs, zt), taken, strict=False) if len(t) or picks)

    first = next((c for n, c in enumerate(cand) if valid(n) and clear(c, [])), None)
    if first is None:
        return None
    # the second cut: another vertex on both rings, a quarter of the hole away from the first if possible
    gap = np.abs(hi[cand] - hi[first])
    gap = np.minimum(gap, len(hole) - gap)
    other = (hv[cand] != hv[first]) & (bv[cand] != bv[first])
    for want in (max(1, len(hole) // 4), 1):
        second = next((c for n, c in enumerate(cand) if other[n] and gap[n] >= want and valid(n)
                       and clear(c, [first])), None)
        if second is not None:
            return float(d[hi[first], bi[first]]), tuple((int(bv[c]), int(hv[c])) for c in (first, second))
    return None


# ---------------------------------------------------------------- refinement
def _incircle(pa, pb, pc, pd):
    """> 0 when pd lies inside the circle through the ccw triangle (pa, pb, pc)."""
    a, b, c = pa - pd, pb - pd, pc - pd
    return (np.abs(a) ** 2 * (np.conj(b) * c).imag + np.abs(b) ** 2 * (np.conj(c) * a).imag
            + np.abs(c) ** 2 * (np.conj(a) * b).imag)


def _independent(score, fa, fb, n_faces):
    """Mask of candidate flips (best score first) that share no face."""
    rank = np.empty(len(score), dtype=np.int64)
    rank[np.argsort(-score, kind="stable")] = np.arange(len(score))
    claim = np.full(n_faces, len(score), dtype=np.int64)
    np.minimum.at(claim, fa, rank)
    np.minimum.at(claim, fb, rank)
    return (claim[fa] == rank) & (claim[fb] == rank)


def _flip(f, h, twin, a, b, c):
    """Flip the edges of half-edges h (each in its own pair of faces), in place."""
    g = twin[h]
    f1, f2 = h // 3, g // 3
    d = c[g]
    f[f1] = np.stack([a[h], d, c[h]], axis=1)  # (np.c_ costs more than the flips on small meshes)
    f[f2] = np.stack([d, b[h], c[h]], axis=1)


def _lawson(z, f, fixed_keys, rounds=200, tiny=0.0):
    """Flip non-Delaunay edges (not fixed ones) until none is left; f is changed in place.

    The longest edge of a face with an area at most ``tiny`` (a sliver of
    nearly collinear vertices) is flipped too where both new faces are
    positive.
    """
    for _ in range(rounds):
        a, b, c, key, twin = edge_table(f)
        h = np.flatnonzero((twin > np.arange(len(a))) & ~np.isin(key, fixed_keys))
        d = c[twin[h]]
        s = _incircle(z[a[h]], z[b[h]], z[c[h]], z[d])
        scale = np.abs(z[a[h]] - z[b[h]]) ** 4
        if tiny > 0:
            area = triangle_areas(z, f)
            sliver = (area[h // 3] <= tiny) | (area[twin[h] // 3] <= tiny)
            s = np.where(sliver, np.inf, s)
        h, s = h[s > 1e-12 * scale], s[s > 1e-12 * scale]
        if not len(h):
            return f
        h = h[_independent(s, h // 3, twin[h] // 3, len(f))]
        new1 = triangle_areas(z, np.stack([a[h], c[twin[h]], c[h]], axis=1))
        new2 = triangle_areas(z, np.stack([c[twin[h]], b[h], c[h]], axis=1))
        h = h[(new1 > 0) & (new2 > 0)]
        if not len(h):
            return f
        _flip(f, h, twin, a, b, c)
    return f


def _refine(z, f, fixed_keys, size, rounds=30, grade=0.0):
    """Insert interior Steiner points (triangle centroids) until no triangle is much too large.

    Too large means much larger than an equilateral triangle of side
    ``size``, or, with ``grade``, of side ``max(size, grade * d)`` where its
    vertices lie ``d`` or more from the outline: the mesh follows the
    outline's detail near it and coarsens inside. Lawson flips keep the mesh
    Delaunay.

    Returns
    -------
    (N,) complex positions (input vertices first), (F, 3) faces
    """
    f = _lawson(z, f.copy(), fixed_keys)
    big = 1.5 * np.sqrt(3) / 4 * size ** 2
    far = _OutlineDistance(z, f) if grade > 0 else None
    depth = np.zeros(len(z))  # every vertex is on the outline at first
    for _ in range(rounds):
        area = triangle_areas(z, f)
        bad = np.flatnonzero(area > big)
        if far is not None and len(bad):  # away from the outline, larger triangles do
            bad = bad[area[bad] > big * np.maximum(1.0, grade * depth[f[bad]].min(axis=1) / size) ** 2]
        if not len(bad):
            break
        m = len(z) + np.arange(len(bad))
        centroids = z[f[bad]].mean(axis=1)
        z = np.r_[z, centroids]
        if far is not None:
            depth = np.r_[depth, far(centroids)]
        t = f[bad]
        f = np.r_[np.delete(f, bad, axis=0), np.c_[t[:, 0], t[:, 1], m], np.c_[t[:, 1], t[:, 2], m],
                  np.c_[t[:, 2], t[:, 0], m]]
        f = _lawson(z, f, fixed_keys)
    return z, f


class _OutlineDistance:
    """Distance of points to the outline of a triangle mesh (its edges in one face), by an R-tree of its edges."""

    def __init__(self, z, f):
        import shapely

        a, b, _, _, twin = edge_table(f)
        self.a, self.b = z[a[twin < 0]], z[b[twin < 0]]
        self.tree = shapely.STRtree(shapely.linestrings(np.stack([np.c_[self.a.real, self.a.imag],
                                                                   np.c_[self.b.real, self.b.imag]], axis=1)))

    def __call__(self, p):
        """(m,) distances of points ``p`` (m,) complex to the outline."""
        import shapely

        _, j = self.tree.query_nearest(shapely.points(p.real, p.imag), all_matches=False)
        return segment_distance(p, self.a[j], self.b[j])


def _chords(f, K):
    """(C, 2) interior edges of faces ``f`` whose two ends are both ring vertices (index below ``K``)."""
    e = np.sort(np.stack([f, np.roll(f, -1, axis=1)], axis=-1).reshape(-1, 2), axis=1)
    _, first, count = np.unique(_keys(e), return_index=True, return_counts=True)
    edges = e[first]
    return edges[(count == 2) & (edges[:, 1] < K)]


def _split_edges(f, split, n):
    """Faces ``f`` (F, 3) with the edges ``split`` (S, 2) cut at their midpoints, vertices n .. n+S-1.

    Every face is subdivided by the templates of red-green refinement (one,
    two or three of its sides cut: two, three or four faces), which keep
    its orientation; the new vertex of ``split[s]`` is ``n + s``, at the
    midpoint of its ends in any positions (the caller appends them).
    """
    if not len(split):
        return f
    N = int(max(f.max(), split.max())) + 1
    key = np.sort(split, axis=1) @ [N, 1]
    order = np.argsort(key)
    side = np.sort(np.stack([f, np.roll(f, -1, axis=1)], axis=-1), axis=-1) @ [N, 1]  # (F, 3): side j = (v_j, v_j+1)
    at = np.minimum(np.searchsorted(key[order], side), len(key) - 1)
    m = np.where(key[order][at] == side, n + order[at], -1)
    cut = m >= 0
    count = cut.sum(axis=1)
    out = [f[count == 0]]
    for j in range(3):
        one = (count == 1) & cut[:, j]  # side j cut: rotate it to side 0
        v, a = np.roll(f[one], -j, axis=1), m[one, j]
        out += [np.c_[v[:, 0], a, v[:, 2]], np.c_[a, v[:, 1], v[:, 2]]]
        two = (count == 2) & ~cut[:, j]  # side j whole: rotate it to side 2
        r = (j + 1) % 3
        v, a = np.roll(f[two], -r, axis=1), np.roll(m[two], -r, axis=1)
        out += [np.c_[a[:, 0], v[:, 1], a[:, 1]], np.c_[v[:, 0], a[:, 0], a[:, 1]], np.c_[v[:, 0], a[:, 1], v[:, 2]]]
    v, a = f[count == 3], m[count == 3]
    out += [np.c_[v[:, 0], a[:, 0], a[:, 2]], np.c_[a[:, 0], v[:, 1], a[:, 1]], np.c_[a[:, 2], a[:, 1], v[:, 2]], a]
    return np.concatenate(out).astype(f.dtype, copy=False)




# ---------------------------------------------------------------- cuts opened, the disc's boundary
def _open_cuts(f, cuts, first_copy):
    """Faces (F, 3) with the first cut (u, v) of every hole opened.

    The boundary cycle runs ``.., p, u, v, (hole).., v', u', q, ..`` with the
    copies ``u' = first_copy + 2 i`` and ``v' = first_copy + 2 i + 1`` for
    the i-th entry of ``cuts`` (see `_cuts`): faces
    around u between the cut and q take u', faces around v between the cut
    and the hole vertex before v take v'.
    """
    out = f.copy()
    for i, (_, (u, v), _) in enumerate(cuts):
        for vert, other, copy, reached in ((u, v, first_copy + 2 * i, False), (v, u, first_copy + 2 * i + 1, True)):
            rows, cols = np.nonzero(f == vert)
            nxt = {int(f[r, (c + 1) % 3]): int(r) for r, c in zip(rows, cols, strict=True)}
            w, side = other, []
            while w in nxt:  # ccw around vert from the cut to the boundary
                face = nxt[w]
                side.append(face)
                w = int(f[face, (int(np.flatnonzero(f[face] == vert)[0]) + 2) % 3])
            mask = np.isin(rows, side) == reached
            out[rows[mask], cols[mask]] = copy
    return out


def _disc_cycle(rings, cuts, first_copy):
    """(B,) boundary cycle of the cut polygon.

    The outer ring ccw with a detour along the first cut of every hole, around the hole (and the holes joined to it) and
    back along the cut's copies.
    """
    detour = {u: (h, v, first_copy + 2 * i, first_copy + 2 * i + 1) for i, (h, (u, v), _) in enumerate(cuts)}
    out = []

    def walk(ring):
        for x in ring:
            out.append(int(x))
            if int(x) in detour:
                h, v, u_copy, v_copy = detour[int(x)]
                hole = rings[h]
                walk(np.roll(hole, -int(np.flatnonzero(hole == v)[0])))  # v first, the hole's order
                out.extend((v_copy, u_copy))

    walk(rings[0])
    return np.array(out, dtype=np.int64)


