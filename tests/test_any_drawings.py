"""Every call that takes shapes takes any drawings: interpolate, keyframes, transfer, edit, compare (issue 22).

The drawings are one closed outline (an ellipse with a three-lobed bump: no
symmetry under a half turn) and copies of it turned, moved and sampled with
other point counts, written as SVG, so each call has to run the pipeline's
correspondence and the expected motion is known.
"""

import numpy as np
import pytest
from click.testing import CliRunner

import isotween
from isotween import Shape
from isotween.cli import main
from isotween.errors import IncompatibleShapesError, ParameterError

pytestmark = pytest.mark.filterwarnings("ignore::UserWarning")


def outline(k, turn_deg=0.0, shift=(0.0, 0.0), scale=1.0):
    """(k, 2) points of the test outline, turned about the origin, scaled and moved."""
    th = np.linspace(0, 2 * np.pi, k, endpoint=False)
    z = scale * (40 * np.cos(th) + 20j * np.sin(th) + 4 * np.cos(3 * th)) * np.exp(1j * np.deg2rad(turn_deg))
    z = z + complex(*shift)
    return np.c_[z.real, z.imag]


def write_svg(path, points):
    text = " ".join(f"{x:.12g},{y:.12g}" for x, y in points)
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg"><polygon points="{text}" fill="black"/></svg>')
    return path


def to_boundary(p, ring):
    """Distance from every point of p (m, 2) to the closed polygon ring (k, 2)."""
    a, b = ring, np.roll(ring, -1, axis=0)
    d = b - a
    t = np.clip(((p[:, None] - a) * d).sum(-1) / (d * d).sum(-1), 0, 1)
    return np.linalg.norm(p[:, None] - (a + t[..., None] * d), axis=-1).min(axis=1)


def hausdorff(frame, shape, ring):
    """Hausdorff distance between the outline of ``frame`` (vertices of ``shape``'s paths) and a ring."""
    idx = np.concatenate([i for i, _ in shape.paths])
    ours = frame[idx]
    return max(to_boundary(ours, ring).max(), to_boundary(ring, ours).max())


def diagonal(*rings):
    p = np.vstack(rings)
    return float(np.hypot(*(p.max(0) - p.min(0))))


def rigid_residual(p, q):
    """Largest distance left after the best rigid motion of p onto q, and its angle (degrees)."""
    z, w = p[:, 0] + 1j * p[:, 1], q[:, 0] + 1j * q[:, 1]
    z, w = z - z.mean(), w - w.mean()
    a = np.vdot(z, w)
    rot = a / abs(a)
    return float(np.abs(rot * z - w).max()), float(np.rad2deg(np.angle(rot)))


@pytest.fixture
def drawings(tmp_path):
    pytest.importorskip("svgelements")
    a = outline(48)
    b = outline(61, turn_deg=90, shift=(150, 20))  # the same drawing turned by 90 degrees, other point count
    return tmp_path, a, b, write_svg(tmp_path / "a.svg", a), write_svg(tmp_path / "b.svg", b)


def test_interpolate_two_svg_drawings_hits_both_and_turns_rigidly(drawings):
    _, a, b, pa, pb = drawings
    seq = isotween.interpolate(pa, pb, frames=5)
    assert seq.info["correspondence"].startswith("correspondence:")
    diag = diagonal(a, b)
    assert hausdorff(seq.frames[0], seq.shape, a) < 1e-3 * diag
    assert hausdorff(seq.frames[-1], seq.shape, b) < 1e-3 * diag
    # the middle frame is the drawing turned halfway, as rigid as the correspondence lets it be: the
    # points matched along two samplings (48 and 61 points) of one outline are a rigid copy only to
    # ~0.7 % of the diagonal, and the middle frame is half as far from one
    ends, _ = rigid_residual(seq.frames[0], seq.frames[-1])
    left, angle = rigid_residual(seq.frames[0], seq.frames[2])
    assert ends < 1e-2 * diag and left < 0.6 * ends and abs(abs(angle) - 45) < 0.5
    # the same as the pipeline's morph, and shapes loaded first give the same (they have paths, other counts)
    np.testing.assert_array_equal(isotween.morph(pa, pb, frames=5).frames, seq.frames)
    np.testing.assert_array_equal(isotween.interpolate(isotween.load(pa), isotween.load(pb), frames=5).frames,
                                  seq.frames)


