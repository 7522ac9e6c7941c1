"""Lottie (Bodymovin JSON) export: Bezier shapes, eased keyframes only where needed, paint included.

Written with the standard library's json; the format follows the Lottie
specification (https://lottiefiles.github.io/lottie-docs/, schema shipped by
the ``lottie-specs`` package). Coordinates are pixels of a ``w x h``
composition framed exactly like isotween's raster outputs (`fit_view`), y down.
"""


import numpy as np

from .._text import document_text
from ..io import write_text
from ..io._json import dumps_finite
from ..paint import sequence_paint
from ._view import check_colour, to_pixels
from .curves import TOLERANCE, fit_curves
from .defaults import FILL, FILL_EDGE, FPS, SIZE, WIRE
from .keys import TOLERANCE as KEY_TOLERANCE
from .keys import X1, X2, reduce_keys
from .outline import edge_chains, mesh_boundary
from .paths import PathData, _Polyline, hex_colour, polylines, tolerance_digits
from .playback import playback_order
from .svg_animation import _pieces
from .web import pixel_frames

__all__ = ["write_lottie", "lottie_data", "to_pixels"]

_EDGE_POINTS = 0.5  # width in points of the edges drawn over the default fill (as `draw_frame`)
_COLOUR_TOL = 0.5 / 255  # colours, opacities (percent) and widths (px) within these of every tick
_ALPHA_TOL = 0.2
_WIDTH_TOL = 0.02


def _static(value):
    return {"a": 0, "k": value}


def _ease(y1, y2):
    """Lottie easing handles of one interval: out tangent (x1, y1), in tangent (x2, y2) of the unit square."""
    return {"o": {"x": [X1], "y": [round(float(y1), 4)]}, "i": {"x": [X2], "y": [round(float(y2), 4)]}}


def _keyed(ticks_values, tol, points, reduce, value):
    """A property animated over the ticks: static when nothing changes, else the keys `reduce_keys` keeps.

    ``ticks_values`` (P, D) numbers per tick; ``value(k)`` is the JSON value of tick ``k``.
    """
    v = np.asarray(ticks_values, dtype=np.float64).reshape(len(ticks_values), -1)
    if not len(v) or np.ptp(v, axis=0).max(initial=0.0) == 0.0:
        return _static(value(0))
    keys, eases = reduce_keys(np.arange(len(v), dtype=np.float64), [(v, tol, points)], reduce=reduce)
    frames = [{"t": int(k), "s": value(int(k)), **_ease(*e)} for k, e in zip(keys[:-1], eases, strict=True)]
    frames.append({"t": int(keys[-1]), "s": value(int(keys[-1]))})
    return {"a": 1, "k": frames}


def _animated(values, digits=4, tol=None, reduce=True):
    """A colour, opacity or width over the ticks (a list or array per tick)."""
    v = np.round(np.asarray(values, dtype=np.float64).reshape(len(values), -1), digits)
    scalar = np.ndim(values[0]) == 0
    tol = 0.5 * 10.0 ** -digits if tol is None else tol
    ks = _keyed(v, tol, False, reduce, lambda k: [float(x) for x in v[k]])
    if ks["a"] == 0 and scalar:  # a static number is written bare, keyframe values as lists
        ks = _static(float(v[0, 0]))
    return ks


def _shape_values(controls, straight, closed):
    """Lottie vertices and tangents of Bezier controls.

    Parameters
    ----------
    controls : (P, S, 4, 2) float array
    straight : (S,) bool array
        Segments drawn as lines (both tangents zero).
    closed : bool

    Returns
    -------
    v, i, o : (P, V, 2) float arrays
        Vertices and their in / out tangents relative to them; V = S for a
        closed path, S + 1 for an open one.
    """
    p0, p1, p2, p3 = (controls[:, :, j] for j in range(4))
    line = straight[None, :, None]
    out_t = np.where(line, 0.0, p1 - p0)  # (P, S, 2): leaving vertex j
    in_t = np.where(line, 0.0, p2 - p3)  # arriving at vertex j + 1
    if closed:
        return p0, np.roll(in_t, 1, axis=1), out_t
    zero = np.zeros_like(p0[:, :1])
    v = np.concatenate([p0, p3[:, -1:]], axis=1)
    return v, np.concatenate([zero, in_t], axis=1), np.concatenate([out_t, zero], axis=1)


