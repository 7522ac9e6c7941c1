"""Automatic correspondence: any two drawings (or several keyframes) made compatible.

Stages (each swappable):

1. object correspondence (`regions.plan`): regions, holes, unfilled rings and
   polylines paired by optimal assignment; a missing item becomes a small copy;
2. point correspondence (`resample`): every ring pair resampled in arc length
   to a common count, best start and orientation;
3. solids: every pair of filled regions triangulated into compatible meshes
   (`_mesh_region`, the one place that names the mesher).
"""

import copy
import hashlib
import numbers
from collections import Counter
from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numpy as np

from ..errors import IncompatibleShapesError, IsotweenError, ParameterError, ResourceError, ShapeError
from ..geometry import MAX_TRIANGLES, bbox_diagonal
from ..shape import Shape
from . import regions as _regions
from .alignment import align
from .compatibility import as_shape, check_compatible
from .matching import match_rings, points_at, project
from .notches import open_holes
from .resample import _counts, _Ring, resample
from .splits import split_regions, split_strokes

__all__ = ["Correspondence", "CorrespondenceReport", "correspond", "correspond_keys", "mesh_outlines", "region_key",
           "MAX_TRIANGLES"]

#: meshes estimated to need more triangles than this (all regions together) are refused

#: a landmark point may lie at most this fraction of its drawing's diagonal from an outline
LANDMARK_REACH = 0.05

#: outlines of corresponded drawings get at least this many points in all (long edges split)
MIN_POINTS = 64

#: default mesh size: at least this fraction of the drawings' bounding-box diagonal
MESH_FRACTION = 1 / 30

#: a stroke with no partner grows out of the nearest stroke within this share of its length, else from its middle
GROW_REACH = 0.25

#: a piece with no partner that lies over its own drawing's fill (all but this share of its area) grows in place
OVER_FILL = 0.05


@dataclass
class CorrespondenceReport:
    """What `correspond` did.

    Attributes
    ----------
    unchanged : bool
        The inputs were compatible already and came back as they were.
    keys : int
        Number of drawings made compatible together.
    unmatched : {'grow', 'split'}
    regions, holes, rings, lines : dict
        Counts per kind of item: ``paired`` (present in every drawing),
        ``grown`` (missing from the first drawing: grows from a small copy),
        ``shrunk`` (missing from a later drawing: shrinks to a small copy).
    pairs : list of (int, int)
        Region pairs (source region, target region) of two drawings.
    points : list of int
        Points per ring of the output.
    meshes : list of (int, int)
        (vertices, triangles) of every meshed region pair.
    flipped : int
        Triangles of the output meshes with the other orientation in the
        target than in the source.
    outlines : list of str
        Filled regions kept as outlines, and why.
    vanishing : list of list of (k,) int arrays
        Per drawing, the vertices of each ring that is only a small copy
        there (an item or hole the drawing lacks): `isotween.morph` collapses
        them to a point in that drawing's frame, so nothing is left of it.
    slits : list of list
        Per drawing, the slits that opened a hole into the other drawing's
        notch (`notches.open_holes`): `isotween.morph` closes them in that
        drawing's frame (`notches.close_slits`).
    hinted : bool
        Landmarks were given: the ring matches are kept as the hints made
        them (no slide).
    slid : int
        Meshed regions whose source points were slid along the outline to
        make the map more rigid (a bent copy: `slide.slid_rings`), then
        meshed again.
    cut : list of int
        Per drawing, the regions cut among the pieces the other drawing
        shows them in (`splits.split_regions`).
    strokes_cut : list of int
        Per drawing, the strokes cut among the pieces the other drawing
        shows them in (`splits.split_strokes`).
    joined : list of list of int
        The output regions that are the parts of one cut region (they meet
        along the cut at that end, and outputs draw them as one path there).
    """

    unchanged: bool = False
    keys: int = 2
    unmatched: str = "grow"
    regions: dict = field(default_factory=dict)
    holes: dict = field(default_factory=dict)
    rings: dict = field(default_factory=dict)
    lines: dict = field(default_factory=dict)
    pairs: list = field(default_factory=list)
    points: list = field(default_factory=list)
    meshes: list = field(default_factory=list)
    flipped: int = 0
    outlines: list = field(default_factory=list)
    vanishing: list = field(default_factory=list)
    slits: list = field(default_factory=list)
    hinted: bool = False
    slid: int = 0
    cut: list = field(default_factory=list)
    strokes_cut: list = field(default_factory=list)
    joined: list = field(default_factory=list)

    def summary(self):
        """One line saying what was done."""
        if self.unchanged:
            return "correspondence: the inputs are compatible already (unchanged)"
        grown, shrunk = ("split off", "merged") if self.unmatched == "split" else ("grown", "shrunk")
        parts = []
        for name, counts in (("regions", self.regions), ("holes", self.holes), ("rings", self.rings),
                             ("polylines", self.lines)):
            if not any(counts.values()):
                continue
            words = {"paired": "paired", "grown": "opened" if name == "holes" else grown,
                     "shrunk": "closed" if name == "holes" else shrunk}
            parts.append(f"{name} " + ", ".join(f"{counts[k]} {words[k]}" for k in ("paired", "grown", "shrunk")
                                                 if counts.get(k)))
        for k, side in enumerate(("source", "target")):
            if len(self.slits) > k and self.slits[k]:
                parts.append(f"{len(self.slits[k])} {side} hole(s) opened into notches")
            if len(self.cut) > k and self.cut[k]:
                parts.append(f"{self.cut[k]} {side} region(s) cut where the {('target', 'source')[k]} parts them")
            if len(self.strokes_cut) > k and self.strokes_cut[k]:
                parts.append(f"{self.strokes_cut[k]} {side} stroke(s) cut where the {('target', 'source')[k]} "
                             "parts them")
        pts = np.asarray(self.points)
        parts.append(f"{int(pts.sum())} points on {len(pts)} ring(s) ({int(pts.min())}-{int(pts.max())} each)")
        if self.meshes:
            v, t = np.sum(self.meshes, axis=0)
            parts.append(f"{len(self.meshes)} solid(s): {int(v)} vertices, {int(t)} triangles, "
                         f"{self.flipped} flipped")
        if self.slid:
            parts.append(f"{self.slid} bent region(s) matched along the bend")
        if self.outlines:
            parts.append(f"{len(self.outlines)} region(s) as outlines ({self.outlines[0]})")
        return "correspondence: " + "; ".join(parts)


