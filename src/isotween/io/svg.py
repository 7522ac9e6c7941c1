"""SVG drawings: every subpath becomes a ring or a polyline, filled ones regions.

Reading uses svgelements (transforms, inherited attributes and CSS applied,
shapes turned into paths). Mapping rule (docs/formats.md): a filled subpath
(fill not ``none``, with or without ``Z``) is a closed ring; an unfilled one
is a closed ring if it ends in ``Z`` and an open polyline otherwise; all of
them, in document order, form one Shape. The ``fill-rule`` of each element
decides which of its rings are outer boundaries and which are holes of which
(``Shape.regions``); each path keeps the element's `Paint`. Elements that
draw nothing (no fill and no stroke) are left out. Degenerate
subpaths (too few distinct points, or a filled ring of zero area) are dropped
with a warning naming them. Coordinates stay in the root's user units with y
pointing down (the viewBox and the width/height of the root are ignored).
"""

import functools
import io
import re
import warnings
import xml.etree.ElementTree as ET
from xml.parsers import expat

import numpy as np

from .._validate import check_int
from ..errors import FileFormatError, ParameterError, ShapeError, require
from ..geometry import bbox_diagonal, edge_keys, edge_table, fill_regions, ring_area
from ..paint import Paint, drawn_groups, svg_paint_attributes
from ..resources import check_memory
from ..shape import MAX_COORDINATE, Shape
from ._files import TEXT_BYTES_PER_BYTE, check_readable, write_text
from ._mesh import chains

__all__ = ["read_svg", "write_svg", "join_strokes", "CURVE_SEGMENTS", "CURVE_TOLERANCE", "SPIKE_SINE"]

#: curves are flattened so that no point of a curve is further than this fraction of the drawing's
#: bounding-box diagonal from the polyline (the default; ``curve_segments`` fixes the count instead)
CURVE_TOLERANCE = 5e-4
#: straight pieces of a curved segment at most, and (the older fixed count) ``curve_segments=16``
MAX_CURVE_SEGMENTS = 256
CURVE_SEGMENTS = 16
#: a filled ring's point where it turns back to within this sine of straight back may be a spike tip
SPIKE_SINE = 0.5
#: parameter steps at which a curve is first sampled to estimate its bending
_PROBE = np.linspace(0.0, 1.0, 17)

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_LENGTH = re.compile(rf"^\s*{_NUMBER}\s*(?:px|pt|pc|mm|cm|in|em|ex|%)?\s*$")
_NUMBERS = re.compile(_NUMBER)
_SEPARATORS = re.compile(r"^[\s,]*$")
_GEOMETRY = {
    "rect": ("x", "y", "width", "height", "rx", "ry"),
    "circle": ("cx", "cy", "r"),
    "ellipse": ("cx", "cy", "rx", "ry"),
    "line": ("x1", "y1", "x2", "y2"),
}


def _label(tag, element_id, index):
    return f"<{tag} id=\"{element_id}\">" if element_id else f"<{tag}> number {index} (in document order)"


def _check_attributes(path, se, el, tag, label):
    """Raise on attribute text that svgelements would silently ignore."""
    values = el.values
    if tag == "path":
        try:
            se.Path(values.get("d", ""))
        except ValueError:
            raise FileFormatError(f"{path}: {label}: malformed path data d=\"{values.get('d', '')}\"") from None
    elif tag in ("polygon", "polyline"):
        pts = values.get("points", "")
        if not _points_ok(pts):
            raise FileFormatError(f"{path}: {label}: malformed points=\"{pts}\" (need x,y pairs)")
    for name in _GEOMETRY.get(tag, ()):
        text = values.get(name)
        if text is not None and text != "auto" and not _LENGTH.match(str(text)):
            raise FileFormatError(f"{path}: {label}: {name}=\"{text}\" is not a length")


def _points_ok(text):
    """Whether a ``points`` attribute is numbers in x,y pairs.

    Checked in linear time: a single regular expression for it backtracks
    exponentially on some texts.
    """
    return bool(_SEPARATORS.match(_NUMBERS.sub(" ", text))) and len(_NUMBERS.findall(text)) % 2 == 0


