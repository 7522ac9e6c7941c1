"""Metrics against values computed by hand from their definitions (SPEC.md)."""

import numpy as np
import pytest

from isotween import Sequence, interpolate, metrics
from shapes import ellipse, grid_mesh


def scaled_sequence(shape, s, frames=5):
    t = np.linspace(0, 1, frames)[:, None, None]
    c = shape.vertices.mean(axis=0)
    return Sequence(c + (shape.vertices - c) * (1 - t + t * s), shape)


@pytest.mark.parametrize("shape", [ellipse(), grid_mesh(4, 3)])
def test_area_and_length_deviation_of_uniform_scaling(shape):
    s = 3.0
    seq = scaled_sequence(shape, s)
    t = seq.times
    # lengths scale by (1 - t + t s): exactly the linear blend of end lengths
    assert metrics.edge_length_deviation(seq) < 1e-12
    # areas scale by (1 - t + t s)^2 against the blend (1 - t) + t s^2
    expected = np.abs((1 - t + t * s) ** 2 / ((1 - t) + t * s**2) - 1)
    np.testing.assert_allclose(metrics.area_deviation(seq, reduce=None), expected, atol=1e-12)
    assert metrics.area_deviation(seq) == pytest.approx(expected.max())


def test_flipped_faces_counts_sign_changes():
    mesh = grid_mesh(3, 2)  # 4 triangles
    frames = np.repeat(mesh.vertices[None], 4, axis=0)
    frames[1, :, 0] *= -1  # mirrored: every face flips
    frames[2, 0] = frames[2, 4] + (frames[2, 4] - frames[2, 0])  # fold one corner over
    seq = Sequence(frames, mesh)
    counts = metrics.flipped_faces(seq, reduce=None)
    assert counts[0] == 0 and counts[1] == mesh.n_faces and counts[3] == 0
    assert 1 <= counts[2] < mesh.n_faces
    assert metrics.flipped_faces(seq) == counts[1] + counts[2]
    assert metrics.flipped_faces(seq, reduce="max") == mesh.n_faces


def test_flips_are_told_against_the_shape_not_an_end_changed_after_solving():
    """A corner folded over in frame 0 alone (a hole collapsed there): the in-betweens, as the mesh, are not flipped."""
    mesh = grid_mesh(3, 2)
    frames = np.repeat(mesh.vertices[None], 4, axis=0)
    frames[0, 0] = frames[0, 4] + (frames[0, 4] - frames[0, 0])  # frame 0: one corner folded over
    seq = Sequence(frames, mesh)
    flipped = metrics.flipped(seq)
    assert flipped[0].any() and not flipped[1:].any()
    assert metrics.flipped_faces(seq) == 0
    frames[0] = mesh.vertices[0]  # frame 0 collapsed to one point: its flat faces tell nothing
    frames[1, :, 0] *= -1
    assert not metrics.flipped(Sequence(frames, mesh))[1].any()


def test_isometric_energy_zero_for_rigid_and_positive_for_stretch():
    src = ellipse()
    rot = src.with_vertices(src.vertices @ np.array([[0, -1], [1, 0]]).T)
    assert metrics.isometric_energy(interpolate(src, rot, frames=9)) < 1e-20
    assert metrics.isometric_energy(scaled_sequence(src, 2.0)) > 1e-3


def test_symmetry_error_of_a_symmetric_solver_and_report():
    src = grid_mesh(8, 3)
    tgt = src.with_vertices(src.vertices * [1.0, 1.5] + [[0.0, 0.1]] * np.arange(src.n_vertices)[:, None] % 1)
    seq = interpolate(src, tgt, frames=7)
    assert metrics.symmetry_error(seq) < 1e-9
    report = metrics.report(seq, symmetry=True)
    assert set(report) >= {"isometric_energy", "edge_length_deviation", "area_deviation",
                           "flipped_faces", "symmetry_error"}
    assert all(np.isfinite(v) for v in report.values())
