"""Folds repaired frame by frame: no flipped triangle, the rest of the frame kept."""

import numpy as np
import pytest

from isotween.foldfree.repair import RINGS, repair_folds
from isotween.geometry import triangle_areas


def grid(n=6):
    x, y = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float))
    z = (x + 1j * y).ravel()
    i = np.arange(n - 1)
    a = (i[:, None] * n + i[None, :]).ravel()
    f = np.r_[np.c_[a, a + 1, a + n + 1], np.c_[a, a + n + 1, a + n]]
    return z, f


def test_a_folded_frame_is_unfolded_and_the_others_kept():
    z, f = grid()
    turn = np.exp(0.3j)
    folded = z * turn
    v = 2 * 6 + 2  # an interior vertex pushed across two of its neighbours
    folded[v] = (z[v] + 1.6 + 1.3j) * turn
    frames = np.stack([z, z * np.exp(0.15j), folded, z * np.exp(0.45j), z * np.exp(0.6j)])
    assert np.any(triangle_areas(folded, f) <= 0)
    out, info = repair_folds(frames, f)
    assert info["frames"] == [2]
    assert np.all(triangle_areas(out[2], f) > 0)
    for k in (0, 1, 3, 4):  # frames that do not fold: bit for bit
        assert np.array_equal(out[k], frames[k])
    far = np.abs(z - z[v]) > 2.5  # away from the fold, the frame is the given one to within a tenth of an edge
    assert np.abs(out[2] - folded)[far].max() < 0.1


def test_a_small_fold_is_repaired_around_it_and_the_rest_kept_bit_for_bit():
    z, f = grid(41)
    folded = z * np.exp(0.2j) + 0.5
    v = 20 * 41 + 20  # the middle vertex pushed across its neighbours
    folded[v] += 1.4 + 1.1j
    frames = np.stack([z, folded, z * np.exp(0.4j) + 1.0])
    out, info = repair_folds(frames, f)
    assert info["frames"] == [1] and np.all(triangle_areas(out[1], f) > 0)
    # the vertices more than the widest local ring count away from the fold do not move at all
    hops = np.maximum(np.abs((z - z[v]).real), np.abs((z - z[v]).imag))
    far = hops > 2 * max(RINGS) + 1
    assert far.sum() > 100 and np.array_equal(out[1][far], folded[far])
    assert not np.array_equal(out[1][hops <= 1], folded[hops <= 1])


def test_nothing_to_repair_is_returned_unchanged():
    z, f = grid(4)
    frames = np.stack([z, z * 1.1, z * 1.2])
    out, info = repair_folds(frames, f)
    assert info["frames"] == [] and np.array_equal(out, frames)


def test_clockwise_faces_are_kept_clockwise():
    z, f = grid(5)
    f = f[:, ::-1]  # every face clockwise in frame 0
    folded = z.copy()
    folded[6] = z[6] + 1.5 + 1.5j
    out, _ = repair_folds(np.stack([z, folded, z]), f)
    assert np.all(triangle_areas(out[1], f) < 0)


def test_a_fold_in_one_piece_leaves_the_others_as_they_were_though_a_scaffold_is_given():
    """With a scaffold, a frame is first repaired in the regions alone, kept where that holds the pieces apart."""
    pytest.importorskip("shapely")
    from isotween import Shape
    from isotween.foldfree.scaffold import Around
    from isotween.metrics import crossing_pairs

    z, f = grid(6)
    side = np.arange(5)
    ring = np.r_[side, 5 + 6 * side, 35 - side, 30 - 6 * side]  # the grid's outline, counter-clockwise
    Z, F = np.r_[z, z + 10], np.r_[f, f + 36]
    shape = Shape(np.c_[Z.real, Z.imag], faces=F, paths=[(ring, True), (ring + 36, True)], regions=[[0], [1]])
    folded = Z.copy()
    folded[2 * 6 + 2] += 1.6 + 1.3j  # an inner vertex of the first piece pushed across two of its neighbours
    frames = np.stack([Z, folded, Z])
    outline = np.c_[np.r_[ring, ring + 36], np.r_[np.roll(ring, -1), np.roll(ring, -1) + 36]]
    apart = lambda k, x: crossing_pairs(x, outline) == 0  # noqa: E731
    out, info = repair_folds(frames, F, accept=apart, scaffold=Around(shape, frames))
    assert info["frames"] == [1] and np.all(triangle_areas(out[1], F) > 0)
    assert np.array_equal(out[1][36:], folded[36:])  # the other piece: bit for bit
    assert np.array_equal(out, repair_folds(frames, F, accept=apart)[0])  # the regions' own repair: no scaffold paid
