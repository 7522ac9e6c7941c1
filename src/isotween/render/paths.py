"""SVG path strings of a sequence at any time: curves or polylines, one ``d`` per drawn group.

`PathData` is the interpolator (like flubber's): built once for a sequence, it
holds which paths are drawn together (a region and its holes, filled by the
even-odd rule, or one open path) and their Bezier structure (`fit_curves`,
chosen once for all frames), and gives the ``d`` strings of any frames or of
any time ``t``. Coordinates are SVG user units with y down: shapes stored y up
are mirrored, as in every isotween output.
"""

import re
from dataclasses import replace
from xml.sax.saxutils import escape

import numpy as np

from ..errors import ParameterError
from ..paint import joined_groups, merge_groups, paint_groups, sequence_paint, svg_paint_attributes
from ._view import PAD, bbox_of, check_colour, sequence_frames, stroke_margin
from .curves import CORNER, fit_curves
from .defaults import FILL, FILL_EDGE, WIRE
from .outline import mesh_boundary

__all__ = ["PathData", "RunStrings", "outline_groups", "polylines", "svg_document", "svg_frames", "default_digits",
           "tolerance_digits"]

_ZEROS = re.compile(r"(\.\d*?)0+(?=[^\d]|$)")
_DOT = re.compile(r"\.(?=[^\d]|$)")
_MINUS_ZERO = re.compile(r"-0(?=[^\d.]|$)")


def compact(text):
    """Numbers of a path string without trailing zeros (``1.500`` -> ``1.5``, ``2.000`` -> ``2``, ``-0`` -> ``0``)."""
    return _MINUS_ZERO.sub("0", _DOT.sub("", _ZEROS.sub(r"\1", text)))


_LEADING_ZERO = re.compile(r"(?<![\d.])0\.(?=\d)")
_SPACE_MINUS = re.compile(r" (?=-)")


def compact_path(text):
    """`compact` path data, also without leading zeros (``0.5`` -> ``.5``) and spaces before a minus.

    Both are valid SVG path grammar (and CSS ``path()``), shorter by about a character a number.

    Examples
    --------
    >>> compact_path("M10.500,0.250 C-0.125,2.000 1.000,-0.500 3.000,4.000Z")
    'M10.5,.25 C-.125,2 1,-.5 3,4Z'
    """
    return _SPACE_MINUS.sub("", _LEADING_ZERO.sub(".", compact(text)))


def default_digits(frames):
    """Decimal places that keep about 1e-4 of the drawing's size."""
    side = float(np.max(np.ptp(np.asarray(frames).reshape(-1, 2), axis=0))) or 1.0
    return int(np.clip(4 - np.floor(np.log10(side)), 0, 15))


def tolerance_digits(tolerance):
    """Decimal places whose rounding (half a unit of the last place) is at most an eighth of ``tolerance``.

    Examples
    --------
    >>> tolerance_digits(0.68), tolerance_digits(0.01)
    (1, 3)
    """
    return int(np.clip(np.ceil(-np.log10(max(float(tolerance), 1e-300) / 4.0)), 0, 15))


def svg_frames(seq):
    """(F, n, 2) frames in SVG user units (y down)."""
    frames = sequence_frames(seq).copy()
    if not seq.shape.y_down:
        frames[..., 1] *= -1.0
    return frames


def outline_groups(shape, regions=None, paint=None):
    """What is drawn as one ``d`` string: lists of ``(indices, closed)`` runs.

    Parameters
    ----------
    shape : Shape
    regions : list of list of int, optional
        Filled regions (default: the shape's).
    paint : list of Paint, optional
        With paint, the groups of `isotween.paint.paint_groups`.

    Returns
    -------
    groups : list of list of ((k,) int array, bool)
        A region's rings (outer ring and holes) form one group, every open
        path one of its own; a triangle mesh without paths is drawn by its
        boundary loops, an edge soup as one group of its edges.
    first : list of int or None
        Index in ``shape.paths`` of each group's first path (whose paint it
        takes); None without paths.
    """
    paths = shape.paths or []
    if paths:
        painted = shape.with_vertices(shape.vertices)
        painted.regions = shape.regions if regions is None else regions
        painted.paint = paint if paint is not None else [None] * len(paths)
        order = [group for group, _ in paint_groups(painted)]
        return [[(np.asarray(paths[i][0]), bool(paths[i][1])) for i in group] for group in order], \
            [group[0] for group in order]
    loops = mesh_boundary(shape.faces) if shape.n_faces else []
    if loops:
        return [[(loop, True) for loop in loops]], None
    return ([[(np.asarray(e), False) for e in shape.edges]] if shape.n_edges else []), None


