"""Alignment of two drawings as wholes: the rotation and scale that take one onto the other.

Candidates come from the two drawings' dominant rings (the outer ring of the
largest filled region, else the longest ring or polyline): every peak of
their circular cross-correlation (`matching.correlation`) is a similarity
``target ~ a (source - c_s) + c_t``; and from a coarse circle of turns about
the drawings' centroids (a round dominant ring shows no turn). The best
candidates are refined by iterative closest points. Each candidate, and the plain
bounding-box frames (no rotation), is scored on the drawings as wholes by the
mean distance between arc-length samples of all their rings and the nearest
samples of the other drawing (both ways); of turns that fit about as well
(`TIE`, a symmetric drawing's), the smallest counts. A rotation is used only when it
fits clearly better than no rotation (`GAIN`), so that drawings that do not
turn keep their places, and a symmetric drawing does not spin; nor where
the plain frames already put most of the source on the target (`KEPT`: a
toggle's frame, which a turn by 180 degrees would also fit, stays while its
knob slides). Without a turn, a shift is used where it puts most of the
source on the target (`_shifted`): the same object drawn in the middle of
canvases of different widths.
"""

import numpy as np

from .matching import SAMPLES, correlation, points_at
from .regions import Frame, ring_area

__all__ = ["align", "GAIN", "MIN_TURN", "COPY", "SMALL_TURN", "KEPT"]

#: a rotation is used when its fit distance is below this fraction of the unrotated fit's
GAIN = 0.5
#: nor unless the unrotated fit is off by at least this fraction of the diagonal (a symmetric drawing stays put)
VISIBLE = 0.005
#: a turn above `SMALL_TURN` is used only when the turned source lies this near (fit distance over the diagonal)
#: the target: a turned copy; two different drawings (a page and a folder) are not spun round to fit
COPY = 0.005
SMALL_TURN = np.deg2rad(20.0)
#: turns whose fit distance is within this fraction of the best one's fit as well (the smallest of them is used)
TIE = 0.05
#: rotations below this angle (radians) count as none
MIN_TURN = np.deg2rad(2.0)
#: candidate rotations tried (correlation peaks of the dominant rings)
CANDIDATES = 8
#: samples of a whole drawing for the fit distance
DRAWING_SAMPLES = 500
#: turns tried besides the correlation peaks (a coarse circle about the drawings' centroids)
GRID_TURNS = 24
#: every this many of the source's samples screen the candidates (all of them refine the best)
SCREEN = 4
#: best candidates refined by iterative closest points
REFINED = 4
#: rounds of iterative closest points
ICP_ROUNDS = 6
#: a shift of the source is used where it brings this share of its samples within `COPY` of the target's
KEPT = 0.6
#: rounds of iterative closest points (median offsets) for the shift, at most
SHIFT_ROUNDS = 20


def _dominant(items):
    """(ring (k,) complex, closed) that best shows a drawing's pose."""
    regions = [it for it in items if it.kind == "region"]
    if regions:
        best = max(regions, key=lambda it: abs(ring_area(it.rings[0])))
        return best.rings[0], True
    return max(((it.rings[0], it.kind != "line") for it in items),
               key=lambda rc: float(np.abs(np.diff(rc[0])).sum()))


def _samples(items, n=DRAWING_SAMPLES):
    """(m,) complex arc-length samples of every ring of a drawing, in proportion to length."""
    rings = [(r, it.kind != "line") for it in items for r in it.rings]
    lengths = np.array([np.abs(np.diff(np.append(r, r[0]) if c else r)).sum() for r, c in rings])
    counts = np.maximum(np.round(n * lengths / max(lengths.sum(), 1e-300)).astype(int), 2)
    return np.concatenate([points_at(r, c, np.arange(k) / k if c else np.linspace(0, 1, k))
                           for (r, c), k in zip(rings, counts, strict=True)])