def test_compatible_shapes_are_untouched_and_never_refuses_drawings(drawings):
    _, a, b, pa, pb = drawings
    src, tgt = Shape.from_polygon(a), Shape.from_polygon(outline(48, turn_deg=90))
    plain = isotween.interpolate(src, tgt, frames=5)
    assert "correspondence" not in plain.info and plain.shape is src
    np.testing.assert_array_equal(isotween.interpolate(src, tgt, frames=5, correspondence="never").frames,
                                  plain.frames)
    assert isotween.interpolate(src, tgt, frames=3, correspondence="always").shape.n_faces > 0
    with pytest.raises(IncompatibleShapesError, match="not compatible.*correspondence='auto'"):
        isotween.interpolate(pa, pb, frames=3, correspondence="never")
    with pytest.raises(IncompatibleShapesError, match="48 vertices but target has 61"):
        isotween.interpolate(src, Shape.from_polygon(b), correspondence="never")
    with pytest.raises(ParameterError, match="correspondence must be one of"):
        isotween.interpolate(src, tgt, correspondence="sometimes")


def test_keyframes_of_three_drawings_pass_through_each(drawings):
    tmp, a, b, pa, pb = drawings
    mid = outline(55, turn_deg=45, shift=(75, -30))
    pm = write_svg(tmp / "m.svg", mid)
    seq = isotween.interpolate_keyframes([pa, pm, pb], frames=9)
    assert seq.info["correspondence"].startswith("correspondence:")
    diag = diagonal(a, mid, b)
    for k, ring in zip(seq.info["keyframe_indices"], (a, mid, b), strict=True):
        # several keys are resampled in arc length (`correspond_keys`), not joined vertex for vertex as two
        # drawings are, so a key is hit to within the sampling's chord error
        assert hausdorff(seq.frames[k], seq.shape, ring) < 5e-3 * diag
    result = CliRunner().invoke(main, ["keyframes", str(pa), str(pm), str(pb), "--frames", "9",
                                       "-o", str(tmp / "keys.npz")])
    assert result.exit_code == 0, result.output
    assert "correspondence:" in result.output
    np.testing.assert_array_equal(isotween.load_sequence(tmp / "keys.npz").frames, seq.frames)


def test_keyframes_of_drawings_with_equal_counts_are_corresponded(tmp_path):
    # the same drawing written from another start: the point order means nothing, so correspondence runs (point
    # by point in path order the outline would turn through itself) and the keys stand still
    pa = write_svg(tmp_path / "a.svg", outline(60))
    pb = write_svg(tmp_path / "b.svg", np.roll(outline(60), 17, axis=0))
    seq = isotween.interpolate_keyframes([pa, pb, pa], frames=7)
    assert seq.info["correspondence"].startswith("correspondence:")
    np.testing.assert_allclose(seq.frames, np.broadcast_to(seq.frames[0], seq.frames.shape), atol=1e-9)
    keys = [isotween.Shape.from_polygon(outline(60)), isotween.Shape.from_polygon(np.roll(outline(60), 17, axis=0))]
    assert "correspondence" not in isotween.interpolate_keyframes(keys, frames=3).info  # shapes: as given


def test_transfer_onto_a_drawing_moves_it_like_the_source(drawings):
    tmp, a, b, pa, pb = drawings
    small = outline(37, scale=0.5, shift=(0, 100))  # a similar copy with another point count
    pt = write_svg(tmp / "t.svg", small)
    seq = isotween.transfer(pa, pb, pt, frames=5)
    assert seq.info["correspondence"].startswith("correspondence:")
    diag = diagonal(small)
    assert hausdorff(seq.frames[0], seq.shape, small) < 5e-3 * diag  # resampled, as keyframes are
    # the last frame is the small copy turned by 90 degrees as the source turned (up to where it went)
    last = seq.frames[-1] - seq.frames[-1].mean(0)
    turned = outline(37, turn_deg=90, scale=0.5)
    assert hausdorff(last, seq.shape, turned - turned.mean(0)) < 1e-2 * diag
    result = CliRunner().invoke(main, ["transfer", str(pa), str(pb), str(pt), "--frames", "5",
                                       "-o", str(tmp / "t.npz")])
    assert result.exit_code == 0, result.output
    # the same morph (to rounding: a first call may run numpy where a later one runs the numba kernels)
    np.testing.assert_allclose(isotween.load_sequence(tmp / "t.npz").frames, seq.frames, rtol=0, atol=1e-9 * diag)