def _number_order(curves, relative=False, first=True):
    """Template and the indices into (S * 4) control points that fill it, for one run.

    Relative templates start with ``M`` for a path's first subpath, else ``m`` (an offset from the
    current point), and write a command letter only where it changes (``m x y dx dy dx dy`` is a
    moveto and two relative lines; ``c`` takes its numbers six at a time), numbers separated by
    spaces (dropped before a minus by `compact_path`).
    """
    if curves.n_segments == 0:
        return "", np.zeros(0, dtype=np.int64)
    parts, index = ["{move}{} {}" if relative else "M{},{}"], [0]
    previous = "l" if first is False else None  # after ``m``, pairs without a letter are relative lines
    straight = curves.straight
    last = curves.n_segments - 1
    for j, line in enumerate(straight.tolist()):
        if line and curves.closed and j == last:
            break  # Z draws the closing line
        if relative:
            command = "l" if line else "c"
            parts.append((" " if command == previous else command) + ("{} {}" if line else "{} {} {} {} {} {}"))
            previous = command
        else:
            parts.append("L{},{}" if line else "C{},{} {},{} {},{}")
        index += [4 * j + 3] if line else [4 * j + 1, 4 * j + 2, 4 * j + 3]
    if curves.closed:
        parts.append("z" if relative else "Z")
    text = "".join(parts)
    return text.replace("{move}", "M" if first else "m") if relative else text, np.asarray(index, dtype=np.int64)


class _Polyline:
    """The `CurvePath` interface for a run drawn with straight segments only."""

    def __init__(self, indices, closed):
        self.indices = np.asarray(indices, dtype=np.int64)
        self.closed = bool(closed)
        k = len(self.indices)
        self.breaks = np.arange(k + 1 if self.closed else k)
        self.corner = np.ones(len(self.breaks), dtype=bool)

    @property
    def n_segments(self):
        return len(self.breaks) - 1

    @property
    def straight(self):
        return np.ones(self.n_segments, dtype=bool)

    def controls(self, frames):
        idx = self.indices[self.breaks % len(self.indices)] if len(self.indices) else self.breaks
        p = np.asarray(frames)[:, idx]  # (F, S + 1, 2)
        a, b = p[:, :-1], p[:, 1:]
        return np.stack([a, (2 * a + b) / 3, (a + 2 * b) / 3, b], axis=2)


class RunStrings:
    """One ``d`` string per frame for a fixed list of runs (curves or polylines) drawn as one path.

    Parameters
    ----------
    runs : list of CurvePath
        Or polylines with the same interface; each is one subpath.
    digits : int
        Decimal places.
    relative : bool
        Relative commands (``m``, ``c``, ``l``: offsets from each segment's
        start, and each subpath's start from where the one before ended;
        shorter numbers, a command letter only where it changes); the offsets
        are differences of positions rounded first, so that no rounding
        error builds up along a path.
    """

    def __init__(self, runs, digits, relative=False):
        self.runs = list(runs)
        self.digits = int(digits)
        self.relative = bool(relative)
        num = f"{{:.{self.digits}f}}"
        self.orders, first = [], True
        for c in self.runs:
            self.orders.append(_number_order(c, self.relative, first))
            first = first and not c.n_segments
        self.template = ("" if self.relative else " ").join(t for t, _ in self.orders if t).replace("{}", num)

    def values(self, frames):
        """(F, N) numbers that fill the template, per frame of (F, n, 2) positions."""
        f = len(frames)
        numbers, here = [], None
        for c, (_, idx) in zip(self.runs, self.orders, strict=True):
            if not len(idx):
                continue
            ctrl = c.controls(frames)  # (F, S, 4, 2)
            if self.relative:
                ctrl = np.round(ctrl, self.digits)
                start, end = ctrl[:, 0, 0].copy(), ctrl[:, -1, 3].copy()
                ctrl = ctrl - ctrl[:, :, :1]  # offsets from each segment's start
                # the moveto: the first subpath's absolute, the others' from where the pen was left
                ctrl[:, 0, 0] = start if here is None else start - here
                here = start if c.closed else end  # z returns the pen to the subpath's start
            numbers.append(ctrl.reshape(f, -1, 2)[:, idx])
        return np.concatenate(numbers, axis=1).reshape(f, -1) if numbers else np.zeros((f, 0))

    def strings(self, frames):
        """The ``d`` string of every frame (list of str)."""
        return [compact_path(self.template.format(*row)) for row in self.values(np.asarray(frames)).tolist()]


