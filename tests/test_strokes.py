"""Strokes that would pass through other paths are drawn off and on (`isotween.strokes`).

`drawn` draws a stroke up to a share of its length, on the stroke itself;
`untangle` (run by `morph`, the command line and the studio) changes the
strokes in crossings that neither drawing has until none is left, keeping
both ends exact.
"""

import numpy as np
import pytest
from click.testing import CliRunner

import isotween
from isotween import metrics
from isotween.cli import main
from isotween.errors import ParameterError
from isotween.metrics import crossing_edges
from isotween.paint import sequence_paint
from isotween.pipeline import prepare_pair
from isotween.strokes import drawn

HEAD = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 24 24" fill="none" stroke="black" '
        'stroke-width="1">')
#: four short strokes round a long bar; the target turns the bar upright, so it sweeps through two of them
BAR_ACROSS = (HEAD + '<path d="M2 12h20"/><path d="M16 7h2"/><path d="M6 7h2"/><path d="M6 17h2"/>'
              '<path d="M16 17h2"/></svg>')
BAR_UPRIGHT = BAR_ACROSS.replace("M2 12h20", "M12 2v20")


def distance_to_polyline(points, line):
    """(m,) distance of complex ``points`` to the polyline ``line`` (k,) complex."""
    a, b = line[:-1], line[1:]
    d = b - a
    w = np.clip(((points[:, None] - a) * np.conj(d)).real / np.maximum(np.abs(d) ** 2, 1e-300), 0, 1)
    return np.abs(points[:, None] - (a + w * d)).min(axis=1)


def wiggle(k, closed):
    s = np.linspace(0, 2 * np.pi, k, endpoint=not closed)
    return (3 + np.cos(3 * s)) * np.exp(1j * s) if closed else s + 1j * np.sin(2 * s)


def test_an_open_stroke_is_drawn_on_itself_up_to_its_share():
    z = wiggle(40, closed=False)
    length = np.abs(np.diff(z)).sum()
    u = np.array([0.0, 0.3, 0.7, 1.0])
    frames = drawn(z, u)
    np.testing.assert_array_equal(frames[-1], z)  # whole: exactly the stroke
    np.testing.assert_array_equal(frames[0], np.full(len(z), z[0]))  # nothing drawn: one point
    for f, share in zip(frames, u, strict=True):
        np.testing.assert_allclose(np.abs(np.diff(f)).sum(), share * length, rtol=1e-12, atol=1e-12)
        assert distance_to_polyline(f, z).max() < 1e-12  # every vertex on the stroke


def test_a_ring_is_drawn_with_no_chord_back_to_its_start():
    z = wiggle(41, closed=True)
    ring = np.r_[z, z[:1]]
    longest = np.abs(ring[2:] - ring[:-2]).max()  # the longest chord over two edges
    k = len(z)
    edges = np.c_[np.arange(k), np.roll(np.arange(k), -1)]
    for u in (0.0, 0.2, 0.5, 0.8, 1.0):
        f = drawn(z, [u], closed=True)[0]
        assert distance_to_polyline(f, ring).max() < 1e-12
        closing = np.abs(np.r_[f, f[:1]][1:] - f)  # every edge, the closing one included
        assert closing.max() <= longest + 1e-12
        assert len(crossing_edges(f, edges)[0]) == 0  # out and back the same way: no self-crossing
    np.testing.assert_array_equal(drawn(z, [0.0], closed=True)[0], np.full(k, z[0]))


@pytest.fixture
def bar_pair(tmp_path):
    a, b = tmp_path / "across.svg", tmp_path / "upright.svg"
    a.write_text(BAR_ACROSS)
    b.write_text(BAR_UPRIGHT)
    return a, b


