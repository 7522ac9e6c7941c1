"""`interpolate`: the public entry point of AIAP interpolation of two shapes."""

from __future__ import annotations

import dataclasses
import functools
import time
from typing import TYPE_CHECKING

import numpy as np

from . import baselines
from ._callable import make_callable
from ._heap import keep_heap_if_asked
from ._validate import is_int
from .correspondence.compatibility import as_shape, check_compatible
from .errors import MethodError, ParameterError
from .initialisation import INITIALISERS
from .optimisation import backend
from .optimisation.global_solver import LINEAR_SOLVERS
from .optimisation.hold import Hold, still_vertices
from .optimisation.local_solver import ASSEMBLY
from .optimisation.problem import DEFAULT_TOL, Result, bbox_diagonal
from .optimisation.schemes import SCHEMES
from .optimisation.solve import SOLVERS, solve
from .problems import check_choice, check_movable, check_stopping, keyed_problem
from .resources import check_memory, solve_bytes
from .spans import check_spans, span_paint, spanned
from .times import frame_times

if TYPE_CHECKING:
    from collections.abc import Callable

    from numpy.typing import ArrayLike

    from .sequence import Sequence
    from .shape import ShapeLike

__all__ = ["interpolate", "SOLVERS", "check_movable", "check_stopping", "fold_notes"]

#: Eq. (10)'s weights the fold check solves AIAP with where the shared ones fold, before any repair ('relative':
#: their squares, which hold a growing small copy's short edges as firmly as long ones)
WEIGHTS = ("relative",)

FOLDS = ("allow", "fallback")