def _path_item(name, curve, ticks, tol, digits, reduce):
    # tol: of the keys
    """An ``sh`` item drawing ``curve`` (`CurvePath` or polyline) at pixel positions ``ticks`` (P, n, 2)."""
    controls = curve.controls(ticks)
    v, i, o = (np.round(a, digits) for a in _shape_values(controls, curve.straight, curve.closed))

    def shape(k):  # fresh lists: players may modify them in place
        return {"c": bool(curve.closed), "v": v[k].tolist(), "i": i[k].tolist(), "o": o[k].tolist()}

    track = np.concatenate([v, v + i, v + o], axis=1).reshape(len(ticks), -1)
    ks = _keyed(track, tol, True, reduce, lambda k: [shape(k)])
    if ks["a"] == 0:
        ks = _static(shape(0))
    return {"ty": "sh", "nm": name, "ks": ks}


def _transform():
    return {"ty": "tr", "a": _static([0, 0]), "p": _static([0, 0]), "s": _static([100, 100]),
            "r": _static(0), "o": _static(100)}


def _colour_items(fill, fill_alpha, stroke, stroke_alpha, width, rule=2, reduce=True):
    """Stroke then fill items (earlier items are drawn on top in Lottie)."""
    items = []
    if stroke is not None:
        items.append({"ty": "st", "nm": "stroke", "c": _animated(stroke, tol=_COLOUR_TOL, reduce=reduce),
                      "o": _animated(stroke_alpha, 2, tol=_ALPHA_TOL, reduce=reduce),
                      "w": _animated(width, 3, tol=_WIDTH_TOL, reduce=reduce), "lc": 2, "lj": 2})
    if fill is not None:
        items.append({"ty": "fl", "nm": "fill", "c": _animated(fill, tol=_COLOUR_TOL, reduce=reduce),
                      "o": _animated(fill_alpha, 2, tol=_ALPHA_TOL, reduce=reduce), "r": rule})
    return items


def _painted_groups(seq, px, order, paints, unit, options):
    """One group per region (its rings, fill and stroke) or open path, in the sequence's paint."""
    data = PathData(seq, curves=options["curves"], frames=px, tolerance=options["tol"])
    ticks = px[order]
    shape = seq.shape
    groups = []
    for runs, first in zip(data.runs, data.first_path, strict=True):
        track = [paints[int(k)][first] for k in order]
        items = [_path_item(f"path {j}", c, ticks, options["key_tol"], options["digits"], options["reduce"])
                 for j, c in enumerate(runs)]
        has_fill = any(p.fill is not None for p in track) and any(c.closed for c in runs)
        has_stroke = any(p.stroke is not None and p.stroke_width > 0 for p in track)

        def colour(p, attr):
            c = getattr(p, attr)
            return ([0.0, 0.0, 0.0, 1.0], 0.0) if c is None else ([*c[:3], 1.0], 100.0 * c[3] * p.opacity)

        fills = [colour(p, "fill") for p in track]
        strokes = [colour(p, "stroke") for p in track]
        items += _colour_items(
            [c for c, _ in fills] if has_fill else None, [a for _, a in fills],
            [c for c, _ in strokes] if has_stroke else None, [a for _, a in strokes],
            [p.stroke_width * unit if p.stroke is not None else 0.0 for p in track], reduce=options["reduce"],
        )
        items.append(_transform())
        groups.append({"ty": "gr", "nm": f"region {first}", "it": items})
    del shape
    return groups


