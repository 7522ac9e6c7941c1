"""Sequence editing (Sec. 5.2): change some frames, keep the motion style."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._validate import is_int
from .correspondence.compatibility import as_shape, check_compatible
from .errors import IncompatibleShapesError, ParameterError
from .initialisation import edge_rotations
from .metrics import isometric_energy
from .problems import assemble, check_movable, held_problem
from .sequence import Sequence
from .shape import Shape

if TYPE_CHECKING:
    from collections.abc import Mapping

    from .sequence import Sequence
    from .shape import Shape

__all__ = ["edit"]


def edit(sequence: Sequence, *, frame: int | None = None, shape: Shape | None = None,
         edits: Mapping[int, Shape] | None = None, keep_ends: bool = True,
         correspondence: str = "auto", correspond_options: dict | None = None) -> Sequence:
    """Edit frames of a sequence and carry the change through its motion.

    Each edited frame k gives every edge a similarity S~_ij(t_k) with
    S~ e(t_k) = e~(t_k). The relative velocities are warped by it (Eq. 14)
    and the edge vectors rebuilt by minimising Eq. (15) with the edited frames
    (and, with ``keep_ends``, the first and last frames) held; frames are then
    assembled by Eq. (10) (the :class:`~isotween.optimisation.problem.Problem`
    of :func:`isotween.problems.held_problem`, solved by
    :func:`isotween.problems.assemble`). Every option is keyword-only.
    With one edit and ``keep_ends=False`` this is the paper's procedure (S~
    constant in time). With several held frames, S~ is blended between them
    (log-scale and angle linear in time) and the mismatch left by Eq. (15)
    is spread linearly between held frames, so an edit fades out towards the
    held frames around it.

    Parameters
    ----------
    sequence : Sequence
    frame : int, optional
        Index of the edited frame (with ``shape``).
    shape : Shape or path, optional
        The edited frame: a shape with the sequence's connectivity, or a
        drawing (a file, or a shape with paths) brought onto it.
    edits : dict {int: Shape or path}, optional
        Several edited frames at once.
    keep_ends : bool
        Hold the first and last frames unless they are edited.
    correspondence : {'auto', 'always', 'never'}
        ``'auto'``: an edited frame with the sequence's connectivity is used
        as it is (also a drawing file: a frame written by ``render`` loads
        back so); a shape or drawing with paths of other connectivity is
        brought onto the sequence's connectivity by
        :func:`isotween.pipeline.onto_connectivity` (the frame corresponded
        with the drawing as outlines, the frame's mesh kept). ``'always'``:
        every edited frame so. ``'never'``: edited frames must be compatible.
    correspond_options : dict, optional
        Options of `isotween.correspond` for ``onto_connectivity``.

    Returns
    -------
    Sequence
        Same length and connectivity; the edited frames are matched exactly.
        ``energy`` holds one value: the isometric energy of the edited frames.

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    >>> seq = isotween.interpolate(bar, bar.rotate(1.0), frames=5)
    >>> bent = seq[2].with_vertices(seq[2].vertices + [[0, 0], [0, 0], [0, 0.3]])
    >>> edited = isotween.edit(seq, frame=2, shape=bent)
    >>> edited[2].equals(bent, atol=1e-9), edited[0].equals(seq[0], atol=1e-12)
    (True, True)
    """
    if not isinstance(sequence, Sequence):
        raise ParameterError(f"sequence must be an isotween.Sequence, got {type(sequence).__name__}")
    if edits is not None and not isinstance(edits, dict):
        raise ParameterError(f"edits must be a dict {{frame: Shape}}, got {type(edits).__name__}")
    _check_sequence(sequence)
    edits = dict(edits or {})
    if frame is not None or shape is not None:
        if frame is None or shape is None:
            raise ParameterError("give both frame= and shape= (or edits={frame: shape})")
        edits[frame] = shape
    if not edits:
        raise ParameterError("nothing to edit: give frame= and shape=, or edits={frame: shape}")
    F = len(sequence)
    for k in edits:
        if not is_int(k) or not 0 <= k < F:
            raise ParameterError(f"frame index {k!r} is out of range for a sequence of {F} frames (0..{F - 1})")
    from .pipeline import _is_path, needs_correspondence, onto_connectivity  # a layer above: at call time

    names = ["sequence"]
    for k, s in edits.items():
        if _is_path(s):
            from .io import load

            name, s = f"{s} (edited frame {k})", load(s)
        else:
            name = f"edited frame {k}"
        names.append(name)
        if needs_correspondence(sequence.shape, s, correspondence=correspondence, names=["sequence", name],
                                options=bool(correspond_options), drawings=False):
            s = onto_connectivity(sequence[k], s, name=name, **(correspond_options or {}))
        edits[k] = s
    edits = {k: as_shape(s, f"edited frame {k}") for k, s in edits.items()}
    try:
        check_compatible(sequence.shape, *edits.values(), names=names)
    except IncompatibleShapesError as exc:
        what = str(exc).split("; put them in correspondence")[0]
        raise IncompatibleShapesError(
            f"{what}; give the edited frame with the sequence's vertices and edges (an edited copy of the "
            "frame), or as a drawing with paths, which correspondence='auto' brings onto them") from None
    base = sequence.shape
    z = sequence.z.T  # (n, F)
    e = base.edge_vectors(z.T).T  # (E, F)
    held = set(edits) | ({0, F - 1} if keep_ends else set())
    keys = np.array(sorted(held))
    target = {k: (edits[k].z if k in edits else z[:, k]) for k in keys}
    # log S~ at held frames, blended in time (constant outside the held range)
    logs = np.empty((len(keys), base.n_edges), dtype=complex)
    for i, k in enumerate(keys):
        s, theta = edge_rotations(base, e[:, k], base.edge_vectors(target[k]))
        logs[i] = np.log(s) + 1j * theta
    t = sequence.times
    mid = 0.5 * (t[:-1] + t[1:])
    S = np.exp(_interp_rows(mid, t[keys], logs))  # (E, F-1)
    d = S * np.diff(e, axis=1)  # Eq. (14), times h
    new = _integrate_held(d, keys, {k: base.edge_vectors(target[k]) for k in keys})  # Eq. (15)
    # translations: component centroids shifted by a blend of the held frames' shifts
    avg = base.topology.avg
    c = avg @ z
    shift = np.stack([avg @ target[k] - c[:, k] for k in keys])  # (K, C)
    centroids = c + _interp_rows(t, t[keys], shift)
    problem = held_problem(base, t, keys, np.stack([target[k] for k in keys], axis=1), centroids=centroids,
                           edges=new, scheme=sequence.scheme)
    done = assemble(problem, 1.0 / np.abs(e).mean(axis=1), owner=sequence)  # Eq. (10), one factorisation per sequence
    result = done.sequence(base, t.copy(), method="edit", scheme=sequence.scheme,
                           info={"edited_frames": sorted(edits), "held_frames": keys.tolist(), "source": sequence})
    result.energy = [isometric_energy(result)]  # of the edited frames
    return result


def _check_sequence(sequence):
    """Refuse a sequence whose frames, times or shape cannot be edited."""
    frames, shape, t = sequence.frames, sequence.shape, sequence.times
    if not isinstance(shape, Shape):
        raise ParameterError(f"the sequence's shape must be an isotween.Shape, got {type(shape).__name__}")
    check_movable(shape, "the sequence's shape")
    if frames.ndim != 3 or frames.shape[1:] != shape.vertices.shape or len(frames) < 2:
        raise ParameterError(
            f"the sequence's frames must have shape (F >= 2, {shape.n_vertices}, 2), got {frames.shape}"
        )
    bad = np.flatnonzero(~np.all(np.isfinite(frames), axis=(1, 2)))
    if bad.size:
        raise ParameterError(f"frame {bad[0]} of the sequence has a non-finite coordinate")
    if t.shape != (len(frames),) or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise ParameterError("the sequence's times must increase strictly, one per frame")


def _interp_rows(x, xp, fp):
    """Piecewise-linear interpolation of every column of fp (K, k) at x -> (k, len(x))."""
    fp = np.asarray(fp)
    if len(xp) == 1:
        return np.repeat(fp.T, len(x), axis=1)
    i = np.clip(np.searchsorted(xp, x, side="right") - 1, 0, len(xp) - 2)
    w = np.clip((x - xp[i]) / (xp[i + 1] - xp[i]), 0.0, 1.0)
    return (fp[i] * (1 - w)[:, None] + fp[i + 1] * w[:, None]).T


def _integrate_held(d, keys, values):
    """Minimise sum_k |x_{k+1} - x_k - d_k|^2 with x held at the frames `keys`.

    Between two held frames the increments are integrated and the mismatch is
    spread evenly over the steps (the exact minimiser); before the first and
    after the last held frame the increments are integrated from it.

    Parameters
    ----------
    d : (E, F-1) complex
    keys : (K,) int, sorted
    values : dict {k: (E,) complex}

    Returns
    -------
    (E, F) complex
    """
    E, F = d.shape[0], d.shape[1] + 1
    x = np.zeros((E, F), dtype=complex)
    x[:, 1:] = np.cumsum(d, axis=1)  # x_k - x_0 along the increments
    out = np.empty_like(x)
    first, last = keys[0], keys[-1]
    out[:, : first + 1] = values[first][:, None] + x[:, : first + 1] - x[:, first : first + 1]
    out[:, last:] = values[last][:, None] + x[:, last:] - x[:, last : last + 1]
    for a, b in zip(keys[:-1], keys[1:], strict=True):
        gap = values[b] - values[a] - (x[:, b] - x[:, a])
        w = np.arange(b - a + 1) / (b - a)
        out[:, a : b + 1] = values[a][:, None] + x[:, a : b + 1] - x[:, a : a + 1] + gap[:, None] * w
    return out
