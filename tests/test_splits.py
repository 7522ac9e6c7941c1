"""A region that the other drawing shows in pieces is cut where the pieces part (`correspondence.splits`)."""

import numpy as np
import pytest

import isotween
from isotween.geometry import ring_area

SVG = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 20 20">{}</svg>'
SQUARE = '<path d="M2 2h16v16h-16Z"/>'
PARTED = '<path d="M2 2h7v16h-7Z M11 2h7v16h-7Z"/>'  # the square with a gap of 2 down its middle, x = 9 to 11


def _report(a, b):
    """The correspondence report of two SVG files."""
    return isotween.correspond(isotween.io.load(a), isotween.io.load(b))[2]


def _pair(tmp_path, a, b):
    (tmp_path / "a.svg").write_text(SVG.format(a))
    (tmp_path / "b.svg").write_text(SVG.format(b))
    return tmp_path / "a.svg", tmp_path / "b.svg"


@pytest.mark.parametrize("whole_first", [True, False])
def test_a_region_the_other_drawing_parts_is_cut_where_they_part(tmp_path, whole_first):
    a, b = _pair(tmp_path, *((SQUARE, PARTED) if whole_first else (PARTED, SQUARE)))
    report = _report(a, b)
    assert report.cut == ([1, 0] if whole_first else [0, 1])
    assert report.regions == {"paired": 2, "grown": 0, "shrunk": 0}
    seq = isotween.morph(a, b, frames=11)
    z = seq.z  # (F, n) complex
    whole = 0 if whole_first else -1
    rings = [idx for idx, closed in seq.shape.paths if closed]
    # at the whole square's end the two parts tile it: they meet at x = 10 and their areas add up to 16 x 16
    assert sum(abs(ring_area(z[whole, idx])) for idx in rings) == pytest.approx(256.0, rel=1e-9)
    for idx in rings:
        side = np.sign(z[-1 - whole, idx].real.mean() - 10.0)
        assert np.all(side * (z[:, idx].real - 10.0) >= -1e-9)  # each part keeps to its side of the cut
    # the parts stay where they are drawn: the cut opens into the gap, nothing else moves much
    assert np.abs(z - z[whole]).max() <= 1.0 + 0.05


def test_a_region_with_a_whole_partner_stays_whole(tmp_path):
    # a face, and the same face with two eyes painted on it: the eyes lie inside the face, but the face has a partner
    face = '<path d="M2 2h16v16h-16Z"/>'
    eyes = face + '<path d="M5 5h3v3h-3Z"/><path d="M12 5h3v3h-3Z"/>'
    a, b = _pair(tmp_path, face, eyes)
    report = _report(a, b)
    assert report.cut == [0, 0] and report.regions == {"paired": 1, "grown": 2, "shrunk": 0}


def test_the_parts_of_a_cut_region_draw_as_the_region_with_no_seam(tmp_path):
    from isotween.render.frame import FramePainter

    # the square and two triangles parted along its diagonal: the cut runs from corner to corner
    a, b = _pair(tmp_path, SQUARE, '<path d="M2 2h14l-14 14Z M18 4v14h-14Z"/>')
    seq = isotween.morph(a, b, frames=5)
    assert seq.info["correspondence"].count("cut") == 1
    rgb = FramePainter(157, 157, (0.0, 0.0, 20.0, 20.0), y_down=True).render(seq.shape.with_vertices(seq.frames[0]))
    # filled as one path, the halves leave no lighter line where they meet: the middle of the square is all black
    assert rgb[47:110, 47:110].max() == 0


@pytest.mark.parametrize("across", [True, False])
def test_a_region_is_cut_only_where_the_other_drawing_fills_most_of_it(tmp_path, across):
    # two bars inside the square cover 62.5 % of it; with a stroke across the gap between them (not inside the
    # square: it reaches out on both sides) the other drawing fills 87.5 % of it, the square struck through and
    # parted; without, the bars stand in an empty square, which stays whole
    bars = '<path d="M2 2h5v16h-5Z M13 2h5v16h-5Z"/>' + ('<path d="M8 -4h4v28h-4Z"/>' if across else "")
    a, b = _pair(tmp_path, SQUARE, bars)
    report = _report(a, b)
    assert report.cut == ([1, 0] if across else [0, 0])


