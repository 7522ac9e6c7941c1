"""An animated SVG of a sequence: every frame's outline as SMIL ``<animate>`` values.

The file is vector art that plays in any browser and stays editable in a
drawing program (which shows the first frame). Coordinates keep the shape's
orientation: y-down shapes (read from SVG) are written as they are, y-up
shapes are mirrored so that they look as in every other isotween output.
"""

from xml.sax.saxutils import escape

import numpy as np

from .._text import document_text
from ..io import write_text
from ..paint import paint_groups, sequence_paint, svg_paint_attributes
from ._frames import sequence_frames
from ._view import PAD, bbox_of
from .animation import FPS, playback_order
from .frame import FILL, FILL_EDGE, WIRE, check_colour
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


def _values(attr, seq_values):
    """One SMIL ``<animate>`` of ``attr`` when its values change, else nothing."""
    if len(set(seq_values)) <= 1:
        return ""
    return f'\n    <animate attributeName="{attr}" values="{";".join(seq_values)}" @@TIMING@@/>'


def write_svg_animation(seq, path, fps=FPS, bounce=False, *, hold=0.0, loop=True, size=480, title=None,
                        background=None):
    """Write a sequence as one animated SVG file.

    Parameters
    ----------
    seq : Sequence
    path : str or os.PathLike
    fps : float
        Frames per second.
    bounce : bool
        Play forward then backward instead of jumping back.
    hold : float
        Seconds to stay on the first and the last frame.
    loop : bool
        Repeat forever; otherwise play once and stay on the last frame.
    size : int or (2,) int
        Longest side of the drawing in px, or ``(width, height)``.
    title : str, optional
        Document title (default: frames, vertices and method).
    background : matplotlib colour, optional
        Fills the view box; transparent when None.

    Notes
    -----
    A sequence with paint (`isotween.paint.sequence_paint`) draws one path
    per region in its colours, animating fill, stroke, opacity and stroke
    width with the shape; without paint it keeps isotween's default look.
    """
    from ..resources import check_output_memory

    order = playback_order(len(seq), fps, hold, bounce)
    frames = sequence_frames(seq).copy()
    shape = seq.shape
    check_output_memory("svg", 0, 0, len(order), "an animated SVG", vertices=shape.n_vertices)
    if not shape.y_down:
        frames[..., 1] *= -1.0
    regions, paints = sequence_paint(seq)
    x0, y0, x1, y1 = bbox_of(frames)
    pad = PAD * max(x1 - x0, y1 - y0, 1e-12)
    box = (x0 - pad, y0 - pad, x1 - x0 + 2 * pad, y1 - y0 + 2 * pad)
    digits = max(_decimals(frames) - 1, 0)  # 1e-4 of the size: below a pixel at any display size
    frames = frames[order]
    seconds = len(order) / fps
    timing = (f'dur="{seconds:.6g}s" repeatCount="indefinite"' if loop else f'dur="{seconds:.6g}s" fill="freeze"')
    timing += ' calcMode="linear"'
    body = []
    if paints is None:
        fill, line = _pieces(shape)
        styles = (
            (fill, f'fill="{FILL}" fill-rule="evenodd" stroke="{FILL_EDGE}" stroke-width="0.5" stroke-linejoin="round" '
                   'vector-effect="non-scaling-stroke"'),
            (line, f'fill="none" stroke="{WIRE}" stroke-width="1.5" stroke-linecap="round" stroke-linejoin="round" '
                   'vector-effect="non-scaling-stroke"'),
        )
        for runs, style in styles:
            d = path_data(runs, frames, digits)
            if d:
                body.append(f'  <path d="{d[0]}" {style}>' + _values("d", d) + "\n  </path>")
    else:
        painted = shape.with_vertices(shape.vertices)
        painted.regions, painted.paint = regions, paints[0]
        for group, _ in paint_groups(painted):
            runs = [shape.paths[i] for i in group]
            d = path_data(runs, frames, digits)
            attrs = [svg_paint_attributes(paints[int(k)][group[0]]) for k in order]
            first = " ".join(f'{key}="{value}"' for key, value in attrs[0].items())
            anim = _values("d", d) + "".join(_values(key, [a[key] for a in attrs]) for key in attrs[0])
            body.append(f'  <path d="{d[0]}" fill-rule="evenodd" stroke-linejoin="round" stroke-linecap="round" '
                        f'{first}>{anim}\n  </path>')
    view = " ".join(f"{v:.{digits}f}" for v in box)
    if np.ndim(size) == 0:
        width, height = (size, size * box[3] / box[2]) if box[2] >= box[3] else (size * box[2] / box[3], size)
    else:
        width, height = (float(v) for v in np.ravel(size))
    title = (document_text(title) if title
             else f"isotween: {len(seq)} frames, {shape.n_vertices} vertices, method {seq.method}")
    back = ""
    if background is not None:
        r, g, b, a = check_colour(background)
        back = (f'  <rect x="{box[0]:.{digits}f}" y="{box[1]:.{digits}f}" width="{box[2]:.{digits}f}" '
                f'height="{box[3]:.{digits}f}" '
                f'fill="#{round(255 * r):02x}{round(255 * g):02x}{round(255 * b):02x}"/>\n')
    text = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{view}" width="{width:.0f}" height="{height:.0f}">\n'
        f"  <title>{escape(title)}</title>\n" + back + "\n".join(body).replace("@@TIMING@@", timing) + "\n</svg>\n"
    )
    write_text(path, text)