def _loose_edges(shape):
    """(k, 2) edges that are no side of a triangle (for a mesh) or of a closed path (else)."""
    edges = np.asarray(shape.edges, dtype=np.int64).reshape(-1, 2)
    if shape.n_faces:
        sides = np.asarray(shape.faces)[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    else:
        rings = [np.asarray(p) for p, closed in shape.paths or [] if closed]
        sides = np.concatenate([np.column_stack([r, np.roll(r, -1)]) for r in rings]) if rings else edges[:0]
    n = max(int(edges.max(initial=0)), int(sides.max(initial=0))) + 1
    key = lambda e: np.sort(e, axis=1) @ np.array([n, 1])  # noqa: E731
    return edges[~np.isin(key(edges), key(sides))]


def _default_groups(shape, px, order, dpi_scale, options):
    """The default look of isotween: light fill (triangles or rings) with thin edges, or wire lines."""
    fill_runs, line_runs = _pieces(shape)
    ticks = px[order]
    groups = []
    reduce, tol, digits = options["reduce"], options["key_tol"], options["digits"]

    def rgb(hex_colour):
        return [*check_colour(hex_colour)[:3], 1.0]

    def shapes(runs):  # curves for outlines, the triangles as they are
        if options["curves"] and not shape.n_faces:
            return fit_curves(px, runs, tolerance=options["tol"])
        return [_Polyline(idx, closed) for idx, closed in runs]

    lean = options["curves"] or options["reduce"]
    loops = mesh_boundary(shape.faces) if lean and shape.n_faces else []
    if loops:  # a mesh: its outline filled (curves), its edges once each as few long strokes, on top
        outline = [(loop, True) for loop in loops]
        rings = fit_curves(px, outline, tolerance=options["tol"]) if options["curves"] else polylines(outline)
        items = [_path_item(f"outline {j}", c, ticks, tol, digits, reduce) for j, c in enumerate(rings)]
        items += _colour_items([rgb(FILL)], [100.0], None, None, None, rule=1)
        items.append(_transform())
        edge_items = [_path_item(f"edges {j}", _Polyline(w, False), ticks, tol, digits, reduce)
                      for j, w in enumerate(edge_chains(shape.edges))]
        edge_items += _colour_items(None, None, [rgb(FILL_EDGE)], [100.0], [_EDGE_POINTS * dpi_scale])
        edge_items.append(_transform())
        groups += [{"ty": "gr", "nm": "fill", "it": items}, {"ty": "gr", "nm": "edges", "it": edge_items}]
        fill_runs = []
    if fill_runs:
        items = []
        runs = fill_runs
        if shape.n_faces:  # every triangle counter-clockwise on screen: non-zero fill is their union
            xy = px[0][np.asarray([idx for idx, _ in fill_runs])]
            d1, d2 = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
            cw = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0  # y down: positive cross is clockwise
            runs = [(idx[::-1] if flip else idx, True) for (idx, _), flip in zip(fill_runs, cw.tolist(), strict=True)]
        items += [_path_item(f"piece {j}", c, ticks, tol, digits, reduce) for j, c in enumerate(shapes(runs))]
        edge_colour = ([rgb(FILL_EDGE)], [100.0], [_EDGE_POINTS * dpi_scale])
        # lean: the pieces' own stroke (listed above their fill) draws the edges; else one path per edge
        extra = _loose_edges(shape) if lean else shape.edges
        edges = [_path_item(f"edge {j}", _Polyline(e, False), ticks, tol, digits, reduce) for j, e in enumerate(extra)]
        items += _colour_items([rgb(FILL)], [100.0], *(edge_colour if lean else (None, None, None)),
                               rule=1 if shape.n_faces else 2)
        items.append(_transform())
        if len(edges):
            edge_items = edges + _colour_items(None, None, *edge_colour)
            edge_items.append(_transform())
            groups.append({"ty": "gr", "nm": "edges", "it": edge_items})
        groups.append({"ty": "gr", "nm": "fill", "it": items})
    if line_runs:
        items = [_path_item(f"line {j}", c, ticks, tol, digits, reduce) for j, c in enumerate(shapes(line_runs))]
        items += _colour_items(None, None, [rgb(WIRE)], [100.0], [1.2 * dpi_scale])
        items.append(_transform())
        groups.insert(0, {"ty": "gr", "nm": "lines", "it": items})
    return groups


def lottie_data(seq, fps=FPS, size=SIZE, bounce=False, hold=0.0, title=None, background=None, *, curves=True,
                reduce=True, tolerance=None, key_tolerance=None):
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
        A solid layer behind the shape; transparent when None.
    curves : bool
        Outlines as cubic Bezier curves (`fit_curves`, the same vertex count
        in every keyframe), else the polylines (triangles always stay
        triangles).
    reduce : bool
        Keep a keyframe only where easing between its neighbours does not
        reproduce the tick (`reduce_keys`; eases as Lottie bezier handles),
        else one linear keyframe per tick.
    tolerance : float, optional
        Of the curves, in pixels (default 0.1 % of the composition's
        diagonal).
    key_tolerance : float, optional
        Of the keyframes, in pixels (default `keys.TOLERANCE`, 0.25 %, of
        the composition's diagonal).

    Returns
    -------
    dict
        Composition with one shape layer (and one solid background layer):
        tick ``k`` of `playback_order` is composition frame ``k``. Without
        ``curves`` and ``reduce`` every tick is a linear keyframe holding
        exactly the sequence frame shown at that tick.
    """
    from ..resources import check_output_memory

    order = playback_order(len(seq), fps, hold, bounce)
    shape = seq.shape
    check_output_memory("lottie", 0, 0, len(order), "a Lottie animation", vertices=shape.n_vertices)
    px, w, h, unit = pixel_frames(seq, size)
    if tolerance is None:
        tolerance = TOLERANCE * float(np.hypot(w, h))
    if key_tolerance is None:
        key_tolerance = KEY_TOLERANCE * float(np.hypot(w, h))
    options = {"curves": bool(curves), "reduce": bool(reduce), "tol": float(tolerance), "key_tol": float(key_tolerance),
               "digits": 3 if not (curves or reduce) else tolerance_digits(tolerance)}
    _, paints = sequence_paint(seq)
    if paints is None:
        groups = _default_groups(shape, px, order, 100.0 / 72.0, options)  # points -> px at the renderers' 100 dpi
    else:
        groups = _painted_groups(seq, px, order, paints, unit, options)
    groups.reverse()  # painting order: the first group drawn is the last listed
    n = len(order)
    layer = {"ddd": 0, "ind": 1, "ty": 4, "nm": "shape", "sr": 1, "ao": 0, "ip": 0, "op": n, "st": 0, "bm": 0,
             "ks": {"o": _static(100), "r": _static(0), "p": _static([0, 0, 0]), "a": _static([0, 0, 0]),
                    "s": _static([100, 100, 100])},
             "shapes": groups}
    layers = [layer]
    if background is not None:
        layers.append({"ddd": 0, "ind": 2, "ty": 1, "nm": "background", "sr": 1, "ao": 0, "ip": 0, "op": n, "st": 0,
                       "bm": 0, "ks": layer["ks"], "sc": hex_colour(background), "sw": int(w), "sh": int(h)})
    name = document_text(title) if title else f"isotween: {len(seq)} frames, {shape.n_vertices} vertices"
    return {
        "v": "5.7.0", "nm": name,
        "fr": float(fps), "ip": 0, "op": n, "w": int(w), "h": int(h), "ddd": 0, "assets": [], "layers": layers,
    }


def write_lottie(seq, path, fps=FPS, size=SIZE, bounce=False, hold=0.0, title=None, background=None, *,
                 curves=True, reduce=True):
    """Write a sequence as a Lottie animation (``.lottie.json``; plays in lottie-web and the Lottie apps).

    Parameters are those of `lottie_data`. Whether the animation loops is the
    player's choice (Lottie files do not say).
    """
    data = lottie_data(seq, fps=fps, size=size, bounce=bounce, hold=hold, title=title, background=background,
                       curves=curves, reduce=reduce)
    write_text(path, dumps_finite(data, path, separators=(",", ":")))
