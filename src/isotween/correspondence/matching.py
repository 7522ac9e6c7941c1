"""Point correspondence along a ring pair: the motion found, every input vertex kept.

A ring (closed) or polyline (open) is parameterised by normalised arc length
``s`` in [0, 1). For one pair of rings:

1. **Alignment.** Both are sampled at ``N`` points uniformly in arc length and
   centred, as complex numbers ``x_m`` and ``y_m``. For a cyclic shift ``k`` the
   best similarity ``a`` (rotation and scale) of ``x`` onto ``y`` shifted by
   ``k`` is the complex least-squares fit ``a = <x, y_k> / <x, x>``; the
   normalised correlation ``rho_k = <x, y_k> / (|x| |y|)`` measures the fit,
   ``|rho_k| = 1`` for a similar copy. All shifts at once are one circular
   cross-correlation (FFT). The chosen shift maximises a score that prefers the
   drawing's rotation ``turn`` (`shift_score`), so that a ring turns with the
   rest of the drawing, and a ring of a symmetric shape does not spin; unless
   no start fits well under that rotation and the ring's own rotation fits
   much better (a 'C' into an arc that opens the other way turns over).
2. **Anchors.** Corners (a vertex turning by more than `CORNER`; where the
   rings are not similar copies, also rounded corners, arcs that turn by
   `ROUND_CORNER` within a short stretch, `_corners`) of the two rings that
   land near each other under the shift are paired (mutual nearest, same turn,
   monotone order). A rounded corner left unpaired pairs, arc to arc, with
   one of the other ring that a sharp corner next to it hid (a stroke
   joining where the arc begins: `_soft_corners`), where the two lie between
   the same anchors. Then every target vertex that lands near a source vertex
   is paired with it. The parameter map ``phi`` from source to target is
   piecewise linear in arc length through the anchors.
3. **Union.** Every source vertex goes into the target at ``phi(s)`` and
   every unpaired target vertex into the source at ``phi^-1``: both rings
   then hold all vertices of both inputs, so the first and last frames are
   the input polygons exactly. Long edges are split at corresponding places,
   which lie on the input polygons' edges.
"""

import numpy as np

from ..errors import IncompatibleShapesError

__all__ = ["RingPair", "arc_params", "points_at", "project", "correlation", "shift_score", "match_rings", "CORNER"]

#: turning angle (radians) from which a ring vertex is a corner that anchors the match
CORNER = np.deg2rad(28.0)
#: samples per ring for the alignment's correlation
SAMPLES = 512
#: a rounded corner turns by at least this angle (radians) within this fraction of the ring on either side
ROUND_CORNER = np.deg2rad(60.0)
ROUND_WINDOW = 0.05
#: cost of a corner pair lying one target ring radius apart in the aligned drawings (an unpaired right angle: 0.5)
PLACE_WEIGHT = 1.0
#: how far (fraction of the ring) a corner may land from its partner and still anchor
CORNER_WINDOW = 0.15
#: the same where the rings are similar copies (the alignment's shift is exact there)
COPY_WINDOW = 0.03
#: rings whose best similarity fit (normalised correlation) is below this are matched by warping
WARP_FIT = 0.97
#: samples per ring of the warped match, the cost of a step along one ring alone, and anchors every so many steps
WARP_SAMPLES = 128
WARP_STEP = 0.02
WARP_EVERY = 4
#: corners within this fraction of the ring of their partner under the warped match are paired exactly
CORNER_SNAP = 0.02
#: corner pairs (source corners x target corners) above which corners are not matched
MAX_CORNER_PAIRS = 4000
#: a polyline target fitting both ways within this share of the better fit goes the way that turns it less
REVERSE_TIE = 0.05
#: weight of a start's worse fit to the drawing's rotation against its corners' cost
SHIFT_WEIGHT = 4.0
#: how much (radians) the turning angles of two paired corners may differ
CORNER_TURN = np.deg2rad(50.0)
#: a target vertex within this fraction of the local spacing of a source vertex is the same point
SNAP = 0.3
#: weight of a ring's own best rotation against the drawing's rotation (0: the drawing's only)
OWN_TURN = 0.5
#: a ring whose best start under the drawing's rotation fits this poorly (|rho|) takes its own best rotation
#: where that fits better by `OWN_GAIN`: upright, it would pair one ring's outer side with the other's inner side
POOR_FIT = 0.6
OWN_GAIN = 0.3


class RingPair:
    """The union of the vertices of two corresponding rings.

    Attributes
    ----------
    source, target : (k,) complex arrays
        Corresponding points: every input vertex of each ring is among them.
    s, u : (k,) float arrays
        Normalised arc parameters of the points on the source and target ring.
    """

    def __init__(self, source, target, s, u):
        self.source, self.target, self.s, self.u = source, target, s, u


