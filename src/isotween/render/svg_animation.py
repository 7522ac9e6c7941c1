"""An animated SVG of a sequence: the outlines' Bezier curves as SMIL ``<animate>`` values, at the keys that matter.

The file is vector art that plays in any browser and stays editable in a
drawing program (which shows the first frame). Coordinates keep the shape's
orientation: y-down shapes (read from SVG) are written as they are, y-up
shapes are mirrored so that they look as in every other isotween output.
"""

from dataclasses import replace
from xml.sax.saxutils import escape

import numpy as np

from .._text import document_text
from ..errors import ParameterError
from ..geometry import bbox_diagonal
from ..io import write_text
from ..paint import sequence_paint, svg_paint_attributes
from ._view import decimals, stroke_margin
from .curves import TOLERANCE, fit_curves
from .defaults import FILL, FILL_EDGE, FPS, WIRE
from .keys import LINEAR, X1, X2, key_counts, reduce_keys, split_by_keys
from .keys import TOLERANCE as KEY_TOLERANCE
from .outline import edge_chains, mesh_boundary
from .paths import (
    PathData,
    RunStrings,
    compact_path,
    hex_colour,
    pixel_size,
    polylines,
    svg_frames,
    view_box,
)
from .playback import playback_order

__all__ = ["write_svg_animation", "svg_animation_text", "path_data"]


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


def _timing(times, keys, eases, duration, reduce):
    """``keyTimes`` (and ``keySplines``) of one element's animations."""
    key_times = ";".join(compact_path(f"{t:.5f}") for t in times[keys] / duration)
    if not reduce or np.allclose(eases, LINEAR, atol=1e-4):
        return f'calcMode="linear" keyTimes="{key_times}"'
    splines = ";".join("0 0 1 1" if np.allclose(e, LINEAR, atol=1e-4) else
                       compact_path(f"{X1:.4f} {e[0]:.4f} {X2:.4f} {e[1]:.4f}") for e in eases)
    return f'calcMode="spline" keyTimes="{key_times}" keySplines="{splines}"'


def _values(attr, seq_values, timing, indent="  "):
    """One SMIL ``<animate>`` of ``attr`` when its values change, else nothing."""
    if len(set(seq_values)) <= 1:
        return ""
    return f'\n{indent}  <animate attributeName="{attr}" values="{";".join(seq_values)}" {timing} @@TIMING@@/>'


def _paint_numbers(track):
    """(P, D) colours and opacities, (P, 1) stroke widths of a list of Paint, for `reduce_keys`."""
    rows = []
    for p in track:
        row = []
        for c in (p.fill, p.stroke):
            row += [0.0, 0.0, 0.0, 0.0] if c is None else list(c)
        rows.append(row + [p.opacity])
    return np.array(rows), np.array([p.stroke_width for p in track])[:, None]


def _points_track(runs, ticks, tolerance):
    """The `reduce_keys` track of the control points of ``runs`` at every tick."""
    return np.concatenate([c.controls(ticks).reshape(len(ticks), -1) for c in runs], axis=1), tolerance, True


#: what one more path element costs, in numbers of a key (its tags and timing, about 200 characters)
_ELEMENT_NUMBERS = 60


def _wire_groups(edges, ticks, times, tolerance, reduce):
    """The edges of a mesh as paths that need different keys: a list of ``(runs, keys, eases)``.

    Each group is one path with its own keys: a wireframe that swings round a
    pivot needs a key every tick near the tip, far fewer near the pivot
    (`key_counts`, `split_by_keys`). One group when splitting saves nothing.
    """
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)

    def keyed(part):
        runs = polylines([(w, False) for w in edge_chains(part)])
        return (runs, *reduce_keys(times, [_points_track(runs, ticks, tolerance)], unit=True, reduce=reduce))

    def cost(runs, keys):  # numbers written: the points of every kept key, and the element
        return 2 * len(keys) * sum(len(r.indices) for r in runs) + _ELEMENT_NUMBERS

    if not reduce or len(edges) < 2:
        return [keyed(edges)] if len(edges) else []
    counts = key_counts(times, ticks, tolerance, unit=True)
    need = np.maximum(counts[edges[:, 0]], counts[edges[:, 1]])
    group = split_by_keys(need, np.full(len(edges), 2.0), _ELEMENT_NUMBERS)
    if group.max() == 0:
        return [keyed(edges)]
    split = [keyed(edges[group == g]) for g in np.unique(group)]
    together = 2 * need.max() * (len(edges) + 1) + _ELEMENT_NUMBERS  # the least one path could cost
    if sum(cost(runs, keys) for runs, keys, _ in split) < together:
        return split
    whole = keyed(edges)
    return split if sum(cost(runs, keys) for runs, keys, _ in split) < cost(*whole[:2]) else [whole]


