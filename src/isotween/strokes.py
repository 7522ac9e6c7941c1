"""Strokes that would pass through each other are drawn off and on instead.

Stroked paths (polylines and unfilled rings) have no mesh around them, so
nothing keeps two of them from passing through each other when they morph
(a bar turning over into a line across a frame, a grown stroke sweeping
across another). Where that happens in an in-between frame and the two
do not cross in either drawing, `untangle` changes the motion of one of
them at a time, the one in most such crossings (of two, the one that moves
farther): its source stroke is drawn
off (it retracts along itself back to its first point, fading at the last) within
the first ``share`` of the morph, and its target stroke is drawn on
(it extends along itself from its first point) within the last, as line
art is drawn on the web. A stroke drawn off or on only covers where it is
in its drawing, so it can only meet what moves across it; the changes stop
when no such crossing is left or no stroke is left to change, the version
with the fewest crossings is kept, and a changed stroke whose change the
others made needless morphs again. Several strokes so changed take turns
where that makes no more crossings (their switches spread over `SPREAD` of
the morph, else half that, in drawing order), so that the drawing does not
empty half way; where it would all but empty still (less than `ON_VIEW` of
its length on view), the longest of them morph again, crossings and all.
"""

import numpy as np

from .metrics import path_crossings
from .paint import Paint, half_widths, key_paint, out_of_sight, paint_at

__all__ = ["drawn", "untangle", "stroke_paths", "FADE"]

#: share of a stroke's time drawn off (on) in which it also fades out (in): its last moments, a dot
FADE = 0.25
#: share of the morph over which the switches of several strokes drawn off and on are spread
SPREAD = 0.4
#: strokes drawn off and on keep at least this share of the drawing's length on view (the smaller end's)
ON_VIEW = 0.15


def drawn(z, u, closed=False):
    """A stroke drawn up to a share of its length, the rest of its vertices at the tip.

    Parameters
    ----------
    z : (k,) complex
        The stroke's vertices.
    u : (F,) float
        Share of its length drawn, in [0, 1], per frame.
    closed : bool
        A ring: its first half of vertices go round it at every other vertex
        and the second half come back the same way, so the undrawn rest is
        never a chord from the tip back to the start (where nothing is drawn
        yet, the ring's closing edge would be one).

    Returns
    -------
    (F, k) complex
        Vertex positions per frame: exactly ``z`` where ``u`` is 1 (for an
        open stroke; a ring covers itself at every other vertex there),
        every vertex at ``z[0]`` where it is 0.
    """
    u = np.clip(np.asarray(u, dtype=np.float64), 0.0, 1.0)
    k = len(z)
    w = np.r_[z, z[:1]] if closed else z
    s = np.r_[0.0, np.cumsum(np.abs(np.diff(w)))]  # arc length at each vertex of the path drawn
    if closed:  # out along the even vertices, back along them
        i = np.arange(k)
        sigma = s[np.minimum(2 * i, 2 * (k - i))]
    else:
        sigma = s
    at = np.minimum(sigma[None, :], u[:, None] * s[-1])  # (F, k) arc length of every vertex
    return np.interp(at, s, w.real) + 1j * np.interp(at, s, w.imag)


def _length(z, closed):
    """Length of a polyline (closed: round the ring) of complex points ``z``."""
    return float(np.abs(np.diff(np.r_[z, z[:1]] if closed else z)).sum())


def stroke_paths(shape):
    """Indices of the paths that are strokes: open ones, and closed ones in no filled region."""
    paths = shape.paths or []
    filled = {i for r in (shape.regions or []) for i in r}
    paint = shape.paint
    out = []
    for k, (idx, closed) in enumerate(paths):
        if len(idx) < 2 or k in filled:
            continue
        if closed and (shape.regions is None or (paint is not None and paint[k].fill is not None)):
            continue
        out.append(k)
    return out