def interpolate(source: ShapeLike, target: ShapeLike, frames: int = 9, *, solver: str = "local",
                init: str = "edge", scheme: str = "midpoint", tol: float = DEFAULT_TOL, max_iter: int = 100,
                callback: Callable[[int, float, float], object] | None = None, method: str = "aiap",
                times: ArrayLike | None = None, assembly: str = "shared",
                linear_solver: str = "cg", max_memory: float | None = None,
                fold: str | None = None, correspondence: str = "auto",
                correspond_options: dict | None = None, spans: ArrayLike | None = None) -> Sequence:
    """Interpolate two shapes as-isometrically-as-possible.

    The two-key case of :func:`isotween.interpolate_keyframes`: both solve a
    :class:`~isotween.optimisation.problem.Problem` built by
    :func:`isotween.problems.keyed_problem`. Every option after ``frames`` is
    keyword-only.

    Parameters
    ----------
    source, target : Shape, (n, 2) array_like, or path
        Two compatible shapes (same vertex count and connectivity) are
        interpolated as they are. Any two drawings otherwise: files, or
        shapes with paths that are not compatible, go through the pipeline
        (:func:`isotween.pipeline.morph`: correspondence, this solve, the
        fold check), as ``correspondence`` says.
    frames : int
        Number of frames, both inputs included (``frames=2`` returns the inputs).
    solver : {'local', 'global'}
        Algorithm 2 (per-edge solves plus frame assembly) or Algorithm 1 (all
        intermediate vertices in one sparse system per iteration).
    init : {'edge', 'linear'}
        Edge-vector initialisation (Eqs. 12-13, angles propagated breadth-first)
        or linear blending of vertex positions.
    scheme : {'midpoint', 'paper'}
        Time discretisation of Eq. (6): the time-symmetric midpoint residual
        (default; see benchmarks/RESULTS.md) or the paper's forward differences
        with the reverse sampling of Sec. 3.2.
    tol : float
        Eq. (11): stop when no vertex moves more than ``tol`` times the
        bounding-box diagonal of both inputs between two iterations.
    max_iter : int
    callback : callable(iteration, energy, max_move), optional
        Called after every iteration.
    method : str
        'aiap' (this paper) or a baseline from :mod:`isotween.baselines`
        ('linear', 'intrinsic', 'arap', 'arap-baxter', 'shapespace', 'convex',
        'injective').
    times : (frames,) array_like, optional
        Increasing frame times from 0 to 1 (default: uniform).
    assembly : {'shared', 'relative', 'per-frame'}
        Local solver only: one factorisation of Eq. (10) with frozen weights
        ``2 / (|e(0)| + |e(1)|)`` for every frame (fast), or with their
        squares ('relative': every residual relative to its edge's length),
        or the paper's weights ``1 / |e(t_k)|`` refactorised per frame and
        iteration (reference). With 'shared' and ``fold='fallback'``, the
        fold check solves again with the weights of `WEIGHTS` where these
        fold, before any repair.
    linear_solver : {'cg', 'direct'}
        Global solver only: preconditioned conjugate gradients or sparse LU.
    max_memory : int, optional
        Bytes the run may use; default the memory available now. A run whose
        estimate (:func:`isotween.resources.solve_bytes`) exceeds it raises
        `ResourceError` before allocating.
    fold : {'allow', 'fallback'}, optional
        Default: 'fallback' when correspondence built the meshes, else
        'allow'. 'allow' keeps the result as it is (the paper's behaviour). 'fallback':
        when an in-between frame has a flipped triangle or an outline that
        crosses itself within a region, the ``method='injective'`` morph
        (never folds, nearly isometric; ``'convex'`` if it cannot be built) is
        returned instead; ``info['fallback']`` says why, or why neither could
        be built (the first result is then kept).
    correspondence : {'auto', 'always', 'never'}
        ``'auto'``: compatible shapes are used as they are; drawing files
        (.svg) and shapes with paths that are not compatible are put in
        correspondence (`isotween.correspond`). ``'always'``: correspond even
        compatible inputs. ``'never'``: the inputs must be compatible
        (`IncompatibleShapesError` otherwise).
    correspond_options : dict, optional
        Options of `isotween.correspond` (``points``, ``segment``,
        ``mesh_size``, ...); giving them puts the inputs in correspondence.
    spans : (n, 2) or (m, n, 2) array_like, optional
        Per vertex, the times ``(start, end)`` within [0, 1] over which it
        moves: before ``start`` it rests where the source has it, after
        ``end`` where the target has it, in between it follows the morph
        played at the speed that fits (staggered timing, e.g. one piece
        leaving before another arrives). Every vertex of a connected piece
        shares its span; its paint follows it. Default: every vertex
        ``(0, 1)``. The frames are solved at the times all spans need and
        each piece takes its own (`ParameterError` for spans that are not
        within [0, 1], not increasing, or differ within a piece). Several
        (m, n, 2) are alternatives: the first is used; where its frames
        fold or collide, the fold check takes the first of the next ones
        whose frames do not, before any repair, else it repairs the first,
        and where that cannot keep its pieces apart it tries the next ones
        in turn (one of ``(0, 1)`` everywhere: every piece on the whole
        morph); ``info['spans']`` says which it kept (``{'used': index,
        'why': ...}``).

    Returns
    -------
    Sequence
        ``frames`` is a (frames, n, 2) float64 array. After correspondence
        ``info['correspondence']`` says what was done, and the sequence's
        shape is the corresponded one (its first and last frames are the
        inputs, resampled).

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0], [3, 0]])
    >>> seq = isotween.interpolate(bar, bar.rotate(np.pi / 2).translate([1, 1]), frames=5)
    >>> seq.frames.shape, seq.converged
    ((5, 4, 2), True)
    >>> bool(isotween.metrics.edge_length_deviation(seq) < 1e-9)  # a rigid motion stays rigid
    True
    """
    from .pipeline import needs_correspondence  # the pipeline is a layer above: reached at call time

    if needs_correspondence(source, target, correspondence=correspondence, options=bool(correspond_options)):
        from .pipeline import morph

        if spans is not None:
            raise ParameterError("spans need compatible inputs: the vertices of two drawings are only known after "
                                 "correspondence (isotween.morph staggers pieces with no partner itself)")

        return morph(source, target, frames=frames, correspondence=correspondence, fold=fold,
                     correspond_options=correspond_options, solver=solver, init=init, scheme=scheme, tol=tol,
                     max_iter=max_iter, callback=callback, method=method, times=times, assembly=assembly,
                     linear_solver=linear_solver, max_memory=max_memory)
    fold = "allow" if fold is None else fold
    keep_heap_if_asked()
    start = time.perf_counter()
    source, target = as_shape(source, "source"), as_shape(target, "target")
    check_movable(source, "source")
    if is_int(frames):  # before any allocation
        check_memory(solve_bytes(frames, source.n_vertices, source.n_edges),
                     f"interpolating {frames} frames of {source.n_vertices} vertices and {source.n_edges} edges",
                     max_memory)
    t = frame_times(frames, times)
    timings = check_spans(spans, source)
    check_choice("solver", solver, SOLVERS)
    check_choice("init", init, INITIALISERS)
    check_choice("scheme", scheme, SCHEMES)
    check_choice("assembly", assembly, ASSEMBLY)
    check_choice("linear_solver", linear_solver, LINEAR_SOLVERS)
    check_choice("fold", fold, FOLDS)
    check_stopping(tol, max_iter)
    options = dict(frames=len(t), solver=solver, init=init, scheme=scheme, tol=tol,
                   max_iter=max_iter, method=method, times=times, assembly=assembly,
                   linear_solver=linear_solver, fold=fold)

    def run(spans, faces=None, max_iter=None, weights=assembly):
        """The morph in ``spans``; AIAP only: on other ``faces``, at most ``max_iter``, Eq. (10)'s ``weights``."""
        if method != "aiap":
            return _baseline(method, source, target, t, options, callback, spans)
        a, b = (source, target) if faces is None else (source.with_faces(faces), target.with_faces(faces))
        progress = callback if faces is None and max_iter is None and weights == assembly else None  # the first's
        opts = {**options, "assembly": weights, **({} if max_iter is None else {"max_iter": max_iter})}
        seq = spanned(lambda grid: _aiap(a, b, grid, opts, progress), t, spans)
        seq.timings["total"] = time.perf_counter() - start
        seq.info.update(span_paint(source, target, spans))
        return seq

    first = None if timings is None else timings[0]
    seq = run(first)
    if fold != "fallback":
        return seq

    def alternatives(weights):  # other timings the fold check tries, before a repair that lets pieces meet
        return [(lambda s=s: run(s, weights=weights), s) for s in ([] if timings is None else timings[1:])]

    resolve = (lambda faces: run(first, faces)) if method == "aiap" else None  # AIAP on other triangles
    fewer = (lambda j, faces=None: run(first, faces, max_iter=j)) if method == "aiap" else None  # j iterations
    # where AIAP folds with the shared weights of Eq. (10): AIAP with the others, before any repair
    others = [(lambda w=w: run(first, weights=w), alternatives(w)) for w in WEIGHTS] \
        if method == "aiap" and assembly == "shared" else []
    return _fallback(seq, source, target, t, options, first, alternatives(assembly), resolve, fewer=fewer,
                     others=others)