def test_a_stroke_that_would_cross_another_is_drawn_off_and_on(bar_pair):
    a, b = bar_pair
    prepared = prepare_pair(a, b)
    plain = isotween.interpolate(prepared.source, prepared.target, frames=11, correspondence="never")
    assert metrics.outline_crossings(plain, visible=True)[1:-1].sum() > 0  # the morph alone crosses
    seq = isotween.morph(a, b, frames=11)
    assert "drawn off and on" in seq.info["strokes"]
    assert not metrics.outline_crossings(seq, visible=True).any()
    np.testing.assert_array_equal(seq.frames[[0, -1]], plain.frames[[0, -1]])  # exact ends
    # the strokes that changed: on their source stroke, then out of sight, then on their target stroke
    _, paints = sequence_paint(seq)
    changed = [k for k, (idx, _) in enumerate(seq.shape.paths)
               if not np.allclose(seq.frames[:, idx], plain.frames[:, idx])]
    assert changed
    z = seq.z
    for k in changed:
        idx = seq.shape.paths[k][0]
        for f, t in enumerate(seq.times):
            if t < 0.5:
                assert distance_to_polyline(z[f, idx], z[0, idx]).max() < 1e-9
            elif t > 0.5:
                assert distance_to_polyline(z[f, idx], z[-1, idx]).max() < 1e-9
            else:
                assert paints[f][k].opacity == 0.0
        assert paints[0][k].opacity == paints[-1][k].opacity == 1.0
    # the strokes left alone keep the morph
    for k, (idx, _) in enumerate(seq.shape.paths):
        if k not in changed:
            np.testing.assert_array_equal(seq.frames[:, idx], plain.frames[:, idx])


def test_the_command_line_says_which_strokes_changed(bar_pair, tmp_path):
    a, b = bar_pair
    out = tmp_path / "m.npz"
    result = CliRunner().invoke(main, ["interpolate", str(a), str(b), "-n", "11", "-o", str(out)])
    assert result.exit_code == 0, result.output
    line = next(s for s in result.output.splitlines() if s.startswith("strokes: "))
    seq = isotween.load_sequence(out)
    assert not metrics.outline_crossings(seq, visible=True).any()
    assert line == f"strokes: {seq.info['strokes']}"


def test_crossings_of_several_frames_at_once_are_those_of_each():
    rng = np.random.default_rng(3)
    z = rng.random((6, 60)) + 1j * rng.random((6, 60))
    edges = np.c_[np.arange(59), np.arange(1, 60)]
    seen = rng.random((6, 59)) < 0.8
    i, j, f = crossing_edges(z, edges, seen=seen)
    for k in range(6):
        rows = np.flatnonzero(seen[k])
        ik, jk = crossing_edges(z[k], edges[rows])
        assert sorted(zip(i[f == k], j[f == k], strict=True)) == sorted(zip(rows[ik], rows[jk], strict=True))
    # two edges with an end at the same place (not the same vertex) only touch
    touch = np.array([0, 2, 1j + 1, -1j + 1])
    assert len(crossing_edges(touch, np.array([[0, 1], [2, 3]]))[0]) == 1
    touch[2] = touch[1]
    assert len(crossing_edges(touch, np.array([[0, 1], [2, 3]]))[0]) == 0


def test_new_crossings_leave_out_those_the_drawings_have():
    from isotween import Shape

    bar = np.c_[np.linspace(-2.0, 2.0, 8), np.zeros(8)]  # no vertex where the two strokes of the x cross
    cross = Shape.from_paths([bar, bar[:, ::-1]], closed=[False, False])  # an 'x' (a '+'): its strokes cross
    turned = cross.with_vertices(cross.vertices @ np.array([[0.6, 0.8], [-0.8, 0.6]]))
    seq = isotween.interpolate(cross, turned, frames=7)
    assert np.all(metrics.outline_crossings(seq) > 0)  # the 'x' crosses itself in every frame
    assert not metrics.new_crossings(seq).any()
    # a bar that moves up across an upright one passes through it: crossings no end has
    upright = np.c_[np.zeros(8), np.linspace(1.0, 3.0, 8)]
    apart = Shape.from_paths([bar, upright], closed=[False, False])
    seq = isotween.interpolate(apart, apart.with_vertices(np.r_[bar + [0.0, 4.0], upright]), frames=7)
    assert not metrics.new_crossings(seq)[[0, -1]].any()
    assert metrics.new_crossings(seq)[1:-1].any()


