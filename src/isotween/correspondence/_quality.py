"""Compatible meshes, stage 4: joint quality improvement (collapses, flips, smoothing) of two meshes.

Part of `isotween.correspondence.compatible_mesh` (see its description).
"""

import numpy as np
from scipy.sparse import coo_matrix

from ..geometry import edge_table, triangle_areas
from ._disc import _flip, _independent, _scale2

STALL_SINE = 0.0005  # the quality step stops after three rounds that raise the smallest angle's sine less
STALL_FACES = 0.002  # and lower the share of faces below the angle limit by less than this


# ---------------------------------------------------------------- joint quality improvement
def _sine(z, f):
    """(F,) sine of the smallest corner angle, 2 A l_min / (l_1 l_2 l_3); negative when inverted.

    (The smallest angle is at most 60 degrees and the sine of an obtuse angle
    is the sine of the sum of the other two, so the smallest sine is the
    sine of the smallest angle.)
    """
    return _sine_area(z, f)[0]


def _sine_area(z, f):
    """(F,) `_sine` and (F,) signed area of triangles ``f`` (F, 3), from one pass over the sides."""
    return _corner_sine_area(z[f])


def _corner_sine_area(p):
    """`_sine_area` of triangles given by their corners ``p`` (..., 3) complex."""
    u = p[..., 1] - p[..., 0]
    v = p[..., 2] - p[..., 0]
    cross = (np.conj(u) * v).imag  # 2 A
    d = v - u
    l1, l2, l3 = u.real ** 2 + u.imag ** 2, v.real ** 2 + v.imag ** 2, d.real ** 2 + d.imag ** 2
    prod = l1 * l2 * l3
    with np.errstate(divide="ignore", invalid="ignore"):
        q = cross * np.sqrt(np.minimum(np.minimum(l1, l2), l3) / prod)
    return np.where(prod > 0, q, 0.0), 0.5 * cross


def _quality(z, w, f):
    """(F,) sine of the smallest corner angle of every face over both meshes."""
    return np.minimum(_sine(z, f), _sine(w, f))


def _valid(z, w, f, eps):
    return (triangle_areas(z, f) > eps[0]) & (triangle_areas(w, f) > eps[1])


def _colour_classes(f, N, K, seed=0):
    """Independent sets of the vertices K.. that have faces, covering all of them.

    Greedy by random priority (Luby): a vertex joins the current class when
    its priority beats that of every neighbour not yet in a class.

    Returns
    -------
    (N,) int : the class of every vertex, -1 for the first K and unused ones
    """
    a, b = f.ravel(), np.roll(f, -1, axis=1).ravel()  # in a closed fan every neighbour once
    prio = np.argsort(np.argsort(np.random.default_rng(seed).random(N)))  # distinct ranks: the best left vertex joins
    left = np.bincount(a, minlength=N) > 0
    left[:K] = False
    colour = np.full(N, -1, dtype=np.int64)
    k = 0
    while left.any():
        e = left[a] & left[b]
        top = np.full(N, -1)
        np.maximum.at(top, a[e], prio[b[e]])
        pick = left & (prio > top)
        colour[pick] = k
        left &= ~pick
        k += 1
    return colour


