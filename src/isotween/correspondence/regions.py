"""Object correspondence: which region, hole and polyline of one drawing goes with which of another.

A drawing is cut into *items*: filled regions (outer ring, then holes),
unfilled closed rings and open polylines. Items of the same kind are paired
by an optimal assignment (scipy's `min_weight_full_bipartite_matching`) on their
position, size and direction, normalised by the drawing's bounding box, and for
regions also on their overlap. Two regions whose pieces would pass through
each other on their way swap partners where that costs little more
(`_uncross`). Holes are paired the same way inside each pair of regions,
normalised by the region's box.

Several drawings (keyframes) are paired with the first one: an item of a
later drawing with no partner opens a new *slot* that every other drawing
fills with a small copy. A slot's small copy is the item scaled down by
`TINY` about its centroid and placed where the item would be (``'grow'``),
or inside the nearest region of that drawing (``'split'``). A missing hole
becomes a small copy inside its region, away from the region's boundary.
"""

from typing import NamedTuple

import numpy as np

from ..errors import IncompatibleShapesError, ParameterError, ShapeError
from ..geometry import fill_regions, ring_area, ring_centroid, winding_numbers

__all__ = ["Item", "Slot", "Frame", "TINY", "items_of", "frames_of", "plan", "winding_numbers", "fill_regions",
           "ring_area", "centroid", "inside_point", "region_polygon", "small_copy", "UNLIKE", "UNLIKE_OVERLAP"]

#: scale of the small copy a missing item grows from (or shrinks to)
TINY = 0.05
#: leaving an item unpaired costs this many times the dearest pair (only where a pair is forbidden)
UNPAIRED = 10.0
#: fills this far apart (Oklab distance) pair only where the regions overlap by `UNLIKE_OVERLAP` at least
UNLIKE = 0.2
UNLIKE_OVERLAP = 0.1
#: rounds of region pairing that forbid the pairs carrying a piece into or out of a paired region's hole
NESTING_ROUNDS = 3
#: two region pairs whose pieces would pass through each other swap partners where their two pieces differ in
#: size by at most this factor and the two new pairs cost at most `UNCROSS_SLACK` more than the old, plus
#: `UNCROSS_PER_HIT` times their collision (`_collisions`: up to 3 where one passes right through the other)
UNCROSS_SIZES = 2.0
UNCROSS_SLACK = 0.15
UNCROSS_PER_HIT = 0.5
#: the times at which `_uncross` places the pieces on their way, and the share of the smaller piece's area
#: that two of them must overlap there to collide
UNCROSS_TIMES = (0.25, 0.5, 0.75)
UNCROSS_OVERLAP = 0.02
#: pairings of more regions than this are not checked for collisions (the check is quadratic), and at most
#: `UNCROSS_TRIES` swaps, of the worst collisions, are tried for each one made
UNCROSS_MAX = 40
UNCROSS_TRIES = 8

_KINDS = ("region", "ring", "line")
#: kinds paired with each other: filled regions; strokes (closed rings and open polylines)
_GROUPS = (("region",), ("ring", "line"))


class Item(NamedTuple):
    """One region, unfilled ring or polyline of a drawing.

    Attributes
    ----------
    kind : {'region', 'ring', 'line'}
    rings : list of (k_i,) complex arrays
        Outer ring first, then holes (one ring for 'ring' and 'line').
    paint : list of Paint or None
        Paint of each ring (None when the shape has none).
    index : int
        Region index (regions) or path index (rings, lines) in its shape.
        The parts of a region cut in pieces (`splits`) share it (drawn as
        one path at that end); the second of an X's two crossed bars, which
        overlap, has ``-1 - index``.
    """

    kind: str
    rings: list
    paint: list
    index: int  # type: ignore[assignment]  # shadows tuple.index, which nothing here calls

    @property
    def stroked(self):
        """Whether a ring of the item is drawn with a stroke (which would draw a seam of no width)."""
        return any(getattr(p, "stroke", None) for p in self.paint)


