"""Lottie (Bodymovin JSON) export: one shape keyframe per frame, paint included.

Written with the standard library's json; the format follows the Lottie
specification (https://lottiefiles.github.io/lottie-docs/, schema shipped by
the ``lottie-specs`` package). Coordinates are pixels of a ``w x h``
composition framed exactly like isotween's raster outputs (`fit_view`), y down.
"""


import numpy as np

from .._text import document_text
from ..io import write_text
from ..io._json import dumps_finite
from ..paint import paint_groups, sequence_paint
from ._frames import sequence_frames
from ._view import bbox_of, fit_view, image_size
from .animation import FPS, SIZE, playback_order
from .frame import FILL, FILL_EDGE, WIRE, check_colour
from .svg_animation import _pieces

__all__ = ["write_lottie", "lottie_data", "to_pixels"]

# a linear keyframe: out tangent (0, 0), in tangent (1, 1) of the unit easing square
_LINEAR = {"o": {"x": [0.0], "y": [0.0]}, "i": {"x": [1.0], "y": [1.0]}}
_EDGE_POINTS = 0.5  # width in points of the edges drawn over the default fill (as `draw_frame`)


def to_pixels(frames, bbox, width, height, y_down):
    """Map data coordinates to composition pixels (x right, y down).

    Parameters
    ----------
    frames : (..., 2) float array
    bbox : (4,) float
        ``(x0, y0, x1, y1)`` shown, framed by `fit_view`.
    width, height : int
    y_down : bool

    Returns
    -------
    (..., 2) float array
    """
    x0, x1, y0, y1 = fit_view(bbox, width, height)
    out = np.empty_like(frames, dtype=np.float64)
    out[..., 0] = (frames[..., 0] - x0) * (width / (x1 - x0))
    out[..., 1] = ((frames[..., 1] - y0) if y_down else (y1 - frames[..., 1])) * (height / (y1 - y0))
    return out


def _static(value):
    return {"a": 0, "k": value}


def _animated(values, digits=4):
    """A property: static when every tick has the same value, else one linear keyframe per tick."""
    rounded = [np.round(np.asarray(v, dtype=np.float64), digits).tolist() for v in values]
    if all(r == rounded[0] for r in rounded):
        return _static(rounded[0])
    keys = [{"t": t, "s": r if isinstance(r, list) else [r], **_LINEAR} for t, r in enumerate(rounded)]
    keys[-1] = {"t": len(rounded) - 1, "s": keys[-1]["s"]}
    return {"a": 1, "k": keys}


def _bezier(points, closed):
    # straight segments: every tangent zero (fresh lists: players may modify them in place)
    return {"c": bool(closed), "v": points, "i": [[0.0, 0.0] for _ in points], "o": [[0.0, 0.0] for _ in points]}


def _path_item(name, runs_xy, closed):
    """An ``sh`` item whose vertices move through ``runs_xy`` (P, k, 2) pixel positions."""
    rounded = np.round(runs_xy, 3).tolist()
    if all(r == rounded[0] for r in rounded):
        ks = _static(_bezier(rounded[0], closed))
    else:
        keys = [{"t": t, "s": [_bezier(r, closed)], **_LINEAR} for t, r in enumerate(rounded)]
        keys[-1] = {"t": len(rounded) - 1, "s": keys[-1]["s"]}
        ks = {"a": 1, "k": keys}
    return {"ty": "sh", "nm": name, "ks": ks}


def _transform():
    return {"ty": "tr", "a": _static([0, 0]), "p": _static([0, 0]), "s": _static([100, 100]),
            "r": _static(0), "o": _static(100)}


def _colour_items(fill, fill_alpha, stroke, stroke_alpha, width, rule=2):
    """Stroke then fill items (earlier items are drawn on top in Lottie)."""
    items = []
    if stroke is not None:
        items.append({"ty": "st", "nm": "stroke", "c": _animated(stroke), "o": _animated(stroke_alpha, 2),
                      "w": _animated(width, 3), "lc": 2, "lj": 2})
    if fill is not None:
        items.append({"ty": "fl", "nm": "fill", "c": _animated(fill), "o": _animated(fill_alpha, 2), "r": rule})
    return items


def _painted_groups(shape, px, order, regions, paints, unit):
    first = shape.with_vertices(shape.vertices)
    first.regions, first.paint = regions, paints[0]
    groups = []
    for group, _ in paint_groups(first):
        track = [paints[int(k)][group[0]] for k in order]
        items = [_path_item(f"path {i}", px[:, shape.paths[i][0]], shape.paths[i][1]) for i in group]
        has_fill = any(p.fill is not None for p in track) and any(shape.paths[i][1] for i in group)
        has_stroke = any(p.stroke is not None and p.stroke_width > 0 for p in track)

        def colour(p, attr):
            c = getattr(p, attr)
            return ([0.0, 0.0, 0.0, 1.0], 0.0) if c is None else ([*c[:3], 1.0], 100.0 * c[3] * p.opacity)

        fills = [colour(p, "fill") for p in track]
        strokes = [colour(p, "stroke") for p in track]
        items += _colour_items(
            [c for c, _ in fills] if has_fill else None, [a for _, a in fills],
            [c for c, _ in strokes] if has_stroke else None, [a for _, a in strokes],
            [p.stroke_width * unit if p.stroke is not None else 0.0 for p in track],
        )
        items.append(_transform())
        groups.append({"ty": "gr", "nm": f"region {group[0]}", "it": items})
    return groups