def arc_params(z, closed):
    """Normalised arc length of each vertex and the ring's length.

    Parameters
    ----------
    z : (k,) complex
        Distinct consecutive points.
    closed : bool

    Returns
    -------
    s : (k,) float
        In [0, 1), increasing (0 to 1 inclusive for a polyline).
    knots : (k + 1,) or (k,) complex
        The vertices, the first repeated at the end of a ring.
    length : float
    """
    knots = np.append(z, z[0]) if closed else z
    cum = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(knots)))])
    length = float(cum[-1])
    return cum[:-1] / length if closed else cum / length, knots, length


def points_at(z, closed, s):
    """Points of the ring ``z`` at normalised arc parameters ``s`` (any shape; wrapped on a ring)."""
    params, knots, _ = arc_params(z, closed)
    grid = np.append(params, 1.0) if closed else params
    s = np.mod(s, 1.0) if closed else np.clip(s, 0.0, 1.0)
    return np.interp(s, grid, knots.real) + 1j * np.interp(s, grid, knots.imag)


def project(z, closed, p):
    """The point of the ring ``z`` nearest ``p``: (distance, normalised arc parameter).

    Parameters
    ----------
    z : (k,) complex
    closed : bool
    p : complex

    Returns
    -------
    distance : float
    s : float
    """
    params, knots, length = arc_params(z, closed)
    a, b = knots[:-1], knots[1:]
    d = b - a
    f = np.clip(((np.conj(d) * (p - a)).real) / np.maximum(np.abs(d) ** 2, 1e-300), 0.0, 1.0)
    gap = np.abs(a + f * d - p)
    k = int(np.argmin(gap))
    cum = params if closed else params[:-1]
    return float(gap[k]), float((cum[k] + f[k] * abs(d[k]) / length) % (1.0 if closed else 2.0))


def correlation(x, y):
    """Normalised circular cross-correlation of centred samples.

    Parameters
    ----------
    x, y : (N,) complex
        Samples of two rings, uniform in arc length.

    Returns
    -------
    rho : (N,) complex
        ``rho[k] = <x, roll(y, -k)> / (|x| |y|)`` (centred): ``|rho| <= 1``; the
        best similarity of ``x`` onto ``y`` shifted by ``k`` is
        ``rho[k] |y| / |x|``.
    """
    x = x - x.mean()
    y = y - y.mean()
    norm = max(np.linalg.norm(x) * np.linalg.norm(y), 1e-300)
    return np.fft.ifft(np.conj(np.fft.fft(x)) * np.fft.fft(y)) / norm


def shift_score(rho, turn):
    """Score of every shift: the fit under the drawing's rotation, and half the fit under the ring's own.

    Parameters
    ----------
    rho : (N,) complex
        From `correlation`.
    turn : complex or None
        The drawing's rotation (unit complex); None: the ring's own only.

    Returns
    -------
    (N,) float
        ``Re(rho conj(turn)) + OWN_TURN (|rho| - Re(rho conj(turn)))``; ``|rho|``
        where the best of that fits worse than `POOR_FIT` and the ring's own
        best rotation better by `OWN_GAIN` (a 'C' into an arc that opens the
        other way: the ring turns rather than pair its outer side with the
        arc's inner side).
    """
    fit = np.abs(rho)
    if turn is None:
        return fit
    fixed = (rho * np.conj(turn)).real
    score = fixed + OWN_TURN * (fit - fixed)
    upright = fit[np.argmax(score)]
    return fit if upright < POOR_FIT and fit.max() > upright + OWN_GAIN else score


def _turning(z, closed):
    """(k,) signed turning angle at every vertex (0 at a polyline's ends)."""
    d = np.diff(np.append(z, z[0])) if closed else np.diff(z)
    if closed:
        return np.angle(d / np.roll(d, 1))
    return np.r_[0.0, np.angle(d[1:] / d[:-1]), 0.0]


def _corners(z, s, closed, rounded=True):
    """Corners of a ring: (c,) arc parameters, increasing, (c,) turning angles, (c,) bool rounded.

    A vertex that turns by at least `CORNER` is a sharp corner. With
    ``rounded``, a rounded corner (an arc sampled by many vertices, none
    turning by much) is found where the turning within `ROUND_WINDOW` of the
    ring on either side of a vertex reaches at least `ROUND_CORNER` and is
    largest, with no sharp corner that near: its angle is that turning, its
    place the turning's centroid in arc length (which does not depend on
    how the arc is sampled).

    Parameters
    ----------
    z : (k,) complex
    s : (k,) float
        Normalised arc parameters (`arc_params`).
    closed : bool
    rounded : bool
    """
    t = _turning(z, closed)
    sharp = np.flatnonzero(np.abs(t) >= CORNER)
    at, turn, soft = s[sharp], t[sharp], np.zeros(len(sharp), dtype=bool)
    if rounded:
        centre, window, _ = _soft_corners(z, s, closed)
        at, turn, soft = np.r_[at, centre], np.r_[turn, window], np.r_[soft, np.ones(len(centre), dtype=bool)]
    order = np.argsort(at, kind="stable")
    return at[order], turn[order], soft[order]


