"""A region that the other drawing shows in pieces: cut where the pieces part, before regions are paired.

An eye and the same eye struck through (Bootstrap's ``eye-fill`` and
``eye-slash-fill``): the stroke cuts the eye in two. Paired one to one, the
whole eye becomes one piece (half its outline travelling round to the cut)
while the other piece grows from nothing; the motion is the eye parting
where the stroke comes in. So, before regions are paired, a region R of one
drawing that holds two or more regions of the other (once the drawings are
aligned: `alignment.align`), each mostly inside it (`INSIDE`; a piece
drawn joined to a bar that reaches out of R, Font Awesome's slash, by what
is left of it without bars up to `NEAR` wide) and filled alike, that
together cover most of it (`COVER`) and with the other drawing's other
regions (the stroke across) more still (`FILLED`: not a cart's body and
wheels inside a bag), where no region of the other drawing
overlaps R as a whole (`WHOLE`), is cut among them (a thin R, an
outline drawing's at most `NEAR` of the diagonal wide, holds what lies
within its width of it: a bell's outline and the struck-through bell's,
drawn a little apart): every point of R goes to the nearest of them (the
Voronoi zones of their outlines, `STEP` apart). The parts touch along the
cuts, so the end still draws R (the cuts are seams of no width, which a
fill does not draw), and each then pairs with its piece like any region.
Regions with a stroke, which would draw the seams, stay whole.

Play and pause: the pause's right bar lies only partly in the triangle.
Pieces no larger than R, not bars, that lie partly in it (`LOOSE`) and in
nothing else of R's drawing count too, alongside one that lies mostly in it
or where R has no holes: the triangle parts into the two bars.

A plus and a minus (`_arms`): the minus is the plus's bar, so the plus is
cut into the bar and the arms the minus lacks, which retract into it.

A menu and a close sign (`_shapes`, `_cross_bars`): the X is taken as its two crossed
bars, which overlap, each to turn into a bar of the menu. A check mark (or
a chevron) and a close sign (`_bent`): the check, bent once, is cut at its
elbow into its two arms, each to turn into a bar of the X.

Strokes alike (`split_strokes`): a bell's outline, and the struck-through
bell's drawn as two strokes that part where the slash comes in (Lucide's
``bell`` and ``bell-off``). A stroke of one drawing along which lie two or
more strokes of the other (each mostly, `INSIDE`, within its stroke width
of it, at least `REACH_LEAST` of the diagonal), that together run along
most of it (`COVER`) and none along nearly all of it (`WHOLE`), is cut
where they part: each point of it goes to the nearest of them, so that
each of them has one stretch of it. The parts meet end to end, so the end
still draws the stroke.
"""

import numpy as np

from ..geometry import bbox_diagonal, ring_area
from .regions import Item, region_polygon

__all__ = ["split_regions", "split_strokes", "INSIDE", "LOOSE", "COVER", "FILLED", "WHOLE", "LEAST", "CORE", "ARM",
           "WITHIN", "NEAR", "STEP", "REACH_LEAST"]

INSIDE = 0.8  # a piece of the other drawing lies at least this share of its area inside the region
LOOSE = 0.15  # ... or, with one that does, this share, where it is no larger and in nothing else of the drawing
COVER = 0.6  # the pieces together cover at least this share of the region
FILLED = 0.7  # and the other drawing's regions, the pieces and others (a slash across), this share of it
WHOLE = 0.9  # a region of the other drawing overlapping the region this much (intersection over union) keeps it whole
LEAST = 0.05  # pieces smaller than this share of the region do not count
NOTCH = np.deg2rad(30.0)  # an inner corner: the outline turns back inward by this much (`_inner_corners`)
CONVEX = 0.95  # each of two crossed bars fills this share of its convex hull (`_cross_bars`)
CORE = (0.35, 0.7)  # one region of the other drawing covering this share of a region: its arms cut off (`_arms`)
ARM = 2.5  # ... where each is a bar, this many times as long as it is wide
WITHIN = 0.97  # ... and the other drawing's region lies within the region (a minus is the plus's bar)
NEAR = 0.08  # a region at most this wide (share of the drawing's diagonal) holds what lies within its width of it
STEP = 0.005  # the pieces' outlines are sampled this far apart (share of the drawing's diagonal) for their zones
REACH_LEAST = 0.01  # a stroke's pieces lie within its width of it, or this share of the diagonal if more
CRUMB = 1e-3  # a part of a zone's cut smaller than this share of the region joins the part it touches most
HAIR = np.deg2rad(2.0)  # a cut's vertex where the outline turns back within this angle is a hair of no width