def _smooth(z, w, f, K, eps, joint):
    """Move every interior vertex to a better place, one independent set (colour class) at a time.

    Goals, from the current positions: the area-weighted mean of the
    circumcentres of the star (optimal Delaunay triangulation smoothing, Chen
    and Xu 2004; not with ``joint``), else the neighbours' mean, at full,
    half and quarter step. All vertices of a class move together (their
    stars share no face) and each is judged on its own star: a move is
    kept where every face of the star keeps a positive area and the star's
    smallest angle grows. ``joint``: a vertex moves in both meshes or in
    neither, judged on the smaller angle of the two (this keeps a target
    that is an affine image of the source one); otherwise each mesh on its
    own (the meshes share connectivity, not positions). ``w`` None: one
    mesh, ``z``, alone (``w`` returned None).

    Returns
    -------
    z, w : (N,) complex, moved : int
    """
    N = len(z)
    one = w is None
    colour = _colour_classes(f, N, K)
    v = f.ravel()
    order = np.argsort(colour[v] * (N + 1) + v, kind="stable")  # corners by class, then vertex
    order = order[colour[v[order]] >= 0]
    vc, fc = v[order], order // 3
    cls = colour[vc]
    bounds = np.r_[0, np.cumsum(np.bincount(cls))]
    pos = [z.copy(), None if one else w.copy()]
    moved = 0
    for k in range(len(bounds) - 1):
        vk, tri = vc[bounds[k]:bounds[k + 1]], f[fc[bounds[k]:bounds[k + 1]]]
        st = np.flatnonzero(np.r_[True, vk[1:] != vk[:-1]])
        own = vk[st]
        count = np.diff(np.r_[st, len(vk)])
        went = np.zeros(len(own), dtype=bool)
        mine = tri == np.repeat(own, count)[:, None]  # (m, 3): the corner of each star face that moves
        for group in ((0,),) if one else ((0, 1),) if joint else ((0,), (1,)):
            goals = [{i: np.add.reduceat(pos[i][tri].sum(axis=1) - pos[i][vk], st) / (2 * count)
                      for i in group}]  # Laplacian (each neighbour twice): affine images stay affine images
            if not joint:
                goals.insert(0, {i: _circumcentre_mean(pos[i][tri], st) for i in group})
            old = np.min([np.minimum.reduceat(_sine(pos[i], tri), st) for i in group], axis=0)
            # every trial (goal, step) of every vertex at once: the stars of a class share no face
            trials = [(g, t) for g in goals for t in (1.0, 0.5, 0.25)]
            ok = np.ones((len(trials), len(own)), dtype=bool)
            q = np.full((len(trials), len(own)), np.inf)
            to = {i: np.stack([pos[i][own] + t * (g[i] - pos[i][own]) for g, t in trials]) for i in group}  # (T, v)
            for i in group:
                corners = np.where(mine, np.repeat(to[i], count, axis=1)[..., None], pos[i][tri])  # (T, m, 3)
                sine, area = _corner_sine_area(corners)
                ok &= np.minimum.reduceat((area > eps[i]).astype(np.int8), st, axis=1) > 0
                q = np.minimum(q, np.minimum.reduceat(sine, st, axis=1))
            gain = ok & (q > old + 1e-9)
            first = np.argmax(gain, axis=0)  # the first trial that gains, in the order tried
            done = gain[first, np.arange(len(own))]
            for i in group:
                pos[i][own[done]] = to[i][first[done], np.flatnonzero(done)]
            went |= done
        moved += int(went.sum())
    return pos[0], pos[1], moved


def _circumcentre_mean(p, st):
    """Area-weighted mean of the circumcentres of consecutive groups of triangles.

    Parameters
    ----------
    p : (m, 3) complex
        Corner positions of the triangles, grouped.
    st : (g,) int
        First triangle of every group.

    Returns
    -------
    (g,) complex
    """
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    area = 0.5 * (np.conj(u) * v).imag
    with np.errstate(divide="ignore", invalid="ignore"):
        cc = p[:, 0] + (np.abs(u) ** 2 * v - np.abs(v) ** 2 * u) / (4j * area)
    cc = np.where(np.isfinite(cc), cc, p.mean(axis=1))
    den = np.add.reduceat(area, st)
    num = np.add.reduceat(area * cc, st)
    mean = np.add.reduceat(p.mean(axis=1), st) / np.diff(np.r_[st, len(p)])
    return np.where(den > 0, num / np.where(den > 0, den, 1), mean)


