"""An animated SVG of a sequence: every frame's outline as SMIL ``<animate>`` values.

The file is vector art that plays in any browser and stays editable in a
drawing program (which shows the first frame). Coordinates keep the shape's
orientation: y-down shapes (read from SVG) are written as they are, y-up
shapes are mirrored so that they look as in every other isotween output.
"""

from xml.sax.saxutils import quoteattr

import numpy as np

from ..io._files import write_text
from ._frames import sequence_frames
from ._view import PAD, bbox_of
from .animation import _check_fps
from .frame import FILL, FILL_EDGE, WIRE
from .html import _decimals

__all__ = ["write_svg_animation", "path_data"]


def _pieces(shape):
    """Drawing commands as ``(fill, line)`` lists of ``(indices, closed)`` runs.

    Triangles are filled (and outlined by their own stroke); closed rings are
    filled by the even-odd rule (holes stay empty); edges that no ring or
    triangle draws (open polylines, edge soups) are stroked.
    """
    paths = shape.paths or []
    if shape.n_faces:
        return [(f, True) for f in shape.faces], []
    fill = [(p, True) for p, closed in paths if closed]
    on_paths = sum(len(p) - (not closed) for p, closed in paths)
    if on_paths == shape.n_edges:
        return fill, [(p, False) for p, closed in paths if not closed]
    return fill, [(e, False) for e in shape.edges]


def path_data(runs, frames, digits):
    """SVG path data of every frame for fixed runs of vertex indices.

    Parameters
    ----------
    runs : list of ((k,) int array, bool)
        Vertex indices drawn as one subpath each; ``True`` closes it.
    frames : (F, n, 2) float array
        Positions, already in SVG user units (y down).
    digits : int
        Decimal places.

    Returns
    -------
    list of str
        One ``d`` string per frame.
    """
    if not runs:
        return []
    order = np.concatenate([r for r, _ in runs])
    num = f"{{:.{digits}f}}"
    template = " ".join(
        "M" + " L".join([f"{num},{num}"] * len(r)) + (" Z" if closed else "") for r, closed in runs
    )
    return [template.format(*xy) for xy in frames[:, order].reshape(len(frames), -1).tolist()]


def write_svg_animation(seq, path, fps=12, bounce=False):
    """Write a sequence as one animated SVG file.

    Parameters
    ----------
    seq : Sequence
    path : str or os.PathLike
    fps : float
        Frames per second.
    bounce : bool
        Play forward then backward (``2 F - 2`` frames) instead of jumping back.
    """
    _check_fps(fps)
    frames = sequence_frames(seq).copy()
    shape = seq.shape
    if not shape.y_down:
        frames[..., 1] *= -1.0
    if bounce and len(frames) > 2:
        frames = np.concatenate([frames, frames[-2:0:-1]])
    x0, y0, x1, y1 = bbox_of(frames)
    pad = PAD * max(x1 - x0, y1 - y0, 1e-12)
    box = (x0 - pad, y0 - pad, x1 - x0 + 2 * pad, y1 - y0 + 2 * pad)
    digits = max(_decimals(frames) - 1, 0)  # 1e-4 of the size: below a pixel at any display size
    fill, line = _pieces(shape)
    styles = (
        (fill, f'fill="{FILL}" fill-rule="evenodd" stroke="{FILL_EDGE}" stroke-width="0.5" stroke-linejoin="round"'),
        (line, f'fill="none" stroke="{WIRE}" stroke-width="1.5" stroke-linecap="round" stroke-linejoin="round"'),
    )
    seconds = len(frames) / fps
    body = []
    for runs, style in styles:
        d = path_data(runs, frames, digits)
        if d:
            body.append(
                f'  <path d="{d[0]}" {style} vector-effect="non-scaling-stroke">\n'
                f'    <animate attributeName="d" dur="{seconds:.6g}s" repeatCount="indefinite" '
                f'calcMode="linear" values="{";".join(d)}"/>\n  </path>'
            )
    view = " ".join(f"{v:.{digits}f}" for v in box)
    width, height = (480, 480 * box[3] / box[2]) if box[2] >= box[3] else (480 * box[2] / box[3], 480)
    title = quoteattr(f"isotween: {len(seq)} frames, {shape.n_vertices} vertices, method {seq.method}")
    text = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{view}" width="{width:.0f}" height="{height:.0f}">\n'
        f"  <title>{title[1:-1]}</title>\n" + "\n".join(body) + "\n</svg>\n"
    )
    write_text(path, text)
