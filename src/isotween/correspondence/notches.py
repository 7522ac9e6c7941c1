"""A hole that opens into a notch: its region cut open along a slit where the other drawing is empty.

A closed lock's shackle encloses a hole; the open lock's shackle does not:
the same empty space is a notch of the outline there. Shrinking the hole to
nothing and growing the notch from nothing melts the drawing; the motion is
the hole opening where the other drawing has a gap. So, before regions are
paired, a hole of one drawing whose area lies mostly (`OPEN`) in a notch of
the other drawing (inside its convex hull, outside its outlines, once the
two are aligned: `alignment.align`) not much larger than the hole (`ROOM`)
is joined to its region's outer ring by a slit of width `SLIT` (only as many
holes as the other drawing's overlapping region lacks: a ring into a
crescent ring pairs their holes instead), across the
region's material where the other drawing is empty (the gap). Failing
that, a notch of the paired region of about the hole's size, moved onto
the hole by at most `MOVE` of the diagonal (an open lock's hook beside
where the closed lock's shackle was), where the cut ring is then more like
the paired outline than the uncut one (`_moved_notch`, `_slit`). The region's
outer ring then runs into the slit, round the hole and out again, and is
matched to the other drawing's notched outline like any ring. At its own
end the slit is closed again (`close_slits`), so that end fills exactly
the input drawing's area (the closed slit is a seam of no width, which a
fill does not draw; regions with a stroke, which would draw it, keep their
holes).
"""

import numpy as np

from ..geometry import ring_area
from .regions import Item

__all__ = ["open_holes", "close_slits", "OPEN", "ROOM", "MOVE", "SLIT", "NEAR"]

OPEN = 0.5  # a hole with this share of its area in a notch of the other drawing opens into it
ROOM = 2.0  # ... if the notch is at most this many times as large as the hole
MOVE = 0.3  # failing that, a notch of the paired region moved by at most this share of the diagonal onto the hole
SLIT = 1e-3  # the slit's width, in bounding-box diagonals of the drawing
CANDIDATES = 12  # places tried for the slit: the thinnest bridges from the hole to the outer ring
SAMPLES = 256  # ring samples compared when choosing among them
NEAR = 0.01  # cut rings whose correlation with the partner is this near the best's are told apart by `_strain`


def open_holes(items, frames):
    """The drawings' items with every hole that opens into a notch of the other drawing cut open.

    Parameters
    ----------
    items : list (two drawings) of list of Item
    frames : list of two `regions.Frame`
        The drawings' aligned frames.

    Returns
    -------
    items : list of list of Item
        The same, a region whose hole opens having that hole joined to its
        outer ring by a slit.
    slits : list (per drawing) of list of ((4,) complex, (2,) complex)
        Per slit, its corners ``(outer_a, hole_a, hole_b, outer_b)`` and
        the outer and hole vertices they replace, ``(outer, hole)``.
    """
    import shapely
    import shapely.affinity

    out, slits = [list(items[0]), list(items[1])], [[], []]
    for k in (0, 1):
        other = 1 - k
        theirs = [it for it in items[other] if it.kind == "region"]
        if not theirs:
            continue
        outlines = [frames[other].to(frames[k], it.rings[0]) for it in theirs]
        shapes = [_polygon(z) for z in outlines]
        filled = shapely.unary_union(shapes)  # inside the other drawing's outer rings
        notches = filled.convex_hull.difference(filled)  # its gaps: inside its hull, outside its outlines
        every = np.concatenate([r for it in items[k] for r in it.rings])
        diagonal = abs(complex(np.ptp(every.real), np.ptp(every.imag)))
        width = SLIT * diagonal
        for i, it in enumerate(out[k]):
            if it.kind != "region" or len(it.rings) < 2 or it.stroked:
                continue  # (a stroke would draw the closed slit: a seam of no width, invisible in a fill)
            rings, paint = list(it.rings), list(it.paint)
            region = _polygon(rings[0])
            best = int(np.argmax([region.intersection(p).area for p in shapes]))
            partner = outlines[best]
            spare = len(rings) - len(theirs[best].rings)  # holes the partner region lacks: only so many open
            h = 1
            while h < len(rings) and spare > 0:
                hole = _polygon(rings[h])
                shift = 0.0 if hole.area > 0 and _opens(hole, notches) else _moved_notch(hole, shapes[best], diagonal)
                if shift is not None:  # the other drawing moved by ``shift`` has the notch where the hole is
                    cut = _slit(rings[0], rings[h], shapely.affinity.translate(filled, shift.real, shift.imag),
                                width, partner + shift, moved=shift != 0,
                                others=[r for j, r in enumerate(rings[1:], 1) if j != h])
                    if cut is not None:
                        rings[0], corners = cut
                        slits[k].append(corners)
                        del rings[h], paint[h]
                        spare -= 1
                        continue
                h += 1
            out[k][i] = Item(it.kind, rings, paint, it.index)
    return out, slits