class Correspondence(NamedTuple):
    """What `correspond` returns: ``src, tgt, report = correspond(a, b)``."""

    source: Shape
    target: Shape
    report: CorrespondenceReport


def correspond(source, target, *, points=None, segment=None, rotation=False, outline=False,
               mesh_size=None, unmatched="grow", pairs=None, landmarks=None, always=False, meshes=None):
    """Make two drawings compatible: same vertices, connectivity and paths.

    Regions (outer ring and holes), unfilled rings and open polylines are
    paired by optimal assignment on normalised position, size and overlap;
    an item with no partner grows from (or shrinks to) a small transparent
    copy (``paint`` opacity 0, when the drawing has paint), a hole
    with no partner opens from (or closes to) a small ring inside its
    region. Every ring pair is then resampled to a common point count (best
    start and orientation), and each pair of filled regions becomes a pair of
    compatible triangle meshes (unless ``outline``).

    Parameters
    ----------
    source, target : Shape
        Drawings with paths (read from SVG, `Shape.from_polygon`,
        `Shape.from_polyline`, OBJ/JSON outlines). Shapes without ``regions``
        have their closed paths grouped into regions by the even-odd rule.
    points : int, optional
        Total number of vertices on all rings of the output outline, shared
        in proportion to length. Default: the larger total of the inputs.
    segment : float, optional
        Largest segment length instead: every ring gets enough points that
        no segment is longer (in both drawings). Not with ``points``.
    rotation : bool
        Kept for `correspond_keys` (several drawings): factor out rotation
        when choosing where each ring starts. Two drawings are always
        aligned as wholes, turn included (`alignment.align`).
    outline : bool
        Keep outlines only (no triangle meshes for filled regions).
    mesh_size : float, optional
        Target edge length of the meshes' interior triangles near the
        outline (inside, they grow with the distance from it). Default, per
        region: the larger of its source outline's mean spacing and 1/30 of
        the bounding-box diagonal of both drawings (a densely sampled
        drawing is not meshed more finely than that).
    unmatched : {'grow', 'split'}
        An item with no partner grows from (shrinks to) a small copy at its
        own centroid (``'grow'``), or splits off from (merges into) the
        nearest region of the other drawing, appearing from a small copy
        inside it (``'split'``).
    pairs : list of (int, int), optional
        Region pairs (source region, target region) to force; the other
        regions are paired by assignment.
    landmarks : list of ((x0, y0), (x1, y1)), optional
        Point pairs that must correspond: a point on (or near) an outline of
        the source and one on the paired outline of the target, like the
        shape hints of animation tools. Each is moved onto the nearest
        outline of its drawing; between landmarks, corners pair with corners
        as they do without them.
    always : bool
        Correspond even inputs that are compatible already (drawings whose
        point order means nothing). Default: those come back unchanged.
    meshes : MutableMapping, optional
        Region meshes kept between calls (a dict, or a mapping that forgets
        old entries): a region pair whose rings and mesh size come again
        takes its meshes from it (`region_key`), new ones are put in. An
        editor re-solving after a hint re-meshes only the regions it changed.

    Returns
    -------
    Correspondence
        ``(source, target, report)``: compatible shapes (with ``regions`` and
        ``paint``) and a `CorrespondenceReport` (``report.summary()`` is one
        line). An already compatible pair comes back unchanged.

    Raises
    ------
    IncompatibleShapesError
        A forced pair that cannot be made (naming the regions).
    ParameterError
        Bad options, or a mesh density whose triangle count (estimated from
        area / mesh_size^2 before meshing) would exceed `MAX_TRIANGLES`.
    ShapeError
        A shape without paths.
    """
    source, target = as_shape(source, "source"), as_shape(target, "target")
    _check_options(points, segment, unmatched, mesh_size)
    if not always and landmarks is None:
        try:
            check_compatible(source, target)
        except IsotweenError:
            pass
        else:
            return Correspondence(source, target, CorrespondenceReport(unchanged=True, unmatched=unmatched))
    shapes, report = _compatible_outlines([source, target], points, segment, rotation, unmatched, pairs,
                                          landmarks)
    if not outline:
        shapes = _solids(shapes, report, mesh_size, meshes)
    return Correspondence(shapes[0], shapes[1], report)


