"""Compatible triangle meshes of two corresponding polygons, with no flipped triangle in either, by construction.

The construction (Aronov, Seidel and Souvaine 1993; Surazhsky and Gotsman
2004):

1. Each polygon is triangulated on its own by shapely's constrained Delaunay
   triangulation (no vertex is added). A polygon with holes is first cut into
   a disc: every hole gets two cuts to the outer ring or to a hole joined
   before, segments between corresponding ring vertices that lie inside both
   polygons. Both polygons
   are triangulated piecewise, so the cuts are edges of both meshes; the
   first cut of every hole is then opened (its two vertices duplicated).
2. First try: the source mesh, refined with interior Steiner points (centroid
   insertion and Lawson flips down to the edge length ``mesh_size``), mapped
   onto the target outline by mean-value weights (which reproduce affine
   maps). If no target triangle is flipped, that is the result.
3. Otherwise both triangulations are mapped onto the unit circle with their
   boundary vertices at the same places (the mean of the two normalised arc
   lengths); interior vertices (``refine_first=True`` only) by mean-value
   weights, which are positive, so Tutte's theorem (Floater 2003) makes both
   maps embeddings. Their overlay is built combinatorially: a target chord is
   cut by the source edges it crosses, an intersection vertex is the pair
   (source edge, target chord), and every overlay cell is a convex polygon
   inside one triangle of each mesh. Sides against chords are decided by the
   cyclic order of the boundary vertices (exact); an interior vertex within
   ``tol`` of a chord is first moved off it inside its star. Cells are
   fan-triangulated and mapped back affinely through their source and their
   target triangle. Faces larger than ``mesh_size`` (in either mesh) are then
   split at their centroid in both meshes.
4. Quality: edge collapses, edge flips (both meshes at once, as they share
   connectivity) and smoothing of interior vertices (each mesh on its own,
   one colour class of vertices, an independent set, at a time), every
   change accepted only when every triangle keeps a positive area and the
   smallest angle around it grows. Rounds stop when three in a row gained
   neither smallest angle nor faces above the angle limit.
"""

import time
from typing import NamedTuple

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..errors import (
    IncompatibleShapesError,
    MethodError,
    MissingDependencyError,
    ParameterError,
    ResourceError,
    ShapeError,
    require,
)
from ..geometry import MAX_TRIANGLES, convex_map, edge_table, orient, ring_area, triangle_angles, triangle_areas
from ..optimisation.barrier import SymmetricDirichlet, max_step, minimise
from ..shape import Shape

__all__ = ["CompatibleMeshes", "compatible_meshes"]

STALL_SINE = 0.0005  # the quality step stops after three rounds that raise the smallest angle's sine less
STALL_FACES = 0.002  # and free fewer than this fraction of the faces from below the angle limit
MAP_ITER = 15  # Newton iterations of the low-distortion map at most
MAP_TOL = 1e-2  # the map's Newton stops when an iteration lowers the energy's excess by less than this
PULL_ITER = 15  # Newton iterations per pull weight
PULL_WEIGHTS = (0.01, 0.1, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5)  # the ring's pull, in units of the least energy


class CompatibleMeshes(NamedTuple):
    """What `compatible_meshes` returns.

    Attributes
    ----------
    source, target : Shape
        Triangle meshes with identical ``faces`` (F, 3), counter-clockwise
        with positive area in both. Vertices 0..K-1 are the ring vertices in
        input order (ring 0 first), then the interior vertices; ``paths`` are
        the rings.
    info : dict
        ``vertices``, ``faces``, ``ring_vertices`` (K), ``steiner`` (interior
        vertices), ``cuts`` (per hole: ``[hole, u1, v1, u2, v2]``, its two
        cuts from vertex u of a joined ring to vertex v of the hole),
        ``overlay`` (whether the overlay was needed), ``crossings``
        (intersection vertices the overlay made, before the quality step),
        ``min_angle_source`` / ``min_angle_target`` (degrees, final),
        ``min_angle_before_source`` / ``min_angle_before_target`` (before the
        quality step), ``seconds``.
    """

    source: Shape
    target: Shape
    info: dict