class Slot(NamedTuple):
    """One item of the common structure and what each drawing puts there.

    Attributes
    ----------
    kind : str
    members : list of int or None
        Per drawing: index of its item in this slot, or None (a small copy).
    holes : list of list of int or None
        Per hole slot: per drawing, the index of the hole in that drawing's
        item (1-based ring position) or None.
    """

    kind: str
    members: list
    holes: list


#: weight of the difference of two strokes' directions in their matching cost (a bar and one across: 4 x this)
TURN_COST = 0.05
#: items are mirror images of each other where centroids, sizes and directions agree this closely (normalised)
MIRROR_TOL = 0.01


# ---------------------------------------------------------------- geometry
def centroid(z, closed):
    """Area centroid of a closed ring (vertex mean if flat), length-weighted mean of a polyline."""
    if closed:
        return ring_centroid(z)
    mid, seg = 0.5 * (z[1:] + z[:-1]), np.abs(np.diff(z))
    return complex(np.sum(mid * seg) / seg.sum()) if seg.sum() > 0 else complex(z.mean())


def _size(z, closed):
    """sqrt(|area|) of a closed ring, length of a polyline."""
    return np.sqrt(abs(ring_area(z))) if closed else float(np.abs(np.diff(z)).sum())


# ---------------------------------------------------------------- items
def items_of(shape, name):
    """The items of a drawing: its regions, unfilled closed rings and polylines.

    A shape without ``regions`` (``from_polygon``, OBJ, JSON) has its closed
    paths grouped into regions by the even-odd rule.

    Parameters
    ----------
    shape : Shape
    name : str
        How to call the shape in messages.

    Returns
    -------
    list of Item
    """
    if not shape.paths:
        raise ShapeError(
            f"the {name} has no paths (rings or polylines) to put in correspondence; "
            "give outlines (SVG, Shape.from_polygon, Shape.from_polyline) or compatible shapes"
        )
    z = shape.z
    rings = [z[idx] for idx, _ in shape.paths]
    paint = shape.paint or [None] * len(rings)
    regions = shape.regions
    if regions is None:
        closed = [k for k, (_, c) in enumerate(shape.paths) if c]
        regions = []
        if closed:
            found, _ = fill_regions([np.c_[rings[k].real, rings[k].imag] for k in closed], "evenodd")
            regions = [[closed[i] for i in r] for r in found]
    used = {k for r in regions for k in r}
    items = [Item("region", [rings[k] for k in r], [paint[k] for k in r], i) for i, r in enumerate(regions)]
    for k, (_, c) in enumerate(shape.paths):
        if k not in used:
            items.append(Item("ring" if c else "line", [rings[k]], [paint[k]], k))
    return items


# ---------------------------------------------------------------- pairing
class Frame(NamedTuple):
    """Normalising frame: centre (complex), scale (bounding-box diagonal) and turn (unit complex).

    Normalised coordinates are ``(z - centre) / (scale * turn)``: a drawing
    turned by ``turn`` against the reference has the reference's normalised
    coordinates.
    """

    centre: complex
    scale: float
    turn: complex = 1.0 + 0j

    @classmethod
    def of(cls, z, turn=1.0 + 0j):
        """The frame of the complex points ``z`` (any shape): bounding-box centre and diagonal."""
        lo, hi = complex(z.real.min(), z.imag.min()), complex(z.real.max(), z.imag.max())
        return cls(0.5 * (lo + hi), max(abs(hi - lo), 1e-300), turn)

    def factor(self, other):
        """The similarity factor (complex) from this frame to ``other``."""
        return (other.scale / self.scale) * (other.turn / self.turn)

    def to(self, other, z):
        """Points of this frame mapped to the same normalised place in ``other``."""
        return other.centre + (z - self.centre) * self.factor(other)


