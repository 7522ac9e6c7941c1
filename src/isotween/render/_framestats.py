"""Per-frame distortion numbers for the viewer and plots (SPEC.md definitions).

Uses ``isotween.metrics`` when it offers per-frame values (``reduce=None``),
otherwise computes them here with the same definitions.
"""

import numpy as np

from ._frames import sequence_frames

__all__ = ["frame_stats"]


def _signed_areas(shape, frames):
    """(F, k) signed areas of the faces, or of the closed rings when there are none."""
    if shape.n_faces:
        return shape.face_areas(frames)
    rings = [idx for idx, closed in (shape.paths or []) if closed]
    if not rings:
        return np.zeros((len(frames), 0))
    cols = []
    for idx in rings:  # one column per ring; the shoelace sum is vectorised over frames
        p = frames[:, idx]
        q = np.roll(p, -1, axis=1)
        cols.append(0.5 * np.sum(p[..., 0] * q[..., 1] - q[..., 0] * p[..., 1], axis=1))
    return np.column_stack(cols)


def _relative_to_blend(values, times):
    """|x_k / ((1 - t_k) x_0 + t_k x_m) - 1| per frame and element, (F, k)."""
    t = times[:, None]
    blend = (1 - t) * values[0] + t * values[-1]
    scale = np.maximum(np.abs(blend), 1e-12 * max(np.abs(values).max(initial=0.0), 1e-300))
    return np.abs(values - blend) / scale


def _own(seq, frames, times):
    shape = seq.shape
    lengths = np.abs(shape.edge_vectors(frames[..., 0] + 1j * frames[..., 1]))  # (F, E)
    edge = _relative_to_blend(lengths, times).max(axis=1, initial=0.0)
    areas = _signed_areas(shape, frames)
    area = _relative_to_blend(areas, times).max(axis=1, initial=0.0)
    flipped = (np.sign(areas) != np.sign(areas[0])) & (areas[0] != 0)
    return edge, area, flipped


def _lead_per_frame(name, seq, n):
    """Per-frame values from ``isotween.metrics.<name>(seq, reduce=None)``, or None."""
    try:
        from .. import metrics
    except ImportError:
        return None
    fn = getattr(metrics, name, None)
    if fn is None:
        return None
    try:
        out = np.asarray(fn(seq, reduce=None), dtype=np.float64)
    except (TypeError, ValueError):
        return None
    if out.ndim == 2 and len(out) == n:
        return out.max(axis=1, initial=0.0)
    if out.ndim == 1 and len(out) == n:
        return out
    return None


def frame_stats(seq):
    """Distortion of every frame of a sequence.

    Parameters
    ----------
    seq : Sequence

    Returns
    -------
    dict
        ``edge_length_deviation`` (F,): max over edges of the relative length
        error against the linear blend of end lengths; ``area_deviation`` (F,):
        the same for signed face (or closed ring) areas; ``flipped_faces`` (F,)
        int: faces whose orientation differs from the source; ``flipped`` (F, k)
        bool: which ones.
    """
    frames = sequence_frames(seq)
    times = np.asarray(seq.times, dtype=np.float64)
    edge, area, flipped = _own(seq, frames, times)
    lead_edge = _lead_per_frame("edge_length_deviation", seq, len(frames))
    lead_area = _lead_per_frame("area_deviation", seq, len(frames))
    edge = edge if lead_edge is None else lead_edge
    area = area if lead_area is None else lead_area
    return {
        "edge_length_deviation": edge,
        "area_deviation": area,
        "flipped_faces": flipped.sum(axis=1).astype(np.int64),
        "flipped": flipped,
    }