def test_paths_that_meet_at_an_end_count_as_crossing_there(tmp_path):
    # a plus whose upright has a vertex on the bar: no proper crossing at the ends, only touching; as the
    # drawing has the two pass through each other there, their crossing in between is no new one. A T (the
    # upright ends on the bar) only joins, a V's tip on the bar only touches it: dipping through the bar, each
    # makes a new crossing
    touch = np.array([0, 2, 1, 1 + 1j])
    assert len(crossing_edges(touch, np.array([[0, 1], [2, 3]]))[0]) == 0
    assert len(crossing_edges(touch, np.array([[0, 1], [2, 3]]), touch=True)[0]) == 1
    from isotween import Sequence, Shape

    for upright, through in (([[0, -2], [0, 0], [0, 2]], True), ([[0, 0], [0, 2]], False),
                             ([[-1, 1], [0, 0], [1, 1]], False)):
        s = Shape.from_paths([[[-2, 0], [2, 0]], upright], closed=[False, False])
        tilted = np.r_[s.vertices[:2], s.vertices[2:] @ [[1, 0.1], [0, 1]] + [0, -0.5]]  # through the bar
        seq = Sequence(frames=np.stack([s.vertices, tilted, s.vertices]), shape=s, times=np.linspace(0, 1, 3))
        crossed = metrics.outline_crossings(seq)
        assert crossed[[0, 2]].tolist() == [0, 0] and crossed[1] > 0
        assert metrics.new_crossings(seq).tolist() == ([0, 0, 0] if through else crossed.tolist())
    # strokes of a plus, resampled with a vertex on the bar: the upright shrinks into the bar, drawn as it is
    plus = HEAD + '<path d="M5 12h14"/><path d="M12 5v14"/></svg>'
    (tmp_path / "plus.svg").write_text(plus)
    (tmp_path / "minus.svg").write_text(HEAD + '<path d="M5 12h14"/></svg>')
    seq = isotween.morph(tmp_path / "plus.svg", tmp_path / "minus.svg", frames=9)
    assert "strokes" not in seq.info  # nothing drawn off and on
    upright = seq.z[:, seq.shape.paths[1][0]]
    assert np.abs(upright.real - 12).max() < 1e-9 and np.abs(upright[-1] - (12 + 12j)).max() < 1e-9


def test_a_stroke_end_that_meets_another_path_may_dip_under_its_stroke(tmp_path):
    from isotween import Shape

    # a T: the upright ends on the bar in both frames and dips through it in between, by less than half the
    # stroke's width (under its own stroke, unseen) or by more
    s = Shape.from_paths([[[-2, 0], [2, 0]], [[0, 0], [0, 2]]], closed=[False, False])
    for dip, seen in ((0.4, False), (0.8, True)):
        dipped = np.r_[s.vertices[:2], s.vertices[2:] + [0, -dip]]
        z = np.stack([s.vertices, dipped, s.vertices]) @ [1, 1j]
        frame, _, _ = metrics.path_crossings(s, z, new=True, reach=[0.5, 0.5])
        assert (len(frame) > 0) == seen
        assert len(metrics.path_crossings(s, z, new=True)[0]) > 0  # with no stroke to hide it: a crossing
    # a lock opening (Lucide's lock and lock-open): the shackle's ends sit on the body; the left one stays while the
    # right one lifts, nudged a little through the body's edge by the morph: the shackle opens, nothing is drawn
    # off and on
    body = '<rect width="18" height="11" x="3" y="11" rx="2" ry="2"/>'
    (tmp_path / "lock.svg").write_text(HEAD.replace('stroke-width="1"', 'stroke-width="2"') + body
                                       + '<path d="M7 11V7a5 5 0 0 1 10 0v4"/></svg>')
    (tmp_path / "open.svg").write_text(HEAD.replace('stroke-width="1"', 'stroke-width="2"') + body
                                       + '<path d="M7 11V7a5 5 0 0 1 9.9-1"/></svg>')
    seq = isotween.morph(tmp_path / "lock.svg", tmp_path / "open.svg", frames=9)
    assert "strokes" not in seq.info
    rect = seq.z[:, seq.shape.paths[0][0]]
    assert np.abs(rect - rect[0]).max() < 1e-6  # the body stays where it is drawn


def test_strokes_morph_keeps_every_stroke_morphing(bar_pair, tmp_path):
    a, b = bar_pair
    prepared = prepare_pair(a, b)
    plain = isotween.interpolate(prepared.source, prepared.target, frames=11, correspondence="never")
    seq = isotween.morph(a, b, frames=11, strokes="morph")
    np.testing.assert_array_equal(seq.frames, plain.frames)
    assert "strokes" not in seq.info
    result = CliRunner().invoke(main, ["interpolate", str(a), str(b), "-n", "11", "--strokes", "morph",
                                       "-o", str(tmp_path / "m.npz")])
    assert result.exit_code == 0 and "strokes:" not in result.output
    with pytest.raises(ParameterError, match="strokes"):
        isotween.morph(a, b, strokes="cross")