def _rounded(t, s, closed):
    """Rounded corners of a ring from its (k,) turning angles ``t``.

    Where the turning within `ROUND_WINDOW` on either side of a vertex
    reaches `ROUND_CORNER` and is the largest that near.

    Returns
    -------
    centre, turn, half, vertex : (r,) float arrays
        The turning's centroid in arc length (the corner's place), the
        turning, the arc's half length (from the turning's spread, as if
        uniform), and the arc parameter of the vertex it is centred on.
    """
    reach = np.r_[s - 1.0, s, s + 1.0] if closed else s  # a ring's window may wrap round
    tt = np.tile(t, 3) if closed else t
    cum, moment = np.r_[0.0, np.cumsum(tt)], np.r_[0.0, np.cumsum(tt * reach)]
    second = np.r_[0.0, np.cumsum(tt * reach**2)]
    lo = np.searchsorted(reach, s - ROUND_WINDOW, side="left")
    hi = np.searchsorted(reach, s + ROUND_WINDOW, side="right")
    window = cum[hi] - cum[lo]
    cand = np.flatnonzero(np.abs(window) >= ROUND_CORNER)
    w = np.abs(window[cand])
    beaten = _near(s[cand], s[cand], closed, every=True) & (
        (w[None, :] > w[:, None]) | ((w[None, :] == w[:, None]) & (cand[None, :] < cand[:, None])))
    cand = cand[~beaten.any(axis=1)]
    lo, hi, window = lo[cand], hi[cand], window[cand]
    centre = (moment[hi] - moment[lo]) / window
    spread = np.maximum((second[hi] - second[lo]) / window - centre**2, 0.0)
    return (np.mod(centre, 1.0) if closed else centre), window, np.sqrt(3.0 * spread), s[cand]


def _near(a, b, closed, every=False):
    """(len(a),) bool: parameters ``a`` within `ROUND_WINDOW` of one of ``b``; ``every``: the (len(a), len(b)) table."""
    d = a[:, None] - b[None, :]
    near = np.abs(_wrap(d) if closed else d) <= ROUND_WINDOW
    return near if every else near.any(axis=1)


def _soft_corners(z, s, closed, hidden=False):
    """Rounded corners of a ring: (r,) arc parameters, turning angles and half lengths of their arcs.

    Those of `_corners` (no sharp corner near), or with ``hidden`` those
    next to a sharp corner that `_corners` leaves out (a stroke joining a
    rounded corner where its arc begins), their turning counted without the
    sharp vertices.
    """
    t = _turning(z, closed)
    sharp = np.abs(t) >= CORNER
    centre, turn, half, vertex = _rounded(t, s, closed)
    keep = ~_near(vertex, s[sharp], closed)
    if hidden:  # near a sharp corner, and not one already found
        found = centre[keep]
        centre, turn, half, vertex = _rounded(np.where(sharp, 0.0, t), s, closed)
        keep = _near(vertex, s[sharp], closed) & ~_near(centre, found, closed)
    return centre[keep], turn[keep], half[keep]


def _wrap(d):
    """Differences of ring parameters wrapped to [-0.5, 0.5)."""
    return np.mod(d + 0.5, 1.0) - 0.5


def _monotone(a, b, closed):
    """Indices of anchor pairs (a sorted) kept so that b increases with a (cyclically on a ring).

    Pairs are dropped, the one furthest from the others' offset first, until the order agrees.
    """
    keep = np.arange(len(a))
    while len(keep) > 1:
        aa, bb = a[keep], b[keep]
        if closed:
            ref = np.angle(np.mean(np.exp(2j * np.pi * (bb - aa)))) / (2 * np.pi)
            d = _wrap(bb - aa - ref)  # b = a + ref + d, unwrapped
            ok_steps = np.diff(np.r_[aa + d, aa[0] + d[0] + 1.0]) > 0
        else:
            d = bb - aa - np.median(bb - aa)
            ok_steps = np.diff(bb) > 0
        if np.all(ok_steps):
            break
        bad = np.flatnonzero(~ok_steps)
        cand = np.unique(np.r_[bad, (bad + 1) % len(keep)])
        keep = np.delete(keep, cand[np.argmax(np.abs(d[cand]))])
    return keep


