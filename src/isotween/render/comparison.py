"""Figures that compare several sequences of one pair: shapes side by side, metrics per frame."""

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from .. import metrics
from ..errors import ParameterError
from ..io import atomic_path
from ..paint import sequence_paint
from ._view import bbox_of, image_size, stroke_margin
from .frame import FramePainter

__all__ = ["compared_frames", "write_methods_figure", "write_metrics_figure", "metrics_figure"]

MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")
LINES = ("-", "--", "-.", ":")


def compared_frames(n, columns=12):
    """Frames to show: every frame when they fit, else evenly spaced ones.

    Parameters
    ----------
    n : int
        Frames in each sequence.
    columns : int
        Most frames to show.

    Returns
    -------
    (k,) int array
        ``0, s, 2 s, ...`` with one step ``s``: the smallest divisor of
        ``n - 1`` that fits (so the last frame is included) when that shows
        at least half of ``columns`` frames, else the smallest step that fits.
    """
    if int(columns) != columns or columns < 2:
        raise ParameterError(f"columns must be an integer >= 2, got {columns!r}")
    if n <= columns:
        return np.arange(n)
    fits = [s for s in range(1, n) if (n - 1) % s == 0 and (n - 1) // s + 1 <= columns]
    if fits and (n - 1) // fits[0] + 1 >= columns / 2:
        step = fits[0]
    else:
        step = -(-(n - 1) // (columns - 1))
    return np.arange(0, n, step)


def _save(fig, path, dpi=100):
    canvas = FigureCanvasAgg(fig)
    with atomic_path(path) as tmp:
        canvas.print_figure(tmp, format="png", dpi=dpi)


def write_methods_figure(sequences, path, columns=12, cell=160):
    """One row per sequence, one column per shown frame, all at one scale.

    Labels (method, time) sit in the margins, clear of the drawings.

    Parameters
    ----------
    sequences : dict of str -> Sequence
        Same number of frames each.
    path : path-like
        PNG file.
    columns : int
        Most frames per row (`compared_frames`).
    cell : int
        Longest side of a cell in pixels.
    """
    seqs = list(sequences.values())
    box = bbox_of(np.concatenate([s.frames.reshape(-1, 2) for s in seqs]),
                  stroke_margin([sequence_paint(s)[1] for s in seqs]))
    w, h = image_size(box, cell)
    painter = FramePainter(w, h, box, y_down=seqs[0].shape.y_down)
    picked = compared_frames(len(seqs[0]), columns)
    rows, cols = len(seqs), len(picked)
    dpi = 100
    fig = Figure(figsize=((cols * w + 110) / dpi, (rows * (h + 22) + 20) / dpi), dpi=dpi)
    fig.subplots_adjust(left=100 / (cols * w + 110), right=1 - 10 / (cols * w + 110),
                        top=1 - 24 / (rows * (h + 22) + 20), bottom=4 / (rows * (h + 22) + 20),
                        wspace=0.02, hspace=22 / h)
    axes = np.atleast_2d(fig.subplots(rows, cols, squeeze=False))
    for r, (method, seq) in enumerate(sequences.items()):
        for c, k in enumerate(picked):
            ax = axes[r, c]
            ax.imshow(painter.render(seq[int(k)]), interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            for spine in ax.spines.values():
                spine.set_color("#cccccc")
            ax.set_title(f"frame {int(k)}, t={seq.times[k]:.2f}", fontsize=8, color="#444444", pad=3)
            if c == 0:
                ax.set_ylabel(method, fontsize=10, rotation=0, ha="right", va="center", labelpad=8)
    _save(fig, path, dpi)


def write_metrics_figure(sequences, path):
    """Write `metrics_figure` as a PNG file."""
    _save(metrics_figure(sequences), path)


def metrics_figure(sequences):
    """Edge-length deviation, area deviation and flipped faces per frame, one line per sequence.

    Equal curves stay visible: every method has its own marker and dash
    pattern and is shifted sideways by a small offset (a fraction of the
    frame spacing); the deviations use a symmetric-log axis when they span
    decades; counts get integer ticks.

    Parameters
    ----------
    sequences : dict of str -> Sequence

    Returns
    -------
    matplotlib.figure.Figure
        Three axes: edge-length deviation (%), area deviation (%), flipped faces.
    """
    fig = Figure(figsize=(13, 3.8), dpi=100, layout="constrained")
    axes = fig.subplots(1, 3)
    names = list(sequences)
    values = {m: (100 * np.asarray(metrics.edge_length_deviation(s, reduce=None)),
                  100 * np.asarray(metrics.area_deviation(s, reduce=None)),
                  np.asarray(metrics.flipped_faces(s, reduce=None)))
              for m, s in sequences.items()}
    for i, (method, seq) in enumerate(sequences.items()):
        t = np.asarray(seq.times, dtype=np.float64)
        dt = float(np.min(np.diff(t))) if len(t) > 1 else 1.0
        shift = (i - (len(names) - 1) / 2) * 0.12 * dt
        style = dict(marker=MARKERS[i % len(MARKERS)], linestyle=LINES[i % len(LINES)], ms=5, lw=1.3,
                     mfc="none", label=method)
        for ax, v in zip(axes, values[method], strict=False):
            ax.plot(t + shift, v, **style)
    for ax, col in zip(axes[:2], (0, 1), strict=False):
        positive = np.concatenate([values[m][col][values[m][col] > 0] for m in names] or [np.zeros(0)])
        if positive.size and positive.max() > 100 * positive.min():
            ax.set_yscale("symlog", linthresh=float(positive.min()))
    most = max((int(values[m][2].max(initial=0)) for m in names), default=0)
    axes[2].set_ylim(-0.5, max(most, 1) + 0.5)  # a flat zero line still gets whole-number ticks
    axes[2].yaxis.set_major_locator(MaxNLocator(integer=True))
    titles = ("max edge-length deviation (%)", "max area deviation (%)", "flipped faces")
    for ax, title in zip(axes, titles, strict=False):
        ax.set_xlabel("t (methods shifted apart slightly)")
        ax.set_title(title)
        ax.grid(alpha=0.3)
    axes[0].legend(loc="best", fontsize=8)
    return fig
