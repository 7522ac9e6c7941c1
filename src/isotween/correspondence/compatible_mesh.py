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
   insertion and Lawson flips down to the edge length ``mesh_size`` near the
   outline, coarser inside: `GRADE` times the distance from it), its
   chords that cannot fit the target (edges between two ring vertices outside
   the target polygon or along its outline, sides of ring triangles turned
   over there) cut at their midpoints, mapped onto the target outline by
   mean-value weights (which reproduce affine maps). If no target triangle is
   flipped, that is the result; else the mesh is pulled onto the target
   outline with no flip (`_pulled`), and the map made least distorted
   (where the pull gets stuck near the outline, it runs again with edges
   flipped on the way, and the result gets step 4's quality pass).
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
   target triangle. Intersection vertices are then merged away where both
   meshes stay valid (`_quality._coarsen`), and faces larger than
   ``mesh_size`` (in either mesh) split at their centroid in both meshes.
4. Quality: edge collapses, edge flips (both meshes at once, as they share
   connectivity) and smoothing of interior vertices (each mesh on its own,
   one colour class of vertices, an independent set, at a time), every
   change accepted only when every triangle keeps a positive area and the
   smallest angle around it grows. Rounds stop when three in a row gained
   neither smallest angle nor share of faces above the angle limit. The overlay's map
   is not made least distorted after (as step 2's is): between unlike
   outlines that squeezes thin triangles into the target, on which AIAP
   folds more often.

This module runs the stages and holds the low-distortion map of step 2
(`_pulled`, `_least_distorted`); the stages live beside it: `_disc` (ring
checks, cuts, triangulation, refinement: step 1), `_overlay` (step 3) and
`_quality` (step 4). The planar primitives (areas, angles, edge tables, the
mean-value convex map) come from `isotween.geometry`.
"""

import time
from typing import NamedTuple

import numpy as np

from ..errors import (
    IncompatibleShapesError,
    MethodError,
    MissingDependencyError,
    ParameterError,
    ResourceError,
    ShapeError,
    require,
)
from ..geometry import MAX_TRIANGLES, convex_map, ring_area, triangle_areas
from ..optimisation.barrier import SymmetricDirichlet, face_steps, max_step, minimise
from ..shape import Shape
from ._disc import (
    _check_rings,
    _chords,
    _cuts,
    _inside,
    _keys,
    _min_angle,
    _orientation,
    _polygon,
    _refine,
    _rings,
    _scale2,
    _shared_diagonals,
    _split_edges,
    _triangulate,
)
from ._overlay import _overlay
from ._quality import _coarsen, _improve, _joint_flips, _joint_refine, _smooth

__all__ = ["CompatibleMeshes", "compatible_meshes"]

GRADE = 1.5  # the source mesh coarsens inside: a triangle d from the outline may have sides of this x d
MAP_ITER = 15  # Newton iterations of the low-distortion map at most
MAP_TOL = 1e-2  # the map's Newton stops when an iteration lowers the energy's excess by less than this
PULL_ITER = 15  # Newton iterations per pull weight
PULL_WEIGHTS = (0.01, 0.1, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5)  # the ring's pull, in units of the least energy
COARSEN = True  # the overlay's intersection vertices merged away where both meshes stay valid (`_coarsen`)
COARSE_ANGLE = 15.0  # the overlay's collapses keep the smallest angle above this (degrees) or make it no smaller
SMOOTH_ROUNDS = 3  # smoothing rounds of the source mesh after its chords are cut
PULL_FLIPS = 5  # rounds of joint edge flips after every pull weight at most (`_pull` with flips)
PULL_RETRY = 2.5  # a pull stuck this far (in mean edges) from the outline or nearer is tried again with flips
PULL_GIVE_UP = (1e3, 0.5)  # a ring still this far (in mean edges) from the target at this weight is stuck
SNAP_ROUNDS = 12  # rounds that move the pulled ring onto the target outline
SNAP_STALL = 1e-3  # three rounds in a row that move the ring less than this fraction of the way: stuck
SNAP_CUT = 0.1  # a round that moves the ring less than this fraction of the way cuts the triangles in the way


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
        Target edge length of the source mesh's interior near the outline;
        farther in, triangles may grow to `GRADE` times their distance from
        it. Default: the mean edge length of the source rings.
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
    z1, f1 = _refine(zs, f_src, fixed_keys, float(mesh_size), grade=GRADE)
    chords = _misfits(f1, K, zt, rings)
    z1, f1 = np.r_[z1, z1[chords].mean(axis=1)], _split_edges(f1, chords, len(z1))
    for _ in range(SMOOTH_ROUNDS if len(chords) else 0):  # a chord's midpoint across a flat ear: slivers smoothed
        z1 = _smooth(z1, None, f1, K, (1e-14 * _scale2(z1),) * 2, False)[0]

    # first try: the source mesh mapped by mean-value weights (reproduces affine maps); if a triangle
    # flips, the source mesh pulled onto the target outline with no flip; then the map made least distorted
    w_tgt = convex_map(z1, f1, np.arange(K), zt)
    flipped = False
    if not np.all(triangle_areas(w_tgt, f1) > 1e-12 * _scale2(zt)):
        z1, f1, w_tgt, flipped = _pulled(z1, f1, K, zt) if pull else (z1, f1, None, False)
    overlay = w_tgt is None
    crossings = 0
    if not overlay:
        before = (_min_angle(z1, f1), _min_angle(w_tgt, f1))
        w_tgt = _least_distorted(z1, w_tgt, f1, K)
        if flipped:  # connectivity changed on the way: the quality pass, as after an overlay
            z1, w_tgt, f1 = _improve(z1, w_tgt, f1, K, False)
    else:  # the two triangulations overlaid, then refined in both at once
        # the target keeps every source diagonal that is a diagonal of the target too: fewer crossings
        shared = _shared_diagonals(f_src, zt, _polygon(zt, rings), cut_edges)
        f_tgt = _triangulate(zt, rings, np.r_[cut_edges, shared], _keys(np.r_[cut_edges, shared]), "target")
        steiner = len(z1) - K if refine_first else 0
        z1, w_tgt, f1 = _overlay(z1, f1, zt, f_tgt, rings, cuts, K) if refine_first else \
            _overlay(zs, f_src, zt, f_tgt, rings, cuts, K)
        crossings = len(z1) - K - steiner
        if COARSEN:
            ratio = np.sqrt(abs(ring_area(zt[rings[0]]) / ring_area(zs[rings[0]])))
            f1 = _coarsen(z1, w_tgt, f1, K, (mesh_size, mesh_size * ratio),
                          (1e-14 * _scale2(z1), 1e-14 * _scale2(w_tgt)), np.sin(np.radians(COARSE_ANGLE)))
        z1, w_tgt, f1 = _joint_refine(z1, w_tgt, f1, float(mesh_size))
        before = (_min_angle(z1, f1), _min_angle(w_tgt, f1))
        # no least-distorted map here: it spreads the distortion of unlike outlines into slivers, and
        # AIAP folds more often on the result (benchmarks/RESULTS.md, Drawings)
        z1, w_tgt, f1 = _improve(z1, w_tgt, f1, K, False)
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


# ---------------------------------------------------------------- low-distortion map
def _misfits(f, K, zt, rings):
    """(C, 2) edges between two ring vertices that cannot stay edges in the target; each gets a midpoint.

    Such an edge lies outside the target polygon (or along its outline), or
    is a side of a triangle of ring vertices that is not positive there: no
    map of the mesh with the ring held keeps it.
    """
    chords = _chords(f, K)
    if not len(chords):
        return chords
    bad = ~_inside(zt, _polygon(zt, rings), chords)
    ear = f[(f < K).all(axis=1)]
    ear = ear[triangle_areas(zt, ear) <= 1e-12 * _scale2(zt)]
    sides = np.sort(np.stack([ear, np.roll(ear, -1, axis=1)], axis=-1).reshape(-1, 2), axis=1) @ [K, 1]
    bad |= np.isin(chords @ [K, 1], sides)
    return chords[bad]


def _reflip(z, w, f):
    """Flip edges (in place in ``f``) that raise the smallest angle of their two faces over both meshes.

    At most `PULL_FLIPS` rounds of `_quality._joint_flips`; returns the number of flips.
    """
    eps = (1e-14 * _scale2(z), 1e-14 * _scale2(w))
    done = 0
    for _ in range(PULL_FLIPS):
        n = _joint_flips(z, w, f, eps)
        if not n:
            break
        done += n
    return done


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
    """The source mesh deformed with no flipped triangle until its ring vertices reach ``zt``.

    `_pull` with the source's connectivity; where that gets stuck near the
    outline (the ring held at most `PULL_RETRY` mean edges off, or stopped
    while snapping or by a singular Newton system), again with edges flipped
    between the pull's weights.

    Returns
    -------
    z : (N',) complex, f : (F', 3) int, w : (N',) complex or None, flipped : bool
        The (refined) source mesh and its deformed copy (``w`` None when
        stuck), and whether the mesh is the one with edges flipped.
    """
    z1, f1, w, gap = _pull(z, f, K, zt)
    if w is not None or gap > PULL_RETRY:
        return z1, f1, w, False
    z1, f1, w, _ = _pull(z, f, K, zt, flips=True)
    return z1, f1, w, w is not None


def _pull(z, f, K, zt, flips=False):
    """The source mesh deformed with no flipped triangle until its ring vertices reach ``zt``.

    Start: the best similarity of the rings onto ``zt`` applied to the whole
    mesh (every triangle positive). Every vertex is then free, the ring
    vertices pulled towards ``zt`` by a penalty of growing weight
    (`PULL_WEIGHTS`) while the symmetric Dirichlet energy against the source
    triangles keeps the mesh from folding; with ``flips``, edges are flipped
    after every weight where that raises the smallest angle of their faces
    (`_reflip`: a mesh pulled far from the source squeezes triangles that
    the other diagonals of the same quads avoid). Last, the ring vertices
    are moved onto ``zt`` in rounds (`SNAP_ROUNDS`): as far as no triangle
    flips, then the interior relaxed with the ring held; a triangle that
    blocks the move gets its sides cut at their midpoints (in the source
    mesh and in the deformed one alike), which frees room around it.

    Returns
    -------
    z : (N',) complex, f : (F', 3) int, w : (N',) complex or None, gap : float
        The (refined) source mesh and its deformed copy; ``w`` None when
        stuck, ``gap`` then how far (in mean target edges) the ring was held
        off the outline where the pull gave up (0 where the snap or a Newton
        system did).
    """
    f = f.copy()
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
            gap = np.abs(w[:K] - zt).max() / np.sqrt(h2)
            if gap < 1e-9:
                break
            if mu >= PULL_GIVE_UP[0] and gap > PULL_GIVE_UP[1]:  # held far off: no snap will reach the outline
                return z, f, None, gap
            if flips and _reflip(z, w, f):  # the energy on the new faces
                energy = SymmetricDirichlet(z, w, f, np.zeros(len(z), dtype=bool))
                energy.rest(0.0)
                energy.pull_towards(ring, zt, mu * unit)
        stalled = 0
        for _ in range(SNAP_ROUNDS):
            step = np.zeros_like(w)
            step[:K] = zt - w[:K]
            s = max_step(w, step, f)
            if s > 1.0:
                w = w + step
                w[:K] = zt
                return z, f, w, 0.0
            stalled = stalled + 1 if s < SNAP_STALL else 0
            if stalled == 3:  # cutting does not free the ring: the overlay it is
                break
            w = w + 0.8 * s * step
            if s < SNAP_CUT:  # the triangles that stop the ring from moving on get their sides cut
                blocked = face_steps(w, step, f) < 1.0
                sides = np.sort(np.stack([f[blocked], np.roll(f[blocked], -1, axis=1)], axis=-1).reshape(-1, 2), axis=1)
                sides = np.unique(sides[sides[:, 1] >= K], axis=0)  # ring sides stay (chords were cut before)
                z, w = np.r_[z, z[sides].mean(axis=1)], np.r_[w, w[sides].mean(axis=1)]
                f = _split_edges(f, sides, len(z) - len(sides))
            held = np.zeros(len(z), dtype=bool)
            held[:K] = True
            relax = SymmetricDirichlet(z, w, f, held)
            relax.rest(0.0)
            w, _ = minimise(relax, w, PULL_ITER, tol=1e-3)
    except MethodError:
        pass
    return z, f, None, 0.0