def _aiap(source, target, t, options, callback):
    """AIAP's sequence of two compatible shapes at frame times ``t`` (Algorithm 1 or 2)."""
    init, scheme, tol, max_iter = (options[k] for k in ("init", "scheme", "tol", "max_iter"))
    start = time.perf_counter()
    diag = bbox_diagonal(source.vertices, target.vertices)
    top = source.topology
    z0, z1 = _complex(source.vertices), _complex(target.vertices)
    if source.n_vertices == target.n_vertices:
        e0, e1 = z0[top.second] - z0[top.first], z1[top.second] - z1[top.first]
        check_compatible(source, target, edge_vectors=(e0, e1), diagonal=diag)
    else:
        check_compatible(source, target)  # raises
    # paths that stay put between the ends are held on their straight way (an outline round a hole that
    # closes, and that hole, shrinking as a copy of itself)
    held = still_vertices(source, z0, z1, diag)
    hold = Hold(source, z0, z1, held) if 0 < held.size < source.n_vertices and len(t) > 2 else None
    flips = _flips(source) if source.n_faces else None
    if len(t) == 2:
        result = Result(np.array([z0, z1]).T)
    else:
        t0 = time.perf_counter()
        with backend.sized(top.n_edges * len(t)):
            problem = keyed_problem([source, target], t, np.array([0, len(t) - 1]), init=init, scheme=scheme,
                                    tol=tol, max_iter=max_iter, diagonal=diag)
            init_time = time.perf_counter() - t0
            # with the fold check, the iterations stop before the first that folds a triangle (where the
            # first does not): Eq. (6) lowered as far as no fold allows, not a fold for the check to repair;
            # where the first folds, once the folds spread (each iteration folds more: GROW)
            folds = flips if options["fold"] == "fallback" else None
            if folds is not None and hold is not None:  # the check sees the frames as they come out
                folds = lambda z: flips(hold(z, t))  # noqa: E731
            result = solve(problem, solver=options["solver"], assembly=options["assembly"],
                           linear_solver=options["linear_solver"], callback=callback, folds=folds)
        result.timings = {"init": init_time, **result.timings}
        if hold is not None:  # where that folds no more triangles
            z = hold(result.z, t)
            if flips is None or flips(z) <= flips(result.z):
                result.z = z
                result.info["held"] = int(held.size)
    result.timings["total"] = time.perf_counter() - start
    return result.sequence(source, t, method="aiap", scheme=scheme,
                           info={"options": options, "max_move": result.max_move})