@pytest.mark.parametrize("shift", [0.0, 0.6])
def test_a_thin_outline_is_cut_where_its_struck_through_copy_parts_though_drawn_apart(tmp_path, shift):
    # a square outline 1 wide, and the same outline parted along x = 10 with a bar in the gap (a bell and the bell
    # struck through): the parted copy drawn 0.6 lower still lies within the outline's width of it, so the outline
    # is cut where the copy parts (about 70 % of each part lies inside the outline itself, short of `INSIDE`)
    outline = '<path fill-rule="evenodd" d="M2 2h16v16h-16Z M3 3v14h14v-14Z"/>'
    top, low = 2 + shift, 18 + shift
    parted = (f'<path d="M2 {top}h7v1h-6v14h6v1h-7Z"/><path d="M11 {top}h7v{low - top}h-7v-1h6v-14h-6Z"/>'
              f'<path d="M9.5 0h1v20h-1Z"/>')
    a, b = _pair(tmp_path, outline, parted)
    report = _report(a, b)
    assert report.cut == [1, 0] and report.regions == {"paired": 2, "grown": 1, "shrunk": 0}


def test_a_region_is_cut_where_a_slash_drawn_joined_to_one_part_parts_it(tmp_path):
    # the square parted down x = 8..9 and struck through by a bar 1.5 wide (x = 9 to 10.5) drawn as one path with
    # the right part (Font Awesome's slashed icons): the bar reaches far out, so only 75 % of that path lies inside
    # the square, short of `INSIDE`; the bar left out, all of the right part does, and the square is cut
    parts = '<path d="M2 2h6v16h-6Z"/><path d="M9 -14h1.5v16h7.5v16h-7.5v16h-1.5Z"/>'
    a, b = _pair(tmp_path, SQUARE, parts)
    report = _report(a, b)
    assert report.cut == [1, 0] and report.regions == {"paired": 2, "grown": 0, "shrunk": 0}
    seq = isotween.morph(a, b, frames=11)
    left = [idx for idx, closed in seq.shape.paths if closed and seq.z[-1, idx].real.mean() < 8.5]
    # the left part keeps left of the gap's middle (the cut, straightened within a quarter `STEP`): not swallowed
    assert len(left) == 1 and np.all(seq.z[:, left[0]].real <= 8.5 + 0.05)


@pytest.mark.parametrize("play_first", [True, False])
def test_play_parts_into_pause(tmp_path, play_first):
    # a triangle and two bars (play and pause): the left bar lies 90 % inside the triangle, the right only 38 %
    # (`LOOSE`), in nothing else of the drawing: the triangle is cut between them, and each part squares into its
    # bar, where paired whole the triangle would become one bar while the other grew from nothing
    play = '<path d="M2 2L18 10L2 18Z"/>'
    pause = '<path d="M2 3h6v14h-6Z"/><path d="M10 3h5.5v14h-5.5Z"/>'
    a, b = _pair(tmp_path, *((play, pause) if play_first else (pause, play)))
    report = _report(a, b)
    assert report.cut == ([1, 0] if play_first else [0, 1])
    assert report.regions == {"paired": 2, "grown": 0, "shrunk": 0}
    seq = isotween.morph(a, b, frames=11)
    z, bars = seq.z, -1 if play_first else 0
    for idx in (idx for idx, closed in seq.shape.paths if closed):
        # each part keeps to its bar's side of the gap's middle (x = 9) in every frame
        side = np.sign(z[bars, idx].real.mean() - 9.0)
        assert np.all(side * (z[:, idx].real - 9.0) >= -0.05)


def test_a_struck_through_copy_drawn_shifted_is_cut_where_it_parts(tmp_path):
    # the parted square and a bar in its gap, all drawn 2 to the right (Font Awesome draws a bell and the bell struck
    # through each in the middle of its own width): in place, 2 of the right half's 7 lie outside the square, short
    # of `INSIDE`; the alignment finds the shift that puts the halves on the square, which is then cut between them
    shifted = '<path d="M4 2h7v16h-7Z M13 2h7v16h-7Z"/><path d="M11.5 -2h1v24h-1Z"/>'
    a, b = _pair(tmp_path, SQUARE, shifted)
    report = _report(a, b)
    assert report.cut == [1, 0] and report.regions == {"paired": 2, "grown": 1, "shrunk": 0}
    seq = isotween.morph(a, b, frames=11)
    z, rings = seq.z, [idx for idx, closed in seq.shape.paths if closed]
    # the square's halves (painted first, the bar last) move 2 to the right and open 1 from the cut: no part of the
    # square travels across it
    for idx in rings[:2]:
        assert np.abs(z[:, idx] - z[0, idx]).max() <= 3.0 + 0.05


