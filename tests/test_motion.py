"""Relative velocity fields, shape transfer, sequence editing and keyframes."""

import numpy as np
import pytest

import isotween
from isotween import interpolate, metrics
from isotween.editing import edit
from isotween.errors import IncompatibleShapesError, ParameterError
from isotween.keyframes import interpolate_keyframes
from isotween.transfer import transfer
from isotween.velocity import relative_velocity_field
from shapes import bend, grid_mesh


@pytest.fixture(scope="module")
def bar():
    src = grid_mesh(20, 3, length=4.0, width=0.4)
    return src, src.with_vertices(bend(src.vertices, np.pi))


def similar(shape, a, b):
    z = a * shape.z + b
    return shape.with_vertices(np.c_[z.real, z.imag])


def test_velocity_field_of_a_rigid_rotation_is_isometric():
    src = grid_mesh(5, 3)
    seq = interpolate(src, similar(src, np.exp(1j * 2.0), 1 + 1j), frames=11)
    field = relative_velocity_field(seq)
    assert field.velocities.shape == (src.n_edges, 10)
    # constant angular speed 2 rad per unit time on every edge, no isometric residual
    assert np.allclose(field.angular_speeds, 2 * np.tan(0.1) / 0.1, rtol=1e-9)
    assert np.max(np.abs(field.isometric_residual())) < 1e-9


def test_transfer_onto_the_source_itself_reproduces_it(bar):
    src, tgt = bar
    seq = interpolate(src, tgt, frames=9)
    out = transfer(src, tgt, src, frames=9)
    np.testing.assert_allclose(out.frames, seq.frames, atol=1e-9)


def test_transfer_is_similarity_equivariant(bar):
    src, tgt = bar
    a, b = 1.7 * np.exp(0.8j), 3 - 2j
    seq = interpolate(src, tgt, frames=9)
    out = transfer(src, tgt, similar(src, a, b), frames=9)
    expected = a * seq.z + b
    np.testing.assert_allclose(out.z, expected, atol=1e-9)


def turning_angles(z, path):
    d = np.diff(z[path])
    return np.angle(d[1:] / d[:-1])


def test_transfer_bends_a_thicker_bar(bar):
    src, tgt = bar
    thick = src.with_vertices(src.vertices * [1.0, 2.5])
    out = transfer(src, tgt, thick, frames=9)
    assert metrics.flipped_faces(out) == 0
    # compare the turning along the middle row of the bar in the end pose
    mid = np.flatnonzero(np.isclose(src.vertices[:, 1], 0.2))
    want = turning_angles(tgt.z, mid)
    got = turning_angles(out.z[-1], mid)
    assert np.max(np.abs(got - want)) < 0.05  # radians per joint
    assert abs(got.sum() - want.sum()) < 0.1


def test_edit_with_unchanged_frame_returns_the_input(bar):
    seq = interpolate(*bar, frames=9)
    out = edit(seq, frame=4, shape=seq[4])
    np.testing.assert_allclose(out.frames, seq.frames, atol=1e-9)


def test_edit_rigid_move_is_matched_and_fades(bar):
    seq = interpolate(*bar, frames=13)
    k = 6
    moved = similar(seq[k], np.exp(0.5j), 0.3 + 0.2j)
    out = edit(seq, frame=k, shape=moved)
    np.testing.assert_allclose(out.frames[k], moved.vertices, atol=1e-9)
    change = np.linalg.norm(out.frames - seq.frames, axis=-1).max(axis=1)
    assert change[0] < 1e-9 and change[-1] < 1e-9
    # change decreases monotonically away from the edited frame, and smoothly
    assert np.all(np.diff(change[: k + 1]) > 0) and np.all(np.diff(change[k:]) < 0)
    # no step in the change is more than 25 % above the even spread change[k] / k
    assert np.max(np.abs(np.diff(change))) <= 1.25 * change[k] / k


def test_edit_several_frames_and_paper_mode(bar):
    seq = interpolate(*bar, frames=9)
    e2, e6 = similar(seq[2], np.exp(-0.3j), 1j), similar(seq[6], 1.2, 0)
    out = edit(seq, edits={2: e2, 6: e6})
    np.testing.assert_allclose(out.frames[2], e2.vertices, atol=1e-9)
    np.testing.assert_allclose(out.frames[6], e6.vertices, atol=1e-9)
    # the paper's procedure (one edit, ends free): every frame moves by the similarity
    a, b = np.exp(0.7j), 2 + 1j
    paper = edit(seq, frame=4, shape=similar(seq[4], a, b), keep_ends=False)
    c = seq.z.mean(axis=1, keepdims=True)
    np.testing.assert_allclose(paper.z - paper.z.mean(axis=1, keepdims=True), a * (seq.z - c), atol=1e-9)