def fold_notes(seq):
    """What the fold check did to ``seq`` (`interpolate` with ``fold='fallback'``), one line each (list of str)."""
    notes = []
    if "stopped" in seq.info:
        stop = seq.info["stopped"]
        notes.append(f"aiap stopped at iteration {stop['iteration']}, before the first in which "
                     f"{stop.get('why', 'a triangle folds')} (iteration {stop['of']})")
    if "spread" in seq.info:
        spread = seq.info["spread"]
        notes.append(f"aiap stopped at iteration {spread['iteration']}: its folds spread from {spread['first']} "
                     f"flipped triangles (over all frames) after the first iteration to {spread['now']}")
    return notes + [seq.info[key] for key in ("weights", "unfolded", "fallback") if key in seq.info]


def _flips(shape):
    """``folds(z)``: the triangles of ``shape`` flipped (`metrics.flipped`) in the frames of ``z`` (n, F), summed."""
    sign = np.sign(shape.face_areas())

    def folds(z):
        areas = shape.face_areas(np.stack([z.real.T, z.imag.T], axis=-1))  # (F, faces)
        return int(np.count_nonzero((np.sign(areas) != sign) & (sign != 0) & (areas[:1] != 0)))

    return folds


def _complex_frames(frames):
    """(T, n) complex copy of (T, n, 2) float frames."""
    frames = np.asarray(frames, dtype=np.float64)
    return frames[..., 0] + 1j * frames[..., 1]


def _complex(v):
    """(n,) complex view of (n, 2) float vertices (read only here)."""
    return np.ascontiguousarray(v, dtype=np.float64).view(complex)[:, 0]


def _baseline(method, source, target, t, options, callback, spans):
    start = time.perf_counter()
    seq = spanned(lambda grid: baselines.run(method, source, target, len(grid), times=grid, tol=options["tol"],
                                              max_iter=options["max_iter"], callback=callback), t, spans)
    seq.timings.setdefault("total", time.perf_counter() - start)
    seq.info.setdefault("options", options)
    seq.info.update(span_paint(source, target, spans))
    return seq