class _Nearest:
    """Nearest of a few hundred points ``q`` (m,) complex to each of other points, by one matrix product.

    The drawings' samples are `DRAWING_SAMPLES` at most, so all distances at
    once cost about what a k-d tree's queries do, without loading
    ``scipy.spatial`` into a short command.
    """

    def __init__(self, q):
        self.q = -2.0 * np.c_[q.real, q.imag].T  # (2, m)
        self.q2 = 0.25 * np.einsum("ij,ij->j", self.q, self.q)
        self._out = np.empty((0, len(q)))  # reused: a fresh (n, m) array each query costs more than the product

    def query(self, x):
        """(n,) distances and (n,) indices of the nearest of ``q`` to each point of ``x`` (n,) complex."""
        xy = np.c_[x.real, x.imag]
        if len(self._out) < len(x):
            self._out = np.empty((len(x), self.q.shape[1]))
        d2 = np.matmul(xy, self.q, out=self._out[:len(x)])
        d2 += self.q2  # |x - q|^2 less |x|^2
        j = np.argmin(d2, axis=1)
        return np.sqrt(np.maximum(d2[np.arange(len(x)), j] + np.einsum("ij,ij->i", xy, xy), 0.0)), j


def _fit_distance(p, q, near_q, transform):
    """Mean nearest distance of transformed ``p`` to ``q`` and of ``q`` to transformed ``p``."""
    tp = transform(p)
    return 0.5 * (near_q.query(tp)[0].mean() + _Nearest(tp).query(q)[0].mean())


def align(items, frames):
    """Frames of two drawings with the rotation between them, when one is clear.

    Parameters
    ----------
    items : list of two lists of Item
        The source's and the target's items.
    frames : list of two Frame
        Their bounding-box frames (no rotation), from `regions.frames_of`.

    Returns
    -------
    frames : list of two Frame
        The given frames, or, when a rotation fits clearly better (and, if
        it turns by more than `SMALL_TURN`, the turned source is nearly the
        target: `COPY`), frames whose ``to`` is that similarity (the
        target's ``turn`` its rotation); else, where a shift puts most of
        the source on the target (`KEPT`), frames whose ``to`` shifts.
    turn : complex
        The rotation (unit complex) from source to target; 1 when none.
    """
    p, q = _samples(items[0]), _samples(items[1])
    near = _Nearest(q)
    diagonal = abs(complex(np.ptp(q.real), np.ptp(q.imag)))
    if _kept(p, near, frames, diagonal) >= KEPT:  # most of the drawing stays where it is: no turn
        return frames, 1.0 + 0j
    cands = []
    (z, closed), (w, closed_w) = _dominant(items[0]), _dominant(items[1])
    if closed and closed_w:
        if np.sign(ring_area(z)) != np.sign(ring_area(w)):
            w = np.roll(w[::-1], 1)
        grid = np.arange(SAMPLES) / SAMPLES
        x, y = points_at(z, True, grid), points_at(w, True, grid)
        rho = correlation(x, y)
        mag = np.abs(rho)
        peaks = np.flatnonzero((mag >= np.roll(mag, 1)) & (mag > np.roll(mag, -1)))
        peaks = peaks[np.argsort(mag[peaks])[::-1][:CANDIDATES]]
        xc, yc = x.mean(), y.mean()
        ratio = np.linalg.norm(y - yc) / max(np.linalg.norm(x - xc), 1e-300)
        cands = [(rho[k] * ratio, xc, yc) for k in peaks]
    plain = _fit_distance(p, q, near, lambda v: frames[0].to(frames[1], v))
    # candidates: the dominant rings' correlation peaks, and a coarse circle of turns about the samples' centroids
    pc, qc = p.mean(), q.mean()
    spread = np.sqrt(np.mean(np.abs(q - qc) ** 2) / max(np.mean(np.abs(p - pc) ** 2), 1e-300))
    cands += [(spread * np.exp(1j * th), pc, qc) for th in np.linspace(0, 2 * np.pi, GRID_TURNS, endpoint=False)]
    # screened one way (some samples of the source to the target's), the best refined and scored both ways
    few = p[::SCREEN]
    scored = sorted((float(near.query(tp)[0].mean()), i)
                    for i, tp in enumerate(d + a * (few - c) for a, c, d in cands))
    fits = []  # (distance, a, b) of the refined turns
    for _, i in scored[:REFINED]:
        a, c, d = cands[i]
        a, b = _icp(p, q, near, a, d - a * c)
        if abs(np.angle(a)) >= MIN_TURN:
            fits.append((_fit_distance(p, q, near, lambda v, a=a, b=b: a * v + b), a, b))
    best, best_a, best_b = np.inf, None, None
    if fits:  # of the turns that fit about as well as the best (a symmetric drawing's), the smallest
        least = min(f[0] for f in fits)
        best, best_a, best_b = min((f for f in fits if f[0] <= (1 + TIE) * least), key=lambda f: abs(np.angle(f[1])))
    if (best_a is None or not best < GAIN * plain or plain < VISIBLE * diagonal
            or (abs(np.angle(best_a)) > SMALL_TURN and best > COPY * diagonal)):  # a large turn only for a copy
        return _shifted(p, q, near, frames, diagonal), 1.0 + 0j
    return _similar(frames, best_a, best_b), best_a / abs(best_a)