def mesh_outlines(source, target, report, *, mesh_size=None, meshes=None):
    """The meshing stage of `correspond`: an outline correspondence made into compatible meshes.

    ``correspond(a, b, **options)`` is ``mesh_outlines(*correspond(a, b, outline=True, **options))``
    with the same ``mesh_size`` and ``meshes``; an editor that shows the
    outline morph first meshes the same correspondence afterwards.

    Parameters
    ----------
    source, target : Shape
        Compatible outlines from ``correspond(..., outline=True)``.
    report : CorrespondenceReport
        Its report; not changed (the result's is a copy with the meshes added).
    mesh_size, meshes
        As in `correspond`.

    Returns
    -------
    Correspondence
    """
    report = copy.deepcopy(report)
    shapes = _solids([source, target], report, mesh_size, meshes)
    return Correspondence(shapes[0], shapes[1], report)


def region_key(source_rings, target_rings, mesh_size):
    """The key of a region pair's meshes in ``meshes`` of `correspond`: (digest of both rings, mesh size).

    Parameters
    ----------
    source_rings, target_rings : list of (k_i, 2) array_like
    mesh_size : float or None
    """
    digest = hashlib.blake2b(digest_size=16)
    for ring in (*source_rings, *target_rings):
        a = np.ascontiguousarray(ring, dtype=np.float64)
        digest.update(repr(a.shape).encode())
        digest.update(a.tobytes())
    return digest.hexdigest(), None if mesh_size is None else float(mesh_size)


def correspond_keys(shapes, *, points=None, segment=None, rotation=False, unmatched="grow", always=False):
    """Make several drawings (keyframes) compatible together, as outlines.

    Every drawing's items are paired with those of the first (an item of a
    later drawing with no partner is added to all others as a small copy),
    then all rings are resampled with one point count per ring. Options as
    in `correspond`; ``always``: compatible shapes too (drawings, whose
    point order means nothing), else they come back as they are.

    Returns
    -------
    shapes : list of Shape
        Compatible outline shapes (unchanged if they were compatible and not ``always``).
    report : CorrespondenceReport
    """
    shapes = [as_shape(s, f"keyframe {k}") for k, s in enumerate(shapes)]
    if len(shapes) < 2:
        raise ParameterError(f"give at least two keyframes, got {len(shapes)}")
    _check_options(points, segment, unmatched)
    try:
        check_compatible(*shapes, names=[f"keyframe {k}" for k in range(len(shapes))])
    except IsotweenError:
        pass
    else:
        if not always:
            return shapes, CorrespondenceReport(unchanged=True, keys=len(shapes), unmatched=unmatched)
    return _compatible_outlines(shapes, points, segment, rotation, unmatched, None)


# ---------------------------------------------------------------- outlines
def _check_options(points, segment, unmatched, mesh_size=None):
    """Raise `ParameterError` on a bad option, before any work."""
    if mesh_size is not None and not (isinstance(mesh_size, numbers.Real) and np.isfinite(mesh_size)
                                      and mesh_size > 0):
        raise ParameterError(f"mesh_size must be a positive length, got {mesh_size!r}")
    if unmatched not in ("grow", "split"):
        raise ParameterError(f"unmatched must be 'grow' or 'split', got {unmatched!r}")
    if points is not None and segment is not None:
        raise ParameterError("give points or segment, not both")
    if segment is not None and not (isinstance(segment, numbers.Real) and np.isfinite(segment) and segment > 0):
        raise ParameterError(f"segment must be a positive length, got {segment!r}")