class _Map:
    """Piecewise-linear monotone map of normalised arc parameters through anchor pairs."""

    def __init__(self, a, b, closed):
        order = np.argsort(a, kind="stable")
        a, b = a[order], b[order]
        self.closed = closed
        if closed:
            b = a + _wrap(b - a - _wrap(b[0] - a[0])) + _wrap(b[0] - a[0])  # unwrapped: b - a close to b0 - a0
            b = np.maximum.accumulate(b)
            self.a = np.r_[a - 1.0, a, a + 1.0]
            self.b = np.r_[b - 1.0, b, b + 1.0]
        else:
            self.a, self.b = a, b

    def __call__(self, s):
        out = np.interp(s, self.a, self.b)
        return np.mod(out, 1.0) if self.closed else out

    def inverse(self, u):
        if not self.closed:
            return np.interp(u, self.b, self.a)
        # u on the ring: its unwrapped value within the period of the map's middle copy
        lo = self.b[len(self.b) // 3]
        uu = lo + np.mod(u - lo, 1.0)
        return np.mod(np.interp(uu, self.b, self.a), 1.0)


def _snap_pairs(s_src, s_tgt_back, closed):
    """Mutual nearest pairs (i, j) of source params and pulled-back target params, closer than SNAP spacing."""
    if len(s_src) == 0 or len(s_tgt_back) == 0:
        return np.zeros(0, int), np.zeros(0, int)

    def nearest(p, q):
        # index into sorted q of the nearest value to each p (cyclic on a ring)
        order = np.argsort(q)
        qs = q[order]
        pos = np.searchsorted(qs, p)
        lo, hi = (pos - 1) % len(qs), pos % len(qs)
        dist = (lambda x, y: np.abs(_wrap(x - y))) if closed else (lambda x, y: np.abs(x - y))
        pick = np.where(dist(p, qs[lo]) <= dist(p, qs[hi]), lo, hi)
        return order[pick], dist(p, qs[pick])

    j_of_i, gap = nearest(s_src, s_tgt_back)
    i_of_j, _ = nearest(s_tgt_back, s_src)
    spacing = np.diff(np.r_[s_src, s_src[0] + 1.0]) if closed else np.r_[np.diff(s_src), np.inf]
    local = np.minimum(spacing, np.roll(spacing, 1)) if closed else np.minimum(spacing, np.r_[np.inf, spacing[:-1]])
    i = np.flatnonzero((i_of_j[j_of_i] == np.arange(len(s_src))) & (gap < SNAP * local))
    return i, j_of_i[i]


def match_rings(z, w, closed, turn=None, anchors=(), spacing=None, reverse=None, place=None):
    """Corresponding points of two rings, every vertex of both kept (see the module notes).

    Parameters
    ----------
    z, w : (k_z,) and (k_w,) complex
        Source and target ring (distinct consecutive points). A closed target
        must turn the same way as the source unless ``reverse`` allows otherwise.
    closed : bool
    turn : complex, optional
        The drawing's rotation from source to target (unit complex): rings
        prefer shifts that turn by it. None: any rotation.
    anchors : sequence of (float, float)
        Anchor pairs (source parameter, target parameter on the target as
        given), e.g. landmarks; they replace the alignment, and corners pair
        between them (`_between_landmarks`).
    spacing : (float, float), optional
        Longest edge allowed in the source and in the target (lengths); longer
        edges of the union are split. Default: no split.
    reverse : bool, optional
        Traverse the target backwards (a polyline's other end first). Default:
        a ring keeps its direction; a polyline takes the better one.
    place : callable, optional
        Source points (complex array) to their place in the target drawing
        (the drawings' alignment). With it, rings that are not similar copies
        (`WARP_FIT`) and have fewer than two corner pairs are matched by `_warp`.

    Returns
    -------
    RingPair
        ``source`` and ``target`` run in the source's direction from the source's first vertex.
    """
    s_z, _, len_z = arc_params(z, closed)
    if reverse is None:
        reverse = False if closed else _polyline_reversed(z, w)
    anchors = [(float(a), float(b)) for a, b in anchors]
    if reverse:
        w = np.roll(w[::-1], 1) if closed else w[::-1]
        anchors = [(a, (1.0 - b) % 1.0 if closed else 1.0 - b) for a, b in anchors]
    s_w, _, len_w = arc_params(w, closed)
    if anchors:
        a_h, b_h = np.array(anchors).T
        order = np.argsort(a_h)
        if len(_monotone(a_h[order], b_h[order], closed)) < len(anchors):
            raise IncompatibleShapesError("the landmarks on this outline are in a different order in the target")
    if closed:
        if anchors:
            a0, b0 = np.array(anchors).T
        else:
            grid = np.arange(SAMPLES) / SAMPLES
            rho = correlation(points_at(z, True, grid), points_at(w, True, grid))
            score = shift_score(rho, turn)
            k = int(np.argmax(score))
            # parabolic refinement of the peak
            left, c, right = score[k - 1], score[k], score[(k + 1) % SAMPLES]
            den = left - 2 * c + right
            frac = 0.5 * (left - right) / den if den < 0 else 0.0
            a0, b0 = np.array([0.0]), np.array([np.mod((k + np.clip(frac, -0.5, 0.5)) / SAMPLES, 1.0)])
    else:
        a0, b0 = np.array([0.0, 1.0]), np.array([0.0, 1.0])
        if anchors:
            a0, b0 = np.r_[a0, np.array(anchors)[:, 0]], np.r_[b0, np.array(anchors)[:, 1]]
    phi = _Map(a0, b0, closed)
    if anchors:  # the landmarks exact, corners to corners between them
        a0, b0 = _between_landmarks(z, w, s_z, s_w, closed, a0, b0, place)
        phi = _Map(a0, b0, closed)
    else:  # corners to corners
        # rounded corners too where the rings are not similar copies (for those the alignment is exact)
        found = _corner_anchors(z, w, s_z, s_w, closed, phi, turn, closed and abs(rho[k]) < WARP_FIT, place)
        if closed and (found is None or len(found[0]) < 2) and place is not None and abs(rho[k]) < WARP_FIT:
            # not a similar copy, too few corners: the match warped along the ring by position and turning
            found = _with_near_corners(z, w, s_z, s_w, *_warp(z, w, phi, place))
        if found is not None:
            a0, b0 = found
            phi = _Map(a0, b0, closed)
    # target vertices that land on source vertices are the same point
    i, j = _snap_pairs(s_z, phi.inverse(s_w), closed)
    paired = np.zeros(len(s_w), bool)
    if len(i):
        a_all, b_all = np.r_[a0, s_z[i]], np.r_[b0, s_w[j]]
        order = np.argsort(a_all, kind="stable")
        keep = order[_monotone(a_all[order], b_all[order], closed)]
        phi = _Map(a_all[keep], b_all[keep], closed)
        kept = keep[keep >= len(a0)] - len(a0)  # the snap pairs that agree with the order
        i, j = i[kept], j[kept]
        paired[j] = True
    # the union: source vertices at phi(s) (a snapped one at its partner exactly), unpaired target
    # vertices at phi^-1(u); sorted by source parameter, a source vertex before a target one at a tie
    u_src = phi(s_z)
    u_src[i] = s_w[j]
    extra = ~paired
    s_all = np.r_[s_z, phi.inverse(s_w[extra])]
    u_all = np.r_[u_src, s_w[extra]]
    order = np.lexsort((np.r_[np.zeros(len(s_z)), np.ones(int(extra.sum()))], s_all))
    s_all, u_all = s_all[order], u_all[order]
    if not closed:
        s_all, u_all = np.clip(s_all, 0, 1), np.clip(u_all, 0, 1)
    # drop repeats (a pulled-back target vertex on a source vertex's parameter)
    ds = np.diff(np.r_[s_all, s_all[0] + 1.0]) if closed else np.r_[np.diff(s_all), 1.0]
    du = np.abs(_wrap(np.diff(np.r_[u_all, u_all[0]]))) if closed else np.r_[np.abs(np.diff(u_all)), 1.0]
    dup = (ds <= 1e-12) & (du <= 1e-12)
    s_all, u_all = s_all[~dup], u_all[~dup]
    if spacing is not None:
        s_all, u_all = _split(s_all, u_all, closed, spacing[0] / len_z, spacing[1] / len_w)
    return RingPair(points_at(z, closed, s_all), points_at(w, closed, u_all), s_all, u_all)


def _warp(z, w, phi, place, n=WARP_SAMPLES):
    """Anchors (source params, target params) of a monotone match warped along two rings.

    Both rings are sampled at ``n`` points uniform in arc length, the target
    from where ``phi`` puts the source's start. The cost of matching sample
    i with sample j is their distance (the source placed in the target
    drawing, over the target's diagonal) squared plus the difference of
    their turning angles squared; a step along one ring alone costs
    `WARP_STEP` more (dynamic time warping, within a band of a quarter ring).
    The path's diagonal steps, every few samples, are the anchors.
    """
    u0 = float(phi(np.zeros(1))[0])
    grid = np.arange(n) / n
    x = place(points_at(z, True, grid))
    y = points_at(w, True, u0 + grid)
    diag = max(abs(complex(np.ptp(y.real), np.ptp(y.imag))), 1e-300)
    kx = _turning(x, True)
    ky = _turning(y, True)
    C = np.abs(x[:, None] - y[None, :]) ** 2 / diag ** 2 + (kx[:, None] - ky[None, :]) ** 2
    band = np.abs(np.arange(n)[:, None] - np.arange(n)[None, :]) > n // 4
    C[band] = 1e6  # outside the band: never taken (finite, so that the prefix sums below stay exact)
    D = np.empty((n, n))
    D[0] = np.cumsum(C[0] + WARP_STEP) - WARP_STEP
    for i in range(1, n):
        x_j = C[i] + np.minimum(np.r_[1e12, D[i - 1, :-1]], D[i - 1] + WARP_STEP)
        P = np.cumsum(C[i] + WARP_STEP)
        D[i] = P + np.minimum.accumulate(x_j - P)
    # back from the end: the diagonal steps of the cheapest path
    i, j, pairs = n - 1, n - 1, []
    while i > 0 and j > 0:
        diag_cost = D[i - 1, j - 1]
        up, left = D[i - 1, j] + WARP_STEP, D[i, j - 1] + WARP_STEP
        if diag_cost <= up and diag_cost <= left:
            pairs.append((i, j))
            i, j = i - 1, j - 1
        elif up <= left:
            i -= 1
        else:
            j -= 1
    pairs.append((0, 0))
    pairs = np.array(pairs[::-1])[:: WARP_EVERY]
    return pairs[:, 0] / n, np.mod(u0 + pairs[:, 1] / n, 1.0)


def _with_near_corners(z, w, s_z, s_w, a0, b0):
    """The anchors with every corner pair that lands within `CORNER_SNAP` of its partner under them."""
    phi = _Map(a0, b0, True)
    cz, tz, _ = _corners(z, s_z, True)
    cw, tw, _ = _corners(w, s_w, True)
    if not len(cz) or not len(cw):
        return a0, b0
    d = np.abs(_wrap(phi(cz)[:, None] - cw[None, :]))
    d = np.where(np.abs(tz[:, None] - tw[None, :]) <= CORNER_TURN, d, np.inf)
    j, i = np.argmin(d, axis=1), np.argmin(d, axis=0)
    mutual = np.flatnonzero((i[j] == np.arange(len(cz))) & (d[np.arange(len(cz)), j] < CORNER_SNAP))
    if not len(mutual):
        return a0, b0
    a1, b1 = cz[mutual], cw[j[mutual]]
    # corners replace the warp's anchors near them
    far = np.min(np.abs(_wrap(a0[:, None] - a1[None, :])), axis=1) > CORNER_SNAP
    a_all, b_all = np.r_[a0[far], a1], np.r_[b0[far], b1]
    order = np.argsort(a_all, kind="stable")
    keep = order[_monotone(a_all[order], b_all[order], True)]
    return a_all[keep], b_all[keep]


def _align_sequences(da, ta, db, tb, window, apart=None):
    """Monotone pairs of two corner sequences by dynamic programming.

    Parameters
    ----------
    da, db : (m,) and (n,) float
        Corner positions (arc parameters from a common cut, increasing).
    ta, tb : (m,) and (n,) float
        Their turning angles.
    window : float
        Pairs further apart than this (in parameter) are not made.
    apart : (m, n) float, optional
        A cost added to each pair (how far apart the two corners lie).

    Returns
    -------
    cost : float
        Unpaired corners cost their turn / pi; a pair costs its position and
        turn differences.
    pairs : list of (int, int)
    """
    m, n = len(da), len(db)
    ga, gb = np.abs(ta) / np.pi, np.abs(tb) / np.pi
    gap = np.abs(da[:, None] - db[None, :])
    c = np.where(gap <= window, gap / window * 0.5 * (ga[:, None] + gb[None, :]) + np.abs(ta[:, None] - tb[None, :])
                 / np.pi, np.inf)
    if apart is not None:
        c = c + apart
    G = np.r_[0.0, np.cumsum(gb)]
    D = np.empty((m + 1, n + 1))
    D[0] = G
    for i in range(1, m + 1):
        x = np.empty(n + 1)
        x[0] = D[i - 1, 0] + ga[i - 1]
        x[1:] = np.minimum(D[i - 1, :-1] + c[i - 1], D[i - 1, 1:] + ga[i - 1])
        D[i] = G + np.minimum.accumulate(x - G)
    pairs, i, j = [], m, n
    while i > 0 and j > 0:
        if np.isclose(D[i, j], D[i, j - 1] + gb[j - 1], rtol=0, atol=1e-12):
            j -= 1
        elif np.isclose(D[i, j], D[i - 1, j - 1] + c[i - 1, j - 1], rtol=0, atol=1e-12):
            pairs.append((i - 1, j - 1))
            i, j = i - 1, j - 1
        else:
            i -= 1
    return float(D[m, n]), pairs[::-1]


def _corner_anchors(z, w, s_z, s_w, closed, phi, turn, rounded, place=None):
    """Anchor pairs (source params, target params) pairing corners with corners, or None.

    The corners of both rings (turning angle at least `CORNER`) are paired by
    `_align_sequences` in arc-length order. On a ring every start is tried
    (the strongest source corner against each target corner of a similar
    turn, and the alignment's own shift); the cost adds how much worse the
    start's shift fits the drawing's rotation (`shift_score`). Rings that
    are similar copies (not ``rounded``) keep the alignment's shift, and
    corners pair within `COPY_WINDOW` of where it puts them. With
    ``place`` (the drawings' alignment), a pair with a rounded corner also
    costs the distance between its two corners, over the target ring's
    radius (`PLACE_WEIGHT`): a rounded rectangle's corners pair with the
    corners where they lie, not with the next ones round. Then rounded
    corners left unpaired pair with hidden ones of the other ring
    (`_gap_pairs`).
    """
    az, qz, rz = _corners(z, s_z, closed, rounded)
    aw, qw, rw = _corners(w, s_w, closed, rounded)
    if not len(az) or not len(aw) or len(az) * len(aw) > MAX_CORNER_PAIRS:
        return None
    apart = _apart(z, w, az, aw, rz, rw, closed, place)
    if not closed:
        _, pairs = _align_sequences(az, qz, aw, qw, CORNER_WINDOW, apart)
        if not pairs:
            return None
        i, j = np.array(pairs).T
        return np.r_[0.0, az[i], 1.0], np.r_[0.0, aw[j], 1.0]
    grid = np.arange(SAMPLES) / SAMPLES
    rho = correlation(points_at(z, True, grid), points_at(w, True, grid))
    score = shift_score(rho, turn)
    lead = int(np.argmax(np.abs(qz)))
    offsets = [float(phi(az[lead]) - az[lead])]
    window = CORNER_WINDOW if rounded else COPY_WINDOW  # a similar copy: the shift stands, corners snap
    if rounded:
        offsets += [float(aw[j] - az[lead]) for j in np.flatnonzero(np.abs(qw - qz[lead]) <= CORNER_TURN)]
    best = (np.inf, None)
    for off in np.mod(offsets, 1.0):
        cut = az[lead] - 0.5 * window  # just before the lead corner, and where it lands
        da = np.mod(az - cut, 1.0)
        db = np.mod(aw - cut - off, 1.0)
        oa, ob = np.argsort(da), np.argsort(db)
        cost, pairs = _align_sequences(da[oa], qz[oa], db[ob], qw[ob], window,
                                       None if apart is None else apart[np.ix_(oa, ob)])
        cost += SHIFT_WEIGHT * (score.max() - score[int(round(off * SAMPLES)) % SAMPLES])
        if cost < best[0]:  # a start that pairs no corner can win too: then no anchors, the shift stands
            best = (cost, None)
            if pairs:
                i, j = np.array(pairs).T
                best = (cost, (az[oa[i]], aw[ob[j]]))
    if not rounded or best[1] is None:
        return best[1]
    a, b = best[1]
    soft_z, soft_w = _soft_corners(z, s_z, True), _soft_corners(w, s_w, True)
    lone_z, lone_w = ~np.isin(soft_z[0], a), ~np.isin(soft_w[0], b)
    one = _gap_pairs(a, b, [x[lone_z] for x in soft_z], _soft_corners(w, s_w, True, hidden=True))
    two = _gap_pairs(b, a, [x[lone_w] for x in soft_w], _soft_corners(z, s_z, True, hidden=True))
    a, b = np.r_[a, one[0], two[1]], np.r_[b, one[1], two[0]]
    order = np.argsort(a, kind="stable")
    keep = order[_monotone(a[order], b[order], True)]
    return a[keep], b[keep]


def _apart(z, w, az, aw, rz, rw, closed, place):
    """(m, n) cost of pairing each corner of ``z`` with each of ``w`` for how far apart they lie, or None.

    The distance between the two corners with the source placed in the
    target drawing (``place``), over the target ring's radius, times
    `PLACE_WEIGHT`; only for pairs with a rounded corner (``rz``, ``rw``).
    None without ``place`` or rounded corners.
    """
    if place is None or not (rz.any() or rw.any()):
        return None
    radius = max(float(np.sqrt(np.mean(np.abs(w - w.mean()) ** 2))), 1e-300)
    apart = np.abs(place(points_at(z, closed, az))[:, None] - points_at(w, closed, aw)[None, :]) / radius
    return PLACE_WEIGHT * np.where(rz[:, None] | rw[None, :], apart, 0.0)


def _between_landmarks(z, w, s_z, s_w, closed, a0, b0, place=None):
    """Landmark anchors ``a0``, ``b0`` (and a polyline's ends) with the corners between them paired.

    Between two consecutive landmarks the source's corners (sharp and
    rounded), carried by the landmarks' map, pair with the target's corners
    of the same stretch by `_align_sequences` (within `CORNER_WINDOW`; with
    ``place``, a pair with a rounded corner also costs how far apart the two
    lie, as in `_corner_anchors`), as the corners of rings without landmarks
    do: a landmark pins its points and leaves the rest of the match to the
    corners, not to arc length. Corners within `CORNER_SNAP` of a landmark
    are left to it.

    Returns
    -------
    (m,) float, (m,) float
        Anchor parameters on the source and the target, the landmarks among them.
    """
    az, qz, rz = _corners(z, s_z, closed)
    aw, qw, rw = _corners(w, s_w, closed)
    if not len(az) or not len(aw) or len(az) * len(aw) > MAX_CORNER_PAIRS:
        return a0, b0
    apart = _apart(z, w, az, aw, rz, rw, closed, place)
    order = np.argsort(a0, kind="stable")
    a0, b0 = a0[order], b0[order]
    phi = _Map(a0, b0, closed)
    pz, a_new, b_new = phi(az), [a0], [b0]
    stretches = range(len(a0)) if closed else range(len(a0) - 1)
    for k in stretches:
        nxt = (k + 1) % len(a0)
        span_b = np.mod(b0[nxt] - b0[k], 1.0) if closed else b0[nxt] - b0[k]
        if closed and len(a0) == 1:
            span_b = 1.0
        # both rings' corners inside the stretch, as target parameters from its start; a corner within
        # `CORNER_SNAP` of a landmark is the landmark's (a point clicked next to a corner means the corner)
        da = np.mod(pz - b0[k], 1.0) if closed else pz - b0[k]
        db = np.mod(aw - b0[k], 1.0) if closed else aw - b0[k]
        i = np.flatnonzero((da > CORNER_SNAP) & (da < span_b - CORNER_SNAP))
        j = np.flatnonzero((db > CORNER_SNAP) & (db < span_b - CORNER_SNAP))
        if not len(i) or not len(j):
            continue
        i, j = i[np.argsort(da[i], kind="stable")], j[np.argsort(db[j], kind="stable")]
        _, pairs = _align_sequences(da[i], qz[i], db[j], qw[j], CORNER_WINDOW,
                                    None if apart is None else apart[np.ix_(i, j)])
        if pairs:
            p, q = np.array(pairs).T
            a_new.append(az[i[p]])
            b_new.append(aw[j[q]])
    a, b = np.concatenate(a_new), np.concatenate(b_new)
    order = np.argsort(a, kind="stable")
    keep = order[_monotone(a[order], b[order], closed)]
    return a[keep], b[keep]


def _gap_pairs(a, b, lone, hidden):
    """Anchors pairing a rounded corner left unpaired on one ring with a hidden one of the other in the same gap.

    Parameters
    ----------
    a, b : (m,) float
        Anchor parameters on the two rings, in order round both from ``a[0]``, ``b[0]``.
    lone : three (p,) float arrays
        Unpaired rounded corners of the first ring: parameters, turning
        angles, half lengths of their arcs (`_soft_corners`).
    hidden : three (h,) float arrays
        The same of the hidden corners of the second ring.

    Returns
    -------
    (k,) float, (k,) float
        Parameters on the first ring and on the second: the two arcs' starts,
        centres and ends, where a gap between two consecutive anchors holds
        one corner of each, of a similar turn.
    """
    (c, q, h), (d, t, g) = lone, hidden
    ends_a, ends_b = np.r_[np.mod(a - a[0], 1.0), 1.0], np.r_[np.mod(b - b[0], 1.0), 1.0]
    c, d = np.mod(c - a[0], 1.0), np.mod(d - b[0], 1.0)
    gap_a, gap_b = np.searchsorted(ends_a, c, side="right"), np.searchsorted(ends_b, d, side="right")
    count = lambda gap: np.bincount(gap, minlength=len(ends_a))[gap] == 1  # noqa: E731
    i, j = np.nonzero((gap_a[:, None] == gap_b[None, :]) & (np.abs(q[:, None] - t[None, :]) <= CORNER_TURN)
                      & count(gap_a)[:, None] & count(gap_b)[None, :])

    def arc(x, half, ends, gap):  # (k, 3) start, centre, end: within half way to the gap's anchors
        lo, hi = ends[gap - 1], ends[gap]
        return np.c_[x - np.minimum(half, 0.5 * (x - lo)), x, x + np.minimum(half, 0.5 * (hi - x))]

    return (np.mod(arc(c[i], h[i], ends_a, gap_a[i]) + a[0], 1.0).ravel(),
            np.mod(arc(d[j], g[j], ends_b, gap_b[j]) + b[0], 1.0).ravel())


def _split(s, u, closed, hs, hu):
    """Split union edges longer than ``hs`` (source) or ``hu`` (target) at equal fractions of both."""
    if closed:
        ds = np.diff(np.r_[s, s[0] + 1.0])
        du = np.mod(np.diff(np.r_[u, u[0]]), 1.0)
    else:
        ds, du = np.diff(s), np.diff(u)
    pieces = np.maximum(np.ceil(np.maximum(ds / hs, du / hu) - 1e-9), 1).astype(np.int64)
    if np.all(pieces == 1):
        return s, u
    start = np.repeat(np.arange(len(ds)), pieces)
    frac = (np.arange(len(start)) - np.repeat(np.cumsum(pieces) - pieces, pieces)) / np.repeat(pieces, pieces)
    s_new = s[start] + frac * ds[start]
    u_new = u[start] + frac * du[start]
    if closed:
        s_new, u_new = np.mod(s_new, 1.0), np.mod(u_new, 1.0)
    else:
        s_new, u_new = np.r_[s_new, s[-1]], np.r_[u_new, u[-1]]
    return s_new, u_new


def _polyline_reversed(z, w):
    """Whether a polyline target fits the source better backwards (similarity fit of arc samples).

    Where both ways fit about as well (within `REVERSE_TIE`: a straight
    stroke, a symmetric arc), the way that turns it less: a menu's bar into
    a cross's stroke turns by 45 degrees, not 135.
    """
    grid = np.linspace(0.0, 1.0, 64)
    x = points_at(z, False, grid)
    x = x - x.mean()
    fits = []
    for ww in (w, w[::-1]):
        y = points_at(ww, False, grid)
        y = y - y.mean()
        fits.append(complex(np.vdot(x, y)))
    size = np.abs(fits)
    if abs(size[1] - size[0]) <= REVERSE_TIE * size.max():
        return bool(abs(np.angle(fits[1])) < abs(np.angle(fits[0])))
    return bool(size[1] > size[0])