def frames_of(items):
    """Normalising frame of every drawing.

    Its bounding box, or one box for all when they share a canvas (each box lies mostly, 80 %, inside the first's or
    contains it), so that items keep their absolute places.

    Parameters
    ----------
    items : list of list of Item

    Returns
    -------
    list of Frame
    """
    pts = [np.concatenate([r for it in key for r in it.rings]) for key in items]
    boxes = np.array([[z.real.min(), z.imag.min(), z.real.max(), z.imag.max()] for z in pts])
    size = np.maximum(boxes[:, 2:] - boxes[:, :2], 1e-12 * np.abs(boxes).max(initial=1.0))
    lo, hi = np.maximum(boxes[:, :2], boxes[0, :2]), np.minimum(boxes[:, 2:], boxes[0, 2:])
    inter = np.prod(np.clip(hi - lo, 0, None), axis=1)
    area = np.prod(size, axis=1)
    if np.all(inter >= 0.8 * np.minimum(area, area[0])):
        joint = Frame.of(np.concatenate(pts))
        return [joint] * len(items)
    return [Frame.of(z) for z in pts]


def _features(item_rings, closed, frame):
    """(centroid, size) of an item's outer ring in normalised coordinates."""
    z = (item_rings[0] - frame.centre) / (frame.scale * frame.turn)
    return centroid(z, closed), _size(z, closed), z


def _cost(a_feats, b_feats, closed, overlap=None):
    """(m, n) matching cost: squared distance of centroids, sizes and directions (`TURN_COST`), plus 1 - overlap.

    The overlap counts for regions only. A bar pairs with a bar of its direction: a check mark's arms cut apart
    each with the bar of a close sign that lies its way.

    ``overlap``: the regions' (m, n) `_overlap`, where the caller has it.
    """
    ca = np.array([f[0] for f in a_feats])
    cb = np.array([f[0] for f in b_feats])
    sa = np.array([f[1] for f in a_feats])
    sb = np.array([f[1] for f in b_feats])
    cost = np.abs(ca[:, None] - cb[None, :]) ** 2 + (sa[:, None] - sb[None, :]) ** 2
    if closed:
        if overlap is None:
            overlap = _overlap([f[2] for f in a_feats], [f[2] for f in b_feats])
        cost = cost + (1.0 - overlap)
    da, db = np.array([_direction(f[2]) for f in a_feats]), np.array([_direction(f[2]) for f in b_feats])
    return cost + TURN_COST * np.abs(da[:, None] - db[None, :]) ** 2


def _unlike(a_paint, b_paint, overlap):
    """Pairs (row, col) of regions of fills more than `UNLIKE` apart (Oklab) that overlap less than `UNLIKE_OVERLAP`."""
    from ..paint import srgb_to_oklab

    def lab(paints):
        fills = [getattr(p, "fill", None) for p in paints]
        return None if any(f is None for f in fills) else srgb_to_oklab(np.array([f[:3] for f in fills]))

    a, b = lab(a_paint), lab(b_paint)
    if a is None or b is None:
        return set()
    far = (np.linalg.norm(a[:, None] - b[None, :], axis=-1) > UNLIKE) & (overlap < UNLIKE_OVERLAP)
    return {(int(r), int(c)) for r, c in zip(*np.nonzero(far), strict=True)}


def _direction(z):
    """A stroke's direction as ``exp(2i theta)`` scaled by how elongated it is (1: a straight line, 0: round)."""
    d = z - z.mean()
    return complex(np.mean(d * d) / max(np.mean(np.abs(d) ** 2), 1e-300))


def _polygon(z):
    import shapely

    poly = shapely.Polygon(np.c_[z.real, z.imag])
    return poly if poly.is_valid else shapely.make_valid(poly)


def _overlap(a_rings, b_rings):
    """(m, n) intersection over union of the areas inside the rings."""
    import shapely

    pa = np.array([_polygon(z) for z in a_rings], dtype=object)
    pb = np.array([_polygon(z) for z in b_rings], dtype=object)
    inter = shapely.area(shapely.intersection(pa[:, None], pb[None, :]))
    union = shapely.area(pa)[:, None] + shapely.area(pb)[None, :] - inter
    return np.where(union > 0, inter / np.maximum(union, 1e-300), 0.0)