def test_the_struck_through_eye_parts_where_it_is_drawn():
    from isotween import examples

    seq = examples.interpolate_example("slash")
    z = seq.z
    rings = sorted((idx for idx, closed in seq.shape.paths if closed), key=lambda idx: -abs(ring_area(z[0, idx])))
    # the two largest rings are the eye's halves: they part along the slash (the gap is 1.2 wide on either side
    # of it) and nothing else of them moves much; turned over, as one piece, the eye's far side would travel
    # across the whole eye
    for idx in rings[:2]:
        assert np.abs(z[:, idx] - z[0, idx]).max() <= 1.5


def test_a_browser_draws_the_parts_of_a_cut_region_with_no_seam(tmp_path, browser):
    from browser import screenshot
    from isotween.render.html import paint_data
    from isotween.render.paths import PathData, svg_document

    a, b = _pair(tmp_path, SQUARE, '<path d="M2 2h14l-14 14Z M18 4v14h-14Z"/>')
    seq = isotween.morph(a, b, frames=5)
    assert seq.info["joined"] == [[0, 1]] and len(PathData(seq).groups) == 1  # one element for both halves
    assert [len(g["paths"]) for g in paint_data(seq)] == [2]  # and one path of the HTML player's canvas
    (tmp_path / "first.svg").write_text(svg_document(seq, 0.0, size=400))
    page = browser.new_page(viewport={"width": 400, "height": 400})
    try:
        page.goto((tmp_path / "first.svg").as_uri())
        rgb = screenshot(page)
    finally:
        page.close()
    # the halves meet along the diagonal; as one element, anti-aliasing leaves no lighter line there
    assert rgb[150:250, 150:250].max() <= 8


def test_svg_frames_draw_the_parts_of_a_cut_region_as_one_element_and_no_triangles(tmp_path):
    import re

    a, b = _pair(tmp_path, SQUARE, PARTED)
    seq = isotween.morph(a, b, frames=5)
    assert seq.info["joined"] == [[0, 1]] and seq.shape.n_faces > 0
    files = isotween.write_output(seq, tmp_path / "frames", format="svg")
    for k, path in enumerate(files):
        text = path.read_text()
        # one filled element holding both halves; the triangles inside them are not drawn as lines
        assert re.findall(r'<path id="(\w+)"', text) == ["path0"]
        back = isotween.io.load(path)
        # the halves read back as two regions, each its ring of frame k (to the 17 digits written)
        assert len(back.regions) == 2
        for (idx, _), (back_idx, _) in zip(seq.shape.paths, back.paths, strict=True):
            np.testing.assert_allclose(back.vertices[back_idx], seq.frames[k][idx], atol=1e-12)


STROKE = 'fill="none" stroke="black" stroke-width="1" stroke-linecap="round"'


@pytest.mark.parametrize("close", ["Z", "V2"])  # a ring, or a line that ends where it starts (drawn without Z)
def test_a_stroke_the_other_drawing_parts_is_cut_where_they_part(tmp_path, close):
    # a square outline, and the square struck through: drawn as two strokes, top and right, bottom and left,
    # parted by gaps of 2 at the corners the slash crosses (Lucide's bell and bell-off)
    square = f'<path {STROKE} d="M2 2H18V18H2{close}"/>'
    parted = f'<path {STROKE} d="M4 2H18V16"/><path {STROKE} d="M16 18H2V4"/><path {STROKE} d="M1 1L19 19"/>'
    a, b = _pair(tmp_path, square, parted)
    report = _report(a, b)
    assert report.strokes_cut == [1, 0] and report.lines == {"paired": 2, "grown": 1, "shrunk": 0}
    seq = isotween.morph(a, b, frames=9)
    z = seq.z
    parts = sorted((idx for idx, _ in seq.shape.paths), key=lambda idx: -np.ptp(z[0, idx].real))[:2]
    ends = np.concatenate([z[0, idx] for idx in parts])
    # at the square's end the two parts are the square: on its outline, every corner a vertex of one of them
    on = np.minimum(np.minimum(abs(ends.real - 2), abs(ends.real - 18)), np.minimum(abs(ends.imag - 2),
                                                                                     abs(ends.imag - 18)))
    assert on.max() < 1e-9
    assert all(np.abs(ends - c).min() < 1e-9 for c in (2 + 2j, 18 + 2j, 18 + 18j, 2 + 18j))
    # each part keeps to its half, cut at the middle of the gaps (the corners): its ends move 2, along the gap,
    # and nothing travels round the square
    for idx in parts:
        assert np.abs(z[:, idx] - z[0, idx]).max() <= 2.1