def split_regions(items, frames):
    """The drawings' items with every region that the other drawing shows in pieces cut among them.

    Parameters
    ----------
    items : list (two drawings) of list of Item
    frames : list of two `regions.Frame`
        The drawings' aligned frames.

    Returns
    -------
    items : list of list of Item
        The same, a region cut in pieces replaced by its parts (in its place, so the painting order holds).
    cut : list of int
        Per drawing, the regions cut.
    """
    import shapely

    out, cut = [list(items[0]), list(items[1])], [0, 0]
    for k in (0, 1):
        other = 1 - k
        theirs = [(region_polygon([frames[other].to(frames[k], r) for r in it.rings]), it.paint[0])
                  for it in items[other] if it.kind == "region"]
        if not theirs:
            continue
        filled = shapely.union_all([p for p, _ in theirs])
        theirs = [(p, q) for p, q in theirs if p.geom_type == "Polygon"]  # not the rings of overlapping pieces
        mine = shapely.union_all([region_polygon(it.rings) for it in items[k] if it.kind == "region"])
        step = STEP * bbox_diagonal(*[r for it in items[k] for r in it.rings])
        barred, crossed = _shapes(theirs)
        new = []
        for it in out[k]:
            parts = bars = None
            region = region_polygon(it.rings) if it.kind == "region" and not it.stroked else None
            if region is not None and region.geom_type == "Polygon":  # (overlapping pieces' rings stay whole)
                parts = (_parts(region, it.paint[0], theirs, filled, mine, step) if len(theirs) >= 2 else None) \
                    or _arms(region, it.paint[0], theirs)
                fill = getattr(it.paint[0], "fill", None)
                bars = None if parts or fill not in barred else _cross_bars(region)
                parts = parts or (None if bars or fill not in crossed else _bent(region))
            if parts is None and bars is None:
                new.append(it)
                continue
            cut[k] += 1
            outer = np.sign(ring_area(it.rings[0]))
            if bars:  # they overlap: each its own region (`index`), not parts drawn as one path (an even-odd fill)
                new += [Item("region", _rings(p, outer), [it.paint[0]], index) for p, index in
                        zip(bars, (it.index, -1 - it.index), strict=True)]
                continue
            new += [Item("region", _rings(p, outer), [it.paint[0]] * (1 + len(p.interiors)), it.index) for p in parts]
        out[k] = new
    return out, cut