def _assign(cost, forced=(), forbidden=()):
    """Optimal pairs (rows, cols) of a cost matrix, after the forced pairs.

    As many pairs as the smaller side allows, least total cost; pairs in
    ``forbidden`` ((row, col) pairs) are never made, their row and column
    left unpaired where no other pair takes them.
    """
    forced = list(forced)
    rows = [r for r in range(cost.shape[0]) if r not in {f[0] for f in forced}]
    cols = [c for c in range(cost.shape[1]) if c not in {f[1] for f in forced}]
    pairs = list(forced)
    if rows and cols:
        from scipy.sparse import csr_array  # scipy.sparse.csgraph, not scipy.optimize (0.1 s more to import)
        from scipy.sparse.csgraph import min_weight_full_bipartite_matching

        sub = cost[np.ix_(rows, cols)] - cost[np.ix_(rows, cols)].min() + 1.0  # every entry stored, above 0
        m, n = sub.shape
        if forbidden:  # each side may also go unpaired (a dummy partner), at a cost above any pair's
            at = {(r, c) for r, c in forbidden}
            keep = np.array([[(r, c) not in at for c in cols] for r in rows])
            lone = UNPAIRED * (sub.max() + 1.0)
            full = np.zeros((m + n, n + m))
            full[:m, :n] = np.where(keep, sub, 0.0)
            full[:m, n:] = lone * np.eye(m)
            full[m:, :n] = lone * np.eye(n)
            full[m:, n:] = 1.0
            sub = full
        r, c = min_weight_full_bipartite_matching(csr_array(sub))
        pairs += [(rows[i], cols[j]) for i, j in zip(r, c, strict=True) if i < m and j < n]
    return pairs


def _mirror_images(feats):
    """Per mirror of the normalised plane, the permutation of the items that it makes, or None.

    The mirrors are about the horizontal, then the vertical axis through the
    frame's centre; an item's image is the item whose centroid, size and
    direction are those of its mirror image within `MIRROR_TOL`.

    Parameters
    ----------
    feats : list of (complex, float, (k,) complex)
        Per item, `_features`: centroid, size and outer ring, normalised.

    Returns
    -------
    list of (n,) int or None
        Per mirror, the index of every item's image (an involution), or None
        where some item has no image.
    """
    c = np.array([f[0] for f in feats])
    s = np.array([f[1] for f in feats])
    d = np.array([_direction(f[2]) for f in feats])
    out = []
    for flip in (1, -1):  # z -> conj(z), z -> -conj(z); a direction exp(2i theta) goes to its conjugate either way
        gap = (np.abs(flip * np.conj(c)[:, None] - c[None, :]) + np.abs(s[:, None] - s[None, :])
               + np.abs(np.conj(d)[:, None] - d[None, :]))
        image = np.argmin(gap, axis=1)
        ok = gap[np.arange(len(c)), image].max(initial=0.0) < MIRROR_TOL and np.all(image[image] == np.arange(len(c)))
        out.append(image if ok else None)
    return out


