"""Convergence and distortion plots (matplotlib, Agg; no display needed)."""

import os

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..errors import ParameterError
from ..io import atomic_path
from ._framestats import frame_stats

__all__ = ["plot_energy"]


def plot_energy(seq, path, dpi=100):
    """Plot energy per iteration and edge-length deviation per frame.

    Parameters
    ----------
    seq : Sequence
        Uses ``seq.energy`` (one value per iteration) and the frames.
    path : str or os.PathLike
        Image file; the format follows the extension (png, svg, pdf).
    dpi : float
    """
    stats = frame_stats(seq)
    energy = np.asarray(seq.energy, dtype=np.float64).ravel()
    fig = Figure(figsize=(9, 3.6), dpi=dpi, layout="constrained")
    canvas = FigureCanvasAgg(fig)
    left, right = fig.subplots(1, 2)
    if energy.size:
        it = np.arange(energy.size)
        left.plot(it, energy, "o-", color="#08519c", ms=4)
        left.set_xticks(it if it.size <= 12 else left.get_xticks())
        if np.all(energy > 0) and energy.max() > 10 * energy.min():
            left.set_yscale("log")  # only when the energy spans a decade or more
    else:
        left.text(0.5, 0.5, "no iterations recorded", ha="center", va="center", transform=left.transAxes)
    left.set_xlabel("iteration")
    left.set_ylabel("isometric energy")
    left.set_title(f"{getattr(seq, 'method', '')}: {getattr(seq, 'iterations', energy.size)} iteration(s)")
    left.grid(alpha=0.3)
    t = np.asarray(seq.times, dtype=np.float64)
    right.plot(t, 100 * stats["edge_length_deviation"], "o-", color="#e6550d", ms=3, label="edge length")
    if seq.shape.n_faces or any(closed for _, closed in (seq.shape.paths or [])):
        right.plot(t, 100 * stats["area_deviation"], "s--", color="#31a354", ms=3, label="area")
    right.set_xlabel("t")
    right.set_ylabel("max deviation from linear blend (%)")
    right.set_title("distortion per frame")
    right.legend(loc="best")
    right.grid(alpha=0.3)
    fmt = os.path.splitext(os.fspath(path))[1].lstrip(".").lower() or "png"
    if fmt not in canvas.get_supported_filetypes():
        raise ParameterError(f"cannot write {os.fspath(path)}: unknown image format '.{fmt}' (use .png, .svg or .pdf)")
    with atomic_path(path) as tmp:
        canvas.print_figure(tmp, format=fmt, dpi=dpi)