def _parts(region, paint, theirs, filled, mine, step):
    """The region cut among the pieces of the other drawing it holds (shapely polygons), or None.

    ``theirs`` are the other drawing's regions (polygon, paint), ``filled`` their union, ``mine`` the union of the
    region's own drawing's regions.
    """
    import shapely

    area = region.area
    if area <= 0:
        return None
    polys = np.array([p for p, _ in theirs], dtype=object)
    inter = shapely.area(shapely.intersection(region, polys))
    union = area + shapely.area(polys) - inter
    if np.any(inter >= WHOLE * union):
        return None
    inside = cover = inter
    width = 2 * area / region.length
    if width <= NEAR * step / STEP:  # a thin region (an outline's) holds what lies within its width of it
        inside = shapely.area(shapely.intersection(region.buffer(width), polys))
        cover = shapely.area(shapely.intersection(region, shapely.buffer(polys, width)))
        filled = filled.buffer(width)
    fill = getattr(paint, "fill", None)
    opened = 0.5 * NEAR * step / STEP  # a piece opened by this much leaves out bars (a slash)
    cores = {}

    def core(i):
        if i not in cores:
            cores[i] = polys[i].buffer(-opened).buffer(opened)
        return cores[i]

    def inside_enough(i):  # or, joined to a bar that reaches out (a slash), without it
        if inside[i] >= INSIDE * polys[i].area:
            return True
        body = core(i)
        return not body.is_empty and shapely.intersection(region, body).area >= INSIDE * body.area >= LEAST * area

    alike = [i for i, (p, q) in enumerate(theirs) if p.area >= LEAST * area and getattr(q, "fill", None) == fill]
    held = [i for i in alike if inside_enough(i)]
    if held or not region.interiors:  # with one of them, or in a region with no holes, pieces no larger than the
        # region, not bars, that lie partly in it and in nothing else of its drawing (a triangle's two bars: play and
        # pause; a person's body, and the two of a pair of people)
        loose = [i for i in alike if i not in held and LOOSE * polys[i].area <= inside[i] and polys[i].area <= area
                 and not core(i).is_empty]
        if loose:
            elsewhere = shapely.area(shapely.intersection(shapely.difference(mine, region), polys[loose]))
            held = sorted(held + [i for i, e in zip(loose, elsewhere, strict=True) if e <= LEAST * polys[i].area])
    if (len(held) < 2 or cover[held].sum() < COVER * area
            or shapely.intersection(region, filled).area < FILLED * area):
        return None
    # every piece's outline sampled; each point's Voronoi cell goes to its piece
    points, owner = [], []
    for n, i in enumerate(held):
        for ring in [polys[i].exterior, *polys[i].interiors]:
            xy = np.asarray(shapely.segmentize(ring, step).coords)[:-1]
            points.append(xy)
            owner.append(np.full(len(xy), n))
    xy, owner = np.concatenate(points), np.concatenate(owner)
    xy, first = np.unique(xy, axis=0, return_index=True)
    owner = owner[first]
    cells = _voronoi(xy, region.bounds)
    if cells is None:
        return None
    try:
        # zone by zone, each part what is left of the region: the parts tile it, the last takes the rest
        # (a zone's outline is a staircase of Voronoi edges, straightened within a quarter step)
        parts, rest = [], region
        for n in range(len(held) - 1):
            zone = shapely.union_all(cells[owner == n]).simplify(0.25 * step)
            parts.append(shapely.intersection(rest, zone))
            rest = shapely.difference(rest, parts[-1])
        return _whole([*parts, rest], area, region)
    except shapely.errors.GEOSException:  # a cut GEOS cannot make: the region stays whole
        return None


def _arms(region, paint, theirs):
    """The region cut into the part one region of the other drawing covers and the arms it lacks, or None.

    A plus and a minus: the minus is the plus's bar, the plus's other arms
    have no counterpart. Cut off, each arm retracts on its own (a piece with
    no partner) while the bar stays, where the whole plus matched to the
    minus squeezes its arms into a diamond. Only where exactly one region of
    the other drawing, filled alike, overlaps the region (more than `LEAST`
    of it), lies within it (`WITHIN`), and covers between `CORE` of
    it, and what is left is one to four arms of at least `LEAST` of it each,
    bars (`ARM`; not a triangle's corners round the circle inside it).
    """
    import shapely

    area = region.area
    if area <= 0:
        return None
    polys = np.array([p for p, _ in theirs], dtype=object)
    inter = shapely.area(shapely.intersection(region, polys))
    over = np.flatnonzero(inter > LEAST * area)
    if len(over) != 1:
        return None
    i = int(over[0])
    piece, fill = polys[i], getattr(theirs[i][1], "fill", None)
    if (inter[i] < WITHIN * piece.area or not CORE[0] * area <= inter[i] <= CORE[1] * area
            or fill != getattr(paint, "fill", None)):
        return None
    try:
        rest = shapely.difference(region, piece)
        pieces = [g for g in getattr(rest, "geoms", [rest]) if g.geom_type == "Polygon"]
        arms = [g for g in pieces if g.area >= LEAST * area]
        if not 1 <= len(arms) <= 4 or min(_aspect(g) for g in arms) < ARM:
            return None
        core = shapely.union_all([shapely.intersection(region, piece), *(g for g in pieces if g.area < LEAST * area)])
        return _whole([core, *arms], area, region)
    except shapely.errors.GEOSException:
        return None