def _mirrored(cost, a_feats, b_feats, forbidden):
    """Least-cost pairs (rows, cols) that commute with a mirror both drawings share, or None.

    Where both sets of items are symmetric about the same axis, an item and
    its mirror image pair with an item and its mirror image (a hamburger's
    top and bottom bars with the two bars of an X, its middle bar with
    nothing): items are grouped in orbits of the mirror (one item on the
    axis, or two), orbits of the same size paired by `_assign`, a pair of
    two-item orbits in the cheaper of its two ways.
    """
    for ia, ib in zip(_mirror_images(a_feats), _mirror_images(b_feats), strict=True):
        if ia is None or ib is None:
            continue
        oa = [(i,) if ia[i] == i else (i, int(ia[i])) for i in range(len(ia)) if ia[i] >= i]
        ob = [(j,) if ib[j] == j else (j, int(ib[j])) for j in range(len(ib)) if ib[j] >= j]
        if all(len(o) == 1 for o in oa) and all(len(o) == 1 for o in ob):
            return None  # every item on the axis: any pairing commutes with the mirror
        orbit_cost = np.zeros((len(oa), len(ob)))
        ways, barred = {}, set()
        for r, a in enumerate(oa):
            for c, b in enumerate(ob):
                options = [list(zip(a, b, strict=True)), list(zip(a, b[::-1], strict=True))] if len(a) == len(b) else []
                options = [o for o in options if not set(o) & forbidden]
                if not options:
                    barred.add((r, c))
                    continue
                best = min(options, key=lambda o: sum(cost[i, j] for i, j in o))
                ways[r, c] = best
                orbit_cost[r, c] = sum(cost[i, j] for i, j in best)
        return [p for r, c in _assign(orbit_cost, (), barred) for p in ways[r, c]]
    return None


def _check_forced(pairs, n_regions):
    """Validated forced region pairs [(source region, target region)]."""
    out = []
    for p in pairs:
        try:
            i, j = (int(x) for x in p)
        except (TypeError, ValueError):
            raise ParameterError(f"pairs must be (source region, target region) index pairs, got {p!r}") from None
        for side, k, n in (("source", i, n_regions[0]), ("target", j, n_regions[1])):
            if not 0 <= k < n:
                raise IncompatibleShapesError(
                    f"cannot pair source region {i} with target region {j}: the {side} has "
                    f"{n} filled region(s)" + (f" (0 to {n - 1})" if n else "")
                )
        out.append((i, j))
    for side in (0, 1):
        seen = [p[side] for p in out]
        twice = sorted({k for k in seen if seen.count(k) > 1})
        if twice:
            name = ("source", "target")[side]
            raise IncompatibleShapesError(
                f"cannot pair {name} region {twice[0]} with two regions: "
                + ", ".join(f"source region {i} with target region {j}" for i, j in out if (i, j)[side] == twice[0])
            )
    return out


def plan(items, frames, pairs=None):
    """Slots of the common structure of several drawings.

    Parameters
    ----------
    items : list of list of Item
        The items of every drawing (the first is the reference).
    frames : list of Frame
        Each drawing's normalising frame.
    pairs : list of (int, int), optional
        Region pairs (source region, target region) forced on two drawings.

    Returns
    -------
    list of Slot
    """
    K = len(items)
    slots = []
    nests = [containers(key) for key in items]
    for group in _GROUPS:
        kind = group[0]
        closed = kind == "region"  # the overlap of filled areas counts for regions only
        own = [[i for i, it in enumerate(key) if it.kind in group] for key in items]
        kind_slots = [[i] + [None] * (K - 1) for i in own[0]]
        owner = [0] * len(kind_slots)
        for k in range(1, K):
            refs = [(s[o], o) for s, o in zip(kind_slots, owner, strict=False)]
            feats_ref = [_features(items[o][i].rings, items[o][i].kind != "line", frames[o]) for i, o in refs]
            feats_k = [_features(items[k][i].rings, items[k][i].kind != "line", frames[k]) for i in own[k]]
            forced = []
            if kind == "region" and pairs:
                n_regions = [len(own[0]), len(own[1])]
                forced = _check_forced(pairs, n_regions)
            done = []
            if feats_ref and feats_k:
                overlap = _overlap([f[2] for f in feats_ref], [f[2] for f in feats_k]) if closed else None
                cost = _cost(feats_ref, feats_k, closed, overlap)
                # regions of unlike colours pair only where they overlap: a smile's red tongue fades out and a
                # frown's blue tear in, rather than one flying across the face into the other
                forbidden = set() if not closed else _unlike(
                    [items[o][i].paint[0] for i, o in refs], [items[k][i].paint[0] for i in own[k]], overlap)
                forbidden -= set(forced)
                done = _assign(cost, forced, forbidden)
                for _ in range(NESTING_ROUNDS if kind == "region" else 0):
                    bad = _nesting_conflicts(done, refs, own[k], k, nests) - set(forced)
                    if not bad & set(done):
                        break
                    forbidden |= bad
                    done = _assign(cost, forced, forbidden)
                mirrored = None if forced else _mirrored(cost, feats_ref, feats_k, forbidden)
                if mirrored is not None and len(mirrored) == len(done) and not (
                        closed and _nesting_conflicts(mirrored, refs, own[k], k, nests) & set(mirrored)):
                    done = mirrored
                elif closed:  # pieces that would pass through each other on their way swap partners
                    done = _uncross(done, cost, feats_ref, feats_k, set(forced), forbidden,
                                    lambda d, r=refs, o=own[k], k=k: not _nesting_conflicts(d, r, o, k, nests) & set(d))
            for r, c in done:
                kind_slots[r][k] = own[k][c]
            taken = {c for _, c in done}
            for c, i in enumerate(own[k]):
                if c not in taken:
                    kind_slots.append([None] * k + [i] + [None] * (K - 1 - k))
                    owner.append(k)
        for members in kind_slots:
            holes = _plan_holes(items, frames, members) if kind == "region" else []
            kinds = {items[k][m].kind for k, m in enumerate(members) if m is not None}
            # an open stroke paired with a closed one: both morph as open polylines
            slots.append(Slot(kinds.pop() if len(kinds) == 1 else "line", members, holes))
    return slots


