"""Paint of a drawing: fill, stroke, opacity and stroke width per path.

A `Shape` read from SVG carries one `Paint` per entry of its ``paths`` (holes
repeat the paint of their region). Colours are straight (not premultiplied)
sRGB in [0, 1]; in-between colours are blended in Oklab (Ottosson 2020), a
perceptual space in which a straight line between two colours looks even.
"""

from dataclasses import dataclass, replace

import numpy as np

from .errors import ParameterError

__all__ = ["Paint", "DEFAULT_FILL", "drawn_groups", "joined_groups", "lerp_paint", "srgb_to_oklab", "oklab_to_srgb",
           "paint_keys", "sequence_paint", "key_paint", "paint_at", "out_of_sight", "half_widths", "paint_groups",
           "merge_groups", "opaque", "svg_paint_attributes"]

#: SVG's initial fill: opaque black
DEFAULT_FILL = (0.0, 0.0, 0.0, 1.0)


def _rgba(value, what):
    if value is None:
        return None
    c = np.asarray(value, dtype=np.float64).ravel()
    if c.shape == (3,):
        c = np.append(c, 1.0)
    if c.shape != (4,) or not np.all(np.isfinite(c)) or np.any((c < 0) | (c > 1)):
        raise ParameterError(f"{what} must be an (r, g, b[, a]) colour with components in [0, 1], got {value!r}")
    return tuple(float(x) for x in c)


@dataclass(frozen=True)
class Paint:
    """How one path is drawn.

    Parameters
    ----------
    fill : (4,) tuple of float or None
        RGBA fill colour in [0, 1] (straight sRGB); None: not filled.
    stroke : (4,) tuple of float or None
        RGBA stroke colour; None: no stroke.
    stroke_width : float
        Stroke width in the shape's units.
    opacity : float
        Opacity of the whole path in [0, 1] (multiplies both alphas).
    """

    fill: tuple = DEFAULT_FILL
    stroke: tuple | None = None
    stroke_width: float = 1.0
    opacity: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "fill", _rgba(self.fill, "fill"))
        object.__setattr__(self, "stroke", _rgba(self.stroke, "stroke"))
        w, o = float(self.stroke_width), float(self.opacity)
        if not np.isfinite(w) or w < 0:
            raise ParameterError(f"stroke_width must be a finite number >= 0, got {self.stroke_width!r}")
        if not 0 <= o <= 1:
            raise ParameterError(f"opacity must be in [0, 1], got {self.opacity!r}")
        object.__setattr__(self, "stroke_width", w)
        object.__setattr__(self, "opacity", o)

    @property
    def filled(self):
        """Whether the path is filled (a closed region)."""
        return self.fill is not None

    def to_dict(self):
        """Plain JSON-ready form (colours as lists or None)."""
        return {
            "fill": None if self.fill is None else list(self.fill),
            "stroke": None if self.stroke is None else list(self.stroke),
            "stroke_width": self.stroke_width,
            "opacity": self.opacity,
        }

    @classmethod
    def from_dict(cls, data):
        """Inverse of `to_dict` (missing keys take the defaults)."""
        return cls(**{k: data[k] for k in ("fill", "stroke", "stroke_width", "opacity") if k in data})


# Oklab (Ottosson 2020): linear sRGB -> LMS -> cube root -> Lab
_M1 = np.array([[0.4122214708, 0.5363325363, 0.0514459929],
                [0.2119034982, 0.6806995451, 0.1073969566],
                [0.0883024619, 0.2817188376, 0.6299787005]])
_M2 = np.array([[0.2104542553, 0.7936177850, -0.0040720468],
                [1.9779984951, -2.4285922050, 0.4505937099],
                [0.0259040371, 0.7827717662, -0.8086757660]])


def _to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _to_gamma(c):
    c = np.clip(c, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)


def srgb_to_oklab(rgb):
    """(..., 3) sRGB in [0, 1] -> (..., 3) Oklab (L, a, b)."""
    return np.cbrt(_to_linear(np.asarray(rgb, dtype=np.float64)) @ _M1.T) @ _M2.T