def _shapes(theirs):
    """The fills of the other drawing's regions that call for crossed bars (`_cross_bars`) and for arms (`_bent`).

    A menu's three bars and a close sign's X (Bootstrap's ``list`` and
    ``x-lg``): the X, one region, paired whole with a bar melts into a blob;
    taken as its two bars, which overlap where they cross, each turns into a
    bar of the menu. So a region is taken as crossed bars where two or more
    regions of the other drawing, filled alike, are bars (`ARM` times as
    long as wide), or one is bent once (`_elbow`: a check mark's two arms);
    and a region bent once is cut into its arms where a region of the other
    drawing, filled alike, is crossed bars.

    Parameters
    ----------
    theirs : list of (shapely Polygon, Paint)

    Returns
    -------
    barred, crossed : set of tuple or None
        The fills with bars or a bent region, and those with crossed bars.
    """
    bars, barred, crossed = {}, set(), set()
    for p, q in theirs:
        fill = getattr(q, "fill", None)
        bars[fill] = bars.get(fill, 0) + (_aspect(p) >= ARM)
        if bars[fill] >= 2 or _elbow(p):
            barred.add(fill)
        if _cross_bars(p):
            crossed.add(fill)
    return barred, crossed


def _bent(region):
    """A region bent once (a check mark, a chevron) cut at its elbow into its two arms: (2,) or None.

    A check into a close sign (Font Awesome's ``check`` and ``xmark``): the
    X is taken as its two crossed bars (`_cross_bars`) and the check as its
    two arms, each to turn into a bar; whole, the check melted into the X.
    The region, with no holes, has one inner corner (`_elbow`); it is cut
    from there along the bisector of the corner into two arms (the cut a seam
    of no width, as `_parts` cuts), each at least `LEAST` of the region.
    """
    import shapely
    from shapely.ops import split

    elbow = _elbow(region)
    if elbow is None:
        return None
    corner, way = elbow
    x0, y0, x1, y1 = region.bounds
    reach = 2 * np.hypot(x1 - x0, y1 - y0)
    a, b = corner - 1e-9 * reach * way, corner + reach * way
    try:
        pieces = split(region, shapely.LineString([(a.real, a.imag), (b.real, b.imag)]))
    except (shapely.errors.GEOSException, ValueError):
        return None
    arms = [g for g in pieces.geoms if g.geom_type == "Polygon"]
    if len(arms) != 2 or min(g.area for g in arms) < LEAST * region.area:
        return None
    return arms


def _inner_corners(region):
    """The inner corners of a region's outer ring: per corner, (vertex indices (r,), summed turn) in (k,) order.

    An inner corner is a run of vertices where the outline turns back
    inward, by `NOTCH` or more in all; with the outline's vertices (k,)
    complex. None where no vertex or every vertex turns inward.
    """
    z = np.asarray(region.exterior.coords)[:-1] @ [1, 1j]
    turn = np.angle((np.roll(z, -1) - z) / (z - np.roll(z, 1)))
    inward = turn * np.sign(turn.sum()) < 0
    if inward.all() or not inward.any():
        return None
    first = int(np.flatnonzero(~inward)[0])  # runs of inward turns, counted from a vertex that turns outward
    order = np.roll(np.arange(len(z)), -first)
    at = order[inward[order]]
    run = np.cumsum(np.r_[False, inward[order][1:] & ~inward[order][:-1]])[inward[order]]
    runs = [at[run == r] for r in np.unique(run)]
    return z, [(r, float(turn[r].sum())) for r in runs if abs(turn[r].sum()) >= NOTCH]