def test_a_stroke_the_source_lacks_is_drawn_on_unseen_until_then():
    from types import SimpleNamespace

    from isotween import Sequence, Shape
    from isotween.paint import Paint, paint_keys
    from isotween.strokes import untangle

    ink = Paint(fill=None, stroke=(0.0, 0.0, 0.0, 1.0), stroke_width=0.5)
    bar = np.c_[np.linspace(-2.0, 2.0, 4), np.zeros(4)]
    upright = np.c_[np.zeros(4), np.linspace(-4.0, -6.0, 4)]  # below the bar at the end
    shape = Shape.from_paths([bar, upright], closed=[False, False], regions=[], paint=[ink, ink])
    start = np.r_[bar, np.tile([0.0, 5.0], (4, 1))]  # the new stroke: one point above the bar at t = 0
    end = np.r_[bar, upright]
    t = np.linspace(0.0, 1.0, 11)
    frames = (1 - t)[:, None, None] * start + t[:, None, None] * end  # it grows down through the bar
    seq = Sequence(frames=frames, shape=shape, times=t, info=paint_keys([shape, shape], [0.0, 1.0]))
    assert metrics.new_crossings(seq).any()
    report = SimpleNamespace(vanishing=[[shape.paths[1][0]], []])
    untangle(seq, report)
    assert seq.info["strokes"].startswith("1 of 2 strokes")
    assert not metrics.new_crossings(seq).any()
    np.testing.assert_array_equal(seq.frames[[0, -1]], frames[[0, -1]])
    _, paints = sequence_paint(seq)
    idx = shape.paths[1][0]
    for f, when in enumerate(t):
        z = seq.z[f, idx]
        if np.ptp(z.real) + np.ptp(z.imag) == 0:  # nothing drawn yet: not even a dot of its caps
            assert paints[f][1].opacity == 0.0
        if when < 0.5:
            assert paints[f][1].opacity == 0.0
        else:  # drawn on along the upright stroke itself
            assert distance_to_polyline(z, upright[:, 0] + 1j * upright[:, 1]).max() < 1e-12
    assert paints[-1][1].opacity == 1.0


def test_a_stroke_prefers_a_partner_of_its_direction():
    from isotween.correspondence import regions

    s = np.linspace(-1.0, 1.0, 9)
    across, upright = s + 0j, 1j * s
    circle = np.exp(2j * np.pi * np.arange(16) / 16)
    assert regions._direction(across) == pytest.approx(1.0) and regions._direction(upright) == pytest.approx(-1.0)
    assert abs(regions._direction(circle)) < 1e-12  # round: no direction
    feats = [regions._features([z], False, regions.Frame(0j, 1.0)) for z in (across, upright)]
    cost = regions._cost(feats, feats, closed=False)  # same place and length: only the directions differ
    assert cost[0, 0] == cost[1, 1] == pytest.approx(0.0)
    assert cost[0, 1] == cost[1, 0] == pytest.approx(4 * regions.TURN_COST)


@pytest.mark.parametrize("drawn_from", ["top", "bottom"])
def test_a_straight_stroke_turns_the_short_way(tmp_path, drawn_from):
    # a menu's bar into one stroke of a cross, the cross's stroke drawn from either end: straight, it fits either
    # way round, and the bar turns by 45 degrees (its left end to the stroke's lower left end), not by 135
    d = "M18 6 6 18" if drawn_from == "top" else "M6 18 18 6"
    (tmp_path / "bar.svg").write_text(HEAD + '<path d="M4 12h16"/></svg>')
    (tmp_path / "stroke.svg").write_text(HEAD + f'<path d="{d}"/></svg>')
    seq = isotween.morph(tmp_path / "bar.svg", tmp_path / "stroke.svg", frames=9)
    z = seq.z[:, seq.shape.paths[0][0]]
    left = int(np.argmin(z[0].real))
    assert abs(z[-1, left] - (6 + 18j)) < 1e-9
    turn = np.unwrap(np.angle(z[:, -1] - z[:, 0]))
    assert abs(turn[-1] - turn[0]) == pytest.approx(np.pi / 4)