def oklab_to_srgb(lab):
    """(..., 3) Oklab -> (..., 3) sRGB in [0, 1] (clipped to the gamut)."""
    lms = np.asarray(lab, dtype=np.float64) @ np.linalg.inv(_M2).T
    return _to_gamma((lms ** 3) @ np.linalg.inv(_M1).T)


def _lerp_colour(a, b, t):
    """(F,) times -> (F, 4) RGBA: Oklab for colour, linear for alpha; None fades in/out."""
    if a is None and b is None:
        return None
    a = (*b[:3], 0.0) if a is None else a
    b = (*a[:3], 0.0) if b is None else b
    t = np.asarray(t, dtype=np.float64)[:, None]
    lab = (1 - t) * srgb_to_oklab(a[:3]) + t * srgb_to_oklab(b[:3])
    alpha = (1 - t) * a[3] + t * b[3]
    return np.concatenate([oklab_to_srgb(lab), alpha], axis=1)


def lerp_paint(a, b, times):
    """Paint at each time between two paints.

    Parameters
    ----------
    a, b : Paint
        Paint at t = 0 and t = 1.
    times : (F,) array_like of float

    Returns
    -------
    list of Paint
        One per time; exact at t = 0 and t = 1. A colour present at one end
        only fades in (or out) through transparency.
    """
    times = np.asarray(times, dtype=np.float64)
    fill = _lerp_colour(a.fill, b.fill, times)
    stroke = _lerp_colour(a.stroke, b.stroke, times)
    width = (1 - times) * a.stroke_width + times * b.stroke_width
    opacity = (1 - times) * a.opacity + times * b.opacity
    out = []
    for k, t in enumerate(times):
        if t == 0:
            out.append(a)
        elif t == 1:
            out.append(b)
        else:
            out.append(replace(
                a,
                fill=None if fill is None else tuple(fill[k]),
                stroke=None if stroke is None else tuple(stroke[k]),
                stroke_width=width[k],
                opacity=opacity[k],
            ))
    return out


def paint_keys(shapes, times):
    """Paint of key shapes, JSON-ready, for ``Sequence.info['paint']``.

    Parameters
    ----------
    shapes : list of Shape
        Key shapes with the same paths (source and target, or keyframes).
    times : (K,) array_like of float
        Time of every key shape, increasing.

    Returns
    -------
    dict
        ``{'paint': {'times': [...], 'keys': [[paint dict per path] per key],
        'regions': regions}}``, or ``{}`` when no key shape has paint. A key
        shape without paint (or with another number of paths) takes the paint
        of the first one that has it.
    """
    painted = [s for s in shapes if s.paint is not None]
    if not painted:
        return {}
    base = painted[0]
    keys = [
        [p.to_dict() for p in (s.paint if s.paint is not None and len(s.paint) == len(base.paint) else base.paint)]
        for s in shapes
    ]
    return {"paint": {"times": [float(t) for t in times], "keys": keys, "regions": base.regions}}


def sequence_paint(seq):
    """Paint of every frame of a sequence, interpolated between its key shapes.

    The keys come from ``seq.info['paint']`` (see `paint_keys`; kept by
    sequence files), else the shape's own ``paint`` holds for every frame.
    Between two keys every path's paint is blended with `lerp_paint` (Oklab).

    Parameters
    ----------
    seq : Sequence

    Returns
    -------
    regions : list of list of int or None
        Filled regions (see `Shape`); None: every closed path, one region
        filled by the even-odd rule.
    paints : list of list of Paint, or None
        ``paints[k][p]`` is the paint of path ``p`` in frame ``k``; None when
        the sequence has no paint.
    """
    keyed = key_paint(seq)
    if keyed is None:
        return seq.shape.regions, None
    regions, key_times, keys = keyed
    return regions, paint_at(key_times, keys, seq.times)