def _elbow(region):
    """A region bent once: (its inner corner (complex), unit direction into the material (complex)), or None.

    No holes and one inner corner (`_inner_corners`); the direction halves
    the corner's angle inside the region.
    """
    found = None if region.interiors else _inner_corners(region)
    if found is None or len(found[1]) != 1:
        return None
    z, ((run, _),) = found
    k = len(z)
    into, out = z[run[0]] - z[run[0] - 1], z[(run[-1] + 1) % k] - z[run[-1]]
    way = into / abs(into) - out / abs(out)  # back along the incoming side, on along the outgoing: the halving line
    if abs(way) < 1e-9:
        return None
    return complex(z[run].mean()), way / abs(way)


def _cross_bars(region):
    """The two crossed bars that make up a region (an X, a plus): (2,) shapely Polygons, or None.

    The region, with no holes, has four inner corners (`_inner_corners`);
    what is left of it without their quadrilateral is four arms, and each two
    opposite arms with the quadrilateral make a bar (`ARM` times as long as
    wide, filling `CONVEX` of its convex hull). The bars overlap there.
    """
    import shapely

    found = None if region.interiors else _inner_corners(region)
    if found is None or len(found[1]) != 4:
        return None
    z, runs = found
    corners = [complex(z[r].mean()) for r, _ in runs]
    try:
        core = shapely.MultiPoint(np.c_[np.real(corners), np.imag(corners)]).convex_hull
        rest = shapely.difference(region, core)
        arms = [g for g in getattr(rest, "geoms", [rest]) if g.geom_type == "Polygon" and g.area >= LEAST * region.area]
        if len(arms) != 4 or core.geom_type != "Polygon":
            return None
        centre = complex(*core.centroid.coords[0])
        arms.sort(key=lambda g: np.angle(complex(*g.centroid.coords[0]) - centre))  # opposite arms two apart
        bars = [shapely.union_all([arms[i], core, arms[i + 2]]) for i in (0, 1)]
    except shapely.errors.GEOSException:
        return None
    if any(b.geom_type != "Polygon" or _aspect(b) < ARM or b.area < CONVEX * b.convex_hull.area for b in bars):
        return None
    return bars


def _aspect(poly):
    """Length over width of the smallest rectangle round ``poly`` (1 for a square, large for a bar)."""
    import shapely

    xy = np.asarray(shapely.minimum_rotated_rectangle(poly).exterior.coords)
    sides = np.hypot(*np.diff(xy[:3], axis=0).T)
    return float(sides.max() / max(sides.min(), 1e-300))


def _voronoi(xy, bounds):
    """(m,) shapely polygons: the Voronoi cell of every point ``xy`` (m, 2) (Qhull), bounded far beyond ``bounds``."""
    import shapely
    from scipy.spatial import QhullError, Voronoi

    lo, hi = np.array(bounds[:2]), np.array(bounds[2:])
    ring = 0.5 * (lo + hi) + 10 * max(np.max(hi - lo), 1e-12) * np.array(
        [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]])  # far points: every cell of xy bounded
    try:
        vor = Voronoi(np.r_[xy, ring])
    except QhullError:
        return None
    cells = [vor.regions[r] for r in vor.point_region[:len(xy)]]
    if any(-1 in c or len(c) < 3 for c in cells):
        return None
    return np.array([shapely.Polygon(vor.vertices[c]) for c in cells], dtype=object)


