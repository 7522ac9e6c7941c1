"""Folds of an interpolated sequence repaired frame by frame, as close to its own frames as no flip allows.

Where AIAP's least-squares frames (Eq. 10) fold a few triangles, the rest of
the frame is still what the method asks for. Every folding frame is
replaced by the minimum of

    E(x) = sum_f A_f (|J_f|^2 + |J_f^-1|^2) + mu sum_v |x_v - a_v|^2,

where ``a`` is the folding frame, ``J_f`` the Jacobian of face f's map from
its rest triangle (the triangle of ``a`` with the same side lengths, so a
folded face rests as its unfolded mirror image), and ``mu`` pulls every
vertex to its place in ``a`` (`PULL`, in units of the least energy per
vertex and squared edge). The symmetric Dirichlet term is infinite on a
degenerate triangle, and the projected Newton of
`isotween.optimisation.barrier` keeps every iterate flip-free, so the start
must be. First only the vertices within a few face rings of the folding
faces move (`RINGS`, widened where the start turns a face over), the
others stay exactly where ``a`` has them: the start is the repaired frame
before, carried by the similarity that best takes its vertices around the
folds to ``a``, at the folds, blended to ``a`` over the rings. Where that
fails (an outline that crosses with no face folded, or a result that
``accept`` refuses), every vertex moves, from the repaired frame before
moved towards ``a`` as far as no triangle degenerates. With a scaffold
(`isotween.foldfree.scaffold`), frames are first repaired in the regions
alone, around their folds, while ``accept`` keeps the result (the
scaffold's guess turns its own triangles over, which widens the band
round the folds to nearly every vertex); from the first frame where it
does not, the empty space around the pieces joins the energy, so pieces
cannot pass through each other either: triangulated where they are before
that frame, then carried from frame to frame with its edges flipped to
Delaunay, and triangulated afresh where its smallest angle falls below
`WORN` of what it was when built, or where a frame repaired in the carried
one is refused (pieces that touch leave it a gap). Frames
from the first folding one to the last folding one are repaired (so the
motion has no jump inside that range), and after it those that the
repaired motion needs to catch up with the given one (pieces held apart
may lag behind where the given ones passed through each other; at most
`CATCH_UP` of the sequence); the others are kept bit for bit.
"""

import numpy as np

from ..errors import MethodError, ShapeError
from ..geometry import triangle_angles, triangle_areas
from ..optimisation.barrier import SymmetricDirichlet, max_step, minimise

__all__ = ["repair_folds", "CATCH_UP", "GAP", "JUMP", "PULL", "MAX_ITER", "SCAFFOLD_WEIGHT", "TOL", "WORK", "WORN"]

PULL = 1.0  # weight of the pull to the folding frame, in units of the least energy per vertex and squared edge
MAX_ITER = 30  # Newton iterations per frame at most
TOL = 1e-2  # stop when an iteration lowers the energy above its least value by less than this fraction
SCAFFOLD_WEIGHT = 0.1  # the scaffold's symmetric Dirichlet per unit area, against the regions'
GAP = 0.25  # the scaffold's triangles rest no smaller than an equilateral one with this fraction of the mean edge
JUMP = 2.0  # the last repaired frame ends at most this many of the sequence's largest steps from the next
CATCH_UP = 0.15  # past the last folding frame, at most this share of the frames is repaired to catch up with the motion
WORN = 0.5  # the scaffold is triangulated afresh once its smallest angle falls below this share of its first
# a frame is first repaired around its folds alone: the vertices within so many face rings move (one try each,
# the vertices of the faces a start turns over held back with the folds in the next)
RINGS = (2, 2, 2, 4, 4, 4, 8, 8)
WORK = 2_000_000  # Newton iterations x vertices for the whole repair; beyond it the repair gives up