def key_paint(seq):
    """A sequence's paint as keys, checked: ``(regions, key times (K,), keys)``, or None where it has no paint.

    ``keys[k][p]`` is the `Paint` of path ``p`` at ``key_times[k]``: those of
    ``seq.info['paint']`` (`paint_keys`), else the shape's own paint (one key).
    """
    info = (getattr(seq, "info", None) or {}).get("paint")
    shape = seq.shape
    if not info:
        if shape.paint is None:
            return None
        return shape.regions, np.array([0.0]), [list(shape.paint)]  # one key: the same paint throughout
    try:
        key_times = np.asarray(info["times"], dtype=np.float64)
        keys = [[Paint.from_dict(p) for p in key] for key in info["keys"]]
        regions = info.get("regions", shape.regions)
    except (KeyError, TypeError, ValueError) as exc:
        raise ParameterError(f"malformed paint in the sequence's info: {exc}") from None
    n_paths = len(shape.paths or [])
    if len(keys) != len(key_times) or not keys or any(len(k) != n_paths for k in keys):
        raise ParameterError(f"the sequence's paint must give one paint per path ({n_paths}) for each key time")
    return regions, key_times, keys


def paint_at(key_times, keys, times):
    """Every path's paint at ``times``, blended with `lerp_paint` between the keys around each.

    Parameters
    ----------
    key_times : (K,) float
        Increasing.
    keys : list (K) of list (P) of Paint
    times : (F,) array_like of float
        Clipped to the keys' times.

    Returns
    -------
    list (F) of list (P) of Paint
    """
    key_times = np.asarray(key_times, dtype=np.float64)
    times = np.clip(np.asarray(times, dtype=np.float64), key_times[0], key_times[-1])
    if len(keys) == 1:
        return [list(keys[0]) for _ in times]
    n_paths = len(keys[0])
    seg = np.clip(np.searchsorted(key_times, times, side="right") - 1, 0, len(key_times) - 2)
    out = [[None] * n_paths for _ in times]
    for s in np.unique(seg):
        frames = np.flatnonzero(seg == s)
        span = key_times[s + 1] - key_times[s]
        u = (times[frames] - key_times[s]) / span if span > 0 else np.ones(len(frames))
        for p in range(n_paths):
            for k, value in zip(frames, lerp_paint(keys[s][p], keys[s + 1][p], u), strict=False):
                out[k][p] = value
    return out


def out_of_sight(seq):
    """(F, P) bool: the paths drawn with opacity 0 in each frame (none where the sequence has no paint).

    Such a path (a piece faded out, or not yet in) cannot be seen to cross
    anything: `isotween.metrics.outline_crossings` (``visible=True``) and
    the fold check leave it out.
    """
    _, paints = sequence_paint(seq)
    n = len(seq.shape.paths or [])
    if paints is None:
        return np.zeros((len(seq), n), dtype=bool)
    return np.array([[p.opacity <= 0 for p in frame] for frame in paints], dtype=bool).reshape(len(seq), n)


def half_widths(seq):
    """(P,) float: half the least stroke width of every path over the sequence's keys (0 where it has no stroke).

    A stroke's centre line within this of another path lies under its own
    stroke there: `isotween.metrics.path_crossings` lets a stroke's end meet
    another path (a T) by this much.
    """
    keyed = key_paint(seq)
    n = len(seq.shape.paths or [])
    if keyed is None:
        return np.zeros(n)
    return np.array([0.5 * min(key[p].stroke_width if key[p].stroke is not None else 0.0 for key in keyed[2])
                     for p in range(n)], dtype=np.float64).reshape(n)


def paint_groups(shape):
    """What a painted shape draws, in order: ``(path indices, paint)`` groups.

    Each region (outer ring then holes, filled together by the even-odd rule)
    is one group; every path in no region is a group of its own. Without
    ``shape.regions`` all closed paths form one region. Groups come in the
    order of their first path (document order for shapes read from SVG); a
    group takes the paint of its first path.

    Parameters
    ----------
    shape : Shape
        With ``paths`` and ``paint``.

    Returns
    -------
    list of (list of int, Paint)
    """
    paths = shape.paths or []
    regions = shape.regions
    if regions is None:
        closed = [i for i, (_, c) in enumerate(paths) if c]
        regions = [closed] if closed else []
    used = {i for r in regions for i in r}
    groups = [list(r) for r in regions] + [[i] for i in range(len(paths)) if i not in used]
    groups.sort(key=min)
    return [(g, shape.paint[g[0]]) for g in groups]