class _Swaps:
    """The sequence's frames and paint with a set of strokes drawn off and on; their crossings."""

    def __init__(self, seq, vanishing, share):
        self.seq, self.share = seq, share
        self.spread = 0.0  # `SPREAD` once the strokes take turns
        self.z = seq.frames[..., 0] + 1j * seq.frames[..., 1]
        self.t = np.asarray(seq.times, dtype=np.float64)
        shape = seq.shape
        self.absent = [set(), set()]  # paths that are small copies at the start, at the end
        first = {int(p[0]): k for k, (p, _) in enumerate(shape.paths) if len(p)}
        for end, rings in enumerate(vanishing[:2]):
            self.absent[end] = {first[int(idx[0])] for idx in rings if int(idx[0]) in first}
        keyed = key_paint(seq)
        self.keys = None if keyed is None else keyed[1:]  # (key times, keys)
        self.out_of_sight = out_of_sight(seq)
        self.reach = half_widths(seq)  # a stroke's end under its own stroke on another path meets it (a T)

    def schedule(self, swapped):
        """Per swapped path: (a, b, h), drawn off within (a - h, a) and on within (b, b + h).

        All at once: off within the first share of the morph, on within the
        last. Taking turns (``spread``): the paths in drawing order, their
        switches spread evenly over ``spread`` of the morph round its middle,
        each as long as its place allows, so that some strokes are on view at
        every moment.
        """
        a, b = self.share, 1.0 - self.share
        order = sorted(swapped)
        spread = min(self.spread, a)  # each one drawn off after 0 and on before 1
        lead = np.linspace(-0.5, 0.5, len(order)) * spread if len(order) > 1 else np.zeros(len(order))
        return {p: (a + d, b + d, min(a, a + d, 1.0 - b - d)) for p, d in zip(order, lead, strict=True)}

    def hidden(self, swapped):
        """(F, P) bool: paths drawn with opacity 0 in each frame."""
        out = self.out_of_sight.copy()
        for p, (a, b, _) in self.schedule(swapped).items():
            out[:, p] = ((self.t >= a) & (self.t <= b)) | ((self.t < a) & (p in self.absent[0])) \
                | ((self.t > b) & (p in self.absent[1]))
            out[0, p] = p in self.absent[0]
            out[-1, p] = p in self.absent[1]
        return out

    def on_view(self, swapped):
        """The least length of all paths on view in an in-between over the smaller end's, with ``swapped`` changed."""
        z, hidden = self.frames(swapped), self.hidden(swapped)
        ink = np.zeros(len(z))
        for k, (idx, closed) in enumerate(self.seq.shape.paths):
            w = z[:, np.r_[idx, idx[:1]]] if closed else z[:, idx]
            ink += np.abs(np.diff(w, axis=1)).sum(axis=1) * ~hidden[:, k]
        return float(ink[1:-1].min() / max(min(ink[0], ink[-1]), 1e-300))

    def frames(self, swapped):
        """(F, n) complex frames with the ``swapped`` paths drawn off and on."""
        z = self.z.copy()
        for p, (a, b, h) in self.schedule(swapped).items():
            idx = self.seq.shape.paths[p][0]
            start, end = self.z[0, idx], self.z[-1, idx]
            closed = self.seq.shape.paths[p][1]
            off = drawn(start, (a - self.t) / h, closed)
            on = drawn(end, (self.t - b) / h, closed)
            if p in self.absent[0]:  # nothing to draw off: it waits, one point, where it is drawn on
                off = np.broadcast_to(end[0], off.shape)
            if p in self.absent[1]:  # nothing to draw on: it stays, one point, where it was drawn off
                on = np.broadcast_to(start[0], on.shape)
            rest = start[0] if p in self.absent[1] else end[0]  # out of sight between the two
            z[:, idx] = np.where((self.t <= a)[:, None], off, np.where((self.t >= b)[:, None], on, rest))
            z[0, idx], z[-1, idx] = start, end
        return z

    def crossings(self, swapped):
        """(P,) crossings per path, in the in-betweens, between paths that do not cross in either drawing."""
        _, p, q = path_crossings(self.seq.shape, self.frames(swapped), self.hidden(swapped), new=True,
                                 reach=self.reach)
        return np.bincount(np.r_[p, q], minlength=len(self.seq.shape.paths))

    def paint(self, swapped):
        """``seq.info['paint']`` with the ``swapped`` paths out of sight while neither drawn off nor on.

        A stroke keeps its paint as it is drawn off and fades out in the last
        `FADE` of that, where it is only a dot (its caps); it fades in the same
        way as it is drawn on.
        """
        key_times, keys = self.keys
        plan = self.schedule(swapped)
        times = np.unique(np.r_[key_times, np.ravel([[a - h * FADE, a, b, b + h * FADE] for a, b, h in plan.values()])])
        new = paint_at(key_times, keys, times)
        for p, (a, b, h) in plan.items():
            start, end = keys[0][p], keys[-1][p]
            for k, t in enumerate(times):
                was = start if t <= a else end
                seen = np.clip(max((a - t) / (h * FADE), (t - b) / (h * FADE)), 0.0, 1.0)
                if (p in self.absent[0] and t < b) or (p in self.absent[1] and t > a):
                    seen = 0.0  # a stroke the drawing lacks: one point, out of sight
                elif t <= 0.0 or t >= 1.0:
                    continue  # the drawing's own paint
                new[k][p] = Paint.from_dict({**was.to_dict(), "opacity": was.opacity * float(seen)})
        info = dict((self.seq.info or {}).get("paint") or {})
        info["times"] = [float(t) for t in times]
        info["keys"] = [[p.to_dict() for p in key] for key in new]
        info.setdefault("regions", self.seq.shape.regions)
        return info


