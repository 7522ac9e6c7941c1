"""Compatible meshes, stage 3: both discs mapped onto the unit circle and overlaid.

Part of `isotween.correspondence.compatible_mesh` (see its description).
"""

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..errors import ShapeError
from ..geometry import convex_map, edge_table, orient, triangle_areas
from ._disc import _disc_cycle, _flip, _independent, _open_cuts, _scale2

#: crossings per boundary vertex past which the target's triangulation is flipped to cross the source's less
OVERLAY_BUDGET = 50


# ---------------------------------------------------------------- overlay of two discs
def _side(D, pos, B, u, a, b):
    """(m,) side of vertices u against chords a -> b: +1 left, -1 right, 0 endpoint.

    Boundary vertices are decided by their cyclic order on the circle (exact);
    interior ones by the orientation sign.
    """
    s = np.sign(orient(D[a], D[b], D[u])).astype(np.int64)
    on = pos[u] >= 0
    pa, pb, pu = pos[a][on], pos[b][on], pos[u][on]
    right = ((pu - pa) % B) < ((pb - pa) % B)
    s[on] = np.where(right, -1, 1)
    s[(u == a) | (u == b)] = 0
    return s


def _overlay(z1, f1, zt, f_tgt, rings, cuts, K, tol=1e-9):
    """Common refinement of the source mesh (z1, f1) and the target triangulation f_tgt.

    Returns
    -------
    z, w : (N,) complex
        Source and target positions; 0..K-1 the rings, then the source's
        interior vertices, then the intersection vertices.
    f : (F, 3) int array
    """
    import shapely

    N1 = len(z1)
    copies = np.array([x for _, (u, v), _ in cuts for x in (u, v)], dtype=np.int64)
    orig = np.r_[np.arange(N1), copies]
    zs_all = z1[orig]
    zt_all = np.full(len(orig), np.nan + 0j)
    ring_ids = orig < K
    zt_all[ring_ids] = zt[orig[ring_ids]]
    F1, F2 = _open_cuts(f1, cuts, N1), _open_cuts(f_tgt, cuts, N1)
    cyc = _disc_cycle(rings, cuts, N1)
    B = len(cyc)
    pos = np.full(len(orig), -1, dtype=np.int64)
    pos[cyc] = np.arange(B)
    # boundary on the unit circle at the mean of both normalised arc lengths
    ls = np.abs(np.diff(zs_all[np.r_[cyc, cyc[:1]]]))
    lt = np.abs(np.diff(zt_all[np.r_[cyc, cyc[:1]]]))
    s = 0.5 * (np.r_[0, np.cumsum(ls)[:-1]] / ls.sum() + np.r_[0, np.cumsum(lt)[:-1]] / lt.sum())
    D = convex_map(zs_all, F1, cyc, np.exp(2j * np.pi * s))
    if np.all(pos[F1] >= 0) and np.all(pos[F2] >= 0):  # two triangulations of the disc's boundary alone
        F2 = _fewer_crossings(F2, F1, pos, zt_all)

    # target chords: edges of F2 that are neither boundary edges nor edges of F1
    a1, b1, _, key1, twin1 = edge_table(F1)
    a2, b2, _, key2, twin2 = edge_table(F2)
    rep2 = np.flatnonzero(twin2 > np.arange(len(a2)))
    chords = np.c_[a2[rep2], b2[rep2]]
    chords = chords[~np.isin(key2[rep2], key1)]
    ca, cb = chords[:, 0], chords[:, 1]
    rep1 = np.flatnonzero(twin1 > np.arange(len(a1)))  # interior edges of F1, one half-edge each
    lo, hi = a1[rep1], b1[rep1]
    interior = pos < 0

    def candidates():
        cl = shapely.linestrings(np.stack([np.c_[D[ca].real, D[ca].imag], np.c_[D[cb].real, D[cb].imag]], axis=1))
        el = shapely.linestrings(np.stack([np.c_[D[lo].real, D[lo].imag], np.c_[D[hi].real, D[hi].imag]], axis=1))
        e, c = shapely.STRtree(cl).query(el)
        return e, c

    for _ in range(20):  # move interior disc vertices off the chords they nearly touch
        e, c = candidates()
        u = np.r_[lo[e], hi[e]]
        cc = np.r_[c, c]
        near = interior[u] & (np.abs(orient(D[ca[cc]], D[cb[cc]], D[u])) < tol * np.abs(D[cb[cc]] - D[ca[cc]]))
        if not near.any():
            break
        for vert, ch in zip(*np.unique(np.c_[u[near], cc[near]], axis=0).T, strict=True):
            _nudge(D, F1, vert, D[cb[ch]] - D[ca[ch]], tol)
    su, sv = _side(D, pos, B, lo[e], ca[c], cb[c]), _side(D, pos, B, hi[e], ca[c], cb[c])
    hit = su * sv == -1
    e, c = e[hit], c[hit]
    ou = orient(D[ca[c]], D[cb[c]], D[lo[e]])
    ov = orient(D[ca[c]], D[cb[c]], D[hi[e]])
    te = np.abs(ou) / (np.abs(ou) + np.abs(ov))  # along lo -> hi; the sides are known exactly
    ncross = len(e)
    Nd = len(orig)
    xid = Nd + np.arange(ncross)
    Dx = D[lo[e]] + te * (D[hi[e]] - D[lo[e]])
    dc = D[cb[c]] - D[ca[c]]
    tc = np.clip((np.conj(dc) * (Dx - D[ca[c]])).real / np.abs(dc) ** 2, 0.0, 1.0)
    zs_x = zs_all[lo[e]] + te * (zs_all[hi[e]] - zs_all[lo[e]])
    zt_x = zt_all[ca[c]] + tc * (zt_all[cb[c]] - zt_all[ca[c]])

    # ports: the corners and edge crossings on the boundary of every source triangle
    nF = len(F1)
    h1 = rep1[e]
    g1 = twin1[h1]
    p_face = np.r_[np.repeat(np.arange(nF), 3), h1 // 3, g1 // 3]
    p_pos = np.r_[np.tile([0.0, 1.0, 2.0], nF), h1 % 3 + te, g1 % 3 + (1 - te)]
    p_vid = np.r_[F1.ravel(), xid, xid]
    p_chord = np.r_[np.full(3 * nF, -1), c, c]
    # chord pieces inside each triangle: pairs of crossing ports, or a crossing and a corner
    xp = 3 * nF + np.arange(2 * ncross)
    key = p_face[xp] * (len(chords) + 1) + p_chord[xp]
    o = np.argsort(key, kind="stable")
    ks = key[o]
    pair = np.flatnonzero(ks[1:] == ks[:-1])
    single = np.ones(len(o), dtype=bool)
    single[pair] = single[pair + 1] = False
    pieces = [np.c_[xp[o[pair]], xp[o[pair + 1]]]]
    lone = xp[o[single]]
    fl, cl_ = p_face[lone], p_chord[lone]
    ka = (F1[fl] == ca[cl_][:, None]) | (F1[fl] == cb[cl_][:, None])  # the chord's end at a corner
    if len(lone) and not ka.any(axis=1).all():
        raise ShapeError("compatible meshing: a chord ends inside a triangle (inconsistent overlay)")
    pieces.append(np.c_[lone, 3 * fl + np.argmax(ka, axis=1)])
    pieces = np.vstack(pieces)

    # faces of each triangle's subdivision (an outerplanar graph) by tracing
    order = np.lexsort((p_pos, p_face))
    nP = len(p_face)
    rank = np.empty(nP, dtype=np.int64)
    count = np.bincount(p_face, minlength=nF)
    first = np.r_[0, np.cumsum(count)[:-1]]
    rank[order] = np.arange(nP) - first[p_face[order]]
    nxt_port = np.empty(nP, dtype=np.int64)
    succ = np.arange(nP) + 1
    succ[first + count - 1] = first
    nxt_port[order] = order[succ]
    h_src = np.r_[np.arange(nP), pieces[:, 0], pieces[:, 1]]
    h_dst = np.r_[nxt_port, pieces[:, 1], pieces[:, 0]]
    P = count[p_face[h_src]]
    off_out = (rank[h_dst] - rank[h_src]) % P
    off_back = (rank[h_src] - rank[h_dst]) % P
    M = int(count.max()) + 1
    kout = h_src * M + off_out
    so = np.argsort(kout, kind="stable")
    idx = np.searchsorted(kout[so], h_dst * M + off_back, side="left") - 1
    nxt = so[idx]
    if np.any(h_src[nxt] != h_dst):
        raise ShapeError("compatible meshing: inconsistent overlay cells")
    nH = len(h_src)
    _, label = connected_components(coo_matrix((np.ones(nH), (np.arange(nH), nxt)), shape=(nH, nH)),
                                    connection="weak")
    apex_h = np.full(label.max() + 1, nH, dtype=np.int64)
    np.minimum.at(apex_h, label, np.arange(nH))
    apex = p_vid[h_src[apex_h[label]]]
    vs, vd = p_vid[h_src], p_vid[h_dst]
    keep = (vs != apex) & (vd != apex)
    faces = np.c_[apex[keep], vs[keep], vd[keep]]

    # target positions of the source's interior vertices: barycentric in the target triangle
    inner = np.flatnonzero(interior)
    if len(inner):
        zt_all[inner] = _locate(D, F2, zt_all, inner)

    # glue the cut copies back and number: rings, source interior, intersections
    vmap = np.r_[np.arange(N1), copies, N1 + np.arange(ncross)]
    z = np.r_[z1, zs_x]
    w = np.r_[zt_all[:N1], zt_x]
    return z, w, vmap[faces]


def _fewer_crossings(F2, F1, pos, w, budget=OVERLAY_BUDGET, rounds=100):
    """``F2``, or where it crosses ``F1`` too often, with diagonals flipped (positive at ``w``) to cross fewer.

    Both triangulate the same polygon with no inner vertex; in the disc their
    diagonals are chords of a circle, and two cross exactly where their ends
    interleave along it (``pos``: each vertex's place on the boundary; the
    rule of `_side` for boundary vertices, here counted for all chord pairs
    at once: through `_side`, pair by pair, it took 20 times longer). Every
    crossing is a vertex of the overlay that the coarsening must merge away
    again; two unlike fans cross tens of thousands of times. Where they cross
    more than ``budget`` times per boundary vertex, each round flips, in
    faces apart, the diagonals whose flip crosses fewer chords of ``F1``
    (the target's Delaunay triangles, which AIAP folds less on, are kept
    below that).

    Returns
    -------
    (F, 3) int
    """
    a1, b1, _, _, twin1 = edge_table(F1)
    h1 = np.flatnonzero(twin1 > np.arange(len(a1)))
    lo1, hi1 = np.minimum(pos[a1[h1]], pos[b1[h1]]), np.maximum(pos[a1[h1]], pos[b1[h1]])

    def crossed(u, v):  # (E,) how many chords of F1 the chords u-v cross, in blocks of rows
        out = np.empty(len(u), dtype=np.int64)
        step = max(1, (1 << 20) // max(len(lo1), 1))
        for k in range(0, len(u), step):
            lo = np.minimum(pos[u[k:k + step]], pos[v[k:k + step]])[:, None]
            hi = np.maximum(pos[u[k:k + step]], pos[v[k:k + step]])[:, None]
            inside_lo, inside_hi = (lo1 > lo) & (lo1 < hi), (hi1 > lo) & (hi1 < hi)
            apart = (lo1 != lo) & (lo1 != hi) & (hi1 != lo) & (hi1 != hi)
            out[k:k + step] = np.count_nonzero((inside_lo != inside_hi) & apart, axis=1)
        return out

    f = F2
    sign = np.sign(triangle_areas(w, f[:1]))[0]
    eps = 1e-12 * _scale2(w)
    for k in range(rounds):
        a, b, c, _, twin = edge_table(f)
        h = np.flatnonzero(twin > np.arange(len(a)))
        now = crossed(a[h], b[h])
        if k == 0:
            if now.sum() <= budget * np.count_nonzero(pos >= 0):
                return F2
            f = F2.copy()  # flipped in place from here
        h, now = h[now > 0], now[now > 0]  # only a diagonal that crosses can cross less
        d = c[twin[h]]
        gain = now - crossed(c[h], d)
        ok = gain > 0
        ok[ok] &= (sign * triangle_areas(w, np.c_[a[h[ok]], d[ok], c[h[ok]]]) > eps) & \
                  (sign * triangle_areas(w, np.c_[d[ok], b[h[ok]], c[h[ok]]]) > eps)
        h, gain = h[ok], gain[ok]
        if not len(h):
            break
        _flip(f, h[_independent(gain.astype(float), h // 3, twin[h] // 3, len(f))], twin, a, b, c)
    return f


def _locate(D, F2, zt_all, inner):
    """Target positions of disc vertices ``inner``: barycentric in the target triangle holding them."""
    import shapely

    tri = shapely.polygons(np.stack([np.c_[D[F2[:, i]].real, D[F2[:, i]].imag] for i in (0, 1, 2, 0)], axis=1))
    pts = shapely.points(np.c_[D[inner].real, D[inner].imag])
    pi, ti = shapely.STRtree(tri).query(pts, predicate="intersects")
    A, Bc, C = D[F2[ti, 0]], D[F2[ti, 1]], D[F2[ti, 2]]
    p = D[inner[pi]]
    area = orient(A, Bc, C)
    lam = np.c_[orient(Bc, C, p), orient(C, A, p), orient(A, Bc, p)] / area[:, None]
    best = np.lexsort((-lam.min(axis=1), pi))
    firsts = np.r_[True, pi[best][1:] != pi[best][:-1]]
    sel = best[firsts]
    if len(sel) != len(inner):
        raise ShapeError("compatible meshing: an interior vertex fell outside the target triangulation")
    out = np.empty(len(inner), dtype=complex)
    out[pi[sel]] = np.sum(lam[sel] * zt_all[F2[ti[sel]]], axis=1)
    return out


def _nudge(D, F, vert, direction, tol):
    """Move interior disc vertex ``vert`` off a line with ``direction``, keeping its star valid."""
    star = np.flatnonzero(np.any(F == vert, axis=1))
    n = 1j * direction / np.abs(direction)
    old = D[vert]
    for step in 1e3 * tol * 0.5 ** np.arange(12):
        for sgn in (1, -1):
            D[vert] = old + sgn * step * n
            if np.all(triangle_areas(D, F[star]) > 0):
                return
    D[vert] = old


