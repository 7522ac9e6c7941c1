"""AIAP interpolation through several keyframes at once."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import numpy as np

from ._heap import keep_heap_if_asked
from ._validate import check_int, check_number
from .correspondence.compatibility import as_shape, check_compatible
from .easing import eased_times
from .errors import ParameterError
from .interpolate import interpolate
from .optimisation import backend
from .optimisation.local_solver import ASSEMBLY
from .optimisation.problem import DEFAULT_TOL, bbox_diagonal
from .optimisation.schemes import SCHEMES
from .optimisation.solve import solve
from .paint import paint_keys
from .problems import check_choice, check_movable, check_stopping, keyed_problem
from .resources import check_memory, solve_bytes
from .sequence import Sequence
from .times import frame_times

if TYPE_CHECKING:
    from collections.abc import Callable
    from collections.abc import Sequence as Seq

    from numpy.typing import ArrayLike

    from .shape import ShapeLike

__all__ = ["interpolate_keyframes"]


def interpolate_keyframes(keyframes: Seq[ShapeLike], *, times: ArrayLike | None = None,
                          frames: int | None = None,
                          easing: str | Callable[[np.ndarray], np.ndarray] = "linear", init: str = "edge",
                          scheme: str = "midpoint", tol: float = DEFAULT_TOL, max_iter: int = 100,
                          smooth: float = 1.0, assembly: str = "shared",
                          callback: Callable[..., object] | None = None,
                          max_memory: float | None = None, solver: str = "local",
                          method: str = "aiap", correspondence: str = "auto",
                          correspond_options: dict | None = None, fit: bool = False) -> Sequence:
    """One AIAP sequence through every keyframe.

    All in-between frames are solved together by the local solver with the
    keyframes held. Besides the isometric energy, a term at every interior
    keyframe asks the edges' velocities to turn smoothly through it (weight
    ``smooth``; 0 makes the segments independent, as if separate two-shape
    runs were glued). Component centroids follow a natural cubic spline
    through the keyframes' centroids (linear for two keyframes). With two
    keyframes the result equals :func:`isotween.interpolate` (both solve the
    :class:`~isotween.optimisation.problem.Problem` of
    :func:`isotween.problems.keyed_problem`). Every option is keyword-only.

    Parameters
    ----------
    keyframes : list of Shape, (n, 2) array_like, or path
        At least two. Compatible shapes are used as they are; files and
        shapes with paths that are not compatible are first put in
        correspondence together, as outlines
        (:func:`isotween.pipeline.prepare_keys`), as ``correspondence`` says.
    times : (K,) array_like, optional
        Keyframe times, strictly increasing from 0 to 1 (default: uniform).
    frames : int, optional
        Total frame count, keyframes included (default 8 per segment + 1).
    easing : str or callable
        Maps uniform frame spacing to frame times (:mod:`isotween.easing`).
    init, scheme, tol, max_iter, assembly, callback
        As in :func:`isotween.interpolate`.
    smooth : float
        Weight of the smoothness term at interior keyframes.
    max_memory : int, optional
        Bytes the run may use (as in :func:`isotween.interpolate`).
    solver, method : str
        As in :func:`isotween.interpolate`. The joint solve above is the
        local solver's with AIAP; ``solver="global"`` or another ``method``
        interpolates each segment between consecutive keyframes on its own
        (the frames pass through every keyframe; ``smooth`` and ``assembly``
        do not apply).
    correspondence : {'auto', 'always', 'never'}
        As in :func:`isotween.interpolate`.
    correspond_options : dict, optional
        Options of `isotween.correspondence.correspond_keys` (``points``,
        ``segment``, ``rotation``, ``unmatched``).
    fit : bool
        Every keyframe after the first scaled (strokes too) and moved into
        the first's bounding box first (`isotween.pipeline.fitted`): drawings
        from sets drawn in different units.

    Returns
    -------
    Sequence
        ``info['keyframe_indices']`` gives the frame index of every keyframe;
        after correspondence ``info['correspondence']`` says what was done.

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    >>> keys = [bar, bar.rotate(0.5), bar.rotate(0.5).translate([1, 0])]
    >>> seq = isotween.interpolate_keyframes(keys, frames=9)
    >>> len(seq), [float(t) for t in seq.times[[0, 4, 8]]]
    (9, [0.0, 0.5, 1.0])
    >>> all(seq[k].equals(key, atol=1e-12) for k, key in zip((0, 4, 8), keys))
    True
    """
    keep_heap_if_asked()
    start = time.perf_counter()
    if isinstance(keyframes, (str, bytes)) or not hasattr(keyframes, "__len__"):
        raise ParameterError(f"keyframes must be a list of shapes, got {type(keyframes).__name__}")
    if len(keyframes) < 2:
        raise ParameterError(f"need at least two keyframes, got {len(keyframes)}")
    names = [f"keyframe {i}" for i in range(len(keyframes))]
    summary = None
    check_choice("scheme", scheme, SCHEMES)
    check_choice("assembly", assembly, ASSEMBLY)
    check_stopping(tol, max_iter)
    check_number("smooth", smooth, strict=False)
    from .pipeline import needs_correspondence  # the pipeline is a layer above: reached at call time

    if fit or needs_correspondence(*keyframes, correspondence=correspondence, names=names,
                                   options=bool(correspond_options)):
        from .pipeline import prepare_keys

        prepared = prepare_keys(keyframes, correspondence=correspondence, fit=fit, **(correspond_options or {}))
        keyframes, summary = prepared.shapes, prepared.summary()
    shapes = [as_shape(s, f"keyframe {i}") for i, s in enumerate(keyframes)]
    check_movable(shapes[0], "keyframe 0")
    check_compatible(*shapes, names=[f"keyframe {i}" for i in range(len(shapes))])
    K = len(shapes)
    frames = 8 * (K - 1) + 1 if frames is None else frames
    check_int("frames", frames, K, bound=f">= the number of keyframes ({K})")
    check_memory(solve_bytes(frames, shapes[0].n_vertices, shapes[0].n_edges),
                 f"interpolating {frames} frames of {shapes[0].n_vertices} vertices and {shapes[0].n_edges} edges",
                 max_memory)
    key_t = frame_times(K, times, per="keyframe")
    t = eased_times(frames, easing)
    idx = np.abs(t[None, :] - key_t[:, None]).argmin(axis=1)
    if np.any(np.diff(idx) <= 0):
        raise ParameterError(f"{frames} frames are too few to give each of the {K} keyframes its own frame")
    t[idx] = key_t
    if np.any(np.diff(t) <= 0):
        raise ParameterError("keyframe times collide with the eased frame times; use more frames")
    if solver != "local" or method != "aiap":
        seq = _segments(shapes, t, idx, key_t, start, solver=solver, method=method, init=init, scheme=scheme,
                        tol=tol, max_iter=max_iter, max_memory=max_memory)
        if summary is not None:
            seq.info["correspondence"] = summary
        return seq
    diag = bbox_diagonal(*(s.vertices for s in shapes))
    with backend.sized(shapes[0].n_edges * len(t)):
        problem = keyed_problem(shapes, t, idx, init=init, scheme=scheme, tol=tol, max_iter=max_iter, diagonal=diag)
        result = solve(problem, assembly=assembly, smooth=smooth, callback=callback)
    del result.timings["solve"]
    result.timings["total"] = time.perf_counter() - start
    seq = result.sequence(shapes[0], t, method="aiap-keyframes", scheme=scheme,
                          info={"keyframe_indices": idx.tolist(), "max_move": result.max_move,
                                **paint_keys(shapes, key_t)})
    if summary is not None:
        seq.info["correspondence"] = summary
    return seq


def _segments(shapes, t, idx, key_t, start, **options):
    """Each keyframe segment interpolated on its own (``solver="global"`` or another ``method``).

    The segments meet at the keyframes (positions continuous, velocities not
    smoothed there: that needs the joint local solve).
    """
    z = np.empty((len(t), shapes[0].n_vertices, 2))
    energy, iterations, converged = 0.0, 0, True
    for j in range(len(shapes) - 1):
        a, b = idx[j], idx[j + 1]
        u = (t[a : b + 1] - t[a]) / (t[b] - t[a])
        u[0], u[-1] = 0.0, 1.0
        seg = interpolate(shapes[j], shapes[j + 1], frames=b - a + 1, times=u, correspondence="never", **options)
        z[a : b + 1] = seg.frames
        iterations += seg.iterations
        converged &= bool(seg.converged)
        energy += float(seg.energy[-1]) if len(seg.energy) else 0.0
    return Sequence(z, shapes[0], times=t, scheme=options["scheme"], energy=[energy], iterations=iterations,
                    converged=converged, timings={"total": time.perf_counter() - start},
                    method=f"{options['method']}-keyframes",
                    info={"keyframe_indices": idx.tolist(), "segments": "each on its own",
                          **paint_keys(shapes, key_t)})