def test_edit_with_a_drawing_of_other_connectivity(drawings):
    tmp, a, b, pa, pb = drawings
    seq = isotween.interpolate(pa, pb, frames=5)
    # the middle frame's outline, stretched and sampled afresh with another point count
    ring = seq.frames[2][seq.shape.paths[0][0]]
    dense = np.stack([ring, 0.5 * (ring + np.roll(ring, -1, axis=0))], axis=1).reshape(-1, 2)[::3]
    centre = ring.mean(0)
    bulged = centre + (dense - centre) * [1.15, 1.0]
    assert len(bulged) != len(ring)
    pe = write_svg(tmp / "edited.svg", bulged)
    edited = isotween.edit(seq, frame=2, shape=pe)
    assert edited.shape is seq.shape and edited.frames.shape == seq.frames.shape
    assert hausdorff(edited.frames[2], seq.shape, bulged) < 1e-2 * diagonal(bulged)
    np.testing.assert_array_equal(edited.frames[0], seq.frames[0])  # the ends are held
    seq.save(tmp / "seq.npz")
    result = CliRunner().invoke(main, ["edit", str(tmp / "seq.npz"), "--frame", "2", "--shape", str(pe),
                                       "-o", str(tmp / "e.npz")])
    assert result.exit_code == 0, result.output
    np.testing.assert_allclose(isotween.load_sequence(tmp / "e.npz").frames, edited.frames, atol=1e-9)
    with pytest.raises(IncompatibleShapesError, match="edited frame 2"):
        isotween.edit(seq, frame=2, shape=Shape.from_polygon(bulged), correspondence="never")


def test_compare_takes_two_drawings(drawings):
    _, a, b, pa, pb = drawings
    rows = isotween.compare(pa, pb, methods=("aiap", "linear"), frames=3)
    assert [r["method"] for r in rows] == ["aiap", "linear"]


def test_edit_refuses_a_shape_without_paths_of_other_connectivity_and_says_what_to_give(tmp_path):
    from shapes import grid_mesh

    bar = grid_mesh(5, 3)
    seq = isotween.interpolate(bar, bar.rotate(0.5), frames=4)
    isotween.save(grid_mesh(4, 3), tmp_path / "other.obj")
    with pytest.raises(IncompatibleShapesError, match=r"other.obj \(edited frame 1\).*drawing with paths"):
        isotween.edit(seq, edits={1: tmp_path / "other.obj"})


def test_the_older_steps_live_in_the_library():
    from isotween.pipeline import prepare_steps

    theta = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    a = np.c_[np.cos(theta), np.sin(theta)]
    b = np.c_[2 * np.cos(theta[::2]), np.sin(theta[::2])]
    done = prepare_steps(a, b, resample=30)
    isotween.check_compatible(done.source, done.target)
    assert done.source.n_vertices == 30 and not done.built_meshes and done.notes == []
    with pytest.raises(ParameterError):
        prepare_steps(a, b)


def test_loaded_drawings_with_matching_counts_are_still_corresponded(tmp_path):
    # two SVG drawings whose rings happen to have the same point count: their point order means nothing,
    # loaded or not (a circle turned a quarter, its path starting elsewhere, must not be morphed point by point)
    pytest.importorskip("svgelements")
    theta = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    ring = np.c_[10 + 5 * np.cos(theta), 10 + 3 * np.sin(theta)]
    turned = 10 + (ring - 10) @ [[0, 1], [-1, 0]]
    files = []
    for name, pts in (("a", ring), ("b", np.roll(turned, 7, axis=0))):
        d = "M" + " L".join(f"{x:.6f} {y:.6f}" for x, y in pts) + " Z"
        f = tmp_path / f"{name}.svg"
        f.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 20 20"><path d="{d}"/></svg>')
        files.append(f)
    a, b = isotween.load(files[0]), isotween.load(files[1])
    assert a.drawing and b.drawing and a.with_vertices(a.vertices).drawing
    isotween.check_compatible(a, b)  # the counts match ...
    seq = isotween.morph(a, b, frames=5)
    assert seq.info["correspondence"]  # ... and correspondence ran all the same
    mid = seq.frames[2][seq.shape.paths[0][0]]
    # a quarter turn halfway is an eighth turn: the middle frame's outline is the same ellipse, turned
    centre = mid.mean(axis=0)
    r = np.hypot(*(mid - centre).T)
    assert r.max() < 5.05 and r.min() > 2.95
    plain = Shape.from_polygon(ring)
    assert not plain.drawing


# ---------------------------------------------------------------- drawings in different units (--fit)
def stroked_svg(path, points, width):
    text = " ".join(f"{x:.12g},{y:.12g}" for x, y in points)
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg"><polygon points="{text}" fill="black"/>'
                    f'<polygon points="{text}" fill="none" stroke="black" stroke-width="{width}"/></svg>')
    return path


def test_fit_scales_a_drawing_in_other_units_onto_the_source(tmp_path):
    # the same drawing in a 32 times larger set of units, elsewhere, written from another start: fitted into the
    # source's box it is the source, its stroke as wide, so the morph stands still
    small = stroked_svg(tmp_path / "small.svg", outline(60), 1.5)
    large = stroked_svg(tmp_path / "large.svg", np.roll(outline(60, scale=32.0, shift=(9000.0, -700.0)), 17, axis=0),
                        48.0)
    seq = isotween.morph(small, large, frames=5, fit=True)
    assert "notes" not in seq.info
    for frame in seq.frames:
        np.testing.assert_allclose(frame, seq.frames[0], atol=1e-6 * seq.shape.bbox_diagonal())
    stroke = isotween.pipeline.fitted(isotween.load(large), isotween.load(small)).paint[1]
    assert stroke.stroke is not None and np.isclose(stroke.stroke_width, 48.0 / 32)
    # unfitted, each keeps its own units, and a note says how to fit them
    seq = isotween.morph(small, large, frames=5)
    assert np.ptp(seq.frames[-1], axis=0).max() > 30 * np.ptp(seq.frames[0], axis=0).max()
    assert len(seq.info["notes"]) == 1 and "32 times" in seq.info["notes"][0] and "fit" in seq.info["notes"][0]


