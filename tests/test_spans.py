"""Staggered timing: every piece moves over its own span of time; pieces with no partner leave before others come.

`interpolate(..., spans=...)` plays each connected piece's morph within its
own (start, end); `morph` gives a piece that vanishes the first half and one
that appears the last half (`pipeline.unmatched_spans`), with its paint; where the fold check cannot keep
the pieces apart, a shorter share, then none.
"""

import numpy as np
import pytest

import isotween
from isotween import Shape, metrics
from isotween.errors import ParameterError
from isotween.paint import Paint, sequence_paint


def two_bars(paint=None):
    """Two separate straight bars of 5 vertices (a polyline each)."""
    left = np.c_[np.linspace(0.0, 4.0, 5), np.zeros(5)]
    return Shape.from_paths([left, left + [0.0, 3.0]], closed=[False, False], paint=paint)


def turned(shape, angle):
    """Every path of ``shape`` turned by ``angle`` about its own centroid."""
    z = shape.z.copy()
    for idx, _ in shape.paths:
        c = z[idx].mean()
        z[idx] = c + (z[idx] - c) * np.exp(1j * angle)
    return shape.with_vertices(np.c_[z.real, z.imag])


def direction(frame, idx):
    """Angle of the first edge of the path ``idx`` in a (n, 2) frame."""
    d = frame[idx[1]] - frame[idx[0]]
    return np.arctan2(d[1], d[0])


def test_each_piece_turns_within_its_own_span():
    src = two_bars()
    tgt = turned(src, np.pi / 2)
    spans = np.tile([0.0, 1.0], (src.n_vertices, 1))
    late = src.paths[1][0]
    spans[late] = (0.5, 1.0)
    frames = 9
    seq = isotween.interpolate(src, tgt, frames=frames, spans=spans)
    t = np.linspace(0.0, 1.0, frames)
    np.testing.assert_allclose(seq.times, t)
    first = [direction(f, src.paths[0][0]) for f in seq.frames]
    second = [direction(f, late) for f in seq.frames]
    # a rigid turn is recovered exactly: the first bar over the whole morph, the second only after t = 0.5
    np.testing.assert_allclose(first, np.pi / 2 * t, atol=1e-6)
    np.testing.assert_allclose(second, np.pi / 2 * np.clip(2 * t - 1, 0, 1), atol=1e-6)
    assert metrics.edge_length_deviation(seq) < 1e-6
    # spans that need times off the frame grid (5 frames, a span of a third) are solved there
    spans[late] = (0.0, 1 / 3)
    seq = isotween.interpolate(src, tgt, frames=5, spans=spans)
    local = np.clip(np.linspace(0, 1, 5) * 3, 0, 1)
    np.testing.assert_allclose([direction(f, late) for f in seq.frames], np.pi / 2 * local, atol=1e-6)


def test_a_piece_paint_follows_its_span():
    src = two_bars([Paint(stroke=(0, 0, 0, 1)), Paint(stroke=(0, 0, 0, 1))])
    tgt = turned(two_bars([Paint(stroke=(0, 0, 0, 1)), Paint(stroke=(0, 0, 0, 1), opacity=0.0)]), 0.3)
    spans = np.tile([0.0, 1.0], (src.n_vertices, 1))
    spans[src.paths[1][0]] = (0.0, 0.5)
    seq = isotween.interpolate(src, tgt, frames=5, spans=spans)
    _, paints = sequence_paint(seq)
    assert [p[1].opacity for p in paints] == pytest.approx([1.0, 0.5, 0.0, 0.0, 0.0])
    assert [p[0].opacity for p in paints] == pytest.approx([1.0] * 5)
    # out of sight where it is drawn with opacity 0, and only there (what the fold check leaves out)
    from isotween.paint import out_of_sight

    assert out_of_sight(seq).tolist() == [[False, False]] * 2 + [[False, True]] * 3
    unpainted = isotween.interpolate(two_bars(), turned(two_bars(), 0.3), frames=5, spans=spans)
    assert not out_of_sight(unpainted).any()  # a piece at rest before its span is still drawn