def _compatible_outlines(shapes, points, segment, rotation, unmatched, pairs, landmarks=None):
    """Object correspondence and resampling of K drawings; (shapes, report)."""
    _check_options(points, segment, unmatched)
    names = ["source", "target"] if len(shapes) == 2 else [f"keyframe {k}" for k in range(len(shapes))]
    items = [_regions.items_of(s, n) for s, n in zip(shapes, names, strict=False)]
    frames = _regions.frames_of(items)
    if pairs is not None and len(shapes) != 2:
        raise ParameterError("pairs are for two drawings")
    turn, slits, cut, strokes_cut = None, [], [], []
    if len(shapes) == 2:
        frames, turn = align(items, frames)
        if pairs is None:  # region pairs given by index: the regions stay as drawn
            items, cut = split_regions(items, frames)
            items, strokes_cut = split_strokes(items, frames)
        items, slits = open_holes(items, frames)
    slots = _regions.plan(items, frames, pairs)
    per_key, closed, paint, layout, tiny = _fill_slots(items, frames, slots, unmatched)
    if landmarks is not None and len(shapes) != 2:
        raise ParameterError("landmarks are for two drawings")
    if len(shapes) == 2:
        hints = _landmark_anchors(landmarks, per_key, closed)
        rings = _matched_rings(per_key, closed, points, segment, turn, hints,
                               place=lambda v: frames[0].to(frames[1], v))
        counts = [len(r) for r in rings[0]]
    else:
        counts = _ring_counts(per_key, closed, points, segment)
        xy = [[np.c_[z.real, z.imag] for z in key] for key in per_key]
        rings = [None] * len(shapes)
        for k in range(1, len(shapes)):
            a, b = resample(xy[0], xy[k], points=counts, closed=closed, rotation=rotation, keep_turn=True)
            rings[0] = rings[0] or [a.z[idx] for idx, _ in a.paths]
            rings[k] = [b.z[idx] for idx, _ in b.paths]
    result = []
    regions = [rs for kind, rs in layout if kind == "region"]
    for k, (shape, key_rings) in enumerate(zip(shapes, rings, strict=True)):
        result.append(Shape.from_paths(key_rings, list(closed), y_down=shape.y_down, regions=regions,
                                       paint=paint[k]))
    report = CorrespondenceReport(keys=len(shapes), unmatched=unmatched, points=[int(c) for c in counts],
                                  hinted=landmarks is not None)
    _count_items(report, slots, len(shapes))
    report.vanishing = [[result[k].paths[r][0] for r in rings_k] for k, rings_k in enumerate(tiny)]
    report.slits = slits
    report.cut = cut
    report.strokes_cut = strokes_cut
    report.joined = _joined(items, slots, cut)
    return result, report


def _joined(items, slots, cut):
    """The output regions (indices in slot order) that are the parts of one region cut in a drawing."""
    regions = [s for s in slots if s.kind == "region"]
    out = []
    for k, n in enumerate(cut):
        parts = {}
        for r, s in enumerate(regions if n else []):
            if s.members[k] is not None:  # the parts of one region keep its index
                parts.setdefault(items[k][s.members[k]].index, []).append(r)
        out += [rs for rs in parts.values() if len(rs) > 1]
    return out


def _landmark_anchors(landmarks, per_key, closed):
    """Per ring, the anchor pairs (source parameter, target parameter) of the landmarks.

    Raises
    ------
    ParameterError
        A landmark that is not a pair of points, or a point far (over
        `LANDMARK_REACH` of the drawing's diagonal) from every outline.
    IncompatibleShapesError
        The two points of a landmark lie on outlines that do not correspond.
    """
    anchors = [[] for _ in closed]
    if landmarks is None:
        return anchors
    try:
        pts = np.asarray(landmarks, dtype=np.float64)
    except (TypeError, ValueError):
        pts = None
    if pts is None or pts.ndim != 3 or pts.shape[1:] != (2, 2) or not np.all(np.isfinite(pts)):
        raise ParameterError(f"landmarks must be a list of ((x0, y0), (x1, y1)) point pairs, got {landmarks!r}")
    for k, pair in enumerate(pts):
        found = []
        for side, key in enumerate(per_key):
            p = complex(*pair[side])
            every = np.concatenate(key)
            diagonal = abs(complex(np.ptp(every.real), np.ptp(every.imag)))
            hits = [project(z, c, p) for z, c in zip(key, closed, strict=True)]
            r = int(np.argmin([h[0] for h in hits]))
            if hits[r][0] > LANDMARK_REACH * diagonal:
                name = ("source", "target")[side]
                raise ParameterError(f"landmark {k}: the {name} point ({pair[side][0]:g}, {pair[side][1]:g}) is "
                                     f"{hits[r][0]:.3g} from the nearest outline of the {name}, more than "
                                     f"{LANDMARK_REACH:.0%} of its diagonal: it is not on the drawing")
            found.append((r, hits[r][1]))
        (r0, s0), (r1, s1) = found
        if r0 != r1:
            raise IncompatibleShapesError(f"landmark {k}: the source point is on outline {r0} but the target point "
                                          f"on outline {r1}, which does not correspond to it (pair the regions "
                                          "first, or move the point)")
        anchors[r0].append((s0, s1))
    return anchors


