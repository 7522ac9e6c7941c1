"""Correspondence that finds the motion: known motions recovered with no options, exact ends, hints.

Targets are the source drawing moved by a known motion and written with other
point counts and other ring starts, so the right in-betweens are known.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

import isotween
from isotween import metrics
from isotween.errors import IncompatibleShapesError, ParameterError
from isotween.geometry import ring_area
from isotween.metrics import flipped_faces

ROOT = Path(__file__).resolve().parents[1]


def glyph_rings(char):
    pytest.importorskip("matplotlib")
    pytest.importorskip("shapely")
    sys.path.insert(0, str(ROOT / "scripts"))
    from build_examples import glyph as outline

    rings = outline(char)
    return [np.asarray(r, float) for r in (rings if isinstance(rings, list) else [rings])]


def resampled(ring, n, start):
    """The same closed polyline with n points uniform in arc length from another start (corners kept)."""
    z = ring[:, 0] + 1j * ring[:, 1]
    knots = np.append(z, z[0])
    cum = np.r_[0, np.cumsum(np.abs(np.diff(knots)))]
    s = np.sort(np.r_[cum[:-1], np.linspace(0, cum[-1], n, endpoint=False)])  # every corner and n more
    s = np.unique(np.round(s, 12))
    w = np.interp(s, cum, knots.real) + 1j * np.interp(s, cum, knots.imag)
    w = np.roll(w, start)
    return np.c_[w.real, w.imag]


def moved(rings, turn_deg, scale=1.0, shift=(40.0, -7.0)):
    a = scale * np.exp(1j * np.deg2rad(turn_deg))
    out = []
    for k, r in enumerate(rings):
        z = r[:, 0] + 1j * r[:, 1]
        w = a * z + complex(*shift)
        out.append(resampled(np.c_[w.real, w.imag], 2 * len(r) + 7, 5 + 3 * k))
    return out


def similarity_residual(z0, z):
    """Largest distance of z from the best similar copy of z0 (vertex for vertex), and that copy's factor."""
    p, q = z0 - z0.mean(), z - z.mean()
    a = np.vdot(p, q) / np.vdot(p, p)
    return np.abs(q - a * p).max(), a


@pytest.mark.parametrize("char,turn,scale", [("G", 90, 1.0), ("B", 150, 1.0), ("e", 40, 1.6)])
def test_turned_glyph_moves_rigidly_with_no_options(char, turn, scale):
    src_rings = glyph_rings(char)
    src = isotween.Shape.from_polygon(src_rings)
    tgt = isotween.Shape.from_polygon(moved(src_rings, turn, scale))
    seq = isotween.morph(src, tgt, frames=9)
    assert seq.method == "aiap" and "fallback" not in seq.info  # the paper's method, no fallback
    assert flipped_faces(seq, None).tolist() == [0] * 9
    diag = src.bbox_diagonal()
    z0 = seq.frames[0, :, 0] + 1j * seq.frames[0, :, 1]
    for k, t in enumerate(seq.times):
        z = seq.frames[k, :, 0] + 1j * seq.frames[k, :, 1]
        resid, a = similarity_residual(z0, z)
        assert resid <= 0.01 * diag  # every in-between a similar copy of the source
        assert abs(np.angle(a, deg=True) - t * turn) < 1.0  # turning at constant speed
        assert abs(abs(a) - (1 + t * (scale - 1))) < 0.01 * scale


def test_exact_ends_every_input_vertex_kept():
    src_rings = glyph_rings("R")
    src = isotween.Shape.from_polygon(src_rings)
    tgt = isotween.Shape.from_polygon(moved(src_rings, 70))
    a, b, _ = isotween.correspond(src, tgt)
    for given, made in ((src, a), (tgt, b)):
        gz, mz = given.z, made.z
        # every input vertex is a vertex of the output, exactly
        assert np.abs(gz[:, None] - mz[None, :]).min(axis=1).max() == 0.0