def test_no_size_hint_within_the_similarities_a_morph_recovers(tmp_path):
    a = write_svg(tmp_path / "a.svg", outline(60))
    b = write_svg(tmp_path / "b.svg", outline(70, turn_deg=30, scale=2.0))
    assert "notes" not in isotween.morph(a, b, frames=3).info


def test_fit_keyframes_and_transfer(tmp_path):
    # keyframes: the same drawing in 32 times larger units comes back fitted onto the first, so nothing moves;
    # transfer: a drawing that stands still moves a large copy of itself not at all either (the test outline
    # with a bump on one side: no half turn maps it onto itself)
    th = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    bump = np.c_[40 * np.cos(th) + 6 * np.cos(2 * th), 20 * np.sin(th)]
    small = write_svg(tmp_path / "small.svg", bump)
    large = write_svg(tmp_path / "large.svg", np.roll(32 * bump + [900.0, -70.0], 17, axis=0))
    seq = isotween.interpolate_keyframes([small, large, small], frames=7, fit=True)
    np.testing.assert_allclose(seq.frames, np.broadcast_to(seq.frames[0], seq.frames.shape),
                               atol=1e-6 * seq.shape.bbox_diagonal())
    moved = isotween.transfer(small, large, large, frames=5, fit=True)
    np.testing.assert_allclose(moved.frames[-1], moved.frames[0], atol=1e-6 * moved.shape.bbox_diagonal())
    np.testing.assert_allclose(np.ptp(moved.frames[0], axis=0), np.ptp(bump, axis=0), rtol=1e-3)  # resampled
    out = tmp_path / "keys.npz"
    run = CliRunner().invoke(main, ["keyframes", str(small), str(large), "-o", str(out), "-n", "3", "--fit"])
    assert run.exit_code == 0, run.output
    np.testing.assert_allclose(np.ptp(isotween.load_sequence(out).frames[-1], axis=0), np.ptp(bump, axis=0),
                               rtol=1e-3)


def test_fit_on_the_command_line(tmp_path):
    small = write_svg(tmp_path / "small.svg", outline(60))
    large = write_svg(tmp_path / "large.svg", outline(60, scale=40.0))
    out = tmp_path / "out.npz"
    plain = CliRunner().invoke(main, ["interpolate", str(small), str(large), "-o", str(out), "-n", "3"])
    assert plain.exit_code == 0 and "40 times" in plain.output and "--fit" in plain.output
    fit = CliRunner().invoke(main, ["interpolate", str(small), str(large), "-o", str(out), "-n", "3", "--fit"])
    assert fit.exit_code == 0 and "times the size" not in fit.output
    np.testing.assert_allclose(np.ptp(isotween.load_sequence(out).frames[-1], axis=0), np.ptp(outline(60), axis=0),
                               rtol=1e-9)
    wrong = CliRunner().invoke(main, ["interpolate", str(small), str(large), "-o", str(tmp_path / "x.npz"),
                                      "--fit", "--resample", "40"])
    assert wrong.exit_code == 2 and "--fit" in wrong.output and not (tmp_path / "x.npz").exists()


def test_a_vanishing_hole_meets_at_the_centre_of_its_stars_kernel():
    # a plus-shaped star round one vertex: its kernel is the middle square, whose largest inscribed circle is
    # centred on the plus's centre; the point keeps every triangle of the star turned as it was
    from isotween.geometry import triangle_areas
    from isotween.pipeline import _kernel_point

    arm = np.array([3 - 1j, 3 + 1j, 1 + 1j])  # the right arm and the inner corner after it
    plus = np.concatenate([arm * 1j ** k for k in range(4)])
    for centre in (0j, 5 + 2j):
        z = np.r_[plus + centre, centre + 0.5 + 0.3j]  # the star's vertex off the centre, inside the kernel
        h = len(plus)
        star = np.c_[np.full(len(plus), h), np.arange(len(plus)), (np.arange(len(plus)) + 1) % len(plus)]
        assert np.all(triangle_areas(z, star) > 0)
        p = _kernel_point(z, star, np.array([h]))
        assert abs(p - centre) < 1e-4
        moved = z.copy()
        moved[h] = p
        assert np.all(triangle_areas(moved, star) > 0)