def _matched_rings(per_key, closed, points, segment, turn, anchors, place=None):
    """Rings of two drawings matched point for point, every input vertex kept (`matching.match_rings`).

    Edges longer than the drawing's outline length over ``points`` (default:
    the larger input's vertex count, at least `MIN_POINTS`), or than
    ``segment``, are split.
    """
    lengths = [sum(_Ring(z, c).length for z, c in zip(key, closed, strict=True)) for key in per_key]
    if segment is not None:
        spacing = (segment, segment)
    else:
        total = points if points is not None else max(MIN_POINTS, *(sum(len(z) for z in key) for key in per_key))
        spacing = (lengths[0] / total, lengths[1] / total)
    out = [[], []]
    for r, (z, w, c) in enumerate(zip(per_key[0], per_key[1], closed, strict=True)):
        reverse = None
        if c:
            reverse = bool(np.sign(_regions.ring_area(z)) != np.sign(_regions.ring_area(w)))
        try:
            pair = match_rings(z, w, c, turn=turn, spacing=spacing, reverse=reverse, anchors=anchors[r],
                               place=place)
        except IncompatibleShapesError as exc:
            raise IncompatibleShapesError(f"outline {r}: {exc}") from None
        out[0].append(pair.source)
        out[1].append(pair.target)
    return out


def _count_items(report, slots, K):
    for kind, target in (("region", report.regions), ("ring", report.rings), ("line", report.lines)):
        target.update(paired=0, grown=0, shrunk=0)
        for s in (s for s in slots if s.kind == kind):
            _tally(target, s.members)
    report.holes.update(paired=0, grown=0, shrunk=0)
    for s in slots:
        if s.kind == "region":
            for h in s.holes:
                _tally(report.holes, h)
            if K == 2 and None not in s.members:
                report.pairs.append(tuple(s.members))


def _tally(counts, members):
    if None not in members:
        counts["paired"] += 1
    elif members[0] is None:
        counts["grown"] += 1
    else:
        counts["shrunk"] += 1


def _fill_slots(items, frames, slots, unmatched):
    """Per drawing, the rings of every slot (real or small copies).

    Returns
    -------
    per_key : list (per drawing) of list of (k,) complex arrays
    closed : list of bool
        Per ring.
    paint : list (per drawing) of list of Paint, or of None
    layout : list of (kind, list of int)
        Per slot, its kind and ring indices in the flat ring list.
    """
    K = len(items)
    per_key = [[] for _ in range(K)]
    paints = [[] for _ in range(K)]
    closed, layout = [], []
    # the parts of a region cut in a drawing (`splits`) share its index: one with no partner (a plus's arm) merges
    # into the nearest region of the other drawing, as if it split off from it
    counts = [Counter(it.index for it in key if it.kind == "region") for key in items]
    parted = [{i for i, n in c.items() if n > 1} for c in counts]
    # regions first: small copies of other items may be placed inside them
    done, tiny_holes = {}, {}
    tiny = [[] for _ in range(K)]
    for si, slot in enumerate(slots):
        if slot.kind != "region":
            continue
        present = {}
        for k, m in enumerate(slot.members):
            if m is None:
                continue
            item = items[k][m]
            rings, paint = [item.rings[0]], [item.paint[0]]
            poly = _regions.region_polygon(item.rings)
            for hs in slot.holes:
                if hs[k] is not None:
                    rings.append(item.rings[hs[k]])
                    paint.append(item.paint[hs[k]])
                else:  # a hole this drawing lacks: a small ring inside the region
                    tiny_holes.setdefault(si, []).append((k, len(rings)))
                    ref = next(j for j, h in enumerate(hs) if h is not None)
                    ref_item = items[ref][slot.members[ref]]
                    hole = ref_item.rings[hs[ref]]
                    f_ref = _regions.Frame.of(ref_item.rings[0], frames[ref].turn)
                    f_k = _regions.Frame.of(item.rings[0], frames[k].turn)
                    at = f_ref.to(f_k, _regions.centroid(hole, True))
                    radius = _regions.TINY * float(np.abs(hole - _regions.centroid(hole, True)).max())
                    at, room = _regions.inside_point(poly, at, radius)
                    copy = _regions.small_copy([hole], True, at, room)[0]
                    rings.append(copy)
                    paint.append(item.paint[0])
                    # the next small hole keeps clear of this one (where both fall back to the same spot)
                    poly = poly.difference(_regions.region_polygon([copy]).buffer(float(np.abs(copy - at).max())))
            present[k] = (rings, paint, poly)
        done[si] = present
    polys = [[(si, p[k][2]) for si, p in done.items() if k in p] for k in range(K)]
    nests = [None] * K  # per drawing, the hole round each item (`regions.containers`), once asked
    room = {}  # (drawing, region slot, hole): the part of that hole that no small copy placed in it takes
    for si, slot in enumerate(slots):
        is_closed = slot.kind != "line"
        if slot.kind == "region":
            present = {k: v[:2] for k, v in done[si].items()}
        else:
            present = {k: ([items[k][m].rings[0]], [items[k][m].paint[0]])
                       for k, m in enumerate(slot.members) if m is not None}
            if slot.kind == "line":  # closed strokes paired with open ones are cut open
                k_line = next(k for k, m in enumerate(slot.members) if m is not None and items[k][m].kind == "line")
                start_point = items[k_line][slot.members[k_line]].rings[0][0]
                for k, (rings, paint) in present.items():
                    if items[k][slot.members[k]].kind == "ring":
                        present[k] = ([_opened(rings[0], frames[k_line].to(frames[k], start_point))], paint)
        ref = min(present)
        ref_rings, ref_paint = present[ref]
        start = len(closed)
        for k, r in tiny_holes.get(si, []):
            tiny[k].append(start + r)
        for k in range(K):
            if k in present:
                rings, paint = present[k]
            else:
                tiny[k] += list(range(start, start + len(ref_rings)))
                strokes = [items[k][m].rings[0] for kk in range(len(slots)) if slots[kk].kind != "region"
                           for m in [slots[kk].members[k]] if m is not None]
                if slot.kind != "region" and strokes:
                    # a stroke grows out of (shrinks into) the nearest stroke of the other drawing, drawn as it is
                    rings = _grown_from(ref_rings, is_closed, frames[ref], frames[k], strokes)
                    paint = list(ref_paint)
                else:
                    part = slot.kind == "region" and items[ref][slot.members[ref]].index in parted[ref]
                    nests[ref] = nests[ref] or _regions.containers(items[ref])
                    paired = _paired_hole(nests[ref][slot.members[ref]], slots, ref, k)
                    key = None if paired is None else (k, *paired)
                    if key is not None and key not in room:
                        room[key] = _regions.region_polygon([done[paired[0]][k][0][1 + paired[1]]])
                    free = room.get(key)
                    free = None if free is None or free.is_empty else free
                    over = [p for j, p in polys[ref] if j != si] if slot.kind == "region" else []
                    rings = _placed_copy(ref_rings, is_closed, frames[ref], frames[k], polys[k],
                                         "split" if part else unmatched, free, over)
                    if key is not None:  # the next small copy in this hole keeps clear of this one
                        at = rings[0].mean()
                        clear = _regions.region_polygon([at + 2 * (rings[0] - at)]).convex_hull
                        room[key] = room[key].difference(clear)
                    # the small copy is also transparent: the item fades in (out) as it grows (shrinks)
                    paint = [None if p is None else replace(p, opacity=0.0) for p in ref_paint]
            per_key[k] += rings
            paints[k] += paint
        closed += [is_closed] * len(ref_rings)
        layout.append((slot.kind, list(range(start, len(closed)))))
    paints = [None if any(p is None for p in key) else key for key in paints]
    return per_key, closed, paints, layout, tiny