def drawn_groups(shape, joined=()):
    """`paint_groups` with the parts of a cut region drawn as one group (`joined_groups`, in this one frame).

    Parameters
    ----------
    shape : Shape
        With ``paths``, ``regions`` and ``paint``.
    joined : list of list of int
        Region indices, the parts of one cut region each (``Sequence.info['joined']``).

    Returns
    -------
    list of (list of int, Paint)
    """
    groups = paint_groups(shape)
    if not joined or not shape.regions:
        return groups
    into = joined_groups([g[0] for g, _ in groups], shape.regions, [shape.paint], joined)
    merged, kept = merge_groups([g for g, _ in groups], into)
    return [(g, groups[k][1]) for g, k in zip(merged, kept, strict=True)]


def merge_groups(groups, into):
    """``groups`` (lists) with every group ``g`` in ``into`` appended to the one before it (`joined_groups`).

    Returns
    -------
    merged : list of list
    kept : list of int
        The index in ``groups`` of the first group of each merged one.
    """
    merged, kept = [], []
    for g, group in enumerate(groups):
        if g in into:
            merged[-1] = merged[-1] + list(group)
        else:
            merged.append(list(group))
            kept.append(g)
    return merged, kept


def opaque(paint):
    """Whether a paint fills opaquely and draws no stroke: painting it twice over looks as painting it once."""
    return paint.stroke is None and paint.fill is not None and paint.fill[3] * paint.opacity >= 1.0


def joined_groups(first, regions, paints, joined):
    """Which paint groups draw as one: the parts of a region cut where the other drawing parts it.

    The parts meet along the cut at their region's end; drawn as separate
    paths, anti-aliasing shows a seam there. They draw as one path where they
    come one after the other, each in the same opaque paint with no stroke
    in every frame, so that filling them together looks as painting each
    (by the even-odd rule, where parts overlap in an in-between, which they
    do by little if at all, the overlap is left out).

    Parameters
    ----------
    first : list of int
        The first path of every group (`paint_groups` order).
    regions : list of list of int
        The shape's regions (path indices).
    paints : list of list of Paint
        ``paints[k][p]``: the paint of path ``p`` in frame ``k``.
    joined : list of list of int
        Region indices, the parts of one cut region each
        (``Sequence.info['joined']``).

    Returns
    -------
    dict
        ``{group: the group it joins}`` for every group drawn with the one before it.
    """
    group_of = {r: first.index(paths[0]) for r, paths in enumerate(regions) if paths and paths[0] in first}
    into = {}
    for parts in joined:
        gs = sorted(group_of[r] for r in parts if r in group_of)
        if len(gs) < 2 or gs != list(range(gs[0], gs[0] + len(gs))):
            continue
        tracks = [[frame[first[g]] for frame in paints] for g in gs]
        if all(t == tracks[0] for t in tracks) and all(opaque(p) for p in tracks[0]):
            into.update({g: gs[0] for g in gs[1:]})
    return into


def _hex(colour):
    r, g, b = (int(round(255 * c)) for c in colour[:3])
    return f"#{r:02x}{g:02x}{b:02x}"


def svg_paint_attributes(paint):
    """SVG presentation attributes of a paint (stroke width in user units).

    Parameters
    ----------
    paint : Paint

    Returns
    -------
    dict
        ``fill``, ``fill-opacity``, ``stroke``, ``stroke-opacity``,
        ``stroke-width`` and ``opacity`` as strings (all six, so that they
        can be animated); the path opacity stays its own attribute, so a
        drawing reads back with the paint it was written with.
    """
    fill, stroke = paint.fill, paint.stroke
    return {
        "fill": "none" if fill is None else _hex(fill),
        "fill-opacity": "0" if fill is None else f"{fill[3]:.4g}",
        "stroke": "none" if stroke is None else _hex(stroke),
        "stroke-opacity": "0" if stroke is None else f"{stroke[3]:.4g}",
        "stroke-width": f"{paint.stroke_width:.6g}",
        "opacity": f"{paint.opacity:.4g}",
    }
