"""Per-frame distortion numbers for the viewer and the plots (`isotween.metrics`)."""

import numpy as np

from .. import metrics
from ._view import sequence_frames

__all__ = ["frame_stats"]


def frame_stats(seq):
    """Distortion of every frame of a sequence (docs/how-it-works.md, Metric definitions).

    Parameters
    ----------
    seq : Sequence

    Returns
    -------
    dict
        ``edge_length_deviation`` (F,) float and ``area_deviation`` (F,) float:
        per-frame maxima of the relative deviation from the linear blend of the
        end values; ``flipped_faces`` (F,) int: faces whose orientation differs
        from the source; ``flipped`` (F, faces) bool: which ones.
    """
    sequence_frames(seq)  # named errors for malformed frames
    flipped = metrics.flipped(seq)  # (F, faces)
    return {
        "edge_length_deviation": np.asarray(metrics.edge_length_deviation(seq, reduce=None), dtype=np.float64),
        "area_deviation": np.asarray(metrics.area_deviation(seq, reduce=None), dtype=np.float64),
        "flipped_faces": flipped.sum(axis=1).astype(np.int64),
        "flipped": flipped,
    }
