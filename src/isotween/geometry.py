"""Planar polygon primitives shared by the readers and the correspondence: ring areas, winding numbers, fill regions.

Rings are closed vertex loops (the closing edge implied), as ``(k,)`` complex
arrays or ``(k, 2)`` float arrays as each function says. This module imports
only numpy, so a reader (`isotween.io.svg`) can use it without loading the
correspondence.
"""

import numpy as np

__all__ = ["ring_area", "winding_numbers", "fill_regions"]


def ring_area(z):
    """Signed shoelace area of closed rings: (k,) complex -> float."""
    return 0.5 * float(np.sum((np.conj(z) * np.roll(z, -1)).imag))


def winding_numbers(points, rings):
    """(m, R) winding number of every closed ring around every point.

    Parameters
    ----------
    points : (m, 2) array
    rings : list of (k_r, 2) arrays
        Closed rings (the closing edge implied).
    """
    a = np.vstack(rings)
    b = np.vstack([np.roll(r, -1, axis=0) for r in rings])
    owner = np.repeat(np.arange(len(rings)), [len(r) for r in rings])
    px, py = points[:, 0:1], points[:, 1:2]
    cross = (b[:, 0] - a[:, 0]) * (py - a[:, 1]) - (px - a[:, 0]) * (b[:, 1] - a[:, 1])  # (m, E)
    up = (a[:, 1] <= py) & (b[:, 1] > py) & (cross > 0)
    down = (a[:, 1] > py) & (b[:, 1] <= py) & (cross < 0)
    w = up.astype(np.int64) - down.astype(np.int64)
    out = np.zeros((len(points), len(rings)), dtype=np.int64)
    np.add.at(out.T, owner, w.T)
    return out


def fill_regions(rings, rule="evenodd"):
    """Regions of rings filled together under a fill rule.

    Each ring's winding number just outside it (the sum over the other rings
    at one of its points) and just inside it (plus its own orientation) says
    whether it bounds the fill: from unfilled outside to filled inside it is
    an outer ring, the other way round a hole of the smallest outer ring
    around it. A ring with the fill on both sides (or neither) bounds nothing.

    Parameters
    ----------
    rings : list of (k_r, 2) arrays
    rule : {'nonzero', 'evenodd'}

    Returns
    -------
    regions : list of list of int
        Outer ring first, then its holes (indices into ``rings``).
    outline : set of int
        Rings that bound no filled region.
    """
    filled = (lambda w: w % 2 == 1) if rule == "evenodd" else (lambda w: w != 0)
    probes = np.array([r[0] for r in rings])
    w = winding_numbers(probes, rings)
    signed = np.array([ring_area(r[:, 0] + 1j * r[:, 1]) for r in rings])
    outside = w.sum(axis=1) - np.diagonal(w)
    inside = outside + np.sign(signed).astype(np.int64)
    is_outer = ~filled(outside) & filled(inside)
    is_hole = filled(outside) & ~filled(inside)
    outers = np.flatnonzero(is_outer)
    area = np.abs(signed)
    regions = {int(o): [int(o)] for o in outers}
    outline = set(np.flatnonzero(~is_outer & ~is_hole).tolist())
    for h in np.flatnonzero(is_hole):
        around = outers[(w[h, outers] != 0) & (area[outers] > area[h])]
        if around.size:
            regions[int(around[np.argmin(area[around])])].append(int(h))
        else:
            outline.add(int(h))
    return list(regions.values()), outline
