"""Boundary sliding: source points moved along their own outline to make a bent copy's map rigid.

Ring matching (`matching`) spaces points by arc length between matched
corners. Where a drawing bends, the inner side of the bend is shorter than
the outer one, so arc length puts the two sides' points out of step across
the bar (a bar bent into an S: by most of the bar's width), and the
in-betweens shear and swell. Here the source mesh is fitted to the target
mesh as rigidly as possible (ARAP: Sorkine and Alexa 2007; per-triangle
rotations and one sparse solve per round, cotangent weights of the target
triangles, the target scaled to the source's area), with every source ring
vertex that lies on a straight stretch of the source outline (collinear with
its neighbours: a point the matching inserted, or a point on a straight
side) free to slide along that stretch, and the kinks (corners, curve
samples) held. The slid points stay on the source outline, so the source
drawing is unchanged; only which source point meets which target point
moves. The fit is kept where it at least halves the map's energy (`GAIN`)
and leaves it no more than moderately distorted (`NEAR`, about a twofold
stretch on average): a bent copy of the source, or one bar-like glyph bent
into another (a sans 'l' into a serif 'u'). Maps that stay far from rigid
after the slide (a 'B' into a 'W') keep the corners-and-arc-length match:
there the slide can send the whole drawing round in a loop.
"""

import numpy as np

from ..geometry import affine_maps, cotangent_laplacian, orient, triangle_angles, triangle_areas

__all__ = ["slid_rings", "arap_energy", "NEAR", "GAIN", "FAR"]

KINK = 1e-7  # a ring vertex whose distance from its neighbours' chord exceeds this fraction of the chord is held
ROUNDS = 12  # ARAP rounds (local rotations, global solve)
NEAR = 1.5  # the slid map is kept if its energy (mean squared distance of the Jacobian from a rotation) is below this
GAIN = 0.5  # ... and at most this fraction of the energy before
FAR = 20.0  # a map with an energy above this is not tried (in the drawings corpus none came below NEAR)
SPREAD = 0.01  # share of even spacing mixed into the slid points of a stretch (keeps them distinct and in order)


def _weights(rest, faces):
    """Per triangle and corner: the cotangent weight of the side opposite, that side (j - k), and j, k; (F, 3)."""
    j, k = np.roll(faces, -1, axis=1), np.roll(faces, -2, axis=1)
    return 0.5 / np.tan(triangle_angles(rest, faces)), rest[j] - rest[k], j, k


def _rotations(rest, cur, faces):
    """(F,) unit complex: each triangle's rotation closest to its affine map from ``rest`` to ``cur``."""
    p = affine_maps(faces, rest, cur)[0]
    return p / np.maximum(np.abs(p), 1e-300)


def arap_energy(rest, cur, faces):
    """Mean squared distance of the map's Jacobian from its nearest rotation, over the area of ``rest``.

    Parameters
    ----------
    rest, cur : (N,) complex
        Vertex positions of the same triangles before and after the map.
    faces : (F, 3) int
        Counter-clockwise in ``rest``.

    Returns
    -------
    float
        0 for a rigid motion; about ``g**2 / 2`` for a shear by ``g``.
    """
    p, q = affine_maps(faces, rest, cur)
    r = p / np.maximum(np.abs(p), 1e-300)
    area = triangle_areas(rest, faces)
    return float((area * 2 * (np.abs(p - r) ** 2 + np.abs(q) ** 2)).sum() / (abs(area.sum()) or 1.0))


def _stretches(z, rings):
    """Ring vertices of ``z`` between kinks: (ids, start, direction, stretch number), all (S,)."""
    ids, start, step, group = [], [], [], []
    offset = 0
    for r in rings:
        p = z[r]
        before, after = np.roll(p, 1), np.roll(p, -1)
        kink = np.flatnonzero(np.abs(orient(before, p, after)) > KINK * np.abs(after - before) ** 2)
        if len(kink) < 2:
            continue
        n = len(r)
        gap = np.diff(np.r_[kink, kink[0] + n]) - 1  # vertices between each kink and the next
        own = np.repeat(np.arange(len(kink)), gap)
        after_kink = np.arange(gap.sum()) - np.repeat(np.cumsum(gap) - gap, gap) + 1  # 1, 2, .. from its kink
        at = (np.repeat(kink, gap) + after_kink) % n
        a, b = p[kink[own]], p[kink[(own + 1) % len(kink)]]
        ids.append(r[at])
        start.append(a)
        step.append(b - a)
        group.append(own + offset)
        offset += len(kink)
    if not ids:
        return None
    return np.concatenate(ids), np.concatenate(start), np.concatenate(step), np.concatenate(group)