def _opens(hole, notches):
    """Whether ``hole`` lies mostly (`OPEN`) in one notch no larger than `ROOM` times itself."""
    parts = getattr(notches, "geoms", [notches])
    return any(part.area <= ROOM * hole.area and hole.intersection(part).area >= OPEN * hole.area
               for part in parts)


def _moved_notch(hole, partner, diagonal):
    """The shift that brings a notch of ``partner`` (its region, once aligned) onto ``hole``; None if none does.

    A notch of the partner region alone (inside its hull, outside it) of
    about the hole's size (within a factor `ROOM`), moved by at most `MOVE`
    of the drawing's ``diagonal`` so that its centroid
    is the hole's, that then covers `OPEN` of the hole: the closed lock's
    shackle hole where the open lock's hook has its notch, the shackle
    moved aside.
    """
    import shapely

    if hole.area <= 0:
        return None
    parts = getattr(notch := partner.convex_hull.difference(partner), "geoms", [notch])
    best, shift = OPEN * hole.area, None
    for part in parts:
        if not hole.area / ROOM <= part.area <= ROOM * hole.area:
            continue
        d = complex(hole.centroid.x - part.centroid.x, hole.centroid.y - part.centroid.y)
        if abs(d) > MOVE * diagonal:
            continue
        cover = hole.intersection(shapely.affinity.translate(part, d.real, d.imag)).area
        if cover >= best:
            best, shift = cover, d
    return shift


def _polygon(z):
    import shapely

    return shapely.Polygon(np.c_[z.real, z.imag]).buffer(0)


def _slit(outer, hole, filled, width, partner, moved=False, others=()):
    """The outer ring run into a slit round ``hole`` and out again, and the slit's corners; None if none fits.

    Candidate bridges join a hole vertex to its nearest outer vertex, mostly
    across the other drawing's gap (outside ``filled``): the shortest few,
    not neighbours; of those, the cut ring most similar to ``partner`` (the
    other drawing's outer ring there: the normalised cross-correlation of
    ring samples, `matching.correlation`) wins, and of cut rings within
    `NEAR` of it the one matched to the partner most nearly rigidly
    (`_strain`). ``moved`` (the notch is the partner's moved onto the
    hole): only a cut ring more similar to the partner than the outer ring
    is. The cut ring must keep clear of the region's ``others`` holes.
    """
    import shapely

    from .matching import correlation, points_at

    d = np.abs(hole[:, None] - outer[None, :])
    j_of = np.argmin(d, axis=1)  # the nearest outer vertex of every hole vertex
    length = d[np.arange(len(hole)), j_of]
    segments = shapely.linestrings(np.stack([np.c_[hole.real, hole.imag],
                                             np.c_[outer[j_of].real, outer[j_of].imag]], axis=1))
    inner = filled.buffer(-width)  # a bridge along the other drawing's outline runs in its gap too
    across = shapely.length(shapely.difference(segments, inner)) >= OPEN * length
    thin = []  # the shortest bridges across the gap, each farther from the others than it is long
    for i in np.flatnonzero(across)[np.argsort(length[across], kind="stable")]:
        if len(thin) == CANDIDATES:
            break
        if all(abs(hole[i] - hole[t]) > length[i] for t in thin):
            thin.append(i)
    area = abs(ring_area(outer)) - abs(ring_area(hole)) - sum(abs(ring_area(r)) for r in others)
    grid = np.arange(SAMPLES) / SAMPLES
    if np.sign(ring_area(partner)) != np.sign(ring_area(outer)):
        partner = partner[::-1]
    target = points_at(partner, True, grid)
    least = -np.inf
    if moved:  # the hole opens only where that makes the ring more like its partner's
        least = np.abs(correlation(points_at(outer, True, grid), target)).max()
    cuts, score = [], []
    for i in thin:
        cut = _spliced(outer, hole, int(j_of[i]), int(i), width)
        if cut is None:
            continue
        poly = shapely.Polygon(np.c_[cut[0].real, cut[0].imag], [np.c_[r.real, r.imag] for r in others])
        if not (poly.is_valid and abs(poly.area - area) <= 0.05 * area):
            continue
        cuts.append(cut)
        score.append(np.abs(correlation(points_at(cut[0], True, grid), target)).max())
    if not cuts or max(score) <= least:
        return None
    # of the cut rings about as similar as the most similar one, the one matched most nearly rigidly (a
    # shackle's leg cut where the body begins rather than a little above: the whole leg goes with the shackle)
    near = [k for k, x in enumerate(score) if x >= max(score) - NEAR]
    return cuts[min(near, key=lambda k: _strain(cuts[k][0], partner))]