def _grown_from(rings, closed, f_from, f_to, strokes):
    """Small copy of a stroke's rings at the point of ``strokes`` (the other drawing's) nearest its centroid.

    Where the strokes pass farther than `GROW_REACH` of the stroke's length
    from its centroid (a slash across the middle of a ring), at the centroid:
    it grows from its middle.
    """
    c = _regions.centroid(rings[0], closed)
    at = f_from.to(f_to, c)
    length = np.abs(np.diff(np.r_[rings[0], rings[0][:1]] if closed else rings[0])).sum()
    near = [project(z, False, at) for z in strokes]  # (distance, arc parameter) on each, as an open line
    j = int(np.argmin([d for d, _ in near]))
    if near[j][0] <= GROW_REACH * length * abs(f_from.factor(f_to)):
        at = points_at(strokes[j], False, near[j][1])
    scaled = [at + (z - c) * f_from.factor(f_to) for z in rings]
    return _regions.small_copy(scaled, closed, at)


def _opened(ring, near):
    """A closed ring as an open polyline from its vertex nearest ``near`` round to that vertex again."""
    k = int(np.argmin(np.abs(ring - near)))
    z = np.roll(ring, -k)
    return np.append(z, z[0])


def _paired_hole(around, slots, ref, k):
    """(region slot, hole slot) of the hole of drawing k paired with ``around``, or None.

    ``around``: (region item, ring) of the hole of drawing ``ref`` that an item
    lies in (`regions.containers`), or None. None where that region or hole
    has no partner in drawing k.
    """
    if around is None:
        return None
    owner, ring = around
    for si, slot in enumerate(slots):
        if slot.kind == "region" and slot.members[ref] == owner and slot.members[k] is not None:
            j = next((j for j, hs in enumerate(slot.holes) if hs[ref] == ring and hs[k] is not None), None)
            return None if j is None else (si, j)
    return None


def _over_fill(rings, polygons):
    """Whether the region of ``rings`` lies over the fill of ``polygons`` (all but `OVER_FILL` of its area)."""
    if not polygons:
        return False
    import shapely

    own = _regions.region_polygon(rings)
    return own.area > 0 and own.difference(shapely.unary_union(polygons)).area <= OVER_FILL * own.area