def containers(items):
    """Per item, (region item, ring) of the smallest hole its outline lies in, or None.

    Parameters
    ----------
    items : list of Item
        One drawing's items (`items_of`).

    Returns
    -------
    list of (int, int) or None
    """
    import shapely

    owner = [(i, h) for i, it in enumerate(items) if it.kind == "region" for h in range(1, len(it.rings))]
    if not owner:
        return [None] * len(items)
    holes = np.array([_polygon(items[i].rings[h]) for i, h in owner], dtype=object)
    points = shapely.points([(it.rings[0][0].real, it.rings[0][0].imag) for it in items])  # a vertex of each
    inside = shapely.contains(holes[None, :], points[:, None])  # (items, holes)
    inside &= np.array([i for i, _ in owner])[None, :] != np.arange(len(items))[:, None]
    area = np.where(inside, shapely.area(holes)[None, :], np.inf)
    return [owner[int(np.argmin(a))] if np.isfinite(a).any() else None for a in area]


def _placed(feats_ref, feats_k, done, t):
    """(P,) shapely polygons: each paired piece ``feats_ref[r]`` at time ``t`` on its way to ``feats_k[c]``.

    A piece keeps its shape on the way: moved along the straight line between
    the two centroids and scaled by the blend of the two sizes.
    """
    import shapely

    out = []
    for r, c in done:
        (ca, sa, z), (cb, sb, _) = feats_ref[r], feats_k[c]
        w = ca + (1 - t + t * sb / max(sa, 1e-300)) * (z - ca) + t * (cb - ca)
        out.append(shapely.Polygon(np.c_[w.real, w.imag]))
    return np.array([p if p.is_valid else shapely.make_valid(p) for p in out], dtype=object)


def _collisions(feats_ref, feats_k, done, apart):
    """(P, P) share of the smaller piece's area that two pieces of ``done`` overlap on their way.

    Summed over `UNCROSS_TIMES`, where it is above `UNCROSS_OVERLAP` and the
    two are ``apart`` (P, P) in the source (`_placed`).
    """
    import shapely

    P = len(done)
    hits = np.zeros((P, P))
    for t in UNCROSS_TIMES:
        poly = _placed(feats_ref, feats_k, done, t)
        i, j = shapely.STRtree(poly).query(poly, predicate="intersects")
        keep = (i < j) & apart[i, j]
        i, j = i[keep], j[keep]
        share = shapely.area(shapely.intersection(poly[i], poly[j])) / np.maximum(
            np.minimum(shapely.area(poly[i]), shapely.area(poly[j])), 1e-300)
        hits[i, j] += np.where(share > UNCROSS_OVERLAP, share, 0.0)
    return hits + hits.T