def _whole(parts, area, region):
    """One clean polygon per zone (`_clean`): crumbs (`CRUMB`) join the part they touch most; else None."""
    import shapely

    pieces = [sorted(getattr(p, "geoms", [p]), key=lambda g: -g.area) for p in parts]
    pieces = [[g for g in ps if g.geom_type == "Polygon" and g.area > 0] for ps in pieces]
    if any(not ps for ps in pieces):
        return None
    main = [ps[0] for ps in pieces]
    for n, ps in enumerate(pieces):
        for crumb in ps[1:]:
            if crumb.area > CRUMB * area:
                return None
            touch = [shapely.intersection(crumb.buffer(1e-9 * np.sqrt(area)), m).area if j != n else -1.0
                     for j, m in enumerate(main)]
            j = int(np.argmax(touch))
            merged = shapely.union_all([main[j], crumb])
            if merged.geom_type != "Polygon":
                return None
            main[j] = merged
    old = np.concatenate([np.asarray(ring.coords) for ring in [region.exterior, *region.interiors]]) @ [1, 1j]
    main = [_clean(m, old) for m in main]
    return None if any(m is None for m in main) else main


def _clean(poly, old):
    """The polygon without the hairs the cut may leave (a vertex it turns back at, `HAIR`); None if it is not valid.

    ``old`` (m,) complex are the region's own vertices.

    Only a vertex on the cut (one it made or next to one) goes: the region's
    own sharp corners elsewhere stay.
    """
    import shapely

    rings = []
    for ring in [poly.exterior, *poly.interiors]:
        z = np.asarray(ring.coords)[:-1] @ [1, 1j]
        while len(z) >= 3:
            z = z[z != np.roll(z, 1)]
            a, b = np.roll(z, 1) - z, np.roll(z, -1) - z
            new = ~np.isin(z, old)
            hair = (np.abs(np.angle(b / a)) < HAIR) & (new | np.roll(new, 1) | np.roll(new, -1))
            if not hair.any():
                break
            z = np.delete(z, np.flatnonzero(hair)[0])
        if len(z) < 3:
            return None
        rings.append(np.c_[z.real, z.imag])
    out = shapely.Polygon(rings[0], rings[1:])
    return out if out.is_valid else None


def _rings(poly, outer):
    """A polygon's rings as complex arrays: the outer ring turning like ``outer`` (its sign), holes the other way."""
    rings = []
    for n, ring in enumerate([poly.exterior, *poly.interiors]):
        z = np.asarray(ring.coords)[:-1] @ [1, 1j]
        want = outer if n == 0 else -outer
        rings.append(z if np.sign(ring_area(z)) == want else z[::-1])
    return rings