def _fallback(seq, source, target, t, options, spans, alternatives=(), resolve=None, apart_only=False,
              fewer=None, others=(), own_only=False):
    """``seq``; where an in-between frame folds or collides, its folding frames repaired, else the fold-free morph.

    A frame folds where a triangle flips or a region's outline crosses
    itself, and collides where two separate pieces cross each other
    (`_crossed`). Where a few faces flip, AIAP is first solved again with
    edges flipped there (`isotween.foldfree.unfold`; ``resolve(faces)``:
    the sequence on other faces): where that folds no face and no outline
    crosses, it is the result (AIAP's, ``info['unfolded']`` says how many
    edges were flipped), else the repairs start from it. Then
    `isotween.foldfree.repair.repair_folds` with the
    scaffold around the pieces (`isotween.foldfree.scaffold`): the frames
    moved as little as no flip in the regions or in the empty space around
    them allows (where AIAP only flips triangles, first in the regions
    alone: fewer unknowns, kept where no pieces meet). Where that cannot
    follow the motion: collisions alone are
    kept; folds are repaired in the regions only, and if a repaired frame
    still has crossing outline edges, the fold-free 'injective' morph (else
    'convex') replaces the whole sequence. ``info['fallback']`` says which.
    ``alternatives``: (``make()``, spans) of other timings of the same
    morph (`interpolate`'s ``spans``): the first of them whose frames are
    clean as they are (its pieces out of sight where it has them so) is the
    result before any repair of this one (AIAP's own); else each is checked
    in turn where this one cannot be repaired with its pieces apart, before
    the repair in the regions alone; ``apart_only``: only the repairs that
    keep pieces apart, else None. ``fewer(j, faces=None)``: the sequence after at
    most j AIAP iterations (on other faces); where outlines cross but no face
    folds, the most iterations whose outlines do not are looked for first
    (`_fewer_iterations`); where the first iteration folds, edges are first
    flipped where it does (`unfold`, judged on first iterations), and AIAP
    on those faces is stopped before a fold, or where its outlines cross,
    at the most iterations whose outlines do not; where that still folds
    and the first iteration (on the flipped faces) folds fewer triangles
    than the last, the first is what is repaired (``info['fallback']``
    says 'at iteration 1'). ``others``: (``make()``, ``alternatives``) of
    AIAP with other weights of Eq. (10) (`interpolate`'s ``assembly``):
    before any repair, the first of them that is clean as it is, or in one
    of its alternatives, is the result (``info['weights']`` says so);
    ``own_only``: None where only a repair would do.
    """
    from . import metrics
    from .foldfree.scaffold import Around

    alternatives = [(functools.cache(make), other) for make, other in alternatives]  # each solved once

    if seq.method in ("convex", "injective") or len(t) < 3:
        return seq
    z = _complex_frames(seq.frames)
    hidden = _hidden(seq)
    within, across = _crossed(seq.shape, z[[0, -1]], hidden)
    inner = np.arange(1, len(t) - 1)

    def folds(s, crossed=(within, across)):  # (flips, crossings, collisions) of s's in-between frames, (F - 2,) each
        x = _complex_frames(s.frames)[1:-1]
        return metrics.flipped_faces(s, None)[1:-1], crossed[0](inner, x), crossed[1](inner, x)

    def clean(s, crossed=(within, across)):
        return not any(x.any() for x in folds(s, crossed))

    def fewest(s, faces=None, found=None):  # s, or where outlines cross, no face folds: most iterations that do not
        flipped, *crossed = folds(s) if found is None else found
        if fewer is None or s.iterations < 2 or flipped.any() or not any(x.any() for x in crossed):
            return s
        return _fewer_iterations(s.iterations, lambda j: fewer(j, faces), clean) or s

    flips, crossings, collisions = folds(seq)
    if not (flips.any() or crossings.any() or collisions.any()):
        return seq
    if not flips.any():  # outlines cross, no face folds
        done = fewest(seq, found=(flips, crossings, collisions))
        if done is not seq:
            return done
    at = ""  # where the repaired frames come from, where not the last iteration
    if resolve is not None and flips.any():  # a few faces fold: AIAP again with edges flipped there
        from .foldfree.unfold import unfold

        first = None
        if fewer is not None and "stopped" not in seq.info and seq.iterations > 1:
            # the first iteration folds already: edges flipped where it folds (judged on first iterations,
            # `fewer(1, faces)`), then AIAP on those faces, stopped before a fold again (or a crossing)
            first = unfold(fewer(1), lambda faces: fewer(1, faces))
            if "unfolded" in first.info and not metrics.flipped_faces(first):
                again = fewest(resolve(first.shape.faces), first.shape.faces)
                if clean(again):
                    again.info["unfolded"] = first.info["unfolded"]
                    return again
        found = None if first is None else folds(first)
        if found is not None and 0 < found[0].sum() < flips.sum():
            # the later iterations fold more than the first (a few faces, flipped where they fold): the first
            # is repaired, with fewer frames and vertices to move, so the outlines stay smooth
            at = f" at iteration 1 of {seq.iterations}"
            seq, z = first, _complex_frames(first.frames)
            flips, crossings, collisions = found
        else:
            seq = unfold(seq, resolve)
            if "unfolded" in seq.info:
                z = _complex_frames(seq.frames)
                flips, crossings, collisions = folds(seq)
                if not (flips.any() or crossings.any() or collisions.any()):
                    return seq
    for n, (make, _) in enumerate(alternatives, 1):  # a quicker timing whose frames are clean, before a repair
        alt = make()
        if clean(alt, _crossed(alt.shape, z[[0, -1]], _hidden(alt))):  # its pieces out of sight in its own frames
            alt.info["spans"] = {"used": n, "why": "the first spans fold or collide where these do not"}
            return alt
    for make, timings in others:  # AIAP with other weights: clean as it is or in another timing
        done = _fallback(make(), source, target, t, options, spans, timings, own_only=True)
        if done is not None:
            done.info["weights"] = (f"{seq.method} folded with the {options['assembly']} weights of Eq. (10); solved "
                                    f"again with the {done.info['options']['assembly']} weights, which do not fold")
            return done
    if own_only:
        return None
    bad = flips | crossings | collisions
    folded = (f"{seq.method} folded{at} in {int(np.count_nonzero(bad))} of {len(t) - 2} in-between frames "
              f"({int(flips.sum())} flipped triangles, {int(crossings.sum() + collisions.sum())} outline crossings)")
    apart = []  # (scaffold, accept) of the repairs that keep pieces apart: the regions alone, then the scaffold
    both = lambda k, x: not (within(k, x) or across(k, x))  # noqa: E731
    if seq.shape.faces is not None and flips.any() and not (crossings.any() or collisions.any()):
        apart.append((None, both))  # flips alone: repaired in the regions, where that keeps pieces apart
    if seq.shape.faces is not None and seq.shape.regions:
        apart.append((Around(seq.shape, z, hidden), both))
    repaired = _repaired(seq, z, apart, folded)
    if repaired is not None:
        return repaired
    for n, (make, other) in enumerate(alternatives, 1):  # another timing of the morph, with its pieces apart
        done = _fallback(make(), source, target, t, options, other, apart_only=True)
        if done is not None:
            done.info["spans"] = {"used": n, "why": "the fold check could not keep the pieces apart with the "
                                                        "first spans"}
            return done
    if apart_only:
        return None
    if seq.shape.faces is not None and (flips.any() or crossings.any()):  # the regions alone, pieces may meet
        repaired = _repaired(seq, z, [(None, lambda k, x: not within(k, x))], folded)
        if repaired is not None:
            return repaired
    if not (flips.any() or crossings.any()):  # pieces meet, but no fold: the method's frames kept
        seq.info["collisions"] = (f"{int(collisions.sum())} crossings between pieces in "
                                  f"{int(np.count_nonzero(collisions))} frames; no scaffold could hold them apart")
        return seq
    try:
        free = _baseline("injective", source, target, t, options, None, spans)
        free.info["fallback"] = f"{folded}; replaced by the fold-free injective morph"
    except MethodError as exc:
        try:
            free = _baseline("convex", source, target, t, options, None, spans)
        except MethodError:
            seq.info["fallback"] = f"{folded}; kept, as no fold-free morph (injective, convex) can be built: {exc}"
            return seq
        free.info["fallback"] = f"{folded}; replaced by the fold-free convex morph (injective failed: {exc})"
    free.timings["total"] = free.timings.get("total", 0.0) + seq.timings.get("total", 0.0)
    return free