def slid_rings(source, target, faces, rings):
    """Source ring positions slid along their own outline to make the map to ``target`` as rigid as possible.

    Parameters
    ----------
    source, target : (N,) complex
        Vertex positions of compatible meshes (vertices 0..K-1 the rings).
    faces : (F, 3) int
        Positive in both.
    rings : list of (k_r,) int arrays
        The rings' vertex ids, in order.

    Returns
    -------
    (N,) complex or None
        ``source`` with its sliding ring vertices moved (interior vertices
        as given), or None where the slide does not bring the map's
        energy below `NEAR` and `GAIN` times its own, or the map is rigid
        already.
    """
    scale = np.sqrt(abs(triangle_areas(source, faces).sum() / (triangle_areas(target, faces).sum() or 1.0)))
    rest = target * scale
    before = arap_energy(rest, source, faces)
    if not (1e-9 < before < FAR):
        return None
    stretch = _stretches(source, rings)
    if stretch is None:
        return None
    ids, a, d, group = stretch
    from scipy.sparse import block_diag, coo_matrix
    from scipy.sparse.linalg import splu

    N = len(source)
    on_ring = np.zeros(N, bool)
    on_ring[np.concatenate(rings)] = True
    interior = np.flatnonzero(~on_ring)
    nI, nS = len(interior), len(ids)
    # positions x = [X; Y] (2N) = B y + c: interior vertices free, sliders a + t d, the rest held
    B = coo_matrix((np.r_[np.ones(2 * nI), d.real, d.imag],
                    (np.r_[interior, N + interior, ids, N + ids],
                     np.r_[np.arange(2 * nI), 2 * nI + np.arange(nS), 2 * nI + np.arange(nS)])),
                   shape=(2 * N, 2 * nI + nS)).tocsc()
    held = source.copy()
    held[interior] = 0
    held[ids] = a
    c = np.r_[held.real, held.imag]
    L = cotangent_laplacian(rest, faces)
    L2 = block_diag([L, L]).tocsc()
    try:
        solve = splu((B.T @ L2 @ B).tocsc()).solve
    except RuntimeError:  # (singular: a stretch free to drift; the match stays as it is)
        return None
    base = L2 @ c
    cw, side, j, k = _weights(rest, faces)
    cur = source
    for _ in range(ROUNDS):  # local step: rotations; global step: the positions nearest to the rotated sides
        part = cw * _rotations(rest, cur, faces)[:, None] * side
        b = np.bincount(j.ravel(), part.ravel().real, N) - np.bincount(k.ravel(), part.ravel().real, N) + 1j * (
            np.bincount(j.ravel(), part.ravel().imag, N) - np.bincount(k.ravel(), part.ravel().imag, N))
        x = B @ solve(B.T @ (np.r_[b.real, b.imag] - base)) + c
        cur = x[:N] + 1j * x[N:]
    after = arap_energy(rest, cur, faces)
    if not (after <= NEAR and after <= GAIN * before):
        return None
    # each stretch's points in their ring order, on the stretch, distinct
    t = np.clip(((cur[ids] - a) * np.conj(d)).real / np.abs(d) ** 2, 0.0, 1.0)
    t = t[np.lexsort((t, group))]
    first = np.r_[0, np.flatnonzero(np.diff(group)) + 1]
    count = np.diff(np.r_[first, len(group)])
    rank = np.arange(len(group)) - np.repeat(first, count) + 1
    t = (1 - SPREAD) * t + SPREAD * rank / np.repeat(count + 1, count)
    out = source.copy()
    out[ids] = a + t * d
    return out
