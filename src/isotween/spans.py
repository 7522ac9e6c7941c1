"""Staggered timing: every connected piece of a shape moves over its own span of the morph.

A vertex with span ``(a, b)`` is, in the frame of time ``t``, where the
morph has it at time ``clip((t - a) / (b - a), 0, 1)``: at rest in the
source before ``a``, in the target after ``b``. `isotween.interpolate`
solves once at every time some span needs (`spanned`) and gives the paint a
key where a span starts or ends (`span_paint`), so a piece with no partner is
out of sight (opacity 0) before or after its span.
"""

import dataclasses

import numpy as np

from .errors import ParameterError
from .paint import Paint, lerp_paint, paint_keys

__all__ = ["check_spans", "spanned", "span_paint"]


def check_spans(spans, shape):
    """``spans`` as a list of alternatives ((n, 2) arrays, None: the whole morph); None if the first is that.

    Parameters
    ----------
    spans : (n, 2) or (m, n, 2) array_like, or None
    shape : Shape
        Its edges: every vertex of a connected piece must share its span.

    Raises
    ------
    ParameterError
        Not (n, 2) or (m, n, 2), a span outside [0, 1] or not increasing, or
        spans that differ across an edge (named).
    """
    if spans is None:
        return None
    try:
        s = np.array(spans, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError("spans must be an (n, 2) array of times") from None
    if s.ndim == 2:
        s = s[None]
    if s.shape[1:] != (shape.n_vertices, 2) or not len(s):
        raise ParameterError(f"spans must be ({shape.n_vertices}, 2), one (start, end) per vertex; got {s.shape}")
    a, b = s[..., 0], s[..., 1]
    if not np.all(np.isfinite(s)) or np.any(a < 0) or np.any(b > 1) or np.any(a >= b):
        raise ParameterError("every span must be (start, end) with 0 <= start < end <= 1")
    top = shape.topology
    differ = np.flatnonzero(np.any(s[:, top.first] != s[:, top.second], axis=(0, 2)))
    if differ.size:
        i, j = top.edges[differ[0]]
        raise ParameterError(f"spans differ across edge ({i}, {j}): every vertex of a connected piece moves "
                             f"over the same span")
    whole = [bool(np.all(x == (0.0, 1.0))) for x in s]
    return None if whole[0] else [None if w else x for x, w in zip(s, whole, strict=True)]


def spanned(run, t, spans):
    """``run(grid)``'s sequence brought to frame times ``t``, every vertex at its own time in its span.

    A vertex with span (a, b) is at time ``clip((t - a) / (b - a), 0, 1)`` of
    the morph in the frame of time ``t``: ``run`` is called once with every
    time some vertex needs (``t`` itself among them), and each frame takes
    every vertex from the time its span asks for.

    Parameters
    ----------
    run : callable
        ``run(times)``: a `Sequence` at those (increasing) frame times.
    t : (F,) float
        Frame times.
    spans : (n, 2) float, or None (``run(t)`` itself)

    Returns
    -------
    Sequence
        With (F, n, 2) frames at times ``t``.
    """
    if spans is None:
        return run(t)
    rows, cls = np.unique(spans, axis=0, return_inverse=True)
    local = np.clip((t - rows[:, :1]) / (rows[:, 1:] - rows[:, :1]), 0.0, 1.0)  # (C, F)
    grid, index = np.unique(np.round(np.r_[t, local.ravel()], 12), return_inverse=True)
    seq = run(grid)
    pick = index[len(t):].reshape(local.shape)
    frames = np.empty((len(t),) + seq.frames.shape[1:])
    for c in range(len(rows)):
        idx = np.flatnonzero(cls.ravel() == c)
        frames[:, idx] = seq.frames[np.ix_(pick[c], idx)]
    return dataclasses.replace(seq, frames=frames, times=np.array(t))


def span_paint(source, target, spans):
    """`paint_keys` of the two ends, with a key wherever a span starts or ends (each path's paint follows its span).

    ``spans`` (n, 2) float, or None: the keys at 0 and 1 only.
    """
    keys = paint_keys([source, target], [0.0, 1.0])
    if not keys or spans is None or not source.paths:
        return keys
    ends = [[Paint.from_dict(p) for p in key] for key in keys["paint"]["keys"]]
    span = spans[[p[0] for p, _ in source.paths]]
    key_times = np.unique(np.r_[0.0, 1.0, span.ravel()])
    local = np.clip((key_times - span[:, :1]) / (span[:, 1:] - span[:, :1]), 0.0, 1.0)  # (P, K)
    keys["paint"]["times"] = [float(k) for k in key_times]
    keys["paint"]["keys"] = [[lerp_paint(a, b, [u[k]])[0].to_dict() for a, b, u in zip(*ends, local, strict=True)]
                             for k in range(len(key_times))]
    return keys