def test_spans_are_checked():
    src = two_bars()
    tgt = turned(src, 0.3)
    n = src.n_vertices
    with pytest.raises(ParameterError, match=r"\(10, 2\)"):
        isotween.interpolate(src, tgt, spans=np.zeros((3, 2)))
    with pytest.raises(ParameterError, match="0 <= start < end <= 1"):
        isotween.interpolate(src, tgt, spans=np.tile([0.5, 0.5], (n, 1)))
    split = np.tile([0.0, 1.0], (n, 1))
    split[0] = (0.0, 0.5)
    with pytest.raises(ParameterError, match=r"edge \(0, 1\)"):
        isotween.interpolate(src, tgt, spans=split)


SQUARES = ('<path fill="#036" d="M1 1h5v5h-5z"/><path fill="#036" d="M10 10h5v5h-5z"/>')
ONE = '<path fill="#036" d="M1 1h6v5h-6z"/>'


def drawing(path, body):
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16">{body}</svg>')
    return str(path)


def test_a_vanishing_piece_is_gone_by_half_time(tmp_path):
    pytest.importorskip("svgelements")
    a, b = drawing(tmp_path / "two.svg", SQUARES), drawing(tmp_path / "one.svg", ONE)
    seq = isotween.morph(a, b, frames=11)
    prepared = isotween.prepare_pair(a, b)
    alternatives = isotween.pipeline.unmatched_spans(prepared.source, prepared.report)
    spans = alternatives[0]
    gone = np.flatnonzero(spans[:, 1] < 1)
    assert len(gone) and np.all(spans[gone] == (0.0, 0.5))
    # the shorter shares follow as the alternatives, for the same piece
    assert len(alternatives) == 1 + len(isotween.pipeline.QUICK_STAGGERS)
    for spans, share in zip(alternatives[1:], isotween.pipeline.QUICK_STAGGERS, strict=True):
        np.testing.assert_array_equal(np.flatnonzero(spans[:, 1] < 1), gone)
        assert np.all(spans[gone] == (0.0, share))
    # morph gives it its own span: it leaves before the square that stays comes to its place (t = 0.45)
    own = isotween.pipeline.unmatched_spans(prepared.source, prepared.report, target=prepared.target)[0]
    assert np.all(own[gone] == (0.0, 0.4))
    _, paints = sequence_paint(seq)
    path = next(k for k, (idx, _) in enumerate(seq.shape.paths) if idx[0] in gone)
    # shrunk and faded out by t = 0.4, then still until the last frame collapses it to a point
    assert [p[path].opacity for p in paints[4:]] == [0.0] * 7 and paints[3][path].opacity > 0
    for k in range(5, 10):
        np.testing.assert_allclose(seq.frames[k, gone], seq.frames[4, gone], atol=1e-9)
    # the piece that stays moves over the whole morph, as without staggering
    whole = isotween.morph(a, b, frames=11, stagger=1.0)
    stay = np.flatnonzero(spans[:, 1] == 1)
    np.testing.assert_allclose(seq.frames[:, stay], whole.frames[:, stay], atol=1e-6)
    assert np.abs(np.diff(whole.frames[5:10, gone], axis=0)).max() > 1e-3  # without it, it is still moving
    with pytest.raises(ParameterError, match="stagger"):
        isotween.morph(a, b, stagger=1.5)


def test_a_vanished_piece_is_one_point_with_every_triangle_flat(tmp_path):
    """The last frame collapses the whole piece that shrank away, its inner mesh vertices too."""
    pytest.importorskip("svgelements")
    turn = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    lobes = 3 * (1 + 0.3 * np.cos(3 * turn))
    blob = np.c_[16 + lobes * np.cos(turn), 5 + lobes * np.sin(turn)]
    square = [[0, 0], [10, 0], [10, 10], [0, 10]]

    def path(rings):
        return '<path d="' + " ".join("M" + " L".join(f"{x:.4f} {y:.4f}" for x, y in r) + " Z" for r in rings) + '"/>'

    a = drawing(tmp_path / "a.svg", path([square, blob]))
    b = drawing(tmp_path / "b.svg", path([[[0, 0], [0, 10], [12, 10], [12, 0]]]))
    seq = isotween.morph(a, b, frames=9)
    shape = seq.shape
    piece = next(k for k, (idx, _) in enumerate(shape.paths) if np.ptp(seq.frames[-1, idx], axis=0).max() == 0)
    members = shape.components == shape.components[shape.paths[piece][0][0]]
    assert members.sum() > len(shape.paths[piece][0])  # the piece's mesh has inner vertices
    assert np.ptp(seq.frames[-1, members], axis=0).max() == 0  # all of them at one point
    area = shape.face_areas(seq.frames[-1])
    assert np.all(area[members[shape.faces].all(axis=1)] == 0) and np.all(area >= 0)