def compatible_meshes(source_rings, target_rings, mesh_size=None, *, refine_first=False, pull=True):
    """Compatible triangle meshes of two corresponding polygons with holes.

    Parameters
    ----------
    source_rings, target_rings : list of (k_r, 2) array_like of float
        Ring 0 is the outer boundary, rings 1.. the holes; the same number of
        rings and the same k_r in both. Vertex i of ring r of the source
        corresponds to vertex i of ring r of the target. Any orientation.
        Every ring must be simple, the holes inside the outer ring, not
        nested and not touching.
    mesh_size : float, optional
        Target edge length of the source mesh's interior. Default: the mean
        edge length of the source rings.
    refine_first : bool
        Overlay the refined source mesh (not the bare triangulation).
    pull : bool
        Where the mean-value map flips a triangle, first try to pull the
        source mesh onto the target outline with no flip (`_pulled`); else
        (or when that gets stuck) overlay the two triangulations.

    Returns
    -------
    CompatibleMeshes
        ``(source, target, info)``; see there.

    Raises
    ------
    ShapeError
        A ring with fewer than 3 vertices, repeated vertices, a ring that
        touches or crosses itself or another, a hole outside the outer ring or
        inside another hole (the message names ring and vertex); or no cut
        joins a hole to the outer ring in both shapes.
    IncompatibleShapesError
        Different numbers of rings or vertices per ring, or a ring that runs
        clockwise in one shape and counter-clockwise in the other (a mirror).
    ParameterError
        ``mesh_size`` is not a positive number, or so small that the source
        mesh would pass ``MAX_TRIANGLES`` triangles (refused before meshing,
        naming the count it would reach).
    MissingDependencyError
        shapely >= 2.1 is missing (``pip install 'isotween[cli]'``).
    """
    started = time.perf_counter()
    shapely = require("shapely", "cli")
    if not hasattr(shapely, "constrained_delaunay_triangles"):
        raise MissingDependencyError(
            f"compatible meshing needs shapely >= 2.1 (found {shapely.__version__}): pip install -U 'shapely>=2.1'")
    src = _rings(source_rings, "source")
    tgt = _rings(target_rings, "target")
    if len(src) != len(tgt):
        raise IncompatibleShapesError(f"the source has {len(src)} ring(s) but the target has {len(tgt)}")
    for r, (a, b) in enumerate(zip(src, tgt, strict=True)):
        if len(a) != len(b):
            raise IncompatibleShapesError(
                f"ring {r} has {len(a)} vertices in the source but {len(b)} in the target")
    for rings, name in ((src, "source"), (tgt, "target")):
        _check_rings(rings, name)
    order = _orientation(src, tgt)
    sizes = np.array([len(r) for r in src])
    start = np.r_[0, np.cumsum(sizes)[:-1]]
    K = int(sizes.sum())
    zs, zt = np.concatenate(src), np.concatenate(tgt)
    rings = [start[r] + order[r] for r in range(len(src))]  # outer ccw, holes cw
    if mesh_size is None:
        mesh_size = float(np.mean(np.concatenate([np.abs(np.diff(np.r_[z, z[:1]])) for z in src])))
    elif not (np.isscalar(mesh_size) and np.isfinite(mesh_size) and mesh_size > 0):
        raise ParameterError(f"mesh_size must be a positive number, got {mesh_size!r}")

    area = abs(ring_area(zs[rings[0]])) - sum(abs(ring_area(zs[r])) for r in rings[1:])
    expected = area / (np.sqrt(3) / 4 * mesh_size ** 2)
    if expected > MAX_TRIANGLES:
        raise ResourceError(
            f"mesh_size={mesh_size:.6g} would make about {expected:.3g} triangles in the source mesh, "
            f"more than the {MAX_TRIANGLES} allowed; use a mesh size of at least "
            f"{np.sqrt(area / (np.sqrt(3) / 4 * MAX_TRIANGLES)):.3g}")
    cuts = _cuts(zs, zt, rings)
    cut_edges = np.array([c for _, *pair in cuts for c in pair], dtype=np.int64).reshape(-1, 2)
    fixed_keys = _keys(cut_edges)
    f_src = _triangulate(zs, rings, cut_edges, fixed_keys, "source")
    z1, f1 = _refine(zs, f_src, fixed_keys, float(mesh_size))

    # first try: the source mesh mapped by mean-value weights (reproduces affine maps); if a triangle
    # flips, the source mesh pulled onto the target outline with no flip; then the map made least distorted
    w_tgt = convex_map(z1, f1, np.arange(K), zt)
    if not np.all(triangle_areas(w_tgt, f1) > 1e-12 * _scale2(zt)):
        w_tgt = _pulled(z1, f1, K, zt) if pull else None
    overlay = w_tgt is None
    crossings = 0
    if not overlay:
        before = (_min_angle(z1, f1), _min_angle(w_tgt, f1))
        w_tgt = _least_distorted(z1, w_tgt, f1, K)
    else:  # the two triangulations overlaid, then refined in both at once
        # the target keeps every source diagonal that is a diagonal of the target too: fewer crossings
        shared = _shared_diagonals(f_src, zt, _polygon(zt, rings), cut_edges)
        f_tgt = _triangulate(zt, rings, np.r_[cut_edges, shared], _keys(np.r_[cut_edges, shared]), "target")
        steiner = len(z1) - K if refine_first else 0
        z1, w_tgt, f1 = _overlay(z1, f1, zt, f_tgt, rings, cuts, K) if refine_first else \
            _overlay(zs, f_src, zt, f_tgt, rings, cuts, K)
        crossings = len(z1) - K - steiner
        z1, w_tgt, f1 = _joint_refine(z1, w_tgt, f1, float(mesh_size))
        before = (_min_angle(z1, f1), _min_angle(w_tgt, f1))
        z1, w_tgt, f1 = _improve(z1, w_tgt, f1, K, False)
        w_tgt = _least_distorted(z1, w_tgt, f1, K)
    a1, a2 = triangle_areas(z1, f1), triangle_areas(w_tgt, f1)
    if not (np.all(a1 > 0) and np.all(a2 > 0)):  # a construction error, never expected
        bad = int(np.flatnonzero((a1 <= 0) | (a2 <= 0))[0])
        raise ShapeError(f"compatible meshing produced a degenerate triangle {bad} {f1[bad].tolist()}; "
                         "the outlines may be too close to degenerate")
    paths = [(start[r] + np.arange(sizes[r]), True) for r in range(len(sizes))]
    s = Shape(np.c_[z1.real, z1.imag], faces=f1, paths=paths)
    t = s.with_vertices(np.c_[w_tgt.real, w_tgt.imag])
    info = {
        "ring_vertices": K, "vertices": len(z1), "faces": len(f1), "steiner": len(z1) - K,
        "crossings": crossings, "cuts": [[h, *u, *v] for h, u, v in cuts], "overlay": overlay,
        "min_angle_before_source": before[0], "min_angle_before_target": before[1],
        "min_angle_source": _min_angle(z1, f1), "min_angle_target": _min_angle(w_tgt, f1),
        "seconds": time.perf_counter() - started,
    }
    return CompatibleMeshes(s, t, info)


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
    e = np.sort(np.asarray(e, dtype=np.int64).reshape(-1, 2), axis=1)
    return e[:, 0] * (1 << 32) + e[:, 1]


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
    tris = [g for p in pieces for g in shapely.constrained_delaunay_triangles(p).geoms]
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
    while len(joined) < len(rings):
        best = None
        for h in (h for h in range(1, len(rings)) if h not in joined):
            base = np.concatenate([rings[j] for j in joined])
            picks = _hole_cuts(zs, zt, rings, h, base, polys, used, taken, near)
            if picks is None:  # every pair, not only the nearest
                picks = _hole_cuts(zs, zt, rings, h, base, polys, used, taken, len(base))
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