def polylines(runs):
    """Straight-segment stand-ins of `CurvePath` for ``(indices, closed)`` runs (triangles, edges)."""
    return [_Polyline(idx, closed) for idx, closed in runs]


class PathData:
    """SVG ``d`` strings of a sequence's outlines at any time.

    Parameters
    ----------
    seq : Sequence
    curves : bool
        Cubic Bezier curves (`fit_curves`) or the polylines themselves.
    precision : int, optional
        Decimal places (default `default_digits`: about 1e-4 of the size).
    tolerance : float, optional
        Curve tolerance in shape units (default: `curves.TOLERANCE` of the
        diagonal of all frames).
    corner : float
        Corner angle in degrees (see `fit_curves`).
    frames : (F, n, 2) float array, optional
        The sequence's frames in other units (composition pixels, say) to
        choose the curves on; default `svg_frames`. `__call__` always
        gives SVG user units.
    relative : bool
        Relative commands after each subpath's moveto (see `RunStrings`).

    Attributes
    ----------
    groups : list of list of ((k,) int array, bool)
        `outline_groups` of the sequence.
    first_path : list of int or None
        The path whose paint each group takes (`outline_groups`).
    runs : list of list of CurvePath
        The segment structure of every run of every group, the same for any t.

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> circle = isotween.Shape.from_polygon([np.c_[np.cos(np.arange(32) / 5.1), np.sin(np.arange(32) / 5.1)]])
    >>> seq = isotween.interpolate(circle, circle.rotate(1.0), frames=3)
    >>> d = PathData(seq, precision=2)(0.5)
    >>> len(d), d[0][0], d[0].count("C") < 10
    (1, 'M', True)
    """

    def __init__(self, seq, curves=True, precision=None, tolerance=None, corner=CORNER, frames=None, relative=False):
        self.seq = seq
        frames = svg_frames(seq) if frames is None else np.asarray(frames, dtype=np.float64)
        if precision is None:
            precision = default_digits(frames)
        if isinstance(precision, bool) or not isinstance(precision, (int, np.integer)) or not 0 <= precision <= 15:
            raise ParameterError(f"precision must be a number of decimal places from 0 to 15, got {precision!r}")
        self.digits = int(precision)
        regions, paints = sequence_paint(seq)
        self.groups, self.first_path = outline_groups(seq.shape, regions, None if paints is None else paints[0])
        if paints is not None and regions:
            self.groups, self.first_path = _merge_joined(self.groups, self.first_path, regions, paints,
                                                   seq.info.get("joined") or [])
        flat = [run for group in self.groups for run in group]
        if curves:
            fitted = fit_curves(frames, flat, tolerance=tolerance, corner=corner)
        else:
            fitted = [_Polyline(idx, closed) for idx, closed in flat]
        self.runs, start = [], 0
        for group in self.groups:
            self.runs.append(fitted[start:start + len(group)])
            start += len(group)
        self._formats = [RunStrings(group, self.digits, relative) for group in self.runs]

    def controls(self, frames):
        """(F, S, 4, 2) control points of every run: list (groups) of lists (runs)."""
        frames = np.asarray(frames, dtype=np.float64)
        return [[c.controls(frames) for c in group] for group in self.runs]

    def strings(self, frames):
        """The ``d`` strings of given frames.

        Parameters
        ----------
        frames : (F, n, 2) float array
            In SVG user units (`svg_frames`).

        Returns
        -------
        list of list of str
            ``out[k][g]``: group ``g`` in frame ``k``.
        """
        frames = np.asarray(frames, dtype=np.float64)
        per_group = [f.strings(frames) for f in self._formats]
        return [list(row) for row in zip(*per_group, strict=True)] if per_group else [[] for _ in frames]

    def frame(self, t):
        """(n, 2) positions at time ``t`` in SVG user units (`Sequence.at`)."""
        if isinstance(t, bool) or not isinstance(t, (int, float, np.number)):
            raise ParameterError(f"t must be a number, got {t!r}")
        seq = self.seq
        times = seq.times
        hit = np.flatnonzero(times == t)
        xy = seq.frames[hit[0]] if len(hit) else seq.at(float(t)).vertices
        xy = np.array(xy, dtype=np.float64)
        if not seq.shape.y_down:
            xy[:, 1] *= -1.0
        return xy

    def __call__(self, t):
        """The ``d`` string of every group at time ``t`` (list of str)."""
        return self.strings(self.frame(t)[None])[0]


