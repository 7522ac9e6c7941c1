"""AIAP solved again on the same vertices with edges flipped where its in-betweens turn a face over.

A compatible pair with every triangle positive at both ends can still fold
in between: Eq. (10) spreads the misfit of the interpolated edge vectors
(Eqs. 6-9) over the mesh, and a face that the map between the ends
stretches far more one way than the other (a needle at a stretch of outline
that the correspondence crowds, a sliver between two rings) turns over.
The same vertices with other connectivity there often do not: every
folding face has one of its edges flipped in both meshes (they share
connectivity), the one of its three whose two new faces stay positive in
both and are stretched most evenly by the map (the smaller largest
dilatation ``|Q| / |P|`` of `isotween.geometry.affine_maps`), and AIAP is
solved again. Rounds go on while they find fewer folding faces; the pair
with the fewest is kept, so it never folds more than it did. The outline,
the vertices and both ends are unchanged: the result is AIAP's, on other
triangles.
"""

import numpy as np

from ..correspondence._disc import _flip, _independent, _scale2
from ..geometry import affine_maps, edge_table, triangle_areas
from ..metrics import flipped

__all__ = ["unfold", "folding", "MOST", "ROUNDS", "STALE"]

ROUNDS = 4  # rounds of flips at most
STALE = 1  # rounds in a row that fold no fewer faces than the best: stop
MOST = 6  # a pair that folds more faces than this is left to the repair (more than a few bad faces fold it)


def unfold(seq, solve):
    """AIAP's sequence on the faces, among those tried, whose in-betweens fold fewest faces.

    Parameters
    ----------
    seq : Sequence
        AIAP's sequence of a compatible triangle-mesh pair (``seq.shape``
        has faces; frame 0 and the last frame have every face positive).
    solve : callable
        ``solve(faces)``: AIAP's sequence of the same pair with faces
        ``faces`` (F, 3), at the same frame times.

    Returns
    -------
    Sequence
        ``seq`` itself where no face folds, more than `MOST` fold, or no
        flip folds fewer; else the sequence with the fewest folding faces,
        ``info['unfolded']`` saying how many folded before and after and how
        many edges were flipped.
    """
    f = np.asarray(seq.shape.faces, dtype=np.int64)
    bad = folding(seq)
    before = best = len(bad)
    if not 0 < best <= MOST:
        return seq
    kept, count, total, stale = seq, 0, 0, 0
    z0, z1 = (seq.frames[k, :, 0] + 1j * seq.frames[k, :, 1] for k in (0, -1))
    eps = (1e-14 * _scale2(z0), 1e-14 * _scale2(z1))
    for _ in range(ROUNDS):
        f = f.copy()
        done = _flip_folds(z0, z1, f, bad, eps)
        if not done:
            break
        total += done
        new = solve(f)
        bad = folding(new)
        stale = 0 if len(bad) < best else stale + 1
        if len(bad) < best:
            best, kept, count = len(bad), new, total
        if best == 0 or stale == STALE:
            break
    if kept is not seq:
        kept.info["unfolded"] = (f"{seq.method} folded {before} faces; {count} edges flipped where they fold: "
                                 f"{best} fold")
    return kept


def folding(seq):
    """(B,) int: the faces of ``seq.shape`` flipped (`isotween.metrics.flipped`) in some in-between frame."""
    return np.flatnonzero(flipped(seq)[1:-1].any(axis=0))


def _flip_folds(z0, z1, f, bad, eps):
    """Flip one edge of each folding face ``bad`` in ``f`` (in place); the number flipped.

    Of a face's interior edges, the flip whose two new faces are positive
    in both ends ``z0``, ``z1`` (area above ``eps``) and have the smallest
    largest dilatation of the map ``z0 -> z1``; where two folding faces
    would flip into the same faces, the better flip goes first.
    """
    a, b, c, _, twin = edge_table(f)
    h = np.flatnonzero(np.isin(np.arange(len(a)) // 3, bad) & (twin >= 0))
    d = c[twin[h]]
    new = np.concatenate([np.stack([a[h], d, c[h]], axis=1), np.stack([d, b[h], c[h]], axis=1)])
    ok = (triangle_areas(z0, new) > eps[0]) & (triangle_areas(z1, new) > eps[1])
    ok = ok[:len(h)] & ok[len(h):]
    P, Q = affine_maps(new[np.r_[ok, ok]], z0, z1)
    h = h[ok]
    k = np.abs(Q) / np.abs(P)
    score = -np.maximum(k[:len(h)], k[len(h):])
    h = h[_independent(score, h // 3, twin[h] // 3, len(f))]
    _flip(f, h, twin, a, b, c)
    return len(h)