def test_pieces_that_turn_together_turn_as_a_whole():
    sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    rings = [sq, sq + [6, 1]]  # two separate squares
    src = isotween.Shape.from_polygon(rings)
    tgt = isotween.Shape.from_polygon(moved(rings, 150))
    seq = isotween.morph(src, tgt, frames=7)
    z0 = seq.frames[0, :, 0] + 1j * seq.frames[0, :, 1]
    for k in range(7):
        z = seq.frames[k, :, 0] + 1j * seq.frames[k, :, 1]
        resid, _ = similarity_residual(z0, z)
        assert resid <= 1e-3 * src.bbox_diagonal()  # the pair stays rigid: no piece cuts across


def test_landmarks_are_honoured_and_bad_ones_named():
    src_rings = glyph_rings("L")
    src = isotween.Shape.from_polygon(src_rings)
    tgt = isotween.Shape.from_polygon(moved(src_rings, 0, shift=(0, 0)))
    p = src.vertices[0]
    q = tgt.vertices[len(tgt.vertices) // 3]  # a point the automatic match would not give
    a, b, _ = isotween.correspond(src, tgt, landmarks=[(p, q)])
    i = int(np.argmin(np.hypot(*(a.vertices - p).T)))
    assert np.hypot(*(b.vertices[i] - q)) < 1e-9 * src.bbox_diagonal()
    with pytest.raises(ParameterError, match="landmark 0: the source point .* not on the drawing"):
        isotween.correspond(src, tgt, landmarks=[((1e4, 1e4), q)])
    with pytest.raises(ParameterError, match="landmarks must be"):
        isotween.correspond(src, tgt, landmarks=[(1, 2)])
    with pytest.raises(IncompatibleShapesError, match="different order"):
        n = len(tgt.vertices)
        isotween.correspond(src, tgt, landmarks=[(src.vertices[0], tgt.vertices[0]),
                                                 (src.vertices[3], tgt.vertices[n // 2]),
                                                 (src.vertices[5], tgt.vertices[n // 4])])


def test_a_landmark_leaves_the_other_corners_paired_with_corners():
    # a square into a 2:1 rectangle, one landmark at a corner: the other corners still go to corners (by arc
    # length from the landmark alone, the square's next corner would land a third of the way along a long side)
    square = resampled(np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float), 24, 5)
    wide = resampled(np.array([[0, 0], [8, 0], [8, 4], [0, 4]], float) + [10, 0], 30, 7)
    src, tgt = isotween.Shape.from_polygon(square), isotween.Shape.from_polygon(wide)
    for landmark in ([(0, 0), (10, 0)], [(4, 4), (18, 4)]):
        a, b, _ = isotween.correspond(src, tgt, landmarks=[landmark])
        for corner, partner in zip([0, 4, 4 + 4j, 4j], [10, 18, 18 + 4j, 10 + 4j], strict=True):
            i = int(np.argmin(np.abs(a.z - corner)))
            assert abs(a.z[i] - corner) < 1e-9 and abs(b.z[i] - partner) < 1e-9


def test_drawings_always_corresponded_and_the_policy_says_so(tmp_path):
    pytest.importorskip("svgelements")
    sq = '<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 H4 V4 H0 Z" fill="black"/></svg>'
    turned = '<svg xmlns="http://www.w3.org/2000/svg"><path d="M4 0 V4 H0 V0 Z" fill="black"/></svg>'
    (tmp_path / "a.svg").write_text(sq)
    (tmp_path / "b.svg").write_text(turned)
    # same point counts, other starts: a drawing's point order means nothing, so correspondence runs
    prepared = isotween.prepare_pair(tmp_path / "a.svg", tmp_path / "b.svg")
    assert prepared.report is not None and prepared.source.n_faces > 0
    np.testing.assert_allclose(prepared.target.vertices - prepared.source.vertices, 0, atol=1e-9)  # no spin
    kept = isotween.prepare_pair(tmp_path / "a.svg", tmp_path / "b.svg", correspondence="never")
    assert kept.report is None and kept.source.n_vertices == 4
    with pytest.raises(IncompatibleShapesError, match="not compatible"):
        isotween.prepare_pair(np.eye(3)[:, :2], [[0, 0], [1, 0], [1, 1], [0, 1]], correspondence="never")
    with pytest.raises(ParameterError, match="correspondence must be"):
        isotween.prepare_pair(tmp_path / "a.svg", tmp_path / "b.svg", correspondence="sometimes")


def test_a_hole_that_closes_leaves_no_speck():
    outer = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    hole = np.array([[3, 3], [3, 7], [7, 7], [7, 3]], float)  # clockwise: a hole
    src = isotween.Shape.from_polygon([outer, hole])
    tgt = isotween.Shape.from_polygon([outer + [20, 0]])
    seq = isotween.morph(src, tgt, frames=5)
    shape = seq.shape
    last = seq.frames[-1, :, 0] + 1j * seq.frames[-1, :, 1]
    areas = [abs(np.sum((np.conj(r) * np.roll(r, -1)).imag)) / 2 for r in (last[idx] for idx, _ in shape.paths)]
    assert sorted(areas)[0] < 1e-12 and sorted(areas)[1] == pytest.approx(100.0)  # the hole is a point at the end
    first = seq.frames[0, :, 0] + 1j * seq.frames[0, :, 1]
    assert sorted(abs(np.sum((np.conj(r) * np.roll(r, -1)).imag)) / 2
                  for r in (first[idx] for idx, _ in shape.paths)) == pytest.approx([16.0, 100.0])


def test_open_and_closed_strokes_morph_as_strokes():
    zig = isotween.Shape.from_polyline([[0, 0], [1, 2], [2, 0], [3, 2], [4, 0]])
    theta = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    circle = isotween.Shape.from_paths([np.c_[2 + 2 * np.cos(theta), 1 + 2 * np.sin(theta)]], closed=True,
                                       regions=[])  # a closed stroke, not a filled region
    a, b, report = isotween.correspond(zig, circle)
    assert report.lines == {"paired": 1, "grown": 0, "shrunk": 0}  # one stroke, not a cross-fade
    assert len(a.paths) == 1 and not a.paths[0][1]
    idx = a.paths[0][0]
    assert np.allclose(b.vertices[idx[0]], b.vertices[idx[-1]])  # the circle, cut open, closes at the end


def test_a_symmetric_drawing_does_not_spin(tmp_path):
    # Bootstrap Icons' square-fill and folder-fill (MIT): the square fits the folder as well turned by any
    # quarter turn; the turn of least size (none) is the one taken, so the square does not spin
    svg = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16"><path d="{}"/></svg>'
    square = "M0 2a2 2 0 0 1 2-2h12a2 2 0 0 1 2 2v12a2 2 0 0 1-2 2H2a2 2 0 0 1-2-2z"
    folder = ("M9.828 3h3.982a2 2 0 0 1 1.992 2.181l-.637 7A2 2 0 0 1 13.174 14H2.825a2 2 0 0 1-1.991-1.819"
              "l-.637-7a2 2 0 0 1 .342-1.31L.5 3a2 2 0 0 1 2-2h3.672a2 2 0 0 1 1.414.586l.828.828A2 2 0 0 0 9.828 3"
              "m-8.322.12q.322-.119.684-.12h5.396l-.707-.707A1 1 0 0 0 6.172 2H2.5a1 1 0 0 0-1 .981z")
    a, b, outer, turn = _outer_turn(tmp_path, svg.format(square), svg.format(folder))
    assert turn < 10.0
    assert np.abs(a.z[outer] - b.z[outer]).max() < 0.25 * a.bbox_diagonal()  # every point stays near its place


def test_a_toggle_slides_its_knob_and_does_not_spin(tmp_path):
    # a toggle's frame (a stroked pill) and knob (a stroked circle), the knob left, then right: the right
    # toggle is the left one turned by 180 degrees, but the frame is where it was, so nothing turns and only
    # the knob moves (turned as a whole, the frame spun round)
    head = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 24 24" fill="none" stroke="black" '
            'stroke-width="2"><rect x="1" y="5" width="22" height="14" rx="7"/><circle cx="{}" cy="12" r="3"/></svg>')
    (tmp_path / "left.svg").write_text(head.format(8))
    (tmp_path / "right.svg").write_text(head.format(16))
    seq = isotween.morph(tmp_path / "left.svg", tmp_path / "right.svg", frames=9)
    frame, knob = sorted(seq.shape.paths, key=lambda p: -np.ptp(seq.z[0, p[0]].real))
    assert np.abs(seq.z[:, frame[0]] - seq.z[0, frame[0]]).max() < 0.01 * 24
    path = seq.z[:, knob[0]].mean(axis=1)  # the knob's centre slides straight across
    assert np.abs(path.imag - 12).max() < 0.01 * 24 and np.all(np.diff(path.real) > 0)


def _outer_turn(tmp_path, source_svg, target_svg):
    """Two drawings corresponded with no options; (a, b, the largest ring's vertices, its turn in degrees)."""
    for name, text in (("a", source_svg), ("b", target_svg)):
        (tmp_path / f"{name}.svg").write_text(text)
    a, b, _ = isotween.correspond(*(isotween.io.load(tmp_path / f"{n}.svg") for n in ("a", "b")))
    outer = max(a.paths, key=lambda p: len(p[0]))[0]
    p, q = a.z[outer] - a.z[outer].mean(), b.z[outer] - b.z[outer].mean()
    return a, b, outer, abs(np.angle(np.vdot(p, q), deg=True))


def s_bar(bent, width=10.0, per_arc=24):
    """A bar 100 long along a straight centre line, or one bent into an S.

    The S: an arc turning left by 90 degrees, then one turning right by 90 (the centre line keeps its length).
    """
    if not bent:
        return np.array([[0, 5], [50, 5], [100, 5], [100, -5], [50, -5], [0, -5]], float) * [1, width / 10]
    r = 100 / np.pi  # two quarter circles: 100 in all
    t = np.linspace(0, np.pi / 2, per_arc + 1)
    line = np.r_[1j * r * (1 - np.exp(1j * t)), (2 * r + 1j * r) - r * np.exp(-1j * t[1:])]
    heading = np.r_[np.exp(1j * t), 1j * np.exp(-1j * t[1:])]
    left, right = line + width / 2 * 1j * heading, line - width / 2 * 1j * heading
    ring = np.r_[left[::-1], right]
    return np.c_[ring.real, ring.imag]


def test_a_bar_bent_into_an_s_keeps_its_area_in_every_in_between():
    """A bent bar keeps its area in every in-between.

    Arc length between corners puts the bend's inner and outer points out of step (a shear that swells
    the bar by 8 %); the slide along the outline finds the bend.
    """
    rings = [s_bar(b) for b in (False, True)]
    src, tgt = (isotween.Shape.from_polygon(r) for r in rings)
    area = [abs(isotween.geometry.ring_area(r[:, 0] + 1j * r[:, 1])) for r in rings]
    assert abs(area[1] / area[0] - 1) < 2e-3  # an isometric bend
    a, b, report = isotween.correspond(src, tgt)
    assert report.slid == 1
    seq = isotween.interpolate(a, b, frames=11)
    ring = seq.shape.paths[0][0]
    areas = [abs(isotween.geometry.ring_area(f[ring, 0] + 1j * f[ring, 1])) for f in seq.frames]
    assert np.max(np.abs(np.array(areas) / areas[0] - 1)) < 0.01
    # the source drawing is unchanged: its points slid only along its straight sides
    z = a.z[ring]
    on_side = np.isclose(np.abs(z.imag), 5) & (z.real >= -1e-9) & (z.real <= 100 + 1e-9)
    on_end = np.isclose(z.real % 100, 0) & (np.abs(z.imag) <= 5 + 1e-9)
    assert np.all(on_side | on_end)
    # hints keep the match as given: no slide; nor does a rigid copy slide
    assert isotween.correspond(src, tgt, landmarks=[((0, 5), tuple(tgt.vertices[0]))]).report.slid == 0
    turned = isotween.Shape.from_polygon(moved([s_bar(True)], 70)[0])
    assert isotween.correspond(tgt, turned).report.slid == 0


def test_slid_points_stay_on_the_source_outline_and_corners_stay():
    """Random polygons with extra points on straight sides: where the match slides, the source is unchanged."""
    rng = np.random.default_rng(7)

    def polygon():
        t = np.sort(rng.uniform(0, 2 * np.pi, rng.integers(4, 9)))
        z = rng.uniform(0.5, 1.5, len(t)) * np.exp(1j * t)
        out = []
        for a, b in zip(z, np.roll(z, -1), strict=True):  # 0-3 extra points on every side
            out += [a] + [a + s * (b - a) for s in np.sort(rng.uniform(0, 1, rng.integers(0, 4)))]
        return np.array(out)

    slid = 0
    for _ in range(40):
        a, b = polygon(), polygon()
        src, _, report = isotween.correspond(*(isotween.Shape.from_polygon(np.c_[p.real, p.imag]) for p in (a, b)))
        slid += report.slid
        z = src.z[src.paths[0][0]]
        # every point on a side of the input polygon
        p, q = a, np.roll(a, -1)
        u = np.clip(((z[:, None] - p) * np.conj(q - p)).real / np.abs(q - p) ** 2, 0, 1)
        assert np.abs(z[:, None] - (p + u * (q - p))).min(axis=1).max() <= 1e-12
        # every corner of the input a vertex of the output
        corner = np.abs(isotween.geometry.orient(np.roll(a, 1), a, np.roll(a, -1))) > 1e-9
        assert np.abs(a[corner][:, None] - z[None, :]).min(axis=1).max() == 0.0
    assert slid >= 3  # the slide was exercised


def rounded_rectangle(width, height, radius, arc_points, side_points):
    """Closed ring (k,) complex of a rounded rectangle centred at 0, and its corners' midpoints (4,) complex."""
    cx, cy = width / 2 - radius, height / 2 - radius
    centres = np.array([complex(cx, -cy), complex(cx, cy), complex(-cx, cy), complex(-cx, -cy)])
    ring, middles = [], []
    for i, c in enumerate(centres):
        arc = c + radius * np.exp(1j * (np.deg2rad(90 * i - 90) + np.linspace(0, np.pi / 2, arc_points)))
        following = centres[(i + 1) % 4] + radius * np.exp(1j * np.deg2rad(90 * i))
        ring += [arc, arc[-1] + (following - arc[-1]) * np.arange(1, side_points + 1) / (side_points + 1)]
        middles.append(c + radius * np.exp(1j * np.deg2rad(90 * i - 45)))
    return np.concatenate(ring), np.array(middles)


def test_rounded_corners_pair_with_rounded_corners():
    # no vertex turns by much on an arc; the corners are still corners, each to its partner where it lies
    from isotween.correspondence.matching import match_rings

    z, corners_z = rounded_rectangle(12, 8, 2, 9, 3)
    w, corners_w = rounded_rectangle(16, 5, 1.5, 7, 5)
    pair = match_rings(z, w, True, turn=1 + 0j, place=lambda p: p)
    for a, b in zip(corners_z, corners_w, strict=True):
        k = np.argmin(np.abs(pair.source - a))
        assert abs(pair.source[k] - a) < 1e-9 and abs(pair.target[k] - b) < 1e-6


def test_nearest_samples_are_the_nearest():
    from isotween.correspondence.alignment import _Nearest

    rng = np.random.default_rng(3)
    q = rng.normal(size=300) + 1j * rng.normal(size=300)
    near = _Nearest(q)
    for n in (200, 50, 200):  # the buffer follows the query's size
        x = 3 * (rng.normal(size=n) + 1j * rng.normal(size=n))
        d, j = near.query(x)
        every = np.abs(x[:, None] - q[None, :])
        assert np.array_equal(j, every.argmin(axis=1)) and np.allclose(d, every.min(axis=1), rtol=0, atol=1e-9)


def test_a_page_becomes_a_folder_upright(tmp_path):
    # a portrait page fits a landscape folder far better turned by a quarter turn, but it is no turned copy
    # of it (the fit stays off by more than `alignment.COPY`): the page widens upright instead of spinning
    svg = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16"><path d="{}"/></svg>'
    page = "M4 1H9L13 5V14A1 1 0 0 1 12 15H4A1 1 0 0 1 3 14V2A1 1 0 0 1 4 1Z"
    folder = "M1 4A1 1 0 0 1 2 3H6L7.5 4.5H14A1 1 0 0 1 15 5.5V12A1 1 0 0 1 14 13H2A1 1 0 0 1 1 12Z"
    assert _outer_turn(tmp_path, svg.format(page), svg.format(folder))[3] < 10.0


def test_a_house_becomes_a_heart_upright(tmp_path):
    # Bootstrap Icons' house-fill body and heart-fill (MIT): the house's only sharp corner, its apex, is
    # convex and the heart's top dip concave, so no corner pairs with the shift that keeps both upright;
    # that shift stands all the same, rather than the start that pairs the apex with the heart's tip and
    # turns the house upside down (the two fit almost as well turned by half a turn)
    svg = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16"><path d="{}"/></svg>'
    house = "M8 3.293l6 6V13.5a1.5 1.5 0 0 1-1.5 1.5h-9A1.5 1.5 0 0 1 2 13.5V9.293z"
    heart = "M8 1.314C12.438-3.248 23.534 4.735 8 15-7.534 4.736 3.562-3.248 8 1.314"
    a, b, outer, turn = _outer_turn(tmp_path, svg.format(house), svg.format(heart))
    assert turn < 10.0
    apex = outer[np.argmin(a.vertices[outer, 1])]  # y down: the top
    assert b.vertices[apex, 1] < np.median(b.vertices[outer, 1])  # lands in the heart's upper half


def test_a_heart_becomes_a_star_upright(tmp_path):
    # Bootstrap Icons' heart-fill and star-fill (MIT): two blobs whose outlines fit so well (correlation
    # above `matching.WARP_FIT`) that they count as similar copies, so the alignment's upright shift stands;
    # the heart's dip is not pulled onto one of the star's inner corners, which turns the heart by a fifth
    # of a star's turn on its way
    svg = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16"><path d="{}"/></svg>'
    heart = "M8 1.314C12.438-3.248 23.534 4.735 8 15-7.534 4.736 3.562-3.248 8 1.314"
    star = ("M3.612 15.443c-.386.198-.824-.149-.746-.592l.83-4.73L.173 6.765c-.329-.314-.158-.888.283-.95l4.898"
            "-.696L7.538.792c.197-.39.73-.39.927 0l2.184 4.327 4.898.696c.441.062.612.636.282.95l-3.522 3.356.83 "
            "4.73c.078.443-.36.79-.746.592L8 13.187l-4.389 2.256z")
    assert _outer_turn(tmp_path, svg.format(heart), svg.format(star))[3] < 10.0


def test_a_rounded_corner_where_a_stroke_joins_pairs_with_its_partner():
    # a lock's body: the shackle's leg joins the top-left corner right where its arc begins (a sharp corner
    # next to the arc); in the target the leg stands further right. The arcs' middles pair all the same
    from isotween.correspondence.matching import match_rings

    def body(width, height, leg):
        ring, middles = rounded_rectangle(width, height, 2, 9, 0)
        top = height / 2
        start = np.flatnonzero(np.isclose(ring, complex(2 - width / 2, top)))[0]  # the top-left arc's start
        foot = [leg + 1 + 1j * top, leg + 1 + 1j * (top + 3), leg + 1j * (top + 3)]
        foot += [] if np.isclose(leg, 2 - width / 2) else [leg + 1j * top]
        return np.r_[ring[:start], foot, ring[start:]], middles[2]

    z, corner_z = body(30, 20, -13.0)
    w, corner_w = body(40, 12, 0.0)
    pair = match_rings(z, w, True, turn=1 + 0j, place=lambda p: p)
    k = np.argmin(np.abs(pair.source - corner_z))
    # the middle of the arc (radius 2) lands on its partner's within a quarter of the radius, not on the top side
    assert abs(pair.source[k] - corner_z) < 1e-9 and abs(pair.target[k] - corner_w) < 0.5


def test_a_piece_does_not_pair_into_the_hole_of_a_paired_region(tmp_path):
    # a disc and a square beside it -> a ring with a square island in its hole: the disc becomes the ring,
    # and the square beside it would have to cross the ring to reach the island; it leaves, the island grows
    svg = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 40 24"><path fill-rule="evenodd" d="{}"/></svg>'
    disc = "M2 12a8 8 0 1 0 16 0a8 8 0 1 0 -16 0Z"
    beside = disc + " M30 9h6v6h-6Z"
    island = disc + " M5 12a5 5 0 1 0 10 0a5 5 0 1 0 -10 0Z M8 9h4v4h-4Z"
    (tmp_path / "a.svg").write_text(svg.format(beside))
    (tmp_path / "b.svg").write_text(svg.format(island))
    _, _, report = isotween.correspond(*(isotween.io.load(tmp_path / f"{n}.svg") for n in ("a", "b")))
    assert report.regions == {"paired": 1, "grown": 1, "shrunk": 1}
    seq = isotween.morph(tmp_path / "a.svg", tmp_path / "b.svg", frames=21)
    assert "fallback" not in seq.info and not metrics.outline_crossings(seq, visible=True).any()


def test_a_c_into_a_c_that_opens_the_other_way_turns_rather_than_turning_inside_out():
    # a thick 'C' into a taller, thinner one that opens to the left: upright, the best start pairs the C's outer
    # side with the other's inner side (the fit of the paired outlines is poor, and the area swings); the ring
    # takes its own turn instead, so the C turns over and its area follows the blend of the two ends
    def c_ring(n, inner, gap, turn, stretch):
        t = np.linspace(gap, 2 * np.pi - gap, n)
        z = np.r_[np.exp(1j * t), inner * np.exp(1j * t[::-1])]
        z = (z.real + 1j * stretch * z.imag) * np.exp(1j * turn)
        return np.c_[z.real, z.imag]

    src = isotween.Shape.from_polygon(c_ring(60, 0.6, np.pi / 3, 0.0, 1.0))
    tgt = isotween.Shape.from_polygon(c_ring(45, 0.55, np.pi / 4, np.pi, 1.3))
    a, b, _ = isotween.correspondence.correspond(src, tgt)
    z, w = a.z[a.paths[0][0]], b.z[b.paths[0][0]]
    zc, wc = z - z.mean(), w - w.mean()
    fit = abs(np.vdot(zc, wc) / np.vdot(zc, zc)) * np.linalg.norm(zc) / np.linalg.norm(wc)
    assert fit > 0.95  # the paired outlines are nearly one similarity apart (upright: 0.39)
    seq = isotween.interpolate(a, b, frames=9)
    assert not flipped_faces(seq, reduce=None).any()
    area = np.abs([ring_area(f[a.paths[0][0]] @ [1, 1j]) for f in seq.frames])
    blend = np.linspace(area[0], area[-1], len(area))
    assert np.all(np.abs(area - blend) <= 0.02 * blend)  # upright: 12 % off at t = 0.5