def _hole_cuts(zs, zt, rings, h, base, polys, used, taken, near):
    """The shortest two valid cuts from hole h to the vertices ``base``, or None.

    Returned as (summed length, ((u1, v1), (u2, v2))).
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
    ok = ~np.isin(bv, list(used)) & ~np.isin(hv, list(used))
    for z, poly in zip((zs, zt), polys, strict=False):
        ok[ok] = _inside(z, poly, np.c_[bv[ok], hv[ok]])
    def clear(c, picks):
        """Cut c crosses no chosen cut (nor the picks) in either shape."""
        return not any(np.any(shapely.intersects(
            shapely.linestrings(np.c_[z[[bv[c], hv[c]]].real, z[[bv[c], hv[c]]].imag]),
            t + [shapely.linestrings(np.c_[z[[bv[p], hv[p]]].real, z[[bv[p], hv[p]]].imag]) for p in picks]))
            for z, t in zip((zs, zt), taken, strict=False) if len(t) or picks)

    cand = np.flatnonzero(ok)
    first = next((c for c in cand if clear(c, [])), None)
    if first is None:
        return None
    # the second cut: another vertex on both rings, a quarter of the hole away from the first if possible
    gap = np.abs(hi[cand] - hi[first])
    gap = np.minimum(gap, len(hole) - gap)
    other = (hv[cand] != hv[first]) & (bv[cand] != bv[first])
    for want in (max(1, len(hole) // 4), 1):
        second = next((c for c in cand[other & (gap >= want)] if clear(c, [first])), None)
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
    f[f1] = np.c_[a[h], d, c[h]]
    f[f2] = np.c_[d, b[h], c[h]]


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
        new1 = triangle_areas(z, np.c_[a[h], c[twin[h]], c[h]])
        new2 = triangle_areas(z, np.c_[c[twin[h]], b[h], c[h]])
        h = h[(new1 > 0) & (new2 > 0)]
        if not len(h):
            return f
        _flip(f, h, twin, a, b, c)
    return f


def _refine(z, f, fixed_keys, size, rounds=30):
    """Insert interior Steiner points (triangle centroids) until no triangle is much too large.

    Too large means much larger than an equilateral triangle of side ``size``;
    Lawson flips keep the mesh Delaunay.

    Returns
    -------
    (N,) complex positions (input vertices first), (F, 3) faces
    """
    f = _lawson(z, f.copy(), fixed_keys)
    big = 1.5 * np.sqrt(3) / 4 * size ** 2
    for _ in range(rounds):
        area = triangle_areas(z, f)
        bad = np.flatnonzero(area > big)
        if not len(bad):
            break
        m = len(z) + np.arange(len(bad))
        z = np.r_[z, z[f[bad]].mean(axis=1)]
        t = f[bad]
        f = np.r_[np.delete(f, bad, axis=0), np.c_[t[:, 0], t[:, 1], m], np.c_[t[:, 1], t[:, 2], m],
                  np.c_[t[:, 2], t[:, 0], m]]
        f = _lawson(z, f, fixed_keys)
    return z, f


# ---------------------------------------------------------------- low-distortion map
def _least_distorted(z, w, f, K):
    """Interior target positions (N,) complex that make the map ``z -> w`` least distorted, no triangle flipped.

    The symmetric Dirichlet energy of the map (rest: the source triangles) is
    minimised over the interior vertices with the ``K`` ring vertices fixed,
    by the flip-free projected Newton of `isotween.optimisation.barrier`,
    from ``w`` (every triangle positive). A similarity is a minimum: a rigid
    or similar pair of outlines gives the rigid (similar) map.
    """
    fixed = np.zeros(len(z), dtype=bool)
    fixed[:K] = True
    if fixed.all():
        return w
    try:
        energy = SymmetricDirichlet(z, w, f, fixed)
        energy.rest(0.0)
        w, _ = minimise(energy, w, MAP_ITER, tol=MAP_TOL)
    except MethodError:  # a singular Newton system: the valid start stands
        pass
    return w


def _pulled(z, f, K, zt):
    """The source mesh ``z`` deformed with no flipped triangle until its ring vertices reach ``zt``; None if stuck.

    Start: the best similarity of the rings onto ``zt`` applied to the whole
    mesh (every triangle positive). Every vertex is then free, the ring
    vertices pulled towards ``zt`` by a penalty of growing weight
    (`PULL_WEIGHTS`) while the symmetric Dirichlet energy against the source
    triangles keeps the mesh from folding; last, the ring vertices are moved
    onto ``zt`` in one step, which must flip no triangle.
    """
    zk = z[:K] - z[:K].mean()
    a = np.vdot(zk, zt - zt.mean()) / np.vdot(zk, zk)
    w = zt.mean() + a * (z - z[:K].mean())
    ring = np.arange(K)
    h2 = float(np.mean(np.abs(np.diff(zt)) ** 2))
    try:
        energy = SymmetricDirichlet(z, w, f, np.zeros(len(z), dtype=bool))
        energy.rest(0.0)
        unit = energy.least / (K * h2)  # a pull of h at every ring vertex weighs as much as the least energy
        for mu in PULL_WEIGHTS:
            energy.pull_towards(ring, zt, mu * unit)
            w, _ = minimise(energy, w, PULL_ITER, tol=1e-2)
            if np.abs(w[:K] - zt).max() < 1e-9 * np.sqrt(h2):
                break
    except MethodError:
        return None
    step = np.zeros_like(w)
    step[:K] = zt - w[:K]
    if max_step(w, step, energy.faces) <= 1.0:
        return None
    w = w + step
    w[:K] = zt
    return w


# ---------------------------------------------------------------- disc and overlay
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
    u = z[f[:, 1]] - z[f[:, 0]]
    v = z[f[:, 2]] - z[f[:, 0]]
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
    own (the meshes share connectivity, not positions).

    Returns
    -------
    z, w : (N,) complex, moved : int
    """
    N = len(z)
    colour = _colour_classes(f, N, K)
    v = f.ravel()
    order = np.argsort(colour[v] * (N + 1) + v, kind="stable")  # corners by class, then vertex
    order = order[colour[v[order]] >= 0]
    vc, fc = v[order], order // 3
    cls = colour[vc]
    bounds = np.r_[0, np.cumsum(np.bincount(cls))]
    pos = [z.copy(), w.copy()]
    moved = 0
    for k in range(len(bounds) - 1):
        vk, tri = vc[bounds[k]:bounds[k + 1]], f[fc[bounds[k]:bounds[k + 1]]]
        st = np.flatnonzero(np.r_[True, vk[1:] != vk[:-1]])
        own = vk[st]
        count = np.diff(np.r_[st, len(vk)])
        went = np.zeros(len(own), dtype=bool)
        for group in ((0, 1),) if joint else ((0,), (1,)):
            goals = [{i: np.add.reduceat(pos[i][tri].sum(axis=1) - pos[i][vk], st) / (2 * count)
                      for i in group}]  # Laplacian (each neighbour twice): affine images stay affine images
            if not joint:
                goals.insert(0, {i: _circumcentre_mean(pos[i][tri], st) for i in group})
            old = np.min([np.minimum.reduceat(_sine(pos[i], tri), st) for i in group], axis=0)
            done = np.zeros(len(own), dtype=bool)
            for goal, step in [(g, t) for g in goals for t in (1.0, 0.5, 0.25)]:
                if done.all():
                    break
                ok = np.ones(len(own), dtype=bool)
                q = np.full(len(own), np.inf)
                trial = {}
                for i in group:
                    trial[i] = pos[i].copy()
                    trial[i][own[~done]] += step * (goal[i] - pos[i][own])[~done]
                    sine, area = _sine_area(trial[i], tri)
                    ok &= np.minimum.reduceat((area > eps[i]).astype(np.int8), st) > 0
                    q = np.minimum(q, np.minimum.reduceat(sine, st))
                gain = ~done & ok & (q > old + 1e-9)
                for i in group:
                    pos[i][own[gain]] = trial[i][own[gain]]
                done |= gain
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
    around x grows. Collapses in one call touch disjoint faces.

    Returns
    -------
    (F', 3) faces (removed vertices are no longer referenced), number of collapses
    """
    N = len(z)
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
    if not len(x):
        return f, 0
    o = np.lexsort((score, x))
    x, y, score = x[o], y[o], score[o]
    keep = np.r_[True, x[1:] != x[:-1]]
    x, y, score = x[keep], y[keep], score[keep]
    nF = len(f)
    vf = coo_matrix((np.ones(3 * nF), (f.ravel(), np.repeat(np.arange(nF), 3))), shape=(N, nF)).tocsr()
    A = coo_matrix((np.ones(3 * nF), (f.ravel(), np.roll(f, -1, axis=1).ravel())), shape=(N, N)).tocsr()
    A = ((A + A.T) > 0).astype(np.int64).tocsr()
    link = np.asarray(A[x].multiply(A[y]).sum(axis=1)).ravel() == 2
    cx, fx = vf[x].nonzero()  # faces around x
    cy, fy = vf[y].nonzero()
    rank = np.empty(len(x), dtype=np.int64)
    rank[np.argsort(score, kind="stable")] = np.arange(len(x))
    cc, ff = np.r_[cx, cy], np.r_[fx, fy]
    claim = np.full(nF, len(x), dtype=np.int64)
    np.minimum.at(claim, ff, rank[cc])
    win = np.ones(len(x), dtype=bool)
    np.logical_and.at(win, cc, claim[ff] == rank[cc])
    old = np.full(len(x), np.inf)
    np.minimum.at(old, cx, q[fx])
    stay = ~np.any(f[fx] == y[cx][:, None], axis=1)
    cs, fs = cx[stay], fx[stay]
    nf = np.where(f[fs] == x[cs][:, None], y[cs][:, None], f[fs])
    ok = np.ones(len(x), dtype=bool)
    np.logical_and.at(ok, cs, _valid(z, w, nf, eps))
    new = np.full(len(x), np.inf)
    np.minimum.at(new, cs, _quality(z, w, nf))
    take = win & link & ok & (new > old)
    if not take.any():
        return f, 0
    vmap = np.arange(N)
    vmap[x[take]] = y[take]
    g = vmap[f]
    g = g[(g[:, 0] != g[:, 1]) & (g[:, 1] != g[:, 2]) & (g[:, 2] != g[:, 0])]
    return g, int(take.sum())


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
    worst, bad, stalled = q.min(), np.count_nonzero(q < sin_limit), 0
    for _ in range(rounds):
        f, collapsed = _collapse(z, w, f, K, eps, sin_limit)
        flips = _joint_flips(z, w, f, eps)
        z, w, moved = _smooth(z, w, f, K, eps, joint)
        if not (collapsed or flips) and moved <= 0.01 * (len(z) - K):
            break
        # effort in proportion to the gain: stop after three rounds that raised neither the smallest
        # angle's sine (by STALL_SINE) nor the count of faces above the limit (by STALL_FACES of the faces)
        q = _quality(z, w, f)
        gain = (q.min() > worst + STALL_SINE) or np.count_nonzero(q < sin_limit) < bad - STALL_FACES * len(f)
        worst, bad = max(worst, q.min()), min(bad, np.count_nonzero(q < sin_limit))
        stalled = 0 if gain else stalled + 1
        if stalled == 3:
            break
    used = np.zeros(len(z), dtype=bool)
    used[f] = True
    used[:K] = True
    new_id = np.cumsum(used) - 1
    return z[used], w[used], new_id[f]
