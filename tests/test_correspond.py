"""Automatic correspondence: regions, holes and polylines paired; what has no partner grows from a small copy.

The in-betweens neither fold nor cross.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

import isotween
from isotween import Shape
from isotween.correspondence import check_compatible, correspond
from isotween.correspondence.regions import (
    TINY,
    UNCROSS_PER_HIT,
    UNCROSS_SIZES,
    UNCROSS_SLACK,
    _collisions,
    _uncross,
    centroid,
    items_of,
    ring_area,
)
from isotween.errors import IncompatibleShapesError, ParameterError, ResourceError, ShapeError
from isotween.metrics import flipped_faces, outline_crossings

ROOT = Path(__file__).resolve().parents[1]


def disc(n, r=1.0, centre=0j, ry=None, reverse=False):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    z = centre + r * np.cos(t) + 1j * (r if ry is None else ry) * np.sin(t)
    z = z[::-1] if reverse else z
    return np.c_[z.real, z.imag]


def glyph(char):
    pytest.importorskip("matplotlib")
    sys.path.insert(0, str(ROOT / "scripts"))
    from build_examples import glyph as outline

    return Shape.from_polygon(outline(char))


def morph(src, tgt, frames=9):
    check_compatible(src, tgt)
    seq = isotween.interpolate(src, tgt, frames=frames)
    return seq, flipped_faces(seq, reduce=None), outline_crossings(seq)


def box(x0, y0, x1, y1):
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)


def ring(shape, path):
    return shape.z[shape.paths[path][0]]


def is_small_copy(small, big):
    """Whether ring ``small`` is ``big`` scaled by TINY (or less) about its centroid, moved."""
    a, b = small - small.mean(), big - big.mean()
    s = np.vdot(b, a).real / np.vdot(b, b).real
    return 0 < s <= TINY * (1 + 1e-9) and np.allclose(a, s * b, atol=1e-9 * np.abs(b).max())


def test_one_region_into_two_grows_the_second_from_a_small_copy():
    src = Shape.from_polygon(disc(40, 1.0, -1.5))
    tgt = Shape.from_polygon([disc(40, 1.0, -1.5), disc(30, 0.6, 1.5)])
    a, b, report = correspond(src, tgt, points=120)
    assert report.regions == {"paired": 1, "grown": 1, "shrunk": 0}
    assert report.pairs == [(0, 0)]
    assert len(a.regions) == len(b.regions) == 2 and a.n_faces == b.n_faces > 0
    # the paired disc is the same in both: every vertex stays where it is (known exact motion)
    kept = a.paths[a.regions[0][0]][0]
    np.testing.assert_allclose(a.vertices[kept], b.vertices[kept], atol=1e-12)
    # the new disc grows from a small copy of itself, at its own place
    grown = a.regions[1][0]
    assert is_small_copy(ring(a, grown), ring(b, grown))
    assert abs(ring(a, grown).mean() - 1.5) < 1e-9
    seq, flips, crossings = morph(a, b)
    assert not flips.any() and not crossings.any()


def test_two_regions_into_one_shrinks_the_unpaired_one_outside_the_fill():
    src = Shape.from_polygon([disc(40, 1.0, -1.5), disc(30, 0.6, 0.2)])
    tgt = Shape.from_polygon(disc(50, 1.3, 0.0))
    a, b, report = correspond(src, tgt)
    assert report.regions == {"paired": 1, "grown": 0, "shrunk": 1}
    # the larger source disc overlaps the target disc more and is closer in size
    assert report.pairs == [(0, 0)]
    shrunk = a.regions[1][0]
    assert is_small_copy(ring(b, shrunk), ring(a, shrunk))
    # its small copy lies outside the target disc, so the two never cross
    assert np.all(np.abs(ring(b, shrunk)) > 1.3)
    seq, flips, crossings = morph(a, b)
    assert not flips.any() and not crossings.any()


def test_a_piece_in_a_hole_shrinks_inside_the_hole_it_lies_in():
    # a dot in a square hole; the other drawing's hole is a thin slot above the dot's place, too thin for the
    # space just outside the fill: the dot shrinks into the slot, not out through the frame round it
    src = Shape.from_polygon([box(0, 0, 4, 4), box(1, 1, 3, 3)[::-1], disc(24, 0.8, 2 + 2j)])
    tgt = Shape.from_polygon([box(0, 0, 4, 4), box(0.6, 2.3, 3.4, 2.5)[::-1]])
    a, b, report = correspond(src, tgt)
    assert report.regions == {"paired": 1, "grown": 0, "shrunk": 1}
    dot = a.regions[1][0]
    assert is_small_copy(ring(b, dot), ring(a, dot))
    slot = ring(b, a.regions[0][1])
    assert np.all((ring(b, dot).real > slot.real.min()) & (ring(b, dot).real < slot.real.max()))
    assert np.all((ring(b, dot).imag > slot.imag.min()) & (ring(b, dot).imag < slot.imag.max()))
    seq, flips, crossings = morph(a, b)
    assert not flips.any() and not crossings.any()


def test_pieces_that_shrink_into_one_hole_keep_apart():
    # four dots in a wide hole; the other drawing's hole is a small disc in a corner, the same way from all four
    dots = [disc(24, 0.25, c) for c in (1.6 + 1.6j, 2.4 + 1.6j, 1.6 + 2.4j, 2.4 + 2.4j)]
    src = Shape.from_polygon([box(0, 0, 4, 4), box(0.5, 0.5, 3.5, 3.5)[::-1], *dots])
    tgt = Shape.from_polygon([box(0, 0, 4, 4), disc(24, 0.25, 3.3 + 3.3j, reverse=True)])
    a, b, report = correspond(src, tgt)
    assert report.regions == {"paired": 1, "grown": 0, "shrunk": 4}
    hole = ring(b, a.regions[0][1])
    copies = [ring(b, r[0]) for r in a.regions[1:]]
    assert all(np.abs(c - (3.3 + 3.3j)).max() < 0.25 for c in copies)  # each inside the hole
    centres = np.array([c.mean() for c in copies])
    radii = np.array([np.abs(c - c.mean()).max() for c in copies])
    gaps = np.abs(centres[:, None] - centres[None, :]) - radii[:, None] - radii[None, :]
    assert np.all(gaps[~np.eye(4, dtype=bool)] > 0)  # and clear of one another
    assert np.abs(hole - (3.3 + 3.3j)).max() < 0.25 + 1e-9
    assert outline_crossings(isotween.interpolate(a, b, frames=3))[-1] == 0


def test_split_mode_merges_into_the_nearest_region():
    src = Shape.from_polygon([disc(40, 1.0, -1.5), disc(30, 0.4, 1.5)])
    tgt = Shape.from_polygon(disc(50, 1.0, -1.5))
    a, b, report = correspond(src, tgt, unmatched="split", outline=True)
    assert report.regions == {"paired": 1, "grown": 0, "shrunk": 1}
    assert "merged" in report.summary()
    small = ring(b, a.regions[1][0])
    assert np.all(np.abs(small + 1.5) < 1.0)  # inside the disc it merges into


def test_a_hole_opens_from_a_small_ring_inside_the_region():
    square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    src = Shape.from_polygon(square)
    tgt = Shape.from_polygon([square, disc(24, 0.8, 1.6 + 2.2j, reverse=True)])
    a, b, report = correspond(src, tgt, points=100)
    assert report.holes == {"paired": 0, "grown": 1, "shrunk": 0} and "1 opened" in report.summary()
    hole = a.regions[0][1]
    assert is_small_copy(ring(a, hole), ring(b, hole))
    assert abs(ring(a, hole).mean() - (1.6 + 2.2j)) < 1e-4  # where the hole will be (resampled)
    seq, flips, crossings = morph(a, b)
    assert not flips.any() and not crossings.any()


def test_holes_that_open_where_the_source_has_no_room_open_apart():
    # a frame (a square with a wide square hole) into a plate with a large hole and two small ones side by
    # side: the small ones would open inside the frame's hole, where there is no material; the nearest
    # material is the same for both, yet they open apart, not one inside the other
    square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    frame = Shape.from_polygon([square, (square * 0.8 + 1)[::-1]])
    holes = [disc(32, 2.0, 6.5 + 5j, reverse=True), disc(16, 0.15, 3 + 5j, reverse=True),
             disc(16, 0.15, 3.4 + 5j, reverse=True)]
    plate = Shape.from_polygon([square] + holes)
    a, b, report = correspond(frame, plate)
    assert report.holes["grown"] == 2 and "as outlines" not in report.summary()
    holes = [ring(a, h) for h in a.regions[0][1:]]
    small = [h for h in holes if np.ptp(h.real) < 1]
    assert len(small) == 2
    gap = np.abs(small[0][:, None] - small[1][None]).min()
    assert gap > max(np.abs(h - h.mean()).max() for h in small)  # apart, neither inside the other


def test_small_hole_copies_placed_again_by_the_part_of_the_outline_nearest_their_holes():
    from isotween.correspondence.correspond import _by_the_outline

    square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    t = np.linspace(0, 1, 8, endpoint=False)[:, None]
    outer = np.vstack([a + t * (b - a) for a, b in zip(square, np.roll(square, -1, axis=0), strict=True)])
    real = [disc(12, 1.0, 8.5 + 2j, reverse=True), disc(12, 1.0, 2 + 8.5j, reverse=True)]
    copies = [disc(12, 0.05, 5 + 5j, reverse=True), disc(12, 0.05, 5.2 + 5j, reverse=True)]
    rs, rt = _by_the_outline([outer, *copies], [outer * 1.5, *real], [[1, 2], []])
    for h, hole in ((1, real[0]), (2, real[1])):
        z, c = rs[h][:, 0] + 1j * rs[h][:, 1], copies[h - 1][:, 0] + 1j * copies[h - 1][:, 1]
        np.testing.assert_allclose(z - z.mean(), c - c.mean(), atol=1e-12)  # moved, not reshaped
        w = hole[:, 0] + 1j * hole[:, 1]
        j = np.argmin(np.abs(outer[:, 0] * 1.5 + 1j * outer[:, 1] * 1.5 - w.mean()))
        assert abs(z.mean() - (outer[j, 0] + 1j * outer[j, 1])) < 0.5  # by that vertex of the outline
        assert z.real.min() > 0 and z.imag.min() > 0 and z.real.max() < 10 and z.imag.max() < 10
    np.testing.assert_array_equal(rs[0], outer)
    for a, b in zip(rt, [outer * 1.5, *real], strict=True):
        np.testing.assert_array_equal(a, b)


def test_i_into_l_cuts_the_l_where_the_i_parts_and_drops_the_dot_onto_the_stem():
    i, l_ = glyph("i"), glyph("l")
    a, b, report = correspond(i, l_)
    assert report.cut == [0, 1]  # the l is cut where the i's stem and dot part (`correspondence.splits`)
    assert report.regions == {"paired": 2, "grown": 0, "shrunk": 0}
    seq, flips, _ = morph(a, b)
    assert not flips.any()
    # the dot comes down onto the stem and stays above it: their outlines never cross on the way
    stem, dot = sorted((idx for idx, _ in seq.shape.paths), key=lambda idx: seq.z[0, idx].imag.mean())
    assert np.all(seq.z[:, stem].imag.max(axis=1) <= seq.z[:, dot].imag.min(axis=1) + 1e-9)


def test_b_into_d_closes_one_hole():
    B, D = glyph("B"), glyph("D")
    a, b, report = correspond(B, D)
    assert report.regions["paired"] == 1 and report.holes == {"paired": 1, "grown": 0, "shrunk": 1}
    assert a.n_faces > 0 and report.flipped == 0
    # AIAP folds a few triangles around the hole that shrinks to a point; the fold-free fallback does not
    seq = isotween.interpolate(a, b, frames=9, fold="fallback")
    flips, crossings = flipped_faces(seq, reduce=None), outline_crossings(seq)
    assert not flips.any() and not crossings.any()
    # D's hole pairs with the B hole nearer to it; the other one closes to a small copy of itself
    d_hole = centroid(items_of(D, "D")[0].rings[1], True)
    b_holes = [centroid(h, True) for h in items_of(B, "B")[0].rings[1:]]
    near, far = sorted(b_holes, key=lambda c: abs(c - d_hole))
    sizes = {k: np.ptp(ring(b, k).real) for k in a.regions[0][1:]}
    paired, closed = max(sizes, key=sizes.get), min(sizes, key=sizes.get)
    tol = 0.01 * np.ptp(B.vertices[:, 1])  # resampled rings: centroids move a little
    assert abs(centroid(ring(a, paired), True) - near) < tol and abs(centroid(ring(b, paired), True) - d_hole) < tol
    assert abs(centroid(ring(a, closed), True) - far) < tol and is_small_copy(ring(b, closed), ring(a, closed))
    seq, _, crossings = morph(*correspond(B, D, outline=True, points=200)[:2])
    assert not crossings.any()


def test_compatible_pair_comes_back_unchanged():
    src = Shape.from_polygon(disc(30))
    tgt = src.with_vertices(src.vertices * 2)
    a, b, report = correspond(src, tgt)
    assert a is src and b is tgt and report.unchanged
    assert "unchanged" in report.summary()


def test_polylines_pair_with_polylines_and_keep_their_ends():
    t = np.linspace(0, 1, 20)
    src = Shape.from_polyline([np.c_[0.3 * t, 0 * t], np.c_[t, 0 * t + 3]])
    tgt = Shape.from_polyline([np.c_[t[:11], 0 * t[:11] + 3.2]])
    a, b, report = correspond(src, tgt)
    assert report.lines == {"paired": 1, "grown": 0, "shrunk": 1}
    assert all(not c for _, c in a.paths) and a.n_faces == 0
    # the source line of the same length goes with the target line
    paired = next(k for k in range(2) if np.allclose(ring(a, k).imag, 3))
    np.testing.assert_allclose(ring(b, paired).imag, 3.2)


def test_segment_bounds_every_segment_in_both_drawings():
    src = Shape.from_polygon(disc(13, 2.0))
    tgt = Shape.from_polygon(disc(7, 1.0, ry=3.0))
    a, b, _ = correspond(src, tgt, segment=0.25, outline=True)
    for s in (a, b):
        assert np.abs(s.edge_vectors()).max() <= 0.25 + 1e-12


def test_forced_pairs_and_their_errors():
    two = Shape.from_polygon([disc(20, 1.0, -2), disc(20, 1.0, 2)])
    swapped = Shape.from_polygon([disc(24, 1.0, 2.1), disc(24, 1.0, -2.1)])
    assert correspond(two, swapped, outline=True).report.pairs == [(0, 1), (1, 0)]
    forced = correspond(two, swapped, outline=True, pairs=[(0, 0)]).report
    assert sorted(forced.pairs) == [(0, 0), (1, 1)]
    with pytest.raises(IncompatibleShapesError, match="cannot pair source region 0 with target region 5"):
        correspond(two, swapped, pairs=[(0, 5)])
    with pytest.raises(IncompatibleShapesError, match="source region 1 with two regions"):
        correspond(two, swapped, pairs=[(1, 0), (1, 1)])


def test_pieces_that_would_pass_through_each_other_swap_partners():
    # two candles of a cake become two rays of a sun: paired as the cost has it, the right candle crosses the
    # left one on its way to the far ray; swapped, each goes its own way (cake2-fill -> brightness-alt-high-fill)
    def bar(c, length, deg):
        z = np.array([-length, length, length, -length]) / 2 + 0.03j * np.array([-1, -1, 1, 1])
        z = c + z * np.exp(1j * np.radians(deg))
        return centroid(z, True), np.sqrt(abs(ring_area(z))), z

    src = [bar(-0.2 - 0.206j, 0.25, 90), bar(-0.066 - 0.198j, 0.25, 90)]
    tgt = [bar(-0.203 - 0.071j, 0.15, 45), bar(-0.287 + 0.132j, 0.15, 0)]
    apart = np.ones((2, 2), dtype=bool)
    crossing, swapped = [(0, 0), (1, 1)], [(0, 1), (1, 0)]
    hit = _collisions(src, tgt, crossing, apart)[0, 1]
    assert hit > 0.25
    assert _collisions(src, tgt, swapped, apart).sum() == 0
    # the swap may cost UNCROSS_SLACK more, and more again the worse the collision
    slack = UNCROSS_SLACK + UNCROSS_PER_HIT * hit
    cost = lambda more: np.array([[1.0, 1 + more / 2], [1 + more / 2, 1.0]])  # noqa: E731
    ok = lambda pairs: True  # noqa: E731
    assert _uncross(crossing, cost(slack - 0.01), src, tgt, set(), set(), ok) == swapped
    # not where it costs more than that, a pair is forced or forbidden, or the result is refused
    assert _uncross(crossing, cost(slack + 0.01), src, tgt, set(), set(), ok) == crossing
    cheap = cost(0.1)
    assert _uncross(crossing, cheap, src, tgt, set(), set(), ok) == swapped
    assert _uncross(crossing, cheap, src, tgt, {(0, 0)}, set(), ok) == crossing
    assert _uncross(crossing, cheap, src, tgt, set(), {(1, 0)}, ok) == crossing
    assert _uncross(crossing, cheap, src, tgt, set(), set(), lambda pairs: False) == crossing
    # nor between pieces of unlike sizes (a cake's body and a candle)
    big = [bar(-0.2 - 0.206j, 0.25 * UNCROSS_SIZES ** 3, 90), src[1]]
    assert _collisions(big, tgt, crossing, apart).sum() > 0
    assert _uncross(crossing, cheap, big, tgt, set(), set(), ok) == crossing


def test_overlapping_pieces_are_paired_and_kept_exactly():
    # forty squares on a circle, some overlapping at their corners (the fill of a pair is then no valid
    # polygon), into forty squares at other radii: the drawings pair and every input corner is kept exactly
    def square(c):
        return np.c_[c.real + 0.3 * np.array([-1, 1, 1, -1]), c.imag + 0.3 * np.array([-1, -1, 1, 1])]

    turns = np.exp(1j * np.linspace(0, 2 * np.pi, 40, endpoint=False))
    rng = np.random.default_rng(0)
    src = Shape.from_polygon([square(5 * t) for t in turns])
    tgt = Shape.from_polygon([square(5 * t * (0.5 + rng.random())) for t in rng.permutation(turns)])
    a, b, report = correspond(src, tgt, always=True)
    assert report.regions["paired"] >= 30
    for given, made in ((src, a), (tgt, b)):
        gap = np.abs(given.z[:, None] - made.z[None, :]).min(axis=1)
        assert gap.max() == 0.0


def test_bad_options_are_refused_before_any_work():
    src, tgt = Shape.from_polygon(disc(20)), Shape.from_polygon(disc(30, 2.0))
    with pytest.raises(ResourceError, match=r"mesh_size=1e-05 would make about") as err:
        correspond(src, tgt, mesh_size=1e-5)
    # the estimate: the larger region's area over that of an equilateral triangle of side 1e-5
    estimate = float(str(err.value).split("about ")[1].split()[0])
    assert abs(estimate / (4 * np.pi / (np.sqrt(3) / 4 * 1e-10)) - 1) < 0.02
    with pytest.raises(ParameterError, match="points or segment"):
        correspond(src, tgt, points=40, segment=0.1)
    with pytest.raises(ParameterError, match="unmatched"):
        correspond(src, tgt, unmatched="vanish")
    with pytest.raises(ParameterError, match="mesh_size must be a positive length"):
        correspond(src, src.with_vertices(src.vertices * 2), mesh_size=-1)  # even when compatible
    with pytest.raises(ShapeError, match="the target has no paths"):
        correspond(src, Shape(disc(5), [[0, 1], [2, 3]]))


# ---------------------------------------------------------------- command line
HEART = ('<path fill="#c00" fill-rule="evenodd" d="M8 1.314C12.438-3.248 23.534 4.735 8 15'
         '-7.534 4.736 3.562-3.248 8 1.314"/>')
BLOCKS = ('<path fill="#036" fill-rule="evenodd" d="M1 2h6v11h-6z M2.5 4h3v3h-3z"/>'
          '<rect x="9" y="2" width="6" height="11" fill="#036"/>')


def svg(path, body):
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16">{body}</svg>')
    return str(path)


def cli(*args):
    from click.testing import CliRunner

    from isotween.cli import main

    return CliRunner().invoke(main, [str(a) for a in args])


def test_cli_morphs_two_drawings_with_different_ring_counts_without_flags(tmp_path):
    pytest.importorskip("svgelements")
    a, b = svg(tmp_path / "heart.svg", HEART), svg(tmp_path / "blocks.svg", BLOCKS)
    result = cli("interpolate", a, b, "-n", 7, "-o", tmp_path / "out.npz")
    assert result.exit_code == 0, result.output
    report = result.stdout.splitlines()[0]
    assert report.startswith("correspondence: regions 1 paired, 1 grown; holes 1 opened;")
    assert "solid(s)" in report and "0 flipped" in report
    seq = isotween.io.load_sequence(tmp_path / "out.npz")
    assert seq.shape.n_faces > 0 and len(seq) == 7
    # in Python: the paint comes along, and the grown square fades in from a transparent copy
    src, tgt, _ = correspond(isotween.load(a), isotween.load(b))
    grown = src.regions[1][0]
    assert src.paint[grown].opacity == 0.0 and tgt.paint[grown].opacity == 1.0
    assert src.paint[src.regions[0][0]].fill == (0.8, 0.0, 0.0, 1.0)
    assert tgt.paint[grown].fill == (0.0, 0.2, 0.4, 1.0)
    assert not flipped_faces(seq, reduce=None).any() and not outline_crossings(seq).any()
    quiet = cli("interpolate", a, b, "-n", 3, "-q", "-o", tmp_path / "q.npz")
    assert quiet.exit_code == 0 and not quiet.stdout.startswith("correspondence")


def test_cli_keyframes_and_transfer_make_all_inputs_compatible(tmp_path):
    pytest.importorskip("svgelements")
    k0, k1 = svg(tmp_path / "k0.svg", HEART), svg(tmp_path / "k1.svg", BLOCKS)
    k2 = svg(tmp_path / "k2.svg", '<circle cx="8" cy="8" r="6" fill="#c00"/>')
    result = cli("keyframes", k0, k1, k2, "--frames", 9, "-o", tmp_path / "keys.npz")
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("correspondence: regions 1 paired, 1 grown; holes 1 opened;")
    seq = isotween.io.load_sequence(tmp_path / "keys.npz")
    # the keyframes are hit: frame 0 is the heart resampled (every vertex on its outline)
    shapely = pytest.importorskip("shapely")
    heart = shapely.LinearRing(isotween.load(k0).vertices)
    outline = seq.frames[0][seq.shape.paths[0][0]]
    assert np.all(shapely.distance(heart, shapely.points(outline)) < 1e-9)
    result = cli("transfer", k0, k2, k1, "--frames", 5, "-o", tmp_path / "t.npz")
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("correspondence:")


def test_cli_correspondence_options_and_errors(tmp_path):
    pytest.importorskip("svgelements")
    a, b = svg(tmp_path / "heart.svg", HEART), svg(tmp_path / "blocks.svg", BLOCKS)
    result = cli("interpolate", a, b, "--outline", "--points", 120, "-n", 3, "-o", tmp_path / "o.npz")
    assert result.exit_code == 0, result.output
    seq = isotween.io.load_sequence(tmp_path / "o.npz")
    assert seq.shape.n_vertices >= 120 and seq.shape.n_faces == 0  # at least N points, every input vertex kept
    result = cli("interpolate", a, b, "--segment", 0.5, "--outline", "-n", 3, "-o", tmp_path / "s.npz")
    assert result.exit_code == 0, result.output
    seq = isotween.io.load_sequence(tmp_path / "s.npz")
    assert np.abs(seq.edge_vectors()[[0, -1]]).max() <= 0.5 + 1e-12
    for args, needle in [
        (["--mesh-size", 1e-6], "mesh_size=1e-06 would make about"),
        (["--points", 40, "--segment", 1], "give points or segment, not both"),
    ]:
        result = cli("interpolate", a, b, *args, "-o", tmp_path / "bad.npz")
        assert result.exit_code == 2 and needle in result.stderr, result.output
        assert len(result.stderr.strip().splitlines()) == 1 and not (tmp_path / "bad.npz").exists()


# ---------------------------------------------------------------- crossings metric
def test_outline_crossings_counts_known_crossings():
    star = np.exp(2j * np.pi * np.arange(5) * 2 / 5)  # pentagram {5/2}: every edge crosses two others
    pentagram = Shape.from_polygon(np.c_[star.real, star.imag])
    bowtie = Shape.from_polygon([[0, 0], [2, 2], [2, 0], [0, 2]])  # one crossing pair
    square = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    overlap = Shape.from_polygon([square, square + 1])  # two separate squares crossing twice
    for shape, total, own in ((pentagram, 5, 5), (bowtie, 1, 1), (overlap, 2, 0)):
        seq = isotween.Sequence(np.stack([shape.vertices, 2 * shape.vertices + 1]), shape)
        np.testing.assert_array_equal(outline_crossings(seq), [total, total])  # similarity: same count
        np.testing.assert_array_equal(outline_crossings(seq, scope="region"), [own, own])
    # a random polygon: the same count as checking every pair of edges
    rng = np.random.default_rng(0)
    z = rng.normal(size=40) + 1j * rng.normal(size=40)
    shape = Shape.from_polygon(np.c_[z.real, z.imag])
    e = shape.edges
    a, b = z[e[:, 0]], z[e[:, 1]]

    def orient(p, q, r):
        return ((q - p).conj() * (r - p)).imag

    i, j = np.triu_indices(len(e), 1)
    apart = np.all(e[i][:, :, None] != e[j][:, None, :], axis=(1, 2))
    cross = (orient(a[i], b[i], a[j]) * orient(a[i], b[i], b[j]) < 0) & (
        orient(a[j], b[j], a[i]) * orient(a[j], b[j], b[i]) < 0)
    seq = isotween.Sequence(shape.vertices[None], shape)
    assert outline_crossings(seq)[0] == np.count_nonzero(cross & apart) > 0


def test_rings_keep_their_turn_so_mirror_symmetric_pairs_still_mesh():
    # a square against a clockwise 2:1 rectangle: the mirrored start matches as well as the true one
    square = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [2, 2], [1, 2], [0, 2], [0, 1]], float)
    rect = np.array([[0, 0], [0, 1], [4, 1], [4, 0]], float) + [-1, 0.5]
    src, tgt = isotween.resample(square, rect, points=24, keep_turn=True)
    assert ring_area(src.z) * ring_area(tgt.z) > 0
    a, b, report = correspond(Shape.from_polygon(square), Shape.from_polygon(rect))
    assert not report.outlines and a.n_faces > 0 and report.flipped == 0
    assert np.all(a.face_areas() * b.face_areas() > 0)


def test_room_inside_a_region_made_valid_into_pieces():
    """A region that shapely makes valid into a collection still measures the room around a point."""
    import shapely

    from isotween.correspondence.regions import _room

    pieces = shapely.GeometryCollection([shapely.box(0, 0, 2, 2), shapely.box(3, 0, 4, 1)])
    assert _room(pieces, 1 + 1j) == pytest.approx(1.0)
    assert _room(pieces, 2.5 + 0.5j) == 0.0


def test_a_mesh_cache_gives_the_same_meshes_and_is_used_again(tmp_path):
    pytest.importorskip("svgelements")
    from isotween.correspondence import mesh_outlines

    a = isotween.load(svg(tmp_path / "heart.svg", HEART))
    b = isotween.load(svg(tmp_path / "blocks.svg", BLOCKS))
    plain = correspond(a, b)
    kept = {}
    first = correspond(a, b, meshes=kept)
    assert len(kept) == len(plain.source.regions)  # one entry per region pair
    calls = []

    class Watch(dict):
        def __getitem__(self, key):
            calls.append(key)
            return dict.__getitem__(self, key)

    watched = Watch(kept)
    again = mesh_outlines(*correspond(a, b, outline=True), meshes=watched)
    assert len(calls) == len(kept) and len(watched) == len(kept)  # every region's meshes from the mapping
    for shapes in (first, again):
        assert shapes.source.equals(plain.source) and shapes.target.equals(plain.target)


def test_regions_of_unlike_colours_pair_only_where_they_overlap(tmp_path):
    # a face with a red tongue below its mouth, and the face with a blue tear at its side: the tongue fades out and
    # the tear in, where paired by place and size the tongue flew across the face into the tear. A red heart into
    # the blue heart beside it still pairs: they overlap
    face = '<circle cx="18" cy="18" r="17" fill="#FFCC4D"/><rect x="10" y="20" width="16" height="3" fill="#664500"/>'
    svg = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 36 36">{}</svg>'
    (tmp_path / "a.svg").write_text(svg.format(face + '<circle cx="18" cy="26" r="2.5" fill="#E75A70"/>'))
    (tmp_path / "b.svg").write_text(svg.format(face + '<circle cx="29" cy="9" r="2.5" fill="#5DADEC"/>'))
    _, _, report = correspond(isotween.io.load(tmp_path / "a.svg"), isotween.io.load(tmp_path / "b.svg"), always=True)
    assert report.regions == {"paired": 2, "grown": 1, "shrunk": 1}
    (tmp_path / "c.svg").write_text(svg.format('<circle cx="16" cy="18" r="8" fill="#E75A70"/>'))
    (tmp_path / "d.svg").write_text(svg.format('<circle cx="20" cy="18" r="8" fill="#5DADEC"/>'))
    _, _, report = correspond(isotween.io.load(tmp_path / "c.svg"), isotween.io.load(tmp_path / "d.svg"), always=True)
    assert report.regions == {"paired": 1, "grown": 0, "shrunk": 0}


def test_a_piece_painted_over_the_fill_grows_in_place(tmp_path):
    # a tear on a face, in the target only: it grows on the face at its own place (as an animator would
    # draw it), not from outside the face across the face's outline
    pytest.importorskip("svgelements")
    face = '<circle cx="8" cy="8" r="7" fill="#fc3"/>'
    tear = '<path fill="#39f" d="M11 7c1 1.5 1.6 2.4 1.6 3.2a1.6 1.6 0 0 1-3.2 0c0-.8.6-1.7 1.6-3.2z"/>'
    a, b = svg(tmp_path / "a.svg", face), svg(tmp_path / "b.svg", face + tear)
    src, tgt, report = correspond(isotween.load(a), isotween.load(b))
    assert report.regions["grown"] == 1
    grown = src.regions[1][0]
    assert is_small_copy(ring(src, grown), ring(tgt, grown))
    assert abs(ring(src, grown).mean() - ring(tgt, grown).mean()) < 0.5  # at its place
    seq = isotween.interpolate(src, tgt, frames=9)
    assert not isotween.metrics.new_crossings(seq).any()