def write_svg_animation(seq, path, fps=FPS, bounce=False, *, hold=0.0, loop=True, size=480, title=None,
                        background=None, curves=True, reduce=True, tolerance=None, key_tolerance=None):
    """Write a sequence as one animated SVG file (the text of `svg_animation_text`).

    Parameters
    ----------
    seq : Sequence
    path : str or os.PathLike
    fps, bounce, hold, loop, size, title, background, curves, reduce, tolerance, key_tolerance
        As in `svg_animation_text`.
    """
    write_text(path, svg_animation_text(seq, fps, bounce, hold=hold, loop=loop, size=size, title=title,
                                        background=background, curves=curves, reduce=reduce, tolerance=tolerance,
                                        key_tolerance=key_tolerance))


def svg_animation_text(seq, fps=FPS, bounce=False, *, hold=0.0, loop=True, size=480, title=None, background=None,
                       curves=True, reduce=True, tolerance=None, key_tolerance=None):
    """A sequence as the text of one animated SVG document.

    Parameters
    ----------
    seq : Sequence
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
    curves : bool
        Outlines as cubic Bezier curves (`fit_curves`; triangles stay
        triangles), else the polylines.
    reduce : bool
        Keep a tick as a key only where easing between its neighbours does
        not reproduce it (`reduce_keys`, eases as ``keySplines``), else
        every tick, linear.
    tolerance : float, optional
        Of the curves, in shape units (default 0.1 % of the diagonal of
        all frames).
    key_tolerance : float, optional
        Of the keys, in shape units (default `keys.TOLERANCE`, 0.25 %, of
        the diagonal).

    Returns
    -------
    str
        The SVG document (what `write_svg_animation` writes; the HTML page embeds it).

    Notes
    -----
    A sequence with paint (`isotween.paint.sequence_paint`) draws one path
    per region in its colours, animating fill, stroke, opacity and stroke
    width with the shape; without paint it keeps isotween's default look.
    Tick ``k`` of `playback_order` shows at ``k / fps`` seconds; one pass
    lasts one tick more than the ticks (the last frame shows for a tick).
    """
    from ..resources import check_output_memory

    order = playback_order(len(seq), fps, hold, bounce)
    frames = svg_frames(seq)
    shape = seq.shape
    check_output_memory("svg", 0, 0, len(order), "an animated SVG", vertices=shape.n_vertices)
    regions, paints = sequence_paint(seq)
    box = view_box(frames, stroke_margin(paints))
    for name, value in (("tolerance", tolerance), ("key_tolerance", key_tolerance)):
        if value is not None and not (isinstance(value, (int, float, np.number)) and np.isfinite(value) and value > 0):
            raise ParameterError(f"{name} must be a positive number of shape units, got {value!r}")
    diagonal = bbox_diagonal(frames.reshape(-1, 2)) or 1.0  # a drawing of no size: any unit will do
    tolerance = TOLERANCE * diagonal if tolerance is None else tolerance
    key_tolerance = KEY_TOLERANCE * diagonal if key_tolerance is None else key_tolerance
    lean = curves or reduce
    # before: 1e-4 of the size; lean: whole numbers of a user unit of a quarter of the curve tolerance
    # (rounding within an eighth of it, as `tolerance_digits`), with no decimal point to write; at most 12 digits
    unit = max(tolerance / 4.0, 1e-12 * max(diagonal, float(np.abs(frames).max(initial=0.0)))) if lean else 1.0
    digits = 0 if lean else max(decimals(frames) - 1, 0)
    frames, box = frames / unit, tuple(v / unit for v in box)
    tolerance, key_tolerance = tolerance / unit, key_tolerance / unit
    ticks_order = np.append(order, order[-1])  # one more tick: the last frame shows for 1 / fps
    ticks = frames[ticks_order]
    times = np.arange(len(ticks)) / float(fps)
    duration = times[-1]
    timing = (f'dur="{duration:.6g}s" repeatCount="indefinite"' if loop else f'dur="{duration:.6g}s" fill="freeze"')
    body = []

    def keyed(runs, extra=(), known=None):
        """Keys, eases and d strings of one element drawing ``runs`` (curves or polylines)."""
        strings = RunStrings(runs, digits, relative=lean)
        keys, eases = known or reduce_keys(times, [_points_track(runs, ticks, key_tolerance), *extra], unit=True,
                                           reduce=reduce)
        return keys, eases, strings.strings(ticks[keys])

    def element(runs, style, indent="  ", known=None):
        keys, eases, d = keyed(runs, known=known)
        return (f'{indent}<path d="{d[0]}"{style}>' + _values("d", d, _timing(times, keys, eases, duration, reduce),
                                                              indent) + f"\n{indent}</path>")

    if paints is None:
        fill, line = _pieces(shape)
        edge_style = (f'stroke="{FILL_EDGE}" stroke-width="0.5" stroke-linejoin="round" '
                      'vector-effect="non-scaling-stroke"')
        styles = [
            (fill, f'fill="{FILL}" fill-rule="evenodd" {edge_style}'),
            (line, f'fill="none" stroke="{WIRE}" stroke-width="1.5" stroke-linecap="round" stroke-linejoin="round" '
                   'vector-effect="non-scaling-stroke"'),
        ]
        loops = mesh_boundary(shape.faces) if lean and shape.n_faces else []
        wire = []
        if loops:  # a mesh: its outline filled, its edges as few long strokes (not every triangle)
            styles = [([(loop, True) for loop in loops], f'fill="{FILL}" fill-rule="nonzero"')]
            wire = _wire_groups(shape.edges, ticks, times, key_tolerance, reduce)
        elif lean and line and all(len(idx) == 2 for idx, _ in line):  # an edge soup: chained
            styles[1] = ([(w, False) for w in edge_chains([idx for idx, _ in line])], styles[1][1])
        for k, (runs, style) in enumerate(styles):
            if not runs:
                continue
            smooth = curves and (not shape.n_faces or (bool(loops) and k == 0))  # outlines, not triangles or edges
            fitted = fit_curves(frames, runs, tolerance=tolerance) if smooth else polylines(runs)
            body.append(element(fitted, " " + style))
        if len(wire) == 1:
            runs, *known = wire[0]
            body.append(element(runs, f' fill="none" {edge_style}', known=known))
        elif wire:  # edges that need different keys (a pivot turns less than a tip): one path each, one style
            inherited, own = edge_style.split(' vector-effect="')  # vector-effect is not inherited
            body.append(f'  <g fill="none" {inherited}>')
            body += [element(runs, f' vector-effect="{own}', "    ", known=known) for runs, *known in wire]
            body.append("  </g>")
    else:
        data = PathData(seq, curves=curves, precision=digits, tolerance=tolerance, frames=frames, relative=lean)
        for runs, first in zip(data.runs, data.first_path, strict=True):
            track = [replace(paints[int(k)][first], stroke_width=paints[int(k)][first].stroke_width / unit)
                     for k in ticks_order]  # the stroke width in the file's units
            attrs = [svg_paint_attributes(p) for p in track]
            colours, widths = _paint_numbers(track)
            keys, eases, d = keyed(runs, [(colours, 0.5 / 255, False), (widths, 0.01 * tolerance, False)])
            kept = [attrs[k] for k in keys]
            when = _timing(times, keys, eases, duration, reduce)
            first_attrs = " ".join(f'{key}="{value}"' for key, value in kept[0].items())
            anim = _values("d", d, when) + "".join(_values(key, [a[key] for a in kept], when) for key in kept[0])
            body.append(f'  <path d="{d[0]}" fill-rule="evenodd" stroke-linejoin="round" stroke-linecap="round" '
                        f'{first_attrs}>{anim}\n  </path>')
    view = " ".join(f"{v:.{digits}f}" for v in box)
    width, height = pixel_size(box, size)
    title = (document_text(title) if title
             else f"isotween: {len(seq)} frames, {shape.n_vertices} vertices, method {seq.method}")
    back = ""
    if background is not None:
        back = (f'  <rect x="{box[0]:.{digits}f}" y="{box[1]:.{digits}f}" width="{box[2]:.{digits}f}" '
                f'height="{box[3]:.{digits}f}" fill="{hex_colour(background)}"/>\n')
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{view}" width="{width:.0f}" height="{height:.0f}">\n'
        f"  <title>{escape(title)}</title>\n" + back + "\n".join(body).replace("@@TIMING@@", timing) + "\n</svg>\n"
    )