def _uncross(done, cost, feats_ref, feats_k, forced, forbidden, valid):
    """Region pairs ``done`` with partners swapped where their pieces would pass through each other.

    Every piece is moved on a straight line to its partner's place, keeping
    its shape (`_placed`); two pieces that do not overlap in the source but
    do on the way (`_collisions`) swap partners where the two pieces differ
    in size by at most `UNCROSS_SIZES` times, the two new pairs cost at most
    `UNCROSS_SLACK` more than the two old ones plus `UNCROSS_PER_HIT` times
    their collision (the worse the collision, the dearer a swap may be),
    neither is forced or forbidden, ``valid(pairs)`` holds (no piece carried
    into a hole), and the pieces collide less in all. The collision worst
    first (the `UNCROSS_TRIES` worst), until no swap helps.
    """
    import shapely

    done = list(done)
    if not 2 <= len(done) <= UNCROSS_MAX:
        return done
    src = _placed(feats_ref, feats_k, done, 0.0)
    i, j = shapely.STRtree(src).query(src, predicate="intersects")
    apart = np.ones((len(done),) * 2, dtype=bool)
    apart[i, j] = False
    for _ in range(len(done)):
        hits = _collisions(feats_ref, feats_k, done, apart)
        total = hits.sum()
        worst = np.argsort(-np.triu(hits), axis=None)[:UNCROSS_TRIES]
        for a, b in zip(*np.unravel_index(worst, hits.shape), strict=True):
            if not hits[a, b]:
                continue
            (ra, ca), (rb, cb) = done[a], done[b]
            swapped = [(ra, cb), (rb, ca)]
            sizes = feats_ref[ra][1], feats_ref[rb][1]
            slack = UNCROSS_SLACK + UNCROSS_PER_HIT * hits[a, b]
            if set(swapped) & forbidden or {done[a], done[b]} & forced or max(sizes) > UNCROSS_SIZES * min(sizes) or (
                    cost[ra, cb] + cost[rb, ca] > slack + cost[ra, ca] + cost[rb, cb]):
                continue
            trial = list(done)
            trial[a], trial[b] = swapped
            if valid(trial) and _collisions(feats_ref, feats_k, trial, apart).sum() < total:
                done = trial
                break
        else:
            return done
    return done


def _nesting_conflicts(done, refs, own, k, nests):
    """Region pairs (row, col) that would carry a piece into or out of a hole of a region ``done`` pairs.

    A pair conflicts where one of its two regions lies in a hole of a region
    that has a partner, and the other does not lie in a hole of that partner:
    it would cross the partner's outline on its way (an island of the
    target's hole paired with a piece outside its container's partner).

    Parameters
    ----------
    done : list of (int, int)
        Pairs (row into ``refs``, column into ``own``).
    refs : list of (int, int)
        Per row, (item, drawing) of the reference.
    own : list of int
        Per column, the item of drawing ``k``.
    nests : list of list
        `containers` of every drawing.

    Returns
    -------
    set of (int, int)
        Every such (row, column), paired in ``done`` or not.
    """
    partner = {refs[r]: own[c] for r, c in done}  # (item, drawing) -> item of drawing k
    back = {own[c]: refs[r] for r, c in done}
    bad = set()
    for r, (i, o) in enumerate(refs):
        src = nests[o][i]
        src = None if src is None else (src[0], o)
        for c, j in enumerate(own):
            tgt = nests[k][j]
            if src is not None and tgt is not None and partner.get(src) == tgt[0]:
                continue  # in holes of two partners
            if (src is not None and src in partner) or (tgt is not None and tgt[0] in back):
                bad.add((r, c))
    return bad


