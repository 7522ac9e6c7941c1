"""Baselines: each method's defining property, and clear errors for shapes it cannot take."""

import numpy as np
import pytest

from isotween import Shape, interpolate, metrics
from isotween.baselines import run
from isotween.baselines.intrinsic import path_edges
from isotween.errors import MethodError
from shapes import bend, ellipse, grid_mesh, rotation


def moved(shape, deg, scale=1.0, shift=(0.0, 0.0)):
    return shape.with_vertices(scale * shape.vertices @ rotation(deg).T + shift)


def wavy_polyline(k, amplitude):
    x = np.linspace(0.0, 3.0, k)
    return Shape.from_polyline(np.c_[x + 0.1 * np.sin(5 * x), amplitude * np.sin(2 * x)])


def test_linear_is_exact_lerp_at_given_times():
    src = ellipse()
    tgt = moved(src, 70, 1.5, (2.0, -1.0))
    t = np.array([0.0, 0.1, 0.5, 0.55, 1.0])
    seq = interpolate(src, tgt, frames=5, times=t, method="linear")
    expect = (1 - t)[:, None, None] * src.vertices + t[:, None, None] * tgt.vertices
    np.testing.assert_allclose(seq.frames, expect, rtol=0, atol=1e-14)
    assert seq.method == "linear" and np.array_equal(seq.times, t)


def _turning(e):
    return np.angle(e[:, 1:] / e[:, :-1])


def test_intrinsic_polyline_blends_lengths_and_turning_angles():
    src, tgt = wavy_polyline(15, 0.3), moved(wavy_polyline(15, -0.8), 120, 0.7, (1.0, 2.0))
    seq = interpolate(src, tgt, frames=6, method="intrinsic")
    t = seq.times[:, None]
    idx, closed = src.paths[0]
    e = path_edges(seq.z, idx, closed)
    np.testing.assert_allclose(np.abs(e), (1 - t) * np.abs(e[:1]) + t * np.abs(e[-1:]), atol=1e-12)
    np.testing.assert_allclose(_turning(e), (1 - t) * _turning(e[:1]) + t * _turning(e[-1:]), atol=1e-12)
    first = np.angle(e[:, 0] / e[0, 0])  # the first edge turns at a constant rate
    np.testing.assert_allclose(first, seq.times * first[-1], atol=1e-12)


def test_intrinsic_polygon_closes_with_blended_turning_angles():
    src = ellipse(20)
    th = np.linspace(0, 2 * np.pi, 20, endpoint=False)
    tgt = Shape.from_polygon((1 + 0.3 * np.cos(2 * th) + 0.2 * np.sin(th))[:, None] * np.c_[np.cos(th), np.sin(th)])
    seq = interpolate(src, tgt, frames=7, method="intrinsic")
    t = seq.times[:, None]
    idx, closed = src.paths[0]
    e = path_edges(seq.z, idx, closed)  # includes the closing edge
    ring = np.concatenate([e, e[:, :1]], axis=1)  # every turning angle, also at the closing vertices
    np.testing.assert_allclose(_turning(ring), (1 - t) * _turning(ring[:1]) + t * _turning(ring[-1:]),
                               atol=1e-10)
    assert seq.info["closure_correction"] > 1e-3  # these lengths alone would not close the ring


def test_intrinsic_of_similar_polygons_needs_no_closure_correction():
    src = ellipse(16)
    tgt = moved(src, 50, 2.0, (3.0, 1.0))
    seq = interpolate(src, tgt, frames=5, method="intrinsic")
    assert seq.info["closure_correction"] < 1e-12
    # the blend of a similarity is the similarity with blended scale and angle
    for k, t in enumerate(seq.times):
        zc = seq.z[k] - seq.z[k].mean()
        expect = (1 - t + 2 * t) * np.exp(1j * np.deg2rad(50) * t) * (src.z - src.z.mean())
        np.testing.assert_allclose(zc, expect, atol=1e-12)


def test_intrinsic_needs_polygons_or_polylines():
    mesh = grid_mesh(4, 3)
    with pytest.raises(MethodError, match="polygons or polylines"):
        interpolate(mesh, mesh, frames=3, method="intrinsic")


def test_arap_reproduces_a_rigid_rotation_exactly():
    src = grid_mesh(6, 4)
    tgt = moved(src, 150, 1.0, (5.0, 2.0))
    for method in ("arap", "arap-baxter"):
        seq = interpolate(src, tgt, frames=7, method=method)
        c0, c1 = src.z.mean(), tgt.z.mean()
        for k, t in enumerate(seq.times):
            expect = np.exp(1j * np.deg2rad(150) * t) * (src.z - c0) + (1 - t) * c0 + t * c1
            np.testing.assert_allclose(seq.z[k], expect, atol=1e-12)


def test_arap_needs_a_triangle_mesh():
    soup = ellipse()
    for method in ("arap", "arap-baxter"):
        with pytest.raises(MethodError, match="needs a triangle mesh"):
            interpolate(soup, soup, frames=3, method=method)


def test_baxter_removes_the_inconsistent_rotation_artefact_of_plain_arap():
    src = grid_mesh(30, 3, length=6.0, width=0.5)
    tgt = src.with_vertices(bend(src.vertices, 1.5 * np.pi))  # curled by 270 degrees
    plain = interpolate(src, tgt, frames=9, method="arap")
    baxter = interpolate(src, tgt, frames=9, method="arap-baxter")
    assert baxter.info["rotation_span"] > np.pi  # the triangles' rotations span more than 180 deg
    assert metrics.flipped_faces(plain) > 0
    assert metrics.flipped_faces(baxter) == 0
    assert metrics.edge_length_deviation(baxter) < 0.01


def test_shapespace_lowers_its_energy_monotonically_and_beats_linear():
    src = grid_mesh(20, 3)
    tgt = src.with_vertices(bend(src.vertices, np.pi))
    energies = []
    seq = interpolate(src, tgt, frames=9, method="shapespace",
                      callback=lambda it, energy, move: energies.append(energy))
    history = [seq.info["initial_energy"], *seq.energy]
    assert seq.converged and seq.iterations >= 2 and energies == seq.energy
    assert np.all(np.diff(history) <= 0) and history[-1] < 0.2 * history[0]
    linear = interpolate(src, tgt, frames=9, method="linear")
    assert metrics.isometric_energy(seq) < 0.05 * metrics.isometric_energy(linear)
    assert metrics.edge_length_deviation(seq) < 0.1 * metrics.edge_length_deviation(linear)
    np.testing.assert_array_equal(seq.frames[[0, -1]], linear.frames[[0, -1]])


def test_unknown_method():
    src = ellipse()
    with pytest.raises(MethodError, match="unknown method 'morph'"):
        run("morph", src, src, 3)