def repair_folds(frames, faces, accept=None, scaffold=None):
    """Frames with no flipped triangle, each as close to the given frame as that allows.

    Parameters
    ----------
    frames : (T, N) complex
        Vertex positions per frame; frame 0 (the source) has no degenerate
        face, and its orientation of every face is the one kept.
    faces : (F, 3) int
    accept : callable, optional
        ``accept(k, x)`` with a repaired frame ``x`` (N,) complex: False
        stops the repair (`MethodError`), e.g. when the frame's outline
        crosses itself, which no repair of flips mends.
    scaffold : Around, optional
        ``scaffold(k, z)``: the empty space around the regions held apart in
        frame k (``scaffold.held(k)``) at positions ``z`` (N,) complex,
        triangulated (a `isotween.foldfree.scaffold.Scaffold`; built afresh
        where the regions held apart change). Its triangles join the
        repair at weight `SCAFFOLD_WEIGHT` (per unit area, against the
        regions'), each resting as it is, grown to at least a small area
        (`GAP`): a barrier that pushes nothing but resists squeezing, so a
        repaired frame is an embedding and no two pieces overlap, while
        pieces can still slide past each other from frame to frame. It
        joins from the first frame that the regions repaired alone do not
        pass ``accept``.

    Returns
    -------
    frames : (T, N) complex
        The repaired frames (a new array; frames outside the repaired range
        are copies).
    info : dict
        ``frames`` (indices repaired), ``iterations`` (Newton iterations in
        all), ``deviation`` (largest distance of a repaired vertex from its
        place in the given frame).

    Raises
    ------
    MethodError
        Frame 0 has a degenerate face, the last frame a flipped or degenerate
        one, a Newton system cannot be solved, ``accept`` refused a frame,
        the repair needs more than `WORK` (Newton iterations times
        vertices), or the last repaired frame (`CATCH_UP` included) ends
        more than `JUMP` times the sequence's largest frame-to-frame step
        away from the next frame (the repair could not follow the motion).
    """
    frames = np.asarray(frames, dtype=complex)
    f = np.asarray(faces, dtype=np.int64)
    n = frames.shape[1]
    area0 = triangle_areas(frames[0], f)
    if np.any(area0 == 0):
        raise MethodError("the first frame has a degenerate triangle; its folds cannot be told")
    f = np.where((area0 < 0)[:, None], f[:, ::-1], f)  # every face positive in frame 0
    if np.any(triangle_areas(frames[-1], f) <= 0):
        raise MethodError("the last frame itself has flipped triangles: no fold-free way leads to it")
    folded = [k for k in range(1, len(frames) - 1) if np.any(triangle_areas(frames[k], f) <= 0)
              or (accept is not None and not accept(k, frames[k]))]
    out = frames.copy()
    info = {"frames": [], "iterations": 0, "deviation": 0.0}
    if not folded:
        return out, info
    share = np.abs(area0).sum()
    energy = None  # the energy over every face, made when a frame is not repaired around its folds alone
    prev = frames[folded[0] - 1]  # the last repaired frame (and the scaffold's vertices, once there is one)
    sc, worst, held = None, 0.0, ()  # the scaffold in use, its smallest angle when built, the regions it holds
    stride = np.abs(np.diff(frames, axis=0)).max()
    k, last = folded[0], folded[-1]
    latest = min(len(frames) - 2, last + int(CATCH_UP * (len(frames) - 1)))
    alone = scaffold is not None  # first the regions alone, around their folds, until a frame needs the scaffold
    while k <= last:
        x = None
        if alone:
            a = frames[k]
            sides = np.abs(a[np.roll(f, -1, axis=1)] - a[f])
            local = _local(prev[:n], a, f, sides, None, np.zeros(n, dtype=bool), n, float(np.mean(sides ** 2)))
            if local is not None:
                _spend(info, local[1], n)
            if local is not None and (accept is None or accept(k, local[0])):
                x = local[0]
            else:
                alone = False
        for retry in () if x is not None else (False, True):
            a, joint, fixed, weight = frames[k], f, np.zeros(n, dtype=bool), None
            state, area = prev, np.zeros(0)
            carried = False
            if scaffold is not None:  # the space around the pieces: the last frame's while it keeps its shape
                carried = (not retry and sc is not None and held == scaffold.held(k)
                           and triangle_angles(prev, sc.faces).min() >= WORN * worst)
                if carried:
                    faces, sc = sc.faces, sc.moved(prev)
                    if not np.array_equal(faces, sc.faces):
                        energy = None
                else:  # triangulated afresh where the pieces are now
                    try:
                        held, sc = scaffold.held(k), scaffold(k, prev[:n])
                    except ShapeError as exc:
                        raise MethodError(f"no scaffold around frame {k - 1}: {exc}") from None
                    worst = triangle_angles(np.r_[prev[:n], sc.source], sc.faces).min()
                    energy = None
                g = np.asarray(sc.faces, dtype=np.int64)
                state = np.r_[prev[:n], sc.source]
                a = np.r_[a, sc.follow(np.stack([state[:n], a]))[1]]
                joint, fixed = np.r_[f, g], np.r_[fixed, sc.fixed]
                area = triangle_areas(state, g)
                weight = np.r_[np.ones(len(f)), np.full(len(g), SCAFFOLD_WEIGHT * share / area.sum())]
            sides = np.abs(a[np.roll(joint, -1, axis=1)] - a[joint])
            h2 = float(np.mean(sides[:len(f)] ** 2))
            # the scaffold rests as it is now, grown to at least the area of an equilateral triangle with a
            # fraction of the regions' mean edge: a barrier that pushes nothing but resists squeezing
            g = joint[len(f):]
            grow = np.sqrt(np.maximum(1.0, np.sqrt(3) / 4 * GAP ** 2 * h2 / area))
            sides[len(f):] = np.abs(state[np.roll(g, -1, axis=1)] - state[g]) * grow[:, None]
            local = _local(state, a, joint, sides, weight, fixed, n, h2)  # first around the folds alone
            if local is not None:
                x, used = local
                _spend(info, used, len(x))
                if accept is None or accept(k, x[:n]):
                    break
            if energy is None:
                energy = SymmetricDirichlet(state, state, joint, fixed, weight)
            if weight is not None:
                energy.weight = weight
            energy.rest_lengths(sides)
            energy.pull_towards(np.arange(n), a[:n], PULL * energy.least / (n * h2))
            step = a - state
            x = state + min(1.0, 0.9 * max_step(state, step, joint)) * step
            x, used = minimise(energy, x, MAX_ITER, tol=TOL)
            _spend(info, used, len(x))
            if accept is None or accept(k, x[:n]):
                break
            if not carried:  # a carried scaffold may have let pieces meet where a fresh one holds them apart
                raise MethodError(f"repaired frame {k} is not accepted")
        prev, out[k] = x, x[:n]
        info["deviation"] = max(info["deviation"], float(np.abs(x[:n] - frames[k]).max()))
        info["frames"].append(k)
        jump = np.abs(frames[k + 1] - prev[:n]).max()
        if k == last < latest and jump > JUMP * stride:
            last += 1  # not caught up with the motion yet: the next frame is repaired too
        k += 1
    if jump > JUMP * stride:
        raise MethodError(f"the repaired frames end {jump / stride:.2g} times the sequence's largest step "
                          f"away from the next frame")
    return out, info