def test_paths_out_of_sight_are_not_crossings():
    # a vertical bar crosses a horizontal one; it fades out by the middle frame
    bars = [[[0, 1], [4, 1]], [[2, 0], [2, 2]]]
    paint = [Paint(stroke=(0, 0, 0, 1)), Paint(stroke=(0, 0, 0, 1))]
    gone = [Paint(stroke=(0, 0, 0, 1)), Paint(stroke=(0, 0, 0, 1), opacity=0.0)]
    seq = isotween.interpolate(Shape.from_paths(bars, closed=False, paint=paint),
                               Shape.from_paths(bars, closed=False, paint=gone), frames=3)
    assert list(metrics.outline_crossings(seq)) == [1, 1, 1]
    assert list(metrics.outline_crossings(seq, visible=True)) == [1, 1, 0]


def test_a_stroke_with_no_partner_is_not_staggered(tmp_path):
    # it grows out of the nearest stroke, drawn as it is: held back, it would sit there as a dot
    pytest.importorskip("svgelements")
    lines = '<path d="M1 1h12M1 8h12" fill="none" stroke="#000" stroke-width="2"/>'
    a, b = drawing(tmp_path / "two.svg", lines), drawing(tmp_path / "one.svg", lines.replace("M1 8h12", ""))
    prepared = isotween.prepare_pair(a, b)
    assert prepared.report.lines["shrunk"] == 1
    assert isotween.pipeline.unmatched_spans(prepared.source, prepared.report) is None


def test_the_command_line_staggers_and_refuses_a_bad_share(tmp_path):
    pytest.importorskip("svgelements")
    from click.testing import CliRunner

    from isotween.cli import main

    a, b = drawing(tmp_path / "two.svg", SQUARES), drawing(tmp_path / "one.svg", ONE)
    bad = CliRunner().invoke(main, ["interpolate", a, b, "--stagger", "0", "-o", str(tmp_path / "bad.npz")])
    assert bad.exit_code == 2 and "stagger" in bad.output and not bad.output.startswith("correspondence")
    assert not (tmp_path / "bad.npz").exists()
    runs = {}
    for share in ("0.5", "1"):
        out = tmp_path / f"{share}.npz"
        assert CliRunner().invoke(main, ["interpolate", a, b, "-n", "11", "--stagger", share, "-q",
                                         "-o", str(out)]).exit_code == 0
        runs[share] = isotween.io.load_sequence(out)
    library = isotween.morph(a, b, frames=11)
    np.testing.assert_allclose(runs["0.5"].frames, library.frames, atol=1e-9)  # as the library does
    assert not np.allclose(runs["1"].frames, library.frames, atol=1e-6)


def bar_and_upright(tmp_path):
    """A bar and an upright above it, read from SVG and meshed (a Shape with two regions)."""
    pytest.importorskip("shapely")
    rings = [[(0, 0), (4, 0), (4, 0.5), (0, 0.5)], [(1.8, 1), (2.2, 1), (2.2, 5), (1.8, 5)]]  # a bar, an upright
    d = " ".join("M " + " L ".join(f"{x} {y}" for x, y in r) + " Z" for r in rings)
    (tmp_path / "a.svg").write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 4 5"><path d="{d}"/></svg>')
    return isotween.interpolate(tmp_path / "a.svg", tmp_path / "a.svg", frames=3).shape