def test_a_stroke_the_other_drawing_draws_nearly_whole_is_not_cut(tmp_path):
    # the square with a gap at a corner, a small corner piece drawn in it: the square has its partner, whole
    square = f'<path {STROKE} d="M2 2H18V18H2Z"/>'
    other = f'<path {STROKE} d="M5 2H18V18H2V5"/><path {STROKE} d="M2 3V2H3"/>'
    a, b = _pair(tmp_path, square, other)
    report = _report(a, b)
    assert report.strokes_cut == [0, 0]


def test_the_struck_ring_parts_and_the_slash_grows_from_its_middle():
    from isotween import examples

    seq = examples.interpolate_example("struck")
    z = seq.z
    arcs, slash = [idx for idx, _ in seq.shape.paths[:2]], seq.shape.paths[2][0]
    # each arc stays where it is drawn: on the ring of radius 4 round (6, 6), give or take the gap it opens
    for idx in arcs:
        assert np.abs(np.abs(z[:, idx] - (6 + 6j)) - 4).max() < 0.05
    # the slash (no partner) passes nowhere near the ring's outline from its middle: it grows from there, not
    # out of the ring
    assert np.abs(z[1, slash] - (6 + 6j)).max() < 0.2 * np.abs(z[-1, slash] - (6 + 6j)).max()


PLUS = '<path d="M9 2h2v7h7v2h-7v7h-2v-7h-7v-2h7Z"/>'  # two bars 2 wide crossing at (10, 10)
MINUS = '<path d="M2 9h16v2h-16Z"/>'  # the plus's cross bar


@pytest.mark.parametrize("plus_first", [True, False])
def test_a_plus_into_a_minus_retracts_its_arms_into_the_bar(tmp_path, plus_first):
    a, b = _pair(tmp_path, *((PLUS, MINUS) if plus_first else (MINUS, PLUS)))
    report = _report(a, b)
    assert report.cut == ([1, 0] if plus_first else [0, 1])
    assert report.regions == {"paired": 1, "grown": 0 if plus_first else 2, "shrunk": 2 if plus_first else 0}
    seq = isotween.morph(a, b, frames=9)
    z = seq.z
    plus = 0 if plus_first else -1
    rings = [idx for idx, closed in seq.shape.paths if closed]
    bar = max(rings, key=lambda idx: np.ptp(z[plus, idx].real))
    arms = [idx for idx in rings if idx is not bar]
    assert np.abs(z[:, bar] - z[plus, bar]).max() < 1e-6  # the bar stays: no diamond squeezed out of the plus
    for idx in arms:
        # each arm (2 x 7) keeps to the vertical line of the plus and collapses onto the bar at the minus's end
        assert np.abs(z[:, idx].real - 10).max() <= 1 + 1e-9
        assert np.abs(z[-1 - plus, idx].imag - 10).max() <= 1 + 1e-9 and np.ptp(z[-1 - plus, idx].imag) < 0.1