def _subpaths(se, segments, curve_segments, tolerance=None):
    """(points (k, 2), closed) of every subpath of a shape's svgelements segments.

    A curved segment becomes ``curve_segments`` straight pieces of equal
    parameter step, or, with ``tolerance`` (a length), as many as keep the
    polyline within it: a curve with second derivative at most ``M`` is within
    ``M / (8 n^2)`` of its ``n``-piece polyline.
    """
    out, current, closed = [], None, False
    fixed = None if curve_segments is None else np.linspace(0.0, 1.0, curve_segments + 1)[1:]
    for seg in segments:
        if isinstance(seg, se.Move) or current is None:
            if current:
                out.append((current, closed))
            start = seg.end if isinstance(seg, se.Move) else seg.start
            current, closed = [np.array([[start.x, start.y]])], False
            if isinstance(seg, se.Move):
                continue
        if isinstance(seg, se.Close):
            closed = True
            out.append((current, closed))
            current = None  # a segment after Z starts a new subpath at the same point
            continue
        if isinstance(seg, se.Line):
            current.append(np.array([[seg.end.x, seg.end.y]]))
            continue
        # quadratic, cubic or arc
        steps = fixed
        if steps is None:
            probe = np.asarray(seg.npoint(_PROBE), dtype=np.float64).reshape(-1, 2)
            # h^2 times the second derivative at the inner probes (exact for a cubic), and at both ends
            # by linear extrapolation (exact too: a cubic's second derivative is linear in t)
            second = probe[2:] - 2 * probe[1:-1] + probe[:-2]
            second = np.r_[second, 2 * second[:1] - second[1:2], 2 * second[-1:] - second[-2:-1]]
            bend = np.hypot(second[:, 0], second[:, 1]).max() * (len(_PROBE) - 1) ** 2
            n = int(np.clip(np.ceil(np.sqrt(bend / (8 * tolerance))), 1, MAX_CURVE_SEGMENTS))
            steps = np.linspace(0.0, 1.0, n + 1)[1:]
        current.append(np.asarray(seg.npoint(steps), dtype=np.float64).reshape(-1, 2))
    if current:
        out.append((current, closed))
    return [(np.vstack(parts), c) for parts, c in out]


def _clean(points, closed, spike=None):
    """Drop repeated consecutive points (and the closing repeat of a ring); with ``spike``, spike tips too.

    A spike tip is a point where a filled ring turns straight back, its two
    edges overlapping (or nearly: the point within ``spike`` of the line
    between its neighbours, turning back to within `SPIKE_SINE` of straight
    or at the end of an edge shorter than ``spike``, as where a path's
    closing edge backs up its last one or rounded path data misses the
    start): the fill draws (next to) nothing there, but the ring touches
    itself, which no mesh can follow. ``spike``: a distance (the curve
    tolerance), for filled rings; None keeps every point.
    """
    scale = max(float(np.ptp(points, axis=0).max()), 1e-300) if len(points) else 1.0
    tol = 1e-9 * scale
    keep = np.ones(len(points), dtype=bool)
    keep[1:] = np.any(np.abs(np.diff(points, axis=0)) > tol, axis=1)
    points = points[keep]
    if closed and len(points) > 1 and np.all(np.abs(points[-1] - points[0]) <= tol):
        points = points[:-1]
    if spike is not None and len(points) > 3:
        before, after = np.roll(points, 1, axis=0), np.roll(points, -1, axis=0)
        u, v, w = points - before, after - points, after - before
        at = np.clip(np.einsum("ij,ij->i", u, w) / np.maximum(np.einsum("ij,ij->i", w, w), tol * tol), 0.0, 1.0)
        off = np.hypot(*(before + at[:, None] * w - points).T)  # from the line between the neighbours
        lu, lv = np.hypot(*u.T), np.hypot(*v.T)
        sine = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / np.maximum(lu * lv, tol * tol)
        stub = np.minimum(lu, lv) <= spike  # (then ``off`` is too)
        tip = (np.einsum("ij,ij->i", u, v) < 0) & ((sine <= 1e-9) | ((off <= spike) & ((sine <= SPIKE_SINE) | stub)))
        if tip.any():
            points = _clean(points[~(tip & ~np.roll(tip, 1))], True)  # of two in a row, the first
    return points


def _same_points(points, tol):
    """(n,) group of every point (n, 2) and (g,) count of each group: points that agree to ``tol`` share one."""
    _, group, count = np.unique(np.round(points / tol).astype(np.int64), axis=0, return_inverse=True,
                                return_counts=True)
    return group.ravel(), count