def _spend(info, iterations, size):
    """Count Newton ``iterations`` on ``size`` vertices in ``info``; `MethodError` once past `WORK`."""
    info["iterations"] += iterations
    if info["iterations"] * size > WORK:
        raise MethodError(f"repairing the folds needs more than {WORK} Newton iterations x vertices")


def _local(state, a, faces, sides, weight, fixed, n, h2):
    """Frame ``a`` (M,) complex repaired around its folds alone, or None where that does not do.

    The vertices within `RINGS` face rings of a folding face (signed area
    at most 0 in ``a``) move, unless ``fixed``; the others stay where ``a``
    has them. Start: ``state`` (the repaired frame before) carried by the
    similarity that best takes the vertices of the rings from ``state`` to
    ``a``, at the folds, blended to ``a`` over the rings (the vertices of a
    face that the blend turns over are held back with the folds in the next
    try); then `repair_folds`'s energy (rest ``sides`` (K, 3), face
    ``weight``, the pull of the first ``n`` vertices, regions against
    scaffold, to ``a`` with squared mean edge ``h2``) over the faces around
    the moving vertices. None when ``a`` has no folding face (a crossing outline
    alone) or no blend is flip-free.

    Returns
    -------
    x : (M,) complex, iterations : int
    """
    held = np.zeros(len(a), dtype=bool)
    held[faces[triangle_areas(a, faces) <= 0].ravel()] = True
    if not held.any():
        return None
    for rings in RINGS:
        depth = np.where(held, 0, rings + 1)
        near = held.copy()
        for ring in range(1, rings + 1):  # the vertices of the faces that touch the rings before
            near[faces[near[faces].any(axis=1)].ravel()] = True
            depth[near & (depth > ring)] = ring
        band = (depth > 0) & (depth <= rings)
        s, t = state[band] - state[band].mean(), a[band] - a[band].mean()
        turn = np.vdot(s, t) / max(np.vdot(s, s).real, 1e-300)  # the similarity of the band from state to a
        moved = a[band].mean() + turn * (state - state[band].mean())
        x = np.where(depth < rings, moved + depth / rings * (a - moved), a)
        turned = triangle_areas(x, faces) <= 0
        if not turned.any():
            break
        held[faces[turned].ravel()] = True
    else:
        return None
    free = (depth <= rings) & ~fixed
    around = np.flatnonzero(free[faces].any(axis=1))
    try:
        energy = SymmetricDirichlet(x, x, faces[around], ~free, None if weight is None else weight[around])
    except MethodError:
        return None
    energy.rest_lengths(sides[around])
    pulled = np.flatnonzero(free[:n])
    energy.pull_towards(pulled, a[pulled], PULL * energy.least / (max(len(pulled), 1) * h2))
    return minimise(energy, x, MAX_ITER, tol=TOL)
