"""Bezier outlines: one segment structure for all frames, within the tolerance in every frame, corners kept."""

import numpy as np
import pytest

from isotween.errors import ParameterError
from isotween.render.curves import curve_controls, fit_curves


def bezier_points(controls, n=64):
    """(F, S * n, 2) points on the curves of (F, S, 4, 2) controls."""
    u = np.linspace(0.0, 1.0, n)[:, None]
    b = np.stack([(1 - u) ** 3, 3 * (1 - u) ** 2 * u, 3 * (1 - u) * u ** 2, u ** 3], axis=-1)[:, 0]  # (n, 4)
    return np.einsum("nc,fscd->fsnd", b, controls).reshape(len(controls), -1, 2)


def polyline_distance(points, ring):
    """(F, m) distance from every point to the polyline ``ring`` (F, k, 2) of the same frame."""
    a, b = ring[:, :-1], ring[:, 1:]
    d = b - a
    rel = points[:, :, None] - a[:, None]
    s = np.clip((rel * d[:, None]).sum(-1) / np.maximum((d * d).sum(-1), 1e-300)[:, None], 0, 1)
    return np.linalg.norm(rel - s[..., None] * d[:, None], axis=-1).min(axis=2)


def wobbly_frames(k=120, frames=6, seed=3):
    """A closed wobbly blob with one sharp corner, deforming over time: (F, k, 2)."""
    rng = np.random.default_rng(seed)
    a = np.linspace(0, 2 * np.pi, k, endpoint=False)
    out = []
    for f in range(frames):
        r = 1 + 0.2 * np.sin(3 * a + f * 0.4) + 0.05 * rng.standard_normal() * np.cos(5 * a)
        z = r * np.exp(1j * a) * np.exp(0.3j * f)
        z[0] = 1.6 * np.exp(0.3j * f)  # a spike: a corner in every frame
        out.append(np.column_stack([z.real, z.imag]))
    return np.array(out)


@pytest.mark.parametrize("closed", [True, False])
def test_curves_follow_every_frame_within_the_tolerance_with_one_structure(closed):
    frames = wobbly_frames()
    k = frames.shape[1]
    tol = 1e-3 * np.hypot(*np.ptp(frames.reshape(-1, 2), axis=0))
    [curve] = fit_curves(frames, [(np.arange(k), closed)], tolerance=tol)
    controls, err = curve_controls(curve, frames)
    assert controls.shape == (len(frames), curve.n_segments, 4, 2)
    assert curve.n_segments < k / 3  # a real reduction
    assert err.max() <= tol
    # segments join up, and a closed path ends where it starts
    np.testing.assert_array_equal(controls[:, 1:, 0], controls[:, :-1, 3])
    ends = frames[:, curve.indices[curve.breaks % k]]
    np.testing.assert_allclose(controls[:, :, 0], ends[:, :-1])
    np.testing.assert_allclose(controls[:, -1, 3], ends[:, -1])
    # the curve lies near the polyline everywhere, both ways
    ring = frames[:, np.append(curve.indices, curve.indices[0]) if closed else curve.indices]
    on_curve = bezier_points(controls)
    assert polyline_distance(on_curve, ring).max() <= 1.5 * tol
    assert polyline_distance(frames[:, curve.indices], on_curve[:, :, :]).max() <= 1.5 * tol
    # the spike is a corner: a break there
    assert 0 in (curve.indices[curve.breaks % k]) and curve.corner[0]


def test_smooth_joints_share_their_tangent_and_corners_stay_sharp():
    frames = wobbly_frames()
    k = frames.shape[1]
    [curve] = fit_curves(frames, [(np.arange(k), True)])
    controls = curve.controls(frames)
    out_dir = controls[:, 1:, 1] - controls[:, 1:, 0]
    in_dir = controls[:, :-1, 3] - controls[:, :-1, 2]
    cross = out_dir[..., 0] * in_dir[..., 1] - out_dir[..., 1] * in_dir[..., 0]
    smooth = ~curve.corner[1:-1] & ~curve.straight[1:] & ~curve.straight[:-1]
    assert smooth.any()
    norm = np.linalg.norm(out_dir, axis=-1) * np.linalg.norm(in_dir, axis=-1)
    np.testing.assert_allclose((cross / norm)[:, smooth], 0.0, atol=1e-9)


def test_a_square_keeps_its_four_corners_as_straight_sides():
    sq = np.array([[[0, 0], [1, 0], [1, 1], [0, 1]]], dtype=float)
    [curve] = fit_curves(sq, [(np.arange(4), True)])
    assert curve.n_segments == 4 and curve.corner.all() and curve.straight.all()
    np.testing.assert_allclose(curve.controls(sq)[0, :, 0], sq[0])


def test_bad_tolerance_is_a_parameter_error():
    with pytest.raises(ParameterError, match="tolerance"):
        fit_curves(wobbly_frames(), [(np.arange(4), True)], tolerance=-1.0)