def test_edit_bad_input(bar):
    seq = interpolate(*bar, frames=5)
    with pytest.raises(ParameterError, match="frame index 7 is out of range"):
        edit(seq, frame=7, shape=seq[1])
    with pytest.raises(IncompatibleShapesError, match="edited frame 1"):
        edit(seq, frame=1, shape=grid_mesh(4, 3))


def test_two_keyframes_equal_interpolate(bar):
    a = interpolate_keyframes(list(bar), frames=9)
    b = interpolate(*bar, frames=9)
    np.testing.assert_allclose(a.frames, b.frames, atol=1e-12)


def test_keyframes_pass_through_and_turn_smoothly(bar):
    src, _ = bar
    k1 = src.with_vertices(bend(src.vertices, np.pi / 2))
    k2 = similar(src.with_vertices(bend(src.vertices, 1.2 * np.pi)), np.exp(0.7j), 2 + 3j)
    seq = interpolate_keyframes([src, k1, k2], frames=17)
    idx = seq.info["keyframe_indices"]
    for i, k in zip(idx, (src, k1, k2), strict=False):
        np.testing.assert_array_equal(seq.frames[i], k.vertices)

    def jump(s, i):
        v = np.diff(s.frames, axis=0)
        return np.linalg.norm(v[i] - v[i - 1], axis=-1).max()

    glued = interpolate_keyframes([src, k1, k2], frames=17, smooth=0.0)
    i = idx[1]
    # the velocity jump at the keyframe is far below the glued runs' and no
    # larger than twice the largest acceleration elsewhere in the sequence
    accel = max(jump(seq, j) for j in range(1, 16) if j != i)
    assert jump(seq, i) < 0.35 * jump(glued, i)
    assert jump(seq, i) < 2.0 * accel


def test_keyframe_times_and_easing(bar):
    src, tgt = bar
    seq = interpolate_keyframes([src, tgt], frames=9, easing="ease-in-out")
    assert np.all(np.diff(seq.times) > 0) and seq.times[1] < 1 / 8
    custom = interpolate_keyframes([src, tgt], frames=9, easing=lambda s: s**3)
    np.testing.assert_allclose(custom.times, np.linspace(0, 1, 9) ** 3)
    for kw, words in [({"times": [0, 0.6, 0.4, 1]}, "increase strictly"),
                      ({"easing": lambda s: np.cos(s)}, "easing curve"),
                      ({"easing": "bouncy"}, "unknown easing"),
                      ({"frames": 3}, "frames must be")]:
        with pytest.raises(ParameterError, match=words):
            interpolate_keyframes([src, tgt, tgt, src], **kw)
    with pytest.raises(ParameterError, match="at least two keyframes"):
        interpolate_keyframes([src])
    with pytest.raises(IncompatibleShapesError, match="keyframe 1"):
        interpolate_keyframes([src, grid_mesh(4, 3)])


def test_keyframes_with_another_method_or_solver_interpolate_each_segment():
    """method='linear' blends vertices within each segment; solver='global' passes through every key."""
    bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0], [3, 0]])
    keys = [bar, bar.rotate(0.8), bar.rotate(0.8).translate([2, 1]).scale(1.5)]
    seq = isotween.interpolate_keyframes(keys, frames=9, method="linear")
    idx = seq.info["keyframe_indices"]
    assert idx == [0, 4, 8]
    for j in range(2):
        a, b = idx[j], idx[j + 1]
        u = (seq.times[a : b + 1] - seq.times[a]) / (seq.times[b] - seq.times[a])
        expected = (1 - u)[:, None, None] * keys[j].vertices + u[:, None, None] * keys[j + 1].vertices
        np.testing.assert_allclose(seq.frames[a : b + 1], expected, atol=1e-12)
    glob = isotween.interpolate_keyframes(keys, frames=9, solver="global")
    for k, key in zip(idx, keys, strict=True):
        np.testing.assert_array_equal(glob.frames[k], key.vertices)
    # a rigid first segment keeps every edge length with the global solver too
    lengths = np.linalg.norm(np.diff(glob.frames[: idx[1] + 1], axis=1), axis=-1)
    np.testing.assert_allclose(lengths, 1.0, atol=1e-6)


def test_eased_times_is_the_one_name_of_the_easing_times():
    """`easing.eased_times` spaces frames by a curve; `times.frame_times` checks given times (a different job)."""
    from isotween import easing, times

    np.testing.assert_array_equal(easing.eased_times(5), times.frame_times(5))
    with pytest.warns(DeprecationWarning, match="eased_times"):
        old = easing.frame_times(5, "ease-in")
    np.testing.assert_array_equal(old, easing.eased_times(5, "ease-in"))