@pytest.mark.parametrize("menu_first", [True, False])
def test_a_menu_turns_into_a_close_sign_as_two_crossed_bars(tmp_path, menu_first):
    # three bars and an X, one region (a menu and a close sign, Bootstrap's list and x-lg): the X is taken as its two
    # bars crossed, each turns into a bar of the menu (paired whole with a bar, the X melted into a blob)
    menu = "".join(f'<path d="M3 {y}h14v2h-14Z"/>' for y in (4, 9, 14))
    r = 1 / 2**0.5  # the X: bars 2 wide from (4, 4) to (16, 16) and from (16, 4) to (4, 16)
    x = [(4 - r, 4 + r), (4 + r, 4 - r), (10, 10 - 2 * r), (16 - r, 4 - r), (16 + r, 4 + r), (10 + 2 * r, 10),
         (16 + r, 16 - r), (16 - r, 16 + r), (10, 10 + 2 * r), (4 + r, 16 + r), (4 - r, 16 - r), (10 - 2 * r, 10)]
    cross = '<path d="M' + " L".join(f"{a!r} {b!r}" for a, b in x) + 'Z"/>'
    a, b = _pair(tmp_path, *((menu, cross) if menu_first else (cross, menu)))
    report = _report(a, b)
    assert report.cut == ([0, 1] if menu_first else [1, 0])
    assert report.regions == ({"paired": 2, "grown": 0, "shrunk": 1} if menu_first
                              else {"paired": 2, "grown": 1, "shrunk": 0})
    seq = isotween.morph(a, b, frames=11)
    # the bars cross where the X is drawn: they may pass through each other on the way, so AIAP's morph stands
    assert not seq.info.get("fallback")
    bars = [idx for idx, closed in seq.shape.paths if closed and abs(ring_area(seq.z[0, idx])) > 1e-9
            and abs(ring_area(seq.z[-1, idx])) > 1e-9]
    assert len(bars) == 2
    for idx in bars:  # each keeps to a bar's area (14 by 2, 17 by 2) in every frame: it turns as a whole
        area = np.abs([ring_area(z) for z in seq.z[:, idx]])
        assert np.all((area >= min(area[0], area[-1]) - 1.0) & (area <= max(area[0], area[-1]) + 1.0))


def test_a_triangle_round_its_inscribed_circle_keeps_its_corners(tmp_path):
    # the circle lies within the triangle, but the corners left over are no bars: the triangle morphs whole
    th = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    circle = "M" + " L".join(f"{10 + 4.6 * np.cos(t):.4f} {11.5 + 4.6 * np.sin(t):.4f}" for t in th) + "Z"
    a, b = _pair(tmp_path, '<path d="M10 1.5 L18.66 16.5 L1.34 16.5Z"/>', f'<path d="{circle}"/>')
    report = _report(a, b)
    assert report.cut == [0, 0] and report.regions == {"paired": 1, "grown": 0, "shrunk": 0}


@pytest.mark.parametrize("check_first", [True, False])
def test_a_check_turns_into_a_close_sign_arm_by_arm(tmp_path, check_first):
    # a check mark (one region bent once) and an X (one region, two bars crossed): the check is cut at its elbow
    # and the X taken as its two bars; each arm turns into the bar of its own direction (whole, the check melted
    # into the X; paired by place and overlap alone, the long arm swung across into the other bar)
    import shapely

    v = shapely.LineString([(3, 10), (8, 15), (17, 4)]).buffer(1, cap_style="flat", join_style="mitre")
    check = '<path d="M' + " L".join(f"{x:.12g} {y:.12g}" for x, y in np.asarray(v.exterior.coords)[:-1]) + 'Z"/>'
    r = 1 / 2**0.5
    x = [(4 - r, 4 + r), (4 + r, 4 - r), (10, 10 - 2 * r), (16 - r, 4 - r), (16 + r, 4 + r), (10 + 2 * r, 10),
         (16 + r, 16 - r), (16 - r, 16 + r), (10, 10 + 2 * r), (4 + r, 16 + r), (4 - r, 16 - r), (10 - 2 * r, 10)]
    cross = '<path d="M' + " L".join(f"{a!r} {b!r}" for a, b in x) + 'Z"/>'
    a, b = _pair(tmp_path, *((check, cross) if check_first else (cross, check)))
    report = _report(a, b)
    assert report.cut == [1, 1]
    assert report.regions == {"paired": 2, "grown": 0, "shrunk": 0}
    seq = isotween.morph(a, b, frames=11)

    def axis(z):  # the direction of a piece's long axis, as exp(2i angle)
        d = z - z.mean()
        m = np.mean(d * d)
        return m / abs(m)

    pieces = [idx for idx, closed in seq.shape.paths if closed]
    assert len(pieces) == 2
    for idx in pieces:
        assert abs(axis(seq.z[0, idx]) - axis(seq.z[-1, idx])) < 2 * np.sin(np.radians(20))  # within 20 degrees
