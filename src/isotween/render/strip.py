"""A contact sheet: selected frames side by side at one common scale."""

import numpy as np

from ..errors import ParameterError
from ._frames import SequenceRenderer
from ._view import sequence_frames
from .defaults import BACKGROUND
from .frame import save_png

__all__ = ["write_strip"]


def _pick(n, frames):
    if frames is None:
        return np.unique(np.round(np.linspace(0, n - 1, min(8, n))).astype(np.int64))
    picked = np.atleast_1d(np.asarray(frames))
    if picked.ndim != 1 or not len(picked) or not np.issubdtype(picked.dtype, np.integer):
        raise ParameterError(f"frames must be a non-empty list of frame indices, got {frames!r}")
    picked = np.where(picked < 0, picked + n, picked)
    bad = picked[(picked < 0) | (picked >= n)]
    if bad.size:
        raise ParameterError(f"frame index {int(bad[0])} out of range for a sequence of {n} frames")
    return picked


def write_strip(seq, path, columns=None, frames=None, texture=None, cell=240, style="auto", background=BACKGROUND):
    """Write selected frames of a sequence side by side as one PNG.

    Every cell shows the same window (the bounding box of all frames), so sizes
    and positions compare directly. Each cell is labelled with its frame index
    and time.

    Parameters
    ----------
    seq : Sequence
    path : str or os.PathLike
    columns : int, optional
        Cells per row (default: all in one row).
    frames : sequence of int, optional
        Which frames (default: up to 8, evenly spaced, first and last included).
    texture : path or (H, W, 3|4) array, optional
    cell : int or (2,) int
        Longest side of one cell in pixels, or its ``(width, height)``.
    style : str
        See `draw_frame`.
    background : matplotlib colour
        Colour behind the shapes.

    Returns
    -------
    (width, height) : tuple of int
        Size of the written image: ``(columns * cell_w, rows * cell_h)``.
    """
    picked = _pick(len(sequence_frames(seq)), frames)
    renderer = SequenceRenderer(seq, cell, texture=texture, style=style, background=background, kind="strip",
                                kept=len(picked))
    cols = len(picked) if columns is None else columns
    if int(cols) != cols or cols < 1:
        raise ParameterError(f"columns must be a positive integer, got {columns!r}")
    cols = min(int(cols), len(picked))
    rows = -(-len(picked) // cols)
    w, h = renderer.width, renderer.height
    sheet = np.full((rows * h, cols * w, 3), 255, np.uint8)
    times = np.asarray(getattr(seq, "times", np.linspace(0, 1, len(renderer))))
    for slot, k in enumerate(picked):
        r, c = divmod(slot, cols)
        img = renderer.image(int(k), label=f"frame {int(k)}  t={times[k]:.3f}")
        sheet[r * h : (r + 1) * h, c * w : (c + 1) * w] = img
    # hairlines between cells
    sheet[:, w - 1 : cols * w - 1 : w] = 200
    sheet[h - 1 : rows * h - 1 : h, :] = 200
    save_png(sheet, path)
    return cols * w, rows * h