def _plan_holes(items, frames, members):
    """Hole slots of one region slot: per hole slot, per drawing, ring position or None."""
    present = [k for k, m in enumerate(members) if m is not None]
    K, first = len(members), present[0]
    slots = []
    for h in range(1, len(items[first][members[first]].rings)):
        slots.append([None] * K)
        slots[-1][first] = h
    owner = [first] * len(slots)
    for k in present[1:]:
        region = items[k][members[k]]
        fk = Frame.of(region.rings[0], frames[k].turn)
        ks = list(range(1, len(region.rings)))
        refs = [(s[o], o) for s, o in zip(slots, owner, strict=False)]
        feats_ref = [_features([items[o][members[o]].rings[h]], True,
                               Frame.of(items[o][members[o]].rings[0], frames[o].turn)) for h, o in refs]
        feats_k = [_features([region.rings[h]], True, fk) for h in ks]
        done = _assign(_cost(feats_ref, feats_k, True)) if feats_ref and feats_k else []
        for r, c in done:
            slots[r][k] = ks[c]
        taken = {c for _, c in done}
        for c, h in enumerate(ks):
            if c not in taken:
                slots.append([None] * k + [h] + [None] * (K - 1 - k))
                owner.append(k)
    return slots


# ---------------------------------------------------------------- small copies
def _room(polygon, point):
    """Distance from ``point`` (complex) to the boundary of ``polygon`` if inside, else 0."""
    import shapely

    p = shapely.Point(point.real, point.imag)
    if not polygon.contains(p):
        return 0.0
    boundary = polygon.boundary
    if boundary is None:  # a collection (a region made valid): the boundaries of its pieces
        boundary = shapely.union_all([g.boundary for g in getattr(polygon, "geoms", []) if g.boundary is not None])
    return float(boundary.distance(p))


def inside_point(polygon, near, radius):
    """A point inside ``polygon`` near ``near`` with room for a ring of ``radius``.

    Returns
    -------
    point : complex
    room : float
        Distance from the point to the polygon's boundary.
    """
    import shapely
    from shapely.ops import nearest_points, polylabel

    room = _room(polygon, near)
    if room >= 2 * radius:
        return near, room
    if polygon.geom_type != "Polygon":  # made valid into several pieces: the largest
        polygon = max(getattr(polygon, "geoms", [polygon]), key=lambda g: g.area)
    if polygon.geom_type != "Polygon" or polygon.area <= 0:
        return near, room
    pole = polylabel(polygon, tolerance=1e-3 * np.sqrt(polygon.area))
    best = complex(pole.x, pole.y)
    depth = _room(polygon, best)
    # the nearest point of the polygon shrunk by half its depth: close to ``near``, still inside
    core = polygon.buffer(-0.5 * depth)
    if not core.is_empty:
        q = nearest_points(core, shapely.Point(near.real, near.imag))[0]
        cand = complex(q.x, q.y)
        cand_room = _room(polygon, cand)
        if cand_room >= min(2 * radius, 0.45 * depth):
            return cand, cand_room
    return best, depth


def region_polygon(rings):
    """A shapely polygon of an outer ring and holes (complex arrays), made valid."""
    import shapely

    poly = shapely.Polygon(np.c_[rings[0].real, rings[0].imag],
                           [np.c_[h.real, h.imag] for h in rings[1:]])
    return poly if poly.is_valid else shapely.make_valid(poly)


def small_copy(rings, closed, at, room=None):
    """Rings scaled by `TINY` about the outer ring's centroid and moved to ``at``.

    When ``room`` (distance to the nearest boundary) is given, the copy is
    made smaller still so that it stays within half that distance.
    """
    c = centroid(rings[0], closed)
    radius = max(float(np.abs(np.concatenate(rings) - c).max()), 1e-300)
    scale = TINY if not room else min(TINY, 0.5 * room / radius)
    return [at + scale * (z - c) for z in rings]