def _placed_copy(rings, closed, f_from, f_to, polygons, unmatched, hole=None, over=()):
    """Small copy of an item's rings in another drawing.

    ``grow``: at its own centroid (mapped into the other drawing's box), moved
    just outside the other drawing's filled regions if it falls inside one,
    so that it does not cross them on its way; unless the item lies over the
    fill of ``over`` (the other regions of its own drawing, shapely polygons:
    a tear or a highlight painted over a face, `_over_fill`): then it grows in
    place over the fill it falls in. Where the item lies in a hole
    whose partner in the other drawing leaves ``hole`` free (a shapely
    polygon), inside that instead: it stays in the hole on its way.
    ``split``: inside the nearest region of the other drawing, as if it split
    off from (merged into) it.
    """
    c = _regions.centroid(rings[0], closed)
    at = f_from.to(f_to, c)
    scaled = [at + (z - c) * f_from.factor(f_to) for z in rings]
    radius = _regions.TINY * float(np.abs(np.concatenate(scaled) - at).max())
    if unmatched != "split" and hole is not None:
        at, room = _regions.inside_point(hole, at, radius)
        return _regions.small_copy(scaled, closed, at, room)
    if not polygons:
        return _regions.small_copy(scaled, closed, at)
    import shapely
    from shapely.ops import nearest_points

    point = shapely.Point(at.real, at.imag)
    if unmatched == "split":
        _, poly = min(polygons, key=lambda sp: sp[1].distance(point))
        at, room = _regions.inside_point(poly, at, radius)
        return _regions.small_copy(scaled, closed, at, room)
    fill = shapely.unary_union([p for _, p in polygons])
    if fill.contains(point) and _over_fill(rings, over):
        at, room = _regions.inside_point(fill, at, radius)
        return _regions.small_copy(scaled, closed, at, room)
    if fill.distance(point) < 2 * radius:
        q = nearest_points(fill.buffer(3 * radius).boundary, point)[0]
        at = complex(q.x, q.y)
    return _regions.small_copy(scaled, closed, at)


def _ring_counts(per_key, closed, points, segment):
    """Points per ring: the total shared by length, or from the largest segment."""
    rings = [[(z, c) for z, c in zip(key, closed, strict=False)] for key in per_key]
    if segment is None:
        return _counts(points, *rings)
    need = np.array([3 if c else 2 for c in closed])
    lengths = np.array([[_Ring(z, c).length for z, c in key] for key in rings])
    return np.maximum(np.ceil(lengths.max(axis=0) / segment - 1e-9).astype(np.int64), need)


# ---------------------------------------------------------------- solids
def _path_of(paths, idx):
    """The index of the path whose vertex indices are ``idx``."""
    return next(p for p, (v, _) in enumerate(paths) if len(v) == len(idx) and v[0] == idx[0])



def _by_the_outline(source_rings, target_rings, small):
    """The rings of a region pair with its small hole copies moved next to the outline where their holes lie.

    Parameters
    ----------
    source_rings, target_rings : list of (k_i, 2) arrays
        Outer ring first, then holes; vertex i of one corresponding to vertex i of the other.
    small : two lists of int
        Per drawing, the holes it draws as small copies of the other's.

    Returns
    -------
    source_rings, target_rings
        The same, each small copy moved (and shrunk where it needs to be) to the material next to the
        outer ring's vertex that lies nearest its hole in the other drawing: a cut from it to that vertex
        is short in both drawings.
    """
    import shapely
    from shapely.ops import nearest_points

    rings = [[r[:, 0] + 1j * r[:, 1] for r in source_rings], [r[:, 0] + 1j * r[:, 1] for r in target_rings]]
    for k in (0, 1):
        for h in small[k]:
            hole = rings[1 - k][h]
            j = int(np.argmin(np.abs(rings[1 - k][0] - _regions.centroid(hole, True))))
            copy = rings[k][h]
            c = _regions.centroid(copy, True)
            radius = float(np.abs(copy - c).max())
            poly = _regions.region_polygon([r for i, r in enumerate(rings[k]) if i not in small[k] or i < h])
            near = rings[k][0][j]
            inner = poly.buffer(-3 * radius)  # three of its radii in from the outline
            if not inner.is_empty:
                q = nearest_points(inner, shapely.Point(near.real, near.imag))[0]
                near = complex(q.x, q.y)
            at, room = _regions.inside_point(poly, near, radius)
            rings[k][h] = at + (copy - c) * min(1.0, 0.5 * room / max(radius, 1e-300))
    return tuple([np.c_[r.real, r.imag] for r in drawing] for drawing in rings)


def _mesh_region(source_rings, target_rings, mesh_size, slide=True):
    """Compatible triangle meshes of one region pair.

    Parameters
    ----------
    source_rings, target_rings : list of (k_i, 2) arrays
        Outer ring first, then holes; same counts, vertex i corresponding.
    mesh_size : float or None
        Target edge length.
    slide : bool
        Where the map is a bend, slide the source points along the outline
        (`slide.slid_rings`) and mesh again.

    Returns
    -------
    source, target : Shape
        Same faces; the ring vertices first, in order, then interior vertices.
    flipped : int
        Target triangles whose orientation differs from the source's.
    slid : bool
        The source points were slid.
    """
    from .compatible_mesh import compatible_meshes
    from .slide import slid_rings

    src, tgt, _ = compatible_meshes(source_rings, target_rings, mesh_size=mesh_size)
    ends = np.cumsum([0] + [len(r) for r in source_rings])
    rings = [np.arange(a, b) for a, b in zip(ends[:-1], ends[1:], strict=True)]
    moved = slid_rings(src.z, tgt.z, src.faces, rings) if slide else None
    if moved is not None:
        try:
            src, tgt, _ = compatible_meshes([np.c_[moved[r].real, moved[r].imag] for r in rings], target_rings,
                                            mesh_size=mesh_size)
        except ShapeError:  # (the slid rings too close to degenerate: the arc-length match stays)
            moved = None
    return src, tgt, int(np.count_nonzero(np.sign(src.face_areas()) != np.sign(tgt.face_areas()))), moved is not None