def untangle(seq, report, share=0.5):
    """Draw off and on, instead of morphing, the strokes that would pass through other paths.

    Parameters
    ----------
    seq : Sequence
        A morph of corresponded drawings; changed in place (frames, paint,
        and ``info['strokes']``, a line saying which strokes were drawn off and on).
    report : CorrespondenceReport or None
        Its ``vanishing`` rings say which strokes are absent at an end.
    share : float
        In (0, 0.5]: a stroke is drawn off within this first share of the
        morph and drawn on within the last.

    Returns
    -------
    Sequence
        ``seq``.
    """
    shape = seq.shape
    candidates = stroke_paths(shape)
    if len(seq) < 3 or not candidates:
        return seq
    share = min(float(share), 0.5)
    swaps = _Swaps(seq, getattr(report, "vanishing", None) or [], share)
    swapped, count = [], swaps.crossings([])
    best = (int(count.sum()), [])
    z = swaps.z
    travel = {k: float(np.abs(z[:, shape.paths[k][0]] - z[0, shape.paths[k][0]]).max()) for k in candidates}
    while best[0] and len(swapped) < len(candidates):
        free = [k for k in candidates if k not in swapped]
        worst = max(free, key=lambda k: (count[k], travel[k]))  # of two in as many crossings, the one that moves
        if not count[worst]:
            break
        swapped.append(worst)
        count = swaps.crossings(swapped)
        if int(count.sum()) < best[0]:
            best = (int(count.sum()), list(swapped))
    left, chosen = best
    for k in list(chosen):  # one that others' changes made needless morphs again
        fewer = [c for c in chosen if c != k]
        n = int(swaps.crossings(fewer).sum())
        if n <= left:
            left, chosen = n, fewer
    if not chosen:
        return seq
    for spread in (SPREAD, 0.5 * SPREAD, 0.0):  # taking turns, where that makes no more crossings
        swaps.spread = spread
        if not spread or int(swaps.crossings(chosen).sum()) <= left:
            break
    while chosen and swaps.on_view(chosen) < ON_VIEW:  # the drawing would all but empty: the longest morphs again
        chosen.remove(max(chosen, key=lambda k: _length(z[0, shape.paths[k][0]], shape.paths[k][1])
                          + _length(z[-1, shape.paths[k][0]], shape.paths[k][1])))
        left = int(swaps.crossings(chosen).sum())
    if not chosen:
        return seq
    z = swaps.frames(chosen)
    seq.frames[...] = np.stack([z.real, z.imag], axis=-1)
    if swaps.keys is not None:
        seq.info["paint"] = swaps.paint(chosen)
    seq.info["strokes"] = (f"{len(chosen)} of {len(candidates)} strokes drawn off and on instead of passing through "
                           f"other paths" + (f"; {left} crossings left" if left else ""))
    return seq