def _merge_joined(groups, first, regions, paints, joined):
    """Groups and their first paths with the parts of a cut region made one group (`paint.joined_groups`)."""
    merged, kept = merge_groups(groups, joined_groups(first, regions, paints, joined))
    return merged, [first[k] for k in kept]


def _paint_at(seq, t):
    """Paint of every path at time ``t`` (list of Paint), or None."""
    one = replace(seq, frames=seq.frames[:1], times=np.array([float(t)]), info=dict(seq.info))
    _, paints = sequence_paint(one)
    return None if paints is None else paints[0]


def view_box(frames, margin=0.0):
    """``(x, y, width, height)`` of all frames (SVG units) with the outputs' margin, strokes' ``margin`` first."""
    x0, y0, x1, y1 = bbox_of(frames, margin)
    pad = PAD * max(x1 - x0, y1 - y0, 1e-12)
    return (x0 - pad, y0 - pad, x1 - x0 + 2 * pad, y1 - y0 + 2 * pad)


def pixel_size(box, size):
    """``(width, height)`` in px of an SVG whose longest side is ``size`` (or ``size`` = (W, H))."""
    if np.ndim(size) == 0:
        return (size, size * box[3] / box[2]) if box[2] >= box[3] else (size * box[2] / box[3], size)
    return tuple(float(v) for v in np.ravel(size))


def hex_colour(colour):
    """``#rrggbb`` of a matplotlib colour (alpha dropped)."""
    r, g, b, _ = check_colour(colour)
    return f"#{round(255 * r):02x}{round(255 * g):02x}{round(255 * b):02x}"


def default_style(closed):
    """Attributes of isotween's default look: light fill with thin edges, or wire lines."""
    if closed:
        return {"fill": FILL, "fill-rule": "evenodd", "stroke": FILL_EDGE, "stroke-width": "0.5",
                "stroke-linejoin": "round", "vector-effect": "non-scaling-stroke"}
    return {"fill": "none", "stroke": WIRE, "stroke-width": "1.5", "stroke-linecap": "round",
            "stroke-linejoin": "round", "vector-effect": "non-scaling-stroke"}


def group_styles(data, paint):
    """Attributes (dict of str) of every group drawn with ``paint`` (list of Paint per path, or None)."""
    if paint is None:
        return [default_style(any(c for _, c in group)) for group in data.groups]
    out = []
    for i in data.first_path:
        attrs = svg_paint_attributes(paint[i])
        out.append({"fill-rule": "evenodd", "stroke-linejoin": "round", "stroke-linecap": "round", **attrs})
    return out


def svg_document(seq, t, *, curves=True, precision=None, size=480, background=None, data=None):
    """A standalone SVG of the sequence at time ``t``, in its paint.

    Parameters
    ----------
    seq : Sequence
    t : float
    curves : bool
    precision : int, optional
    size : int or (2,) int
        Longest side in px, or ``(width, height)``.
    background : matplotlib colour, optional
    data : PathData, optional
        Reused instead of building one.

    Returns
    -------
    str
        The view box is that of all frames, so documents of different times
        line up.
    """
    data = data or PathData(seq, curves=curves, precision=precision)
    box = view_box(svg_frames(seq), stroke_margin(sequence_paint(seq)[1]))
    width, height = pixel_size(box, size)
    styles = group_styles(data, _paint_at(seq, t))
    digits = data.digits
    body = []
    if background is not None:
        body.append(f'  <rect x="{box[0]:.{digits}f}" y="{box[1]:.{digits}f}" width="{box[2]:.{digits}f}" '
                    f'height="{box[3]:.{digits}f}" fill="{hex_colour(background)}"/>')
    for d, style in zip(data(t), styles, strict=True):
        attrs = " ".join(f'{k}="{escape(v)}"' for k, v in style.items())
        body.append(f'  <path d="{d}" {attrs}/>')
    view = " ".join(f"{v:.{digits}f}" for v in box)
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{view}" width="{width:.0f}" height="{height:.0f}">\n'
            + "\n".join(body) + "\n</svg>\n")
