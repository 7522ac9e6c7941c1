"""Contour correspondence: arc-length resampling, best start and orientation, errors."""

import numpy as np
import pytest

from isotween import Shape, check_compatible, resample
from isotween.errors import IncompatibleShapesError, ParameterError, ShapeError


def irregular_ring(k=37, seed=1):
    """A star-shaped ring with no symmetry (uneven angles and radii)."""
    rng = np.random.default_rng(seed)
    th = np.sort(rng.uniform(0, 2 * np.pi, k))
    r = 1 + 0.4 * rng.uniform(size=k)
    return np.c_[r * np.cos(th), 0.7 * r * np.sin(th)]


def complex_of(p):
    return p[:, 0] + 1j * p[:, 1]


def points_of(z):
    return np.c_[z.real, z.imag]


@pytest.mark.parametrize("restart", [0, 5, 29])
@pytest.mark.parametrize("rotation", [0.0, 2.5])
def test_restarted_reversed_moved_copy_matches_exactly(restart, rotation):
    ring = irregular_ring()
    a = 1.7 * np.exp(1j * rotation)  # scale and rotation
    copy = points_of(np.roll(complex_of(ring)[::-1], restart) * a + (3 - 2j))
    src, tgt = resample(ring, copy, points=50, rotation=rotation != 0)
    # found start and orientation exactly: the target samples are the moved source samples
    np.testing.assert_allclose(tgt.z, src.z * a + (3 - 2j), atol=1e-9)
    np.testing.assert_array_equal(src.vertices[0], ring[0])
    check_compatible(src, tgt)
    assert src.paths[0][1] and tgt.paths[0][1]


def test_samples_are_uniform_in_arc_length():
    square = np.array([[0, 0], [2, 0], [2, 2], [0, 2.0]])
    triangle = np.array([[5, 5], [5, 9], [8, 5.0]])  # perimeter 12
    src, tgt = resample(square, triangle, points=12)
    expected = [[0, 0], [2 / 3, 0], [4 / 3, 0], [2, 0], [2, 2 / 3], [2, 4 / 3], [2, 2], [4 / 3, 2],
                [2 / 3, 2], [0, 2], [0, 4 / 3], [0, 2 / 3]]
    np.testing.assert_allclose(src.vertices, expected, atol=1e-12)
    # one unit of arc between samples: 9 steps along a side, 3 cutting a corner
    steps = np.abs(np.diff(np.append(tgt.z, tgt.z[0])))
    assert np.sum(np.isclose(steps, 1.0, rtol=0, atol=1e-12)) >= 9 and np.all(steps <= 1 + 1e-12)


def test_open_polyline_is_reversed_when_that_matches_better():
    t = np.linspace(0, 1, 9)
    line = np.c_[t, t**2]
    src, tgt = resample(line, line[::-1] + [4, 0], points=20, closed=False)
    np.testing.assert_allclose(tgt.vertices, src.vertices + [4, 0], atol=1e-12)
    np.testing.assert_allclose(src.vertices[[0, -1]], [[0, 0], [1, 1]])
    assert not src.paths[0][1] and src.n_edges == 19


def test_points_are_shared_in_proportion_to_length():
    big = np.array([[0, 0], [3, 0], [3, 3], [0, 3.0]])
    small = np.array([[1, 1], [2, 1], [2, 2], [1, 2.0]])
    src, tgt = resample([big, small], [big * 2, small * 2], points=100)
    assert [len(p) for p, _ in src.paths] == [75, 25] == [len(p) for p, _ in tgt.paths]
    src, _ = resample([big, small], [big, small], points=[10, 7])
    assert [len(p) for p, _ in src.paths] == [10, 7]


def test_corners_stay_sample_points():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    corners = {tuple(c) for c in square.tolist()}
    plain, _ = resample(square, square, points=10)
    kept, _ = resample(square, square, points=10, corners=45)
    assert not corners <= {tuple(v) for v in plain.vertices.tolist()}
    assert corners <= {tuple(v) for v in kept.vertices.tolist()}
    assert kept.n_vertices == 10


def test_shapes_with_paths_keep_ring_kinds():
    ring = Shape.from_polygon(irregular_ring())
    line = Shape.from_polyline(np.c_[np.arange(5.0), np.zeros(5)])
    both = Shape(np.vstack([ring.vertices, line.vertices + 10]),
                 np.vstack([ring.edges, line.edges + ring.n_vertices]),
                 paths=ring.paths + [(line.paths[0][0] + ring.n_vertices, False)])
    src, tgt = resample(both, both, points=40)
    assert [c for _, c in src.paths] == [True, False] == [c for _, c in tgt.paths]
    assert src.n_edges == 40 - 1


# ---------------------------------------------------------------- errors
def test_ring_with_too_few_points():
    with pytest.raises(ShapeError, match="target ring 1 has 2 distinct point"):
        resample([irregular_ring(), irregular_ring(seed=2)], [irregular_ring(), [[0, 0], [1, 1]]])


def test_unequal_ring_counts():
    with pytest.raises(IncompatibleShapesError, match="source has 2 ring.*target has 1"):
        resample([irregular_ring(), irregular_ring(seed=2)], [irregular_ring()])


def test_closed_against_open():
    with pytest.raises(IncompatibleShapesError, match="ring 0 is closed in the source but open"):
        resample(Shape.from_polygon(irregular_ring()), Shape.from_polyline(irregular_ring()))


def test_too_few_points_for_the_rings():
    with pytest.raises(ParameterError, match="points=5 is too few for 2 ring"):
        resample([irregular_ring()] * 2, [irregular_ring()] * 2, points=5)


def test_shape_without_paths():
    mesh = Shape.from_mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])
    with pytest.raises(ShapeError, match="no outline paths"):
        resample(mesh, mesh)