def test_strokes_drawn_off_and_on_take_turns(tmp_path):
    # two cells of the bar sweeping through four short strokes: both bars are drawn off and on, one
    # after the other, so the drawing never loses both at once (all at once, both vanish half way)
    head = HEAD.replace("0 0 24 24", "0 0 48 24")
    cell = '<path d="M{} 12h20"/><path d="M{} 7h2"/><path d="M{} 7h2"/><path d="M{} 17h2"/><path d="M{} 17h2"/>'
    across = head + cell.format(2, 16, 6, 6, 16) + cell.format(26, 40, 30, 30, 40) + "</svg>"
    upright = across.replace("M2 12h20", "M12 2v20").replace("M26 12h20", "M36 2v20")
    a, b = tmp_path / "a.svg", tmp_path / "b.svg"
    a.write_text(across)
    b.write_text(upright)
    seq = isotween.morph(a, b, frames=21)
    assert seq.info["strokes"].startswith("2 of 10")
    assert not metrics.outline_crossings(seq, visible=True).any()
    _, paints = sequence_paint(seq)
    bars = [k for k, (idx, _) in enumerate(seq.shape.paths) if len(idx) and np.ptp(seq.z[0, idx].real) > 10]
    ink = sum(np.abs(np.diff(seq.z[:, seq.shape.paths[k][0]], axis=1)).sum(axis=1)
              * np.array([p[k].opacity for p in paints]) for k in bars)
    assert len(bars) == 2 and ink.min() >= 20.0 - 1e-9  # a whole bar (20 long) on view in every frame
    quick = isotween.morph(a, b, frames=21, stagger=0.2)  # off within the first fifth, on within the last
    assert np.isfinite(quick.frames).all() and not metrics.outline_crossings(quick, visible=True).any()
    np.testing.assert_array_equal(quick.frames[[0, -1]], seq.frames[[0, -1]])


def test_a_drawing_does_not_empty_to_untangle_its_strokes(tmp_path):
    # a sun (a ring, eight short rays) into a crescent (one long open stroke round it): the ring becomes the
    # crescent, which sweeps through the rays; drawing every stroke off and on would leave next to nothing half
    # way, so the ring keeps morphing (crossing rays as they retract) and the drawing keeps its ink on view
    rays = "".join(f'<path d="M{12 + 8 * np.cos(a):.3f} {12 + 8 * np.sin(a):.3f}L{12 + 10 * np.cos(a):.3f} '
                   f'{12 + 10 * np.sin(a):.3f}"/>' for a in np.arange(8) * np.pi / 4)
    sun = HEAD + '<circle cx="12" cy="12" r="4"/>' + rays + "</svg>"
    moon = HEAD + '<path d="M21 12.5A9 9 0 1 1 11.5 3c.4 0 .6.5.4.8A6 6 0 0 0 20.2 12.1c.3-.2.8 0 .8.4"/></svg>'
    a, b = tmp_path / "a.svg", tmp_path / "b.svg"
    a.write_text(sun)
    b.write_text(moon)
    seq = isotween.morph(a, b, frames=21)
    _, paints = sequence_paint(seq)
    ink = sum(np.abs(np.diff(seq.z[:, np.r_[idx, idx[:1]] if closed else idx], axis=1)).sum(axis=1)
              * np.array([p[k].opacity for p in paints]) for k, (idx, closed) in enumerate(seq.shape.paths))
    assert ink[1:-1].min() >= 0.15 * min(ink[0], ink[-1])
    assert seq.info["strokes"].startswith("6 of 9")  # the rays; the ring morphs


def test_symmetric_drawings_pair_their_strokes_symmetrically(tmp_path):
    # a menu into an X: both are mirror symmetric about y = 12, so the top and bottom bars become the X's
    # two bars, mirror images of each other in every frame, and the middle bar (on the axis) has no partner;
    # the cheapest pairing alone takes the top and the middle bars, which are no mirror pair
    (tmp_path / "menu.svg").write_text(HEAD + '<path d="M4 5h16"/><path d="M4 12h16"/><path d="M4 19h16"/></svg>')
    (tmp_path / "x.svg").write_text(HEAD + '<path d="M18 6 6 18"/><path d="m6 6 12 12"/></svg>')
    seq = isotween.morph(tmp_path / "menu.svg", tmp_path / "x.svg", frames=9)
    bars = {}
    for idx, _ in seq.shape.paths:
        y = seq.z[0, idx].imag
        if np.ptp(y) < 1e-9:
            bars[round(float(y[0]))] = idx
    assert sorted(bars) == [5, 12, 19]
    top, bottom = seq.z[:, bars[5]], seq.z[:, bars[19]]
    x_bars = {frozenset({6 + 18j, 18 + 6j}), frozenset({6 + 6j, 18 + 18j})}
    ends = {frozenset(np.round(z[-1, [0, -1]], 9).tolist()) for z in (top, bottom)}
    assert ends == x_bars
    mirror = 24j + np.conj(top)  # the top bar mirrored about y = 12, in every frame
    for k in range(len(seq.z)):
        assert distance_to_polyline(mirror[k], bottom[k]).max() < 1e-6
        assert distance_to_polyline(bottom[k], mirror[k]).max() < 1e-6
    middle = seq.z[-1, bars[12]]
    assert np.ptp(middle.real) < 1.0  # drawn off: no length left at the end