def _default_groups(shape, px, dpi_scale):
    """The default look of isotween: light fill (triangles or rings) with thin edges, or wire lines."""
    fill_runs, line_runs = _pieces(shape)
    groups = []

    def rgb(hex_colour):
        return [*check_colour(hex_colour)[:3], 1.0]

    if fill_runs:
        items = []
        for j, (idx, _closed) in enumerate(fill_runs):
            xy = px[:, idx]
            if shape.n_faces:  # every triangle counter-clockwise on screen: non-zero fill is their union
                d1, d2 = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
                cw = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0  # y down: positive cross is clockwise
                xy = np.where(cw[:, None, None], xy[:, ::-1], xy)
            items.append(_path_item(f"piece {j}", xy, True))
        edges = [_path_item(f"edge {j}", px[:, e], False) for j, e in enumerate(shape.edges)]
        items += _colour_items([rgb(FILL)], [100.0], None, None, None, rule=1 if shape.n_faces else 2)
        items.append(_transform())
        edge_items = edges + _colour_items(None, None, [rgb(FILL_EDGE)], [100.0], [_EDGE_POINTS * dpi_scale])
        edge_items.append(_transform())
        groups += [{"ty": "gr", "nm": "edges", "it": edge_items}, {"ty": "gr", "nm": "fill", "it": items}]
    if line_runs:
        items = [_path_item(f"line {j}", px[:, idx], closed) for j, (idx, closed) in enumerate(line_runs)]
        items += _colour_items(None, None, [rgb(WIRE)], [100.0], [1.2 * dpi_scale])
        items.append(_transform())
        groups.insert(0, {"ty": "gr", "nm": "lines", "it": items})
    return groups


def lottie_data(seq, fps=FPS, size=SIZE, bounce=False, hold=0.0, title=None, background=None):
    """The Lottie animation of a sequence as JSON-ready Python values.

    Parameters
    ----------
    seq : Sequence
    fps : float
    size : int or (2,) int
        Longest side of the composition in pixels, or ``(width, height)``.
    bounce : bool
    hold : float
        Seconds on the first and the last frame.
    title : str, optional
    background : matplotlib colour, optional
        A full-size rectangle behind the shape; transparent when None.

    Returns
    -------
    dict
        Composition with one shape layer (and one background layer): every
        tick of `playback_order` is a linear keyframe at its frame number, so
        frame ``t`` of the composition is exactly the sequence frame shown at
        that tick.
    """
    from ..resources import check_output_memory

    order = playback_order(len(seq), fps, hold, bounce)
    frames = sequence_frames(seq)
    shape = seq.shape
    check_output_memory("lottie", 0, 0, len(order), "a Lottie animation", vertices=shape.n_vertices)
    box = bbox_of(frames)
    w, h = image_size(box, size)
    x0, x1, _, _ = fit_view(box, w, h)
    unit = w / (x1 - x0)  # pixels per shape unit
    px = to_pixels(frames, box, w, h, shape.y_down)[order]
    regions, paints = sequence_paint(seq)
    if paints is None:
        groups = _default_groups(shape, px, 100.0 / 72.0)  # points -> px at the renderers' 100 dpi
    else:
        groups = _painted_groups(shape, px, order, regions, paints, unit)
    groups.reverse()  # painting order: the first group drawn is the last listed
    n = len(order)
    layer = {"ddd": 0, "ind": 1, "ty": 4, "nm": "shape", "sr": 1, "ao": 0, "ip": 0, "op": n, "st": 0, "bm": 0,
             "ks": {"o": _static(100), "r": _static(0), "p": _static([0, 0, 0]), "a": _static([0, 0, 0]),
                    "s": _static([100, 100, 100])},
             "shapes": groups}
    layers = [layer]
    if background is not None:
        r, g, b, _ = check_colour(background)
        rect = [{"ty": "rc", "nm": "background", "p": _static([w / 2, h / 2]), "s": _static([w, h]),
                 "r": _static(0)},
                {"ty": "fl", "nm": "fill", "c": _static([r, g, b, 1.0]), "o": _static(100), "r": 1},
                _transform()]
        layers.append({**layer, "ind": 2, "nm": "background",
                       "shapes": [{"ty": "gr", "nm": "background", "it": rect}]})
    name = document_text(title) if title else f"isotween: {len(seq)} frames, {shape.n_vertices} vertices"
    return {
        "v": "5.7.0", "nm": name,
        "fr": float(fps), "ip": 0, "op": n, "w": int(w), "h": int(h), "ddd": 0, "assets": [], "layers": layers,
    }


def write_lottie(seq, path, fps=FPS, size=SIZE, bounce=False, hold=0.0, title=None, background=None):
    """Write a sequence as a Lottie animation (``.lottie.json``; plays in lottie-web and the Lottie apps).

    Parameters are those of `lottie_data`. Whether the animation loops is the
    player's choice (Lottie files do not say).
    """
    data = lottie_data(seq, fps=fps, size=size, bounce=bounce, hold=hold, title=title, background=background)
    write_text(path, dumps_finite(data, path, separators=(",", ":")))