def test_a_later_timing_whose_frames_are_clean_is_taken_before_repairing_the_first(tmp_path):
    src = bar_and_upright(tmp_path)
    tgt = src.translate([0.0, 6.0])  # both rise: together they never meet
    first = np.tile([0.0, 1.0], (src.n_vertices, 1))
    first[src.vertices[:, 1] > 0.75] = (0.5, 1.0)  # the upright waits: the bar rises through it
    waited = isotween.interpolate(src, tgt, frames=5, spans=first)
    assert metrics.outline_crossings(waited)[1:-1].any()
    together = np.tile([0.0, 1.0], (src.n_vertices, 1))
    seq = isotween.interpolate(src, tgt, frames=5, spans=[first, together], fold="fallback")
    np.testing.assert_allclose(seq.frames, isotween.interpolate(src, tgt, frames=5).frames, atol=1e-9)
    assert seq.info["spans"]["used"] == 1 and "fallback" not in seq.info


def test_a_later_timing_is_judged_with_its_own_pieces_out_of_sight(tmp_path, monkeypatch):
    mesh = bar_and_upright(tmp_path)
    up = mesh.vertices[:, 1] > 0.75
    fades = [bool(up[idx].all()) for idx, _ in mesh.paths]  # the upright fades out where it stands

    def drawn(vertices, out):
        paint = [Paint(fill=(0, 0, 0, 1), opacity=0.0 if out and f else 1.0) for f in fades]
        return Shape(vertices, mesh.edges, mesh.faces, paths=mesh.paths, regions=mesh.regions, paint=paint)

    src, tgt = drawn(mesh.vertices, False), drawn(mesh.vertices + np.where(up[:, None], 0.0, [0.0, 6.0]), True)
    slow, quick = np.tile([0.0, 1.0], (2, src.n_vertices, 1))
    slow[up], quick[up] = (0.5, 1.0), (0.0, 0.2)  # the bar rises through the upright, which fades late or soon
    gone = isotween.interpolate(src, tgt, frames=5, spans=quick)
    assert metrics.outline_crossings(gone)[1:-1].any() and not metrics.outline_crossings(gone, visible=True).any()
    from isotween.foldfree import repair

    tried, original = [], repair.repair_folds
    monkeypatch.setattr(repair, "repair_folds", lambda *a, **k: tried.append(1) or original(*a, **k))
    seq = isotween.interpolate(src, tgt, frames=5, spans=[slow, quick], fold="fallback")
    np.testing.assert_allclose(seq.frames, gone.frames, atol=1e-9)  # AIAP's own
    assert not tried  # taken before any repair of the first timing
    assert seq.info["spans"]["used"] == 1 and "fallback" not in seq.info


def test_alternative_spans_are_checked_and_the_first_is_kept_where_it_can_be():
    src = two_bars()
    tgt = turned(src, 0.3)
    first = np.tile([0.0, 1.0], (src.n_vertices, 1))
    first[src.paths[1][0]] = (0.5, 1.0)
    second = np.tile([0.0, 1.0], (src.n_vertices, 1))
    second[src.paths[1][0]] = (0.8, 1.0)
    seq = isotween.interpolate(src, tgt, frames=5, spans=[first, second], fold="fallback")
    one = isotween.interpolate(src, tgt, frames=5, spans=first)
    np.testing.assert_allclose(seq.frames, one.frames)  # nothing to repair: the first timing
    assert "spans" not in seq.info
    with pytest.raises(ParameterError, match=r"\(10, 2\)"):
        isotween.interpolate(src, tgt, spans=np.zeros((2, 3, 2)))
    bad = second.copy()
    bad[0] = (0.2, 0.1)
    with pytest.raises(ParameterError, match="0 <= start < end <= 1"):
        isotween.interpolate(src, tgt, spans=[first, bad])


def test_a_short_stagger_falls_back_to_the_whole_morph(tmp_path):
    pytest.importorskip("svgelements")
    a, b = drawing(tmp_path / "two.svg", SQUARES), drawing(tmp_path / "one.svg", ONE)
    prepared = isotween.prepare_pair(a, b)
    quick = isotween.pipeline.unmatched_spans(prepared.source, prepared.report, stagger=0.05)
    assert len(quick) == 2 and np.all(quick[1] == (0.0, 1.0))
    assert np.all(quick[0][quick[0][:, 1] < 1] == (0.0, 0.05))


def test_the_shares_tried_in_turn():
    shares = isotween.pipeline.stagger_shares
    assert shares(0.5) == [0.5, *isotween.pipeline.QUICK_STAGGERS]
    assert shares(0.15) == [0.15, 0.1] and shares(0.05) == [0.05, 1.0]