def _fewer_iterations(k, fewer, clean):
    """The result of the most AIAP iterations below ``k`` that is ``clean``, or None where the first is not.

    ``fewer(j)``: the sequence after at most j iterations; the clean ones are
    taken to come first (a bisection). ``info['stopped']`` says where, and why.
    """
    best, lo, hi = fewer(1), 1, k - 1
    if not clean(best):
        return None
    while lo < hi:
        mid = (lo + hi + 1) // 2
        seq = fewer(mid)
        if clean(seq):
            best, lo = seq, mid
        else:
            hi = mid - 1
    best.info["stopped"] = {"iteration": best.iterations, "of": lo + 1, "why": "outlines cross"}
    return best


def _repaired(seq, z, attempts, folded):
    """``seq`` with its folding frames repaired by the first of ``attempts`` ((scaffold, accept)) that can, or None."""
    from .foldfree.repair import repair_folds

    started = time.perf_counter()
    for scaffold, accept in attempts:
        try:
            frames, info = repair_folds(z, seq.shape.faces, accept=accept, scaffold=scaffold)
        except MethodError:
            continue
        if not info["frames"]:
            continue
        repaired = dataclasses.replace(seq, frames=np.stack([frames.real, frames.imag], axis=-1),
                                       info=dict(seq.info), timings=dict(seq.timings))
        diag = bbox_diagonal(seq.frames[0])
        repaired.info["fallback"] = (
            f"{folded}; frames {info['frames'][0]}-{info['frames'][-1]} repaired with no flip "
            f"(within {100 * info['deviation'] / diag:.2g} % of the diagonal of {seq.method}'s)")
        repaired.info["repair"] = info
        repaired.timings["repair"] = time.perf_counter() - started
        return repaired
    return None