def split_strokes(items, frames):
    """The drawings' items with every stroke that the other drawing shows in pieces cut among them.

    Parameters
    ----------
    items : list (two drawings) of list of Item
    frames : list of two `regions.Frame`
        The drawings' aligned frames.

    Returns
    -------
    items : list of list of Item
        The same, a stroke cut in pieces replaced by its parts (open
        strokes, in its place).
    cut : list of int
        Per drawing, the strokes cut.
    """
    import shapely

    from .matching import points_at

    out, cut = [list(items[0]), list(items[1])], [0, 0]
    for k in (0, 1):
        other = 1 - k
        strokes = [it for it in items[other] if it.kind in ("ring", "line")]
        if len(strokes) < 2:
            continue
        diagonal = bbox_diagonal(*[r for it in items[k] for r in it.rings])
        step = STEP * diagonal
        theirs = [frames[other].to(frames[k], it.rings[0]) for it in strokes]
        closed = [it.kind == "ring" for it in strokes]
        lines = np.array([_outline(w, c) for w, c in zip(theirs, closed, strict=True)])
        # their samples, `step` apart (at least 8 each), once for every stroke of this drawing
        counts = np.maximum((shapely.length(lines) / step).astype(int), 8)
        q = np.concatenate([points_at(w, c, np.arange(n) / n if c else np.linspace(0.0, 1.0, n))
                            for w, c, n in zip(theirs, closed, counts, strict=True)])
        owner = np.repeat(np.arange(len(strokes)), counts)
        samples = shapely.points(np.c_[q.real, q.imag])
        box = shapely.bounds(lines)  # (m, 4)
        new = []
        for it in out[k]:
            parts = None
            if it.kind in ("ring", "line"):
                width = getattr(it.paint[0], "stroke_width", 0.0) if getattr(it.paint[0], "stroke", None) else 0.0
                reach = max(width, REACH_LEAST * diagonal)
                z = it.rings[0]
                ends_meet = it.kind == "line" and len(z) > 3 and abs(z[-1] - z[0]) <= 1e-9 * diagonal
                if ends_meet:  # a line that ends where it starts goes round as a ring
                    z = z[:-1]
                line = _outline(z, it.kind == "ring" or ends_meet)
                lo, hi = np.array(line.bounds[:2]) - reach, np.array(line.bounds[2:]) + reach
                nearby = np.all((box[:, :2] <= hi) & (box[:, 2:] >= lo), axis=1)  # their boxes meet its own
                held = []
                if np.count_nonzero(nearby) >= 2:
                    look = nearby[owner]
                    near = np.bincount(owner[look], shapely.distance(line, samples[look]) <= reach, len(strokes))
                    held = np.flatnonzero(near >= INSIDE * counts)  # the strokes lying mostly along this one
                if len(held) >= 2:
                    parts = _stroke_parts(z, it.kind == "ring" or ends_meet, lines[held], reach, step)
            if parts is None:
                new.append(it)
                continue
            cut[k] += 1
            new += [Item("line", [p], list(it.paint), it.index) for p in parts]
        out[k] = new
    return out, cut


def _outline(z, closed):
    """The shapely ring or line string of the stroke ``z`` (k,) complex."""
    import shapely

    xy = np.c_[z.real, z.imag]
    return shapely.LinearRing(xy) if closed else shapely.LineString(xy)


def _stroke_parts(z, closed, held, reach, step):
    """The stroke ``z`` (k,) complex cut among the strokes ``held`` (shapely) that lie along it, or None.

    Returns
    -------
    list of (m_i,) complex
        Open polylines, in order along the stroke, meeting end to end.
    """
    import shapely

    from .matching import arc_params, points_at

    length = _outline(z, closed).length
    n = max(int(length / step), 8 * len(held))
    u = np.arange(n) / n if closed else np.linspace(0.0, 1.0, n)
    p = points_at(z, closed, u)
    d = shapely.distance(held[:, None], shapely.points(np.c_[p.real, p.imag])[None, :])  # (h, n)
    within = d <= reach
    if within.any(axis=0).mean() < COVER or np.any(within.mean(axis=1) >= WHOLE):
        return None
    # every point of the stroke goes to the nearest stroke held: one stretch each (a closed stroke's wrap round)
    owner = np.argmin(d, axis=0)
    change = np.flatnonzero(owner != np.roll(owner, 1))
    if not closed:
        change = change[change > 0]
    if len(change) + (not closed) != len(held):
        return None
    cut = np.sort((u[change] + u[change - 1] + (change == 0)) / 2 % 1.0)  # halfway between the samples
    bounds = zip(cut, np.r_[cut[1:], cut[0] + 1.0], strict=True) if closed else \
        zip(np.r_[0.0, cut], np.r_[cut, 1.0], strict=True)
    params = arc_params(z, closed)[0]  # every vertex's share of the length along the stroke
    s, v = (np.r_[params, params + 1.0], np.r_[z, z]) if closed else (params, z)
    return [np.r_[points_at(z, closed, a), v[(s > a) & (s < b)], points_at(z, closed, b)] for a, b in bounds]