def _similar(frames, a, b):
    """Frames whose ``to`` is the similarity ``v -> a v + b`` (the source's centre 0 maps to ``b``)."""
    scale = frames[0].scale
    return [Frame(0j, scale, 1.0 + 0j), Frame(b, scale * abs(a), a / abs(a))]


def _shifted(p, q, near, frames, diagonal):
    """The frames, shifted where a shift puts most of the source on the target (`KEPT`).

    Font Awesome's bell is 448 units wide and its struck-through bell 576, the
    bell drawn in the middle of each: in place, the bells lie 64 units apart,
    and the struck-through bell's parts fall across the bell's edge. The
    shift is found by iterative closest points both ways, each round moving
    by the median offset (the slash, which has no counterpart, does not pull
    it); it is used where it brings at least `KEPT` of the source's samples
    within `COPY` of the target's, and the plain frames do not.
    """
    a, b = frames[0].factor(frames[1]), frames[0].to(frames[1], 0j)
    shift, few, few_q = 0j, p[::SCREEN], q[::SCREEN]  # found on every `SCREEN`th sample of each
    near_few = _Nearest(few_q)
    for _ in range(SHIFT_ROUNDS):
        tp = a * few + b + shift
        _, j = near_few.query(tp)
        _, i = _Nearest(tp).query(few_q)
        step = np.r_[few_q[j] - tp, few_q - tp[i]]
        step = complex(np.median(step.real), np.median(step.imag))
        shift += step
        if abs(step) <= 0.1 * COPY * diagonal:
            break
    moved = a * p + b + shift
    if abs(shift) < VISIBLE * diagonal or (near.query(moved)[0] <= COPY * diagonal).mean() < KEPT:
        return frames
    return _similar(frames, a, b + shift)


def _kept(p, near, frames, diagonal):
    """The share of the source's samples ``p`` that the plain frames put within `COPY` of the target's."""
    a, b = frames[0].factor(frames[1]), frames[0].to(frames[1], 0j)
    return float((near.query(a * p + b)[0] <= COPY * diagonal).mean())


def _icp(p, q, near, a, b, rounds=ICP_ROUNDS):
    """A similarity ``v -> a v + b`` refined by iterative closest points (closed-form complex least squares)."""
    for _ in range(rounds):
        tp = a * p + b
        _, j = near.query(tp)
        qq = q[j]
        pm, qm = p.mean(), qq.mean()
        pd = p - pm
        a = np.vdot(pd, qq - qm) / max(np.vdot(pd, pd).real, 1e-300)
        b = qm - a * pm
    return a, b