def _unpinched(points):
    """A filled ring that passes through one point twice, cut there into two rings (and so on); (k, 2) arrays.

    The fill is the same; each ring alone no longer touches itself, which no
    mesh can follow.
    """
    group, count = _same_points(points, 1e-9 * max(float(np.ptp(points, axis=0).max()), 1e-300))
    twice = np.flatnonzero(count[group] > 1)
    if not len(twice):
        return [points]
    i, j = (int(x) for x in twice[group[twice] == group[twice[0]]][:2])  # a point, and where it comes again
    # each starts after the shared point (a ring's first point tells whether another ring is around it)
    rest = np.roll(np.r_[points[:i], points[j:]], -(i + 1), axis=0)
    return _unpinched(np.roll(points[i:j], -1, axis=0)) + _unpinched(rest)


def _quiet_numbers(reader):
    """Run ``reader`` without numpy's overflow warnings (overflowing numbers are refused instead)."""

    @functools.wraps(reader)
    def read(*args, **kwargs):
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return reader(*args, **kwargs)

    return read


#: root attribute with which `write_svg` marks a y-up shape written with y negated (`read_svg` undoes it)
Y_UP_ATTRIBUTE = "data-isotween-y"


@_quiet_numbers
def read_svg(path, curve_segments=None):
    """Read every drawn outline of an SVG file as one Shape.

    Parameters
    ----------
    path : path-like
    curve_segments : int, optional
        Straight pieces per curved segment (quadratic, cubic Bezier, arc).
        Default: as many as keep every curve within `CURVE_TOLERANCE` of the
        drawing's bounding-box diagonal (at most `MAX_CURVE_SEGMENTS`).

    Returns
    -------
    Shape
        Vertices (n, 2) in SVG user units (y down; a y-up shape written by
        `write_svg` reads back y-up, as it was), one path per subpath:
        filled subpaths (closed by ``Z`` or not), closed unfilled subpaths,
        polygons, rects, circles and ellipses as closed rings; other unfilled
        subpaths, polylines and lines as open polylines (open unfilled
        subpaths with the same paint that continue one another, one after
        the other in the drawing, joined into one: `join_strokes`). ``regions`` lists the
        filled regions (outer ring, then its holes, by each element's
        ``fill-rule``) and ``paint`` the fill, stroke, stroke width and
        opacity of every path.

    Warns
    -----
    UserWarning
        Naming each degenerate subpath that was dropped: fewer than 3
        distinct points (2 for an open polyline), or a filled ring that
        encloses no area.

    Raises
    ------
    FileFormatError
        Naming the file and line (XML errors) or the element (its id, or its
        tag and number) that is malformed, or saying that nothing drawable is
        left.
    """
    se = require("svgelements", "cli")
    path = check_readable(path)
    if curve_segments is not None:
        _check_curve_segments(curve_segments)
    _check_xml_safety(path)
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        reason = re.sub(r": line \d+, column \d+$", "", str(exc))
        raise FileFormatError(f"{path}, line {exc.position[0]}: malformed XML ({reason})") from None
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot read: {exc.strerror or exc}") from None
    if root.tag.rsplit("}", 1)[-1] != "svg":
        raise FileFormatError(f"{path}: the root element is <{root.tag.rsplit('}', 1)[-1]}>, not <svg>")
    y_up = root.get(Y_UP_ATTRIBUTE) == "up"  # a y-up shape written by write_svg, y negated
    # keep user coordinates: no viewBox-to-viewport scaling
    for attr in ("viewBox", "width", "height", "preserveAspectRatio", Y_UP_ATTRIBUTE):
        root.attrib.pop(attr, None)
    try:
        document = se.SVG.parse(io.BytesIO(ET.tostring(root)), reify=True)
    except _SVGELEMENTS_ERRORS as exc:
        raise FileFormatError(f"{path}: cannot interpret the drawing ({str(exc)[:120]})") from None
    if not hasattr(document, "elements"):
        raise FileFormatError(f"{path}: the root element is not an SVG <svg> (namespace {root.tag[:80]})")
    drawn, counts = [], {}
    for el in document.elements():
        if not isinstance(el, se.Shape):
            continue
        tag = el.values.get("tag", type(el).__name__.lower())
        counts[tag] = counts.get(tag, 0) + 1
        label = _label(tag, el.id, counts[tag])
        _check_attributes(path, se, el, tag, label)
        paint = _paint(path, el, tag, label)
        if paint.fill is None and paint.stroke is None:
            continue  # draws nothing (e.g. an icon's bounding box with fill="none")
        drawn.append((el, label, paint, _safe_segments(path, se, el, label)))
    diagonal = _control_diagonal([segs for *_, segs in drawn])
    spike = CURVE_TOLERANCE * diagonal if np.isfinite(diagonal) and diagonal > 0 else 0.0
    tolerance = None
    if curve_segments is None:
        tolerance = spike or None
        curve_segments = CURVE_SEGMENTS if tolerance is None else None
    rings, paints, regions, dropped = [], [], [], []
    for el, label, paint, segments in drawn:
        kept = []
        for k, (points, closed) in enumerate(_safe_subpaths(path, se, segments, curve_segments, label, tolerance)):
            _check_numbers(path, label, k, points)
            closed = closed or paint.filled
            points = _clean(points, closed, spike if paint.filled else None)
            need = 3 if closed else 2
            kind = "closed subpath" if closed else "open subpath"
            if len(points) < need:
                dropped.append(f"{label}: {kind} {k} has {len(points)} distinct point(s), needs {need}")
            elif paint.filled and abs(ring_area(points)) <= 1e-9 * _ring_length(points) ** 2:
                dropped.append(f"{label}: filled subpath {k} encloses no area")
            elif paint.filled:  # a ring through one point twice (a wheel drawn onto a cart): cut there
                kept += [(loop, True) for loop in _unpinched(points)
                         if len(loop) >= 3 and abs(ring_area(loop)) > 1e-9 * _ring_length(loop) ** 2]
            else:
                kept.append((points, closed))
        base = len(rings)
        if paint.filled and kept:
            rule = str(el.values.get("fill-rule", "nonzero")).strip().lower()
            element_regions, outline = fill_regions([p for p, _ in kept], rule)
            regions += [[base + i for i in r] for r in element_regions]
            unfilled = Paint(fill=None, stroke=paint.stroke, stroke_width=paint.stroke_width,
                             opacity=paint.opacity)
            for i, (points, closed) in enumerate(kept):
                rings.append((points, closed))
                paints.append(unfilled if i in outline else paint)
        else:
            rings += kept
            paints += [paint] * len(kept)
    if dropped:
        warnings.warn(f"{path}: dropped {len(dropped)} degenerate subpath(s): " + "; ".join(dropped),
                      stacklevel=2)
    unread = _unread(root)
    if unread:
        warnings.warn(f"{path}: drawn without what isotween does not read: {unread}", stacklevel=2)
    if not rings:
        why = f" (dropped: {'; '.join(dropped)})" if dropped else ""
        raise FileFormatError(
            f"{path}: nothing to read (no path, polygon, polyline, rect, circle, ellipse or line){why}"
        )
    rings, paints, regions = join_strokes(rings, paints, regions)
    if y_up:
        rings = [(points * np.array([1.0, -1.0]) + 0.0, closed) for points, closed in rings]
    return _shape_of_rings(path, rings, regions, paints, y_down=not y_up)