def _hidden(seq):
    """``hidden(k)``: the filled regions drawn with opacity 0 in frame k (`paint.out_of_sight`), or None."""
    from .paint import out_of_sight

    gone = out_of_sight(seq)
    if not seq.shape.regions or not gone.any():
        return None
    outer = [r[0] for r in seq.shape.regions]
    return lambda k: set(np.flatnonzero(gone[k, outer]).tolist())


def _crossed(shape, ends, hidden=None):
    """``(within, across)``: functions counting outline crossings at positions ``z`` (N,) complex.

    ``within(k, z)``: crossings within every region (outer ring and holes)
    and path of frame k; ``across(k, z)``: crossings between the outlines
    of different filled regions that lie on no other at either end,
    ``ends`` (2, N) complex (`isotween.foldfree.scaffold.separate_regions`:
    a piece that splits off from another may overlap it), always 0 where
    an end already has such a crossing (layered pieces, as in an emoji).
    Both leave out the regions ``hidden(k)`` (out of sight in frame k: a
    piece faded out, or not yet in). Given frames ``k`` (F,) int and ``z``
    (F, N) complex, both count every frame in one sweep ((F,) int).
    """
    from . import metrics
    from .foldfree.scaffold import separate_regions

    edges, group = metrics.outline_edges(shape, scope="region")
    regions = group is not None
    group = group if regions else np.zeros(len(edges), dtype=np.int64)  # a mesh's boundary: one group

    def seen(k, g):  # (F, B) or (B,) bool: the edges (of groups g) in sight in frames k
        out = np.ones((np.size(k), len(g)), dtype=bool)
        for row, kk in enumerate(np.atleast_1d(k)):
            if hidden is not None and hidden(kk):
                out[row] = ~np.isin(g, len(shape.paths) + np.array(sorted(hidden(kk)), dtype=np.int64))
        return out if np.ndim(k) else out[0]

    def counted(k, z, e, g, apart):  # crossings of edges e in sight, within one group g or (apart) across two
        keep = seen(k, g)
        if np.ndim(k):
            i, j, frame = metrics.crossing_edges(z, e, None if apart else g, seen=keep)
            return np.bincount(frame[g[i] != g[j]] if apart else frame, minlength=len(k)).astype(np.int64)
        i, j = metrics.crossing_edges(z, e[keep], None if apart else g[keep])
        return int(np.count_nonzero(g[keep][i] != g[keep][j])) if apart else len(i)

    def within(k, z):
        return counted(k, z, edges, group, False)

    def nothing(k, z):
        return np.zeros(len(k), dtype=np.int64) if np.ndim(k) else 0

    if not regions:
        return within, nothing
    solid = np.isin(group, len(shape.paths) + np.array(separate_regions(shape, ends), dtype=np.int64))
    pieces, owner = edges[solid], group[solid]

    def across(k, z):
        return counted(k, z, pieces, owner, True)

    if not len(pieces) or any(across(k, z) for k, z in ((0, ends[0]), (-1, ends[1]))):
        return within, nothing
    return within, across


# `isotween.interpolate(...)` calls `interpolate`; `import isotween.interpolate` still gives this module
make_callable(__name__)