def _strain(ring, partner):
    """How far matching ``ring`` to ``partner`` (`matching.match_rings`) is from moving it rigidly.

    Over the matched edges (weights: their lengths in both), the mean
    absolute log of their stretch plus the spread of their turns (one minus
    the length of the mean unit turn): 0 for a rigid motion.
    """
    from .matching import match_rings

    pair = match_rings(ring, partner, True)
    es, et = np.diff(np.r_[pair.source, pair.source[:1]]), np.diff(np.r_[pair.target, pair.target[:1]])
    keep = (np.abs(es) > 0) & (np.abs(et) > 0)
    r = et[keep] / es[keep]
    w = np.abs(es[keep]) + np.abs(et[keep])
    return float(np.sum(w * np.abs(np.log(np.abs(r)))) / w.sum() + 1 - np.abs(np.sum(w * r / np.abs(r))) / w.sum())


def _spliced(outer, hole, j, i, width):
    """``outer`` with a slit of about ``width`` from its vertex j to vertex i of ``hole``, round the hole and back.

    The slit's four corners lie on the rings' own edges next to the two
    vertices they replace, so closing the slit (`close_slits`) puts every
    point of both rings back on the input outline.
    """
    o, h = outer[j], hole[i]
    if o == h:
        return None
    n = 1j * (h - o) / abs(h - o)  # across the bridge
    prev, nxt = outer[j - 1], outer[(j + 1) % len(outer)]
    side = np.sign(((prev - o) / n).real) or 1.0  # the side of the bridge the outer ring comes from
    hn, hp = hole[(i + 1) % len(hole)], hole[i - 1]
    step = 1 if np.sign(((hn - h) / n).real) == side else -1  # round the hole from its side-a neighbour
    ha_to, hb_to = (hn, hp) if step == 1 else (hp, hn)
    if np.sign(((nxt - o) / n).real) == side or np.sign(((hb_to - h) / n).real) == side:
        return None

    def toward(a, b):
        return a + (b - a) * min(0.5, width / 2 / abs(b - a))

    oa, ob, ha, hb = toward(o, prev), toward(o, nxt), toward(h, ha_to), toward(h, hb_to)
    around = hole[(i + step * np.arange(1, len(hole))) % len(hole)]
    ring = np.r_[outer[:j], oa, ha, around, hb, ob, outer[j + 1:]]
    return ring, ((oa, ha, hb, ob), (o, h))


def close_slits(z, slits):
    """Positions ``z`` (n,) complex with every slit closed: both its sides moved onto its centre line.

    Parameters
    ----------
    z : (n,) complex
        One end's vertex positions, whose slit sides are as `open_holes`
        made them (resampling adds vertices along them).
    slits : list of ((4,) complex, (2,) complex)
        `open_holes`'s slits of that end.

    Returns
    -------
    (n,) complex
    """
    z = np.array(z, dtype=complex)
    for (oa, ha, hb, ob), (o, h) in slits:
        for a, b in ((oa, ha), (ob, hb)):  # each side, from the outer ring to the hole
            u = np.clip(((z - a) / (b - a)).real, 0.0, 1.0)
            on = np.abs(a + u * (b - a) - z) <= 1e-9 * abs(b - a)
            z[on] = o + u[on] * (h - o)
    return z