def join_strokes(rings, paints, regions):
    """Open strokes that continue one another joined into one polyline, or a ring where they close.

    Drawings often draw one line in pieces: an outline's sides and rounded
    corners as separate paths, a stroke cut where its curve changes kind.
    Morphed apart, the pieces come apart. Among consecutive open unfilled
    subpaths of the same paint (so the painting order stays), two pieces
    are joined where exactly two of their ends meet (within 1e-9 of the
    drawing's size); where three or more meet, none is. The joined line
    has every point of its pieces, so it draws the same.

    Parameters
    ----------
    rings : list of ((k, 2) float, bool)
        Subpaths and whether each is closed.
    paints : list of Paint
    regions : list of list of int
        Filled regions (indices into ``rings``); their rings are never joined.

    Returns
    -------
    rings, paints, regions
        The same, joined (regions' indices follow).
    """
    filled = {i for r in regions for i in r}
    every = np.concatenate([points for points, _ in rings])
    tol = 1e-9 * max(float(np.ptp(every, axis=0).max()), 1e-300)
    out, out_paints, index = [], [], {}
    i = 0
    while i < len(rings):
        j = i + 1
        if not rings[i][1] and i not in filled:
            while j < len(rings) and not rings[j][1] and j not in filled and paints[j] == paints[i]:
                j += 1
        if j == i + 1:
            index[i] = len(out)
            out.append(rings[i])
            out_paints.append(paints[i])
        else:
            joined = _chained([points for points, _ in rings[i:j]], tol)
            out += joined
            out_paints += [paints[i]] * len(joined)
        i = j
    return out, out_paints, [[index[k] for k in r] for r in regions]