def _solids(shapes, report, mesh_size, meshes=None):
    """Replace every region pair of a compatible outline pair by compatible meshes (``meshes``: see `correspond`)."""
    src, tgt = shapes
    if not src.regions:
        return shapes
    if mesh_size is not None:
        area = sum(max(abs(_regions.ring_area(s.z[s.paths[r[0]][0]])) for s in shapes) for r in src.regions)
        estimate = area / (np.sqrt(3) / 4 * mesh_size**2)
        if estimate > MAX_TRIANGLES:
            raise ResourceError(
                f"mesh_size={mesh_size:g} would make about {estimate:.3g} triangles "
                f"(limit {MAX_TRIANGLES:.3g}); choose a mesh size of at least "
                f"{mesh_size * np.sqrt(estimate / MAX_TRIANGLES):.3g}"
            )
    in_region = {p for r in src.regions for p in r}
    blocks, paths, regions = [], [], []
    offset = 0

    def ring_xy(shape, p):
        return shape.vertices[shape.paths[p][0]]

    both = np.vstack([src.vertices, tgt.vertices])
    starts = [{int(v[0]) for v in gone} for gone in report.vanishing[:2]]  # first vertex of each small copy
    coarsest = MESH_FRACTION * bbox_diagonal(both)
    for r in src.regions:
        rs, rt = [ring_xy(src, p) for p in r], [ring_xy(tgt, p) for p in r]
        size = mesh_size
        if size is None:
            spacing = np.mean(np.concatenate([np.hypot(*(np.roll(x, -1, axis=0) - x).T) for x in rs]))
            size = max(float(spacing), coarsest)
        key = None if meshes is None else region_key(rs, rt, size)
        small = [[i for i, p in enumerate(r) if i and int(src.paths[p][0][0]) in gone]  # the region's holes
                 for gone in starts]  # that one drawing draws as small copies
        try:
            if key is not None and key in meshes:
                ms, mt, flipped, slid = meshes[key]
            else:
                try:
                    ms, mt, flipped, slid = _mesh_region(rs, rt, size, slide=not report.hinted)
                except ShapeError:
                    if not any(small):
                        raise
                    # e.g. no straight cuts join a hole inside both drawings: small copies placed afresh,
                    # by the part of the outline nearest to their hole in the other drawing
                    rs, rt = _by_the_outline(rs, rt, small)
                    ms, mt, flipped, slid = _mesh_region(rs, rt, size, slide=not report.hinted)
                if key is not None:
                    meshes[key] = (ms, mt, flipped, slid)
        except (ShapeError, IncompatibleShapesError) as exc:
            report.outlines.append(f"region {len(regions)}: {exc}")
            ms, mt, flipped = Shape.from_polygon(rs), Shape.from_polygon(rt), 0
        else:
            report.meshes.append((ms.n_vertices, ms.n_faces))
            report.flipped += flipped
            report.slid += slid
        sizes = np.cumsum([0] + [len(x) for x in rs])
        regions.append(list(range(len(paths), len(paths) + len(r))))
        paths += [(offset + np.arange(sizes[i], sizes[i + 1]), True) for i in range(len(r))]
        blocks.append((ms.vertices, mt.vertices, ms.edges + offset,
                       None if ms.faces is None else ms.faces + offset, r))
        offset += ms.n_vertices
    for p, (idx, c) in enumerate(src.paths):
        if p in in_region:
            continue
        k = len(idx)
        local = np.arange(k)
        e = np.column_stack([local, np.roll(local, -1)] if c else [local[:-1], local[1:]])
        paths.append((offset + local, c))
        blocks.append((src.vertices[idx], tgt.vertices[idx], e + offset, None, [p]))
        offset += k
    order = [p for b in blocks for p in b[4]]
    new_index = {p: q for q, p in enumerate(order)}
    old_paths = src.paths
    report.vanishing = [[paths[new_index[_path_of(old_paths, idx)]][0] for idx in key] for key in report.vanishing]
    edges = np.vstack([b[2] for b in blocks])
    faces = [b[3] for b in blocks if b[3] is not None]
    faces = np.vstack(faces) if faces else None
    out = []
    for k, shape in enumerate(shapes):
        v = np.vstack([b[k] for b in blocks])
        paint = None if shape.paint is None else [shape.paint[p] for p in order]
        out.append(Shape(v, edges, faces=faces, paths=paths, y_down=shape.y_down, regions=regions,
                         paint=paint))
    return out