def test_the_fold_check_leaves_a_piece_out_of_sight_out():
    from isotween.foldfree.scaffold import Around
    from isotween.interpolate import _crossed

    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    shape = Shape.from_paths([square, square + [3, 0]], regions=[[0], [1]])
    z = shape.z
    ends = np.stack([z, z])
    onto = z.copy()
    onto[4:] -= 2.5 - 0.5j  # the second square over the first one's corner: their outlines cross
    hidden = lambda k: {1} if k == 2 else set()  # noqa: E731
    within, across = _crossed(shape, ends, hidden)
    assert across(1, onto) > 0 and across(2, onto) == 0 and within(2, onto) == 0
    around = Around(shape, np.stack([z, onto, z]), hidden)
    assert around.held(1) == (0, 1) and around.held(2) == (0,)


def test_a_hole_that_no_own_point_can_close_closes_inside_the_kernel_of_its_star():
    """A hole reaching into both arms of an L closes where every triangle around it keeps its side."""
    from isotween.geometry import triangle_areas
    from isotween.pipeline import _kernel_point

    ell = np.array([0, 3, 3 + 1j, 1 + 1j, 1 + 3j, 3j])  # an L: its kernel is the unit square at the corner
    z = np.r_[2.5 + 0.5j, 0.5 + 2.5j, ell]  # the hole's two vertices, one in each arm, then the L
    hole = np.array([0, 1])
    L = 2 + np.arange(6)
    around = np.array([[0, L[0], L[1]], [0, L[1], L[2]], [0, L[2], L[3]],  # the arms' sides seen from their vertex
                       [1, L[3], L[4]], [1, L[4], L[5]], [1, L[5], L[0]],
                       [1, L[3], 0], [1, L[0], 0]])  # with both of the hole's vertices: flat once it closes
    assert np.all(triangle_areas(z, around) > 0)

    def closed_at(p):
        moved = z.copy()
        moved[hole] = p
        return triangle_areas(moved, around[:6])

    assert all((closed_at(p) < 0).any() for p in [z[hole].mean(), *z[hole]])  # no point of its own does
    p = _kernel_point(z, around, hole)
    assert 0 < p.real < 1 and 0 < p.imag < 1
    assert np.all(closed_at(p) > 0)


def test_a_piece_that_comes_where_another_still_passes_comes_once_it_has_passed(tmp_path):
    pytest.importorskip("svgelements")
    # a bar slides from the left to the right edge; a dot comes in the middle, which the bar covers
    # (blended linearly) from t = 0.25 to t = 0.75: it grows from t = 0.8 on, not from half time
    a = drawing(tmp_path / "a.svg", '<path fill="#036" d="M0 1h4v14h-4z"/>')
    b = drawing(tmp_path / "b.svg", '<path fill="#036" d="M12 1h4v14h-4z"/><path fill="#036" d="M7 7h2v2h-2z"/>')
    prepared = isotween.prepare_pair(a, b)
    dot = prepared.source.paths[prepared.source.regions[1][0]][0]
    shared = isotween.pipeline.unmatched_spans(prepared.source, prepared.report)
    own = isotween.pipeline.unmatched_spans(prepared.source, prepared.report, target=prepared.target)
    np.testing.assert_allclose(shared[0][dot], [[0.5, 1.0]] * len(dot))
    np.testing.assert_allclose(own[0][dot], [[0.8, 1.0]] * len(dot))
    np.testing.assert_array_equal(own[1:], shared[1:])  # the shorter alternatives stay shared
    bar = prepared.source.paths[prepared.source.regions[0][0]][0]
    np.testing.assert_array_equal(own[0][bar], shared[0][bar])
    seq = isotween.morph(a, b, frames=21)
    # held as its small copy (frame 0: that copy collapsed to a point) until t = 0.8, then grown
    np.testing.assert_array_equal(seq.frames[1:17, dot], seq.frames[1:2, dot].repeat(16, axis=0))
    assert np.abs(seq.frames[17, dot] - seq.frames[16, dot]).max() > 1.0
    assert not metrics.outline_crossings(seq, visible=True).any()