def _chained(pieces, tol):
    """(points, closed) of the chains of open ``pieces`` (list of (k, 2) float) joined where two ends meet."""
    m = len(pieces)
    ends = np.array([[p[0], p[-1]] for p in pieces]).reshape(-1, 2)  # end 2i: piece i's start, 2i + 1: its end
    group, count = _same_points(ends, tol)
    link = np.full(2 * m, -1)
    two = np.flatnonzero(count == 2)
    if len(two):
        order = np.argsort(group, kind="stable")
        first = np.searchsorted(group[order], two)
        a, b = order[first], order[first + 1]
        link[a], link[b] = b, a
    seen = np.zeros(m, dtype=bool)

    def walk(end):
        """(first piece, points, closed) of the chain from ``end`` through the pieces it leads to."""
        parts, first, start = [], end // 2, end
        while True:
            piece = end // 2
            seen[piece], first = True, min(first, piece)
            points = pieces[piece] if end % 2 == 0 else pieces[piece][::-1]
            parts.append(points if not parts else points[1:])
            end = link[end ^ 1]
            if end < 0 or seen[end // 2]:
                points = np.concatenate(parts)
                closed = end == start and len(points) > 3  # back where it began: a ring
                return first, points[:-1] if closed else points, closed

    # open chains from a free end, then the rest (which close); in the order of their first pieces
    chains = [walk(start) for start in np.flatnonzero(link < 0) if not seen[start // 2]]
    chains += [walk(2 * piece) for piece in range(m) if not seen[piece]]
    return [(points, closed) for _, points, closed in sorted(chains, key=lambda c: c[0])]


#: elements whose drawing isotween does not read (named in one warning)
_UNREAD_TAGS = ("text", "image", "mask", "filter", "pattern", "foreignObject", "clipPath", "linearGradient",
                "radialGradient")


def _unread(root):
    """One phrase naming what a drawing has that the reader drops or paints plainly, or ''.

    Gradient and pattern paint (``url(#...)``) is read as the SVG initial
    paint (black fill, no stroke); text, images, masks, filters and clip paths
    are not read.
    """
    counts, paints = {}, []
    for el in root.iter():
        tag = str(el.tag).rsplit("}", 1)[-1]
        if tag in _UNREAD_TAGS and "Gradient" not in tag:
            counts[tag] = counts.get(tag, 0) + 1
        for attr in ("fill", "stroke"):
            if el.get(attr, "").strip().startswith("url(") or re.search(rf"{attr}\s*:\s*url\(", el.get("style", "")):
                paints.append(f"<{tag}{' id=' + repr(el.get('id')) if el.get('id') else ''}> {attr}")
    parts = [f"<{tag}> x{n}" for tag, n in counts.items()]
    if paints:
        parts.append(f"gradient or pattern paint read as plain colour ({', '.join(paints[:3])}"
                     + (f" and {len(paints) - 3} more" if len(paints) > 3 else "") + ")")
    return "; ".join(parts)


#: what svgelements raises on drawings it cannot interpret
_SVGELEMENTS_ERRORS = (ValueError, TypeError, ZeroDivisionError, OverflowError, IndexError, KeyError,
                       AttributeError, RecursionError)


def _safe_segments(path, se, element, label):
    """The svgelements segments of a shape, with svgelements' errors as `FileFormatError`."""
    try:
        return list(se.Path(element).segments())
    except _SVGELEMENTS_ERRORS as exc:
        raise FileFormatError(f"{path}: {label}: cannot interpret the geometry ({type(exc).__name__})") from None


def _safe_subpaths(path, se, segments, curve_segments, label, tolerance=None):
    """`_subpaths`, with svgelements' errors on malformed geometry as `FileFormatError`."""
    try:
        return _subpaths(se, segments, curve_segments, tolerance)
    except _SVGELEMENTS_ERRORS as exc:
        raise FileFormatError(f"{path}: {label}: cannot interpret the geometry ({type(exc).__name__})") from None


def _control_diagonal(segment_lists):
    """Diagonal of the bounding box of every segment's end and control points (it holds every curve)."""
    pts = [(p.x, p.y) for segs in segment_lists for seg in segs
           for p in (getattr(seg, name, None) for name in ("start", "end", "control1", "control2", "control"))
           if p is not None]
    if not pts:
        return 0.0
    xy = np.asarray(pts, dtype=np.float64)
    return bbox_diagonal(xy)


def _check_curve_segments(curve_segments):
    """Refuse a ``curve_segments`` that is not an integer from 1 to 10,000."""
    check_int("curve_segments", curve_segments, 1, 10_000)


def _check_numbers(path, label, k, points):
    """Refuse non-finite coordinates and ones beyond `isotween.shape.MAX_COORDINATE`."""
    bad = ~np.all(np.isfinite(points), axis=1)
    if bad.any():
        raise FileFormatError(f"{path}: {label}: subpath {k} has a non-finite coordinate (point {int(np.argmax(bad))})")
    big = np.any(np.abs(points) > MAX_COORDINATE, axis=1)
    if big.any():
        raise FileFormatError(
            f"{path}: {label}: subpath {k} has a coordinate beyond +-{MAX_COORDINATE:g} "
            f"(point {int(np.argmax(big))}); scale the drawing down"
        )


class _Unsafe(Exception):
    """Raised inside the expat handlers of `_check_xml_safety`."""


def _check_xml_safety(path):
    """Refuse what could make reading an SVG reach outside the file or blow up.

    Entity declarations (internal ones can expand exponentially, external
    ones read files or URLs), external DTDs and ``<use>`` elements that refer
    to other files are refused before any XML parser resolves them; this is
    what ``defusedxml`` does with ``forbid_entities`` and ``forbid_external``.
    So are elements nested deeper than `MAX_DEPTH` (the readers recurse).
    Links of other elements (``<image>``, ``<a>``) are never followed.

    Raises
    ------
    FileFormatError
        Naming the file, the line and what was refused.
    """
    size = path.stat().st_size
    check_memory(TEXT_BYTES_PER_BYTE * size, f"reading {path} ({size / 1e6:.0f} MB)", advice="use a smaller file")
    parser = expat.ParserCreate()
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)

    def entity(name, *args):
        raise _Unsafe(f"declares the entity '{name}'; entities are not expanded (remove the DOCTYPE)")

    def external(context, base, system_id, public_id):
        raise _Unsafe(f"refers to the external entity '{system_id}'; it is not read")

    def doctype(name, system_id, public_id, has_internal_subset):
        if system_id and not _KNOWN_DTD.match(system_id):
            raise _Unsafe(f"names the external DTD '{system_id}'; it is not read")

    depth = [0]
    stack, parents, ids, uses = [], [], {}, {}  # the element tree and its <use> links, for `_expanded_count`

    def start(tag, attrs):
        depth[0] += 1
        if depth[0] > MAX_DEPTH:
            raise _Unsafe(f"elements nested deeper than {MAX_DEPTH} levels")
        index = len(parents)
        parents.append(stack[-1] if stack else -1)
        stack.append(index)
        if "id" in attrs:
            ids.setdefault(attrs["id"], index)
        if tag.rsplit(":", 1)[-1].rsplit("}", 1)[-1] != "use":
            return
        for name, value in attrs.items():
            if name.rsplit(":", 1)[-1] == "href" and not str(value).lstrip().startswith("#"):
                raise _Unsafe(f"<use> refers to '{str(value)[:80]}' outside this file; external references "
                              "are not followed (copy the element into the file)")
            if name.rsplit(":", 1)[-1] == "href":
                uses[index] = (str(value).strip()[1:], parser.CurrentLineNumber)

    def end(tag):
        depth[0] -= 1
        stack.pop()

    parser.EntityDeclHandler = entity
    parser.UnparsedEntityDeclHandler = entity
    parser.ExternalEntityRefHandler = external
    parser.StartDoctypeDeclHandler = doctype
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    try:
        with open(path, "rb") as fh:
            parser.ParseFile(fh)
    except _Unsafe as exc:
        raise FileFormatError(f"{path}, line {parser.CurrentLineNumber}: {exc}") from None
    except (LookupError, ValueError) as exc:  # e.g. an unknown encoding in the XML declaration
        raise FileFormatError(f"{path}: malformed XML ({str(exc)[:80]})") from None
    except expat.ExpatError as exc:
        raise FileFormatError(f"{path}, line {exc.lineno}: malformed XML ({expat.ErrorString(exc.code)})") from None
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot read: {exc.strerror or exc}") from None
    total = _expanded_count(path, parents, ids, uses)
    if total > MAX_ELEMENTS:
        raise FileFormatError(f"{path}: {total} elements after <use> expansion; at most {MAX_ELEMENTS} are read "
                              "(about a millisecond each)")
    check_memory(SVG_BYTES_PER_ELEMENT * total, f"reading {path} ({total} elements after <use> expansion)",
                 advice="use fewer elements or <use> copies")


#: most elements read from one SVG file, <use> copies included (100,000 rects read in about 80 s)
MAX_ELEMENTS = 250_000

#: peak bytes per element of reading an SVG (svgelements' objects, the subpaths, the regions); measured
#: 5.4 kB per <rect> for 100,000 rects (545 MB) in `isotween info`
SVG_BYTES_PER_ELEMENT = 6000


def _expanded_count(path, parents, ids, uses):
    """Elements of the drawing once every ``<use>`` is replaced by a copy of what it names.

    Each element counts itself, its children and, for a ``<use>``, the
    element it refers to (with its own copies): memoised, so a file of a
    few kB whose ``<use>`` elements copy each other ten times over eight
    levels is counted, not expanded (10^8 elements).

    Raises
    ------
    FileFormatError
        A ``<use>`` that refers to itself or to one of its ancestors.
    """
    n = len(parents)
    children = [[] for _ in range(n)]
    for i, p in enumerate(parents):
        if p >= 0:
            children[p].append(i)
    links = {i: ids[target] for i, (target, _) in uses.items() if target in ids}
    count = [0] * n
    state = [0] * n  # 0: not seen, 1: being counted, 2: counted
    for root in range(n):
        if state[root]:
            continue
        todo = [(root, False)]
        while todo:
            node, done = todo.pop()
            if done:
                total = 1 + sum(count[c] for c in children[node])
                if node in links:
                    total += count[links[node]]
                count[node], state[node] = total, 2
                continue
            if state[node] == 2:
                continue
            state[node] = 1
            todo.append((node, True))
            for nxt in children[node] + ([links[node]] if node in links else []):
                if state[nxt] == 1:
                    line = uses[node][1] if node in uses else "?"
                    raise FileFormatError(f"{path}, line {line}: <use> refers to '{uses.get(node, ('?',))[0]}', "
                                          "which contains it (an endless copy)")
                if state[nxt] == 0:
                    todo.append((nxt, False))
    return sum(count[i] for i in range(n) if parents[i] < 0)


#: deepest element nesting read (drawings from editors stay below a few dozen)
MAX_DEPTH = 256

#: the SVG 1.0/1.1 DTDs that editors name in their DOCTYPE (never fetched)
_KNOWN_DTD = re.compile(r"^https?://www\.w3\.org/(Graphics/SVG/1\.1/DTD/svg11|TR/2001/REC-SVG-20010904/DTD/svg10)\.dtd$")


def _colour(colour):
    """RGBA tuple in [0, 1] of a svgelements Color, or None for ``none``."""
    if colour is None or colour.value is None:
        return None
    return (colour.red / 255.0, colour.green / 255.0, colour.blue / 255.0, colour.alpha / 255.0)


def _paint(path, el, tag, label):
    """The `Paint` of an element: fill (none for lines), stroke, width, opacity."""
    fill = None if tag == "line" else _colour(el.fill)
    stroke = _colour(el.stroke)
    width = getattr(el, "implicit_stroke_width", None)
    width = el.stroke_width if width is None else width
    try:
        opacity = min(max(float(el.values.get("opacity", 1.0)), 0.0), 1.0)
        return Paint(fill=fill, stroke=stroke, stroke_width=float(width or 0.0), opacity=opacity)
    except (TypeError, ValueError, ParameterError) as exc:
        raise FileFormatError(f"{path}: {label}: unreadable paint ({exc})") from None


def _ring_length(points):
    return float(np.sum(np.hypot(*(np.roll(points, -1, axis=0) - points).T)))


def _shape_of_rings(path, rings, regions=None, paints=None, y_down=True):
    """One Shape from (points, closed) subpaths, in order."""
    try:
        shape = Shape.from_paths([p for p, _ in rings], [c for _, c in rings], y_down=y_down,
                                 regions=regions, paint=paints)
    except ShapeError as exc:
        raise FileFormatError(f"{path}: {exc}") from exc
    shape.drawing = True  # its point order means nothing: always put in correspondence
    return shape


def _subpath_data(points, closed):
    coords = " L ".join(f"{x!r} {y!r}" for x, y in points.tolist())
    return f"M {coords}{' Z' if closed else ''}"


def write_svg(shape, path, joined=()):
    """Write the outline of a shape as SVG.

    Each shape path becomes one ``<path>`` element (``Z`` for a closed ring);
    edges outside every path (triangle sides, edge soups) are drawn as chains
    in one more ``<path id="edges">`` (not the sides of a painted shape's
    triangles: they are its inside). Numbers are shortest round-trip
    decimals in user units, so a shape whose edges are its paths, listing the
    vertices in order (what `read_svg` returns), reads back identically. SVG
    is y-down: a y-down shape is written as it is, a y-up shape with y
    negated, so that the file shows it upright, and marked so (the root's
    ``data-isotween-y="up"``): `read_svg` negates y back and returns the
    y-up shape. A shape with ``paint`` is written in its colours, one
    ``<path>`` per region (holes cut by the even-odd rule) or lone path, so
    regions and paint read back (colours to 8 bits). uv and faces are not
    stored. ``joined``: lists of regions, the parts of one cut region each
    (``Sequence.info['joined']``), written as one element where they share
    an opaque paint, so that anti-aliasing draws no seam between them
    (`isotween.paint.drawn_groups`); they read back as separate regions.
    """
    v = shape.vertices if shape.y_down else shape.vertices * np.array([1.0, -1.0]) + 0.0  # no -0.0
    lo, hi = (v.min(axis=0), v.max(axis=0)) if len(v) else (np.zeros(2), np.ones(2))
    size = np.maximum(hi - lo, 1e-9 * max(float(np.abs(v).max(initial=1.0)), 1.0))
    pad = 0.05 * float(size.max())
    x0, y0 = (float(c) for c in lo - pad)
    w, h = (float(c) for c in size + 2 * pad)
    stroke = 0.004 * float(np.hypot(w, h))
    elements = []
    covered = np.zeros(0, dtype=np.int64)
    paths = shape.paths or []
    if shape.paint is None:
        for k, (idx, closed) in enumerate(paths):
            elements.append(f'  <path id="path{k}" d="{_subpath_data(v[idx], closed)}"/>')
    else:  # one element per region (holes cut by the even-odd rule) or lone path, in its paint
        for group, paint in drawn_groups(shape, joined):
            d = " ".join(_subpath_data(v[paths[i][0]], paths[i][1]) for i in group)
            attrs = " ".join(f'{k}="{a}"' for k, a in svg_paint_attributes(paint).items())
            elements.append(f'  <path id="path{group[0]}" d="{d}" fill-rule="evenodd" {attrs}/>')
    if paths:
        pe = np.vstack([np.column_stack([p, np.roll(p, -1)] if c else [p[:-1], p[1:]]) for p, c in paths])
        covered = np.unique(np.sort(pe, axis=1), axis=0)
    rest = shape.edges
    if shape.paint is not None and shape.n_faces:  # a painted drawing's triangles are its inside, not lines
        rest = rest[~np.isin(edge_keys(rest[:, 0], rest[:, 1]), edge_table(shape.faces)[3])]
    if len(covered):
        key = np.sort(rest, axis=1)
        rest = rest[~_member(key, covered)]
    if len(rest):
        parts = []
        for c in chains(rest):
            closed = len(c) >= 4 and c[0] == c[-1]
            parts.append(_subpath_data(v[c[:-1] if closed else c], closed))
        elements.append(f'  <path id="edges" d="{" ".join(parts)}"/>')
    marker = "" if shape.y_down else f' {Y_UP_ATTRIBUTE}="up"'
    text = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{x0!r} {y0!r} {w!r} {h!r}" '
        f'width="{512 * w / max(w, h):.6g}" height="{512 * h / max(w, h):.6g}"{marker}>\n'
        f'<g fill="none" stroke="black" stroke-width="{stroke!r}" stroke-linejoin="round">\n'
        + "\n".join(elements)
        + "\n</g>\n</svg>\n"
    )
    write_text(path, text)


def _member(rows, table):
    """Whether each row of ``rows`` (k, 2) occurs in the sorted unique ``table`` (m, 2)."""
    view = np.dtype((np.void, rows.dtype.itemsize * 2))
    a = np.ascontiguousarray(rows).view(view).ravel()
    b = np.ascontiguousarray(table.astype(rows.dtype)).view(view).ravel()
    return np.isin(a, b)