def _joint_flips(z, w, f, eps, limit=0.5):
    """Flip edges whose flip raises the smallest angle of their two faces in both meshes together.

    Only edges where that angle's sine is below ``limit`` are flipped; f is
    changed in place. Returns the number of flips.
    """
    a, b, c, key, twin = edge_table(f)
    qf = _quality(z, w, f)
    h = np.flatnonzero(twin > np.arange(len(a)))
    q_old = np.minimum(qf[h // 3], qf[twin[h] // 3])
    h, q_old = h[q_old < limit], q_old[q_old < limit]
    d = c[twin[h]]
    new1, new2 = np.c_[a[h], d, c[h]], np.c_[d, b[h], c[h]]
    ok = _valid(z, w, new1, eps) & _valid(z, w, new2, eps)
    q_new = np.minimum(_quality(z, w, new1), _quality(z, w, new2))
    gain = q_new - q_old
    sel = ok & (gain > 1e-6)
    h, gain = h[sel], gain[sel]
    if not len(h):
        return 0
    h = h[_independent(gain, h // 3, twin[h] // 3, len(f))]
    _flip(f, h, twin, a, b, c)
    return len(h)


def _collapse(z, w, f, K, eps, limit):
    """Collapse the shortest edge of faces whose smallest angle (in either mesh) has a sine below ``limit``.

    An interior vertex x merges into its neighbour y when the link condition
    holds (x and y share exactly the two neighbours across their edge), every
    new face keeps a positive area in both meshes and the smallest angle
    around x grows. Collapses in one call do not interfere (see `_merge`).

    Returns
    -------
    (F', 3) faces (removed vertices are no longer referenced), number of collapses
    """
    q = _quality(z, w, f)
    bad = np.flatnonzero(q < limit)
    if not len(bad):
        return f, 0
    p = f[bad]
    nx = np.roll(p, -1, axis=1)
    ls, lt = np.abs(z[nx] - z[p]), np.abs(w[nx] - w[p])
    L = np.maximum(ls / ls.sum(axis=1, keepdims=True), lt / lt.sum(axis=1, keepdims=True))
    k = np.argmin(L, axis=1)
    r = np.arange(len(bad))
    a, b = p[r, k], nx[r, k]
    x = np.r_[a[a >= K], b[b >= K]]
    y = np.r_[b[a >= K], a[b >= K]]
    score = np.r_[q[bad][a >= K], q[bad][b >= K]]
    return _merge(z, w, f, x, y, score, eps, 1.0)[:2]


def _coarsen(z, w, f, K, sizes, eps, floor, rounds=40):
    """Collapse interior edges shorter than ``sizes`` (source, target) in both meshes, shortest first.

    An interior vertex x merges into its nearest neighbour y (in edge length
    over the mesh's size, the larger of the two meshes') when that is below
    1, the link condition holds, every new face keeps a positive area in both
    meshes and the smallest angle around x stays above ``floor`` (a sine) or
    does not get smaller. The overlay of two triangulations has thousands of
    intersection vertices where one outline's chords cross the other's
    fans; most can go.

    Returns
    -------
    (F', 3) faces (removed vertices are no longer referenced)
    """
    fresh = np.ones(len(z), dtype=bool)  # vertices whose faces changed in the last round
    for _ in range(rounds):
        e = np.stack([f, np.roll(f, -1, axis=1)], axis=-1).reshape(-1, 2)
        e = e[e[:, 0] >= K]  # an interior vertex's fan is closed: each edge out of it once
        L = np.maximum(np.abs(z[e[:, 0]] - z[e[:, 1]]) / sizes[0], np.abs(w[e[:, 0]] - w[e[:, 1]]) / sizes[1])
        short = L < 1.0
        e, L = e[short], L[short]
        if not len(e):
            break
        # a merge found unsafe (or beaten) stays so until the faces around x or y change
        new = fresh[e[:, 0]] | fresh[e[:, 1]]
        f, done, fresh = _merge(z, w, f, e[new, 0], e[new, 1], L[new], eps, floor)
        if done < 0.01 * np.count_nonzero(np.bincount(e[:, 0])):
            break
    return f


def _merge(z, w, f, x, y, score, eps, floor):
    """Merge vertices x into y (lowest ``score`` first, merges that do not interfere), where that is safe.

    Safe: the link condition holds, every new face keeps a positive area in
    both meshes, and the smallest quality ``q`` (sine of the smallest angle)
    around x grows, or stays at least ``floor``. Each x takes its safe merge
    of lowest score: its candidates are checked in turn, lowest score first,
    until one is safe.

    Returns
    -------
    f : (F', 3) int, merged : int, touched : (N,) bool
        The faces after the merges, how many merged, and the vertices of the
        faces that changed (where a merge found unsafe may have become safe).
    """
    N, nF = len(z), len(f)
    if not len(x):
        return f, 0, np.zeros(N, dtype=bool)
    vf = coo_matrix((np.ones(3 * nF), (f.ravel(), np.repeat(np.arange(nF), 3))), shape=(N, nF)).tocsr()
    A = coo_matrix((np.ones(3 * nF), (f.ravel(), np.roll(f, -1, axis=1).ravel())), shape=(N, N)).tocsr()
    A = ((A + A.T) > 0).astype(np.int64).tocsr()
    q = _quality(z, w, f)
    by_score = np.argsort(score, kind="stable")
    rank = np.empty(len(x), dtype=np.int64)
    rank[by_score] = np.arange(len(x))
    o = by_score[np.argsort(x[by_score], kind="stable")]  # per x, its candidates by score
    first = np.flatnonzero(np.r_[True, x[o][1:] != x[o][:-1]])
    last = np.r_[first[1:], len(x)]
    # the candidates of every x in turn, by score (its k-th where its first k - 1 are not safe): each x's
    # first safe one, without checking those after it
    c = o[first]
    safe = _safe(z, w, f, vf, A, q, x[c], y[c], eps, floor)
    open_, later, k = ~safe, [], 1
    while (turn := np.flatnonzero(open_ & (last - first > k))).size:
        at = first[turn] + k
        ok = _safe(z, w, f, vf, A, q, x[o[at]], y[o[at]], eps, floor)
        later.append(at[ok])
        open_[turn[ok]] = False
        k += 1
    later = o[np.sort(np.concatenate(later))] if later else np.zeros(0, dtype=np.int64)
    c = np.r_[c[safe], later]
    if not len(c):
        return f, 0, np.zeros(N, dtype=bool)
    x, y, rank = x[c], y[c], rank[c]
    # a maximal set of merges that do not interfere, lowest score first (Luby): a merge claims the faces
    # around x (the only faces it changes; merges whose x are adjacent share two) and the edges it makes,
    # y to the neighbours of x that are not y's (two merges making the same edge would double it); it wins
    # when it has the lowest rank on all its claims, its claims are then taken and its rivals drop out
    cx, fx = vf[x].nonzero()
    cu, u = A[x].nonzero()
    made = (u != y[cu]) & (np.asarray(A[y[cu], u]).ravel() == 0)
    cu, u = cu[made], u[made]
    _, edge = np.unique(np.minimum(y[cu], u) * N + np.maximum(y[cu], u), return_inverse=True)
    cc, ff = np.r_[cx, cu], np.r_[fx, nF + edge]
    n, nR = len(x), nF + len(cu)
    left = np.ones(n, dtype=bool)
    take = np.zeros(n, dtype=bool)
    taken = np.zeros(nR, dtype=bool)
    while left.any():
        live = left[cc]
        cc, ff = cc[live], ff[live]  # the claims of merges still open (the rest decide nothing more)
        claim = np.full(nR, np.iinfo(np.int64).max)
        np.minimum.at(claim, ff, rank[cc])
        win = left & (np.bincount(cc[claim[ff] != rank[cc]], minlength=n) == 0)
        take |= win
        taken[ff[win[cc]]] = True
        left &= np.bincount(cc[taken[ff]], minlength=n) == 0
    vmap = np.arange(N)
    vmap[x[take]] = y[take]
    touched = np.zeros(N, dtype=bool)
    touched[f[fx[take[cx]]]] = True
    g = vmap[f]
    g = g[(g[:, 0] != g[:, 1]) & (g[:, 1] != g[:, 2]) & (g[:, 2] != g[:, 0])]
    return g, int(take.sum()), touched


def _safe(z, w, f, vf, A, q, x, y, eps, floor):
    """(C,) bool: merging x into y keeps the link condition, positive areas and the quality (see `_merge`)."""
    link = np.asarray(A[x].multiply(A[y]).sum(axis=1)).ravel() == 2
    cx, fx = vf[x].nonzero()  # faces around x
    old = np.full(len(x), np.inf)
    np.minimum.at(old, cx, q[fx])
    stay = ~np.any(f[fx] == y[cx][:, None], axis=1)
    cs, fs = cx[stay], fx[stay]
    nf = np.where(f[fs] == x[cs][:, None], y[cs][:, None], f[fs])
    ok = np.bincount(cs[~_valid(z, w, nf, eps)], minlength=len(x)) == 0
    new = np.full(len(x), np.inf)
    np.minimum.at(new, cs, _quality(z, w, nf))
    return link & ok & ((new > old) | (new >= floor))


def _joint_refine(z, w, f, size, rounds=30):
    """Split large faces at their centroid in both meshes, then flip edges jointly.

    Large means larger than an equilateral triangle of side ``size`` (in the
    source; the target size is scaled by the area ratio).
    """
    ratio = np.sqrt(abs(triangle_areas(w, f).sum() / triangle_areas(z, f).sum()))
    big_s = 1.5 * np.sqrt(3) / 4 * size ** 2
    big_t = big_s * ratio ** 2
    eps = (1e-14 * _scale2(z), 1e-14 * _scale2(w))
    for _ in range(rounds):
        bad = np.flatnonzero((triangle_areas(z, f) > big_s) | (triangle_areas(w, f) > big_t))
        if not len(bad):
            break
        m = len(z) + np.arange(len(bad))
        t = f[bad]
        z = np.r_[z, z[t].mean(axis=1)]
        w = np.r_[w, w[t].mean(axis=1)]
        f = np.r_[np.delete(f, bad, axis=0), np.c_[t[:, 0], t[:, 1], m], np.c_[t[:, 1], t[:, 2], m],
                  np.c_[t[:, 2], t[:, 0], m]]
        for _ in range(3):
            if not _joint_flips(z, w, f, eps):
                break
    return z, w, f


def _improve(z, w, f, K, joint, rounds=40, limit=20.0):
    """Joint edge collapses, edge flips and smoothing of interior vertices in both meshes.

    In the style of Surazhsky and Gotsman (2004); every step keeps both meshes valid.

    Returns
    -------
    z, w : (N',) complex, f : (F', 3); vertices no face uses any more are dropped
    (the first K, the rings, are kept in place).
    """
    eps = (1e-14 * _scale2(z), 1e-14 * _scale2(w))
    sin_limit = np.sin(np.radians(limit))
    f = f.copy()
    q = _quality(z, w, f)
    worst, bad, stalled = q.min(), np.mean(q < sin_limit), 0
    for _ in range(rounds):
        f, collapsed = _collapse(z, w, f, K, eps, sin_limit)
        flips = _joint_flips(z, w, f, eps)
        z, w, moved = _smooth(z, w, f, K, eps, joint)
        if not (collapsed or flips) and moved <= 0.01 * (len(z) - K):
            break
        # effort in proportion to the gain: stop after three rounds that raised neither the smallest
        # angle's sine (by STALL_SINE) nor lowered the share of faces below the limit (by STALL_FACES); a share,
        # not a count: collapses remove faces, which in a mesh bad all over lowers the count, not the share
        q = _quality(z, w, f)
        share = np.mean(q < sin_limit)
        gain = (q.min() > worst + STALL_SINE) or share < bad - STALL_FACES
        worst, bad = max(worst, q.min()), min(bad, share)
        stalled = 0 if gain else stalled + 1
        if stalled == 3:
            break
    used = np.zeros(len(z), dtype=bool)
    used[f] = True
    used[:K] = True
    new_id = np.cumsum(used) - 1
    return z[used], w[used], new_id[f]
