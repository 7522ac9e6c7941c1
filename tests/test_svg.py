"""SVG semantics: fill closes subpaths, fill-rule makes regions and holes, paint is kept."""

import warnings

import numpy as np
import pytest

from isotween import io
from isotween.correspondence import correspond
from isotween.errors import FileFormatError
from isotween.geometry import ring_area

HEART = ('<path fill-rule="evenodd" d="M8 1.314C12.438-3.248 23.534 4.735 8 15-7.534 4.736 '
         '3.562-3.248 8 1.314"/>')


def write(tmp_path, body, name="d.svg"):
    (tmp_path / name).write_text(f'<svg xmlns="http://www.w3.org/2000/svg">{body}</svg>')
    return tmp_path / name


def read(tmp_path, body, name="d.svg"):
    return io.load(write(tmp_path, body, name))


def test_filled_path_without_z_is_a_closed_region(tmp_path):
    s = read(tmp_path, HEART)
    assert [c for _, c in s.paths] == [True]
    assert s.regions == [[0]]
    ring = s.vertices[s.paths[0][0]]
    # the end point repeats the start (8, 1.314) and is dropped: the closing edge is implied
    np.testing.assert_allclose(ring[0], [8, 1.314])
    assert not np.allclose(ring[-1], ring[0])
    assert s.paint[0].fill == (0.0, 0.0, 0.0, 1.0)


def test_unfilled_paths_stay_open_and_keep_their_stroke(tmp_path):
    body = ('<style>.thin{fill:none;stroke:#00ff00;stroke-width:2}</style>'
            '<path class="thin" d="M0 0 L5 5 L9 0"/>'
            '<g fill="none" stroke="red"><path d="M0 10 L5 15 L9 10"/><path d="M0 20 L5 25 L9 20 Z"/></g>'
            '<path style="fill:none;stroke:blue" d="M0 30 L4 30"/>')
    s = read(tmp_path, body)
    assert [c for _, c in s.paths] == [False, False, True, False]
    assert s.regions == []
    assert s.paint[0].stroke == (0.0, 1.0, 0.0, 1.0) and s.paint[0].stroke_width == 2.0
    assert s.paint[1].stroke == (1.0, 0.0, 0.0, 1.0) and s.paint[1].fill is None
    assert s.paint[3].stroke == (0.0, 0.0, 1.0, 1.0)


def test_strokes_drawn_in_pieces_are_joined_where_two_ends_meet(tmp_path):
    # a rounded square's outline in eight pieces (sides and corners, some backwards), three strokes from
    # one point, and a black line continued by a red one
    pieces = ["M2 0 L8 0", "M10 2 A2 2 0 0 0 8 0", "M10 2 L10 8", "M8 10 A2 2 0 0 0 10 8", "M8 10 L2 10",
              "M0 8 A2 2 0 0 0 2 10", "M0 2 L0 8", "M2 0 A2 2 0 0 0 0 2"]
    body = ('<g fill="none" stroke="black">' + "".join(f'<path d="{d}"/>' for d in pieces)
            + '<path d="M20 0 L25 5"/><path d="M20 0 L15 5"/><path d="M20 0 L20 -5"/></g>'
            + '<path fill="none" stroke="black" d="M30 0 L35 0"/><path fill="none" stroke="red" d="M35 0 L35 5"/>')
    s = io.load(write(tmp_path, body), curve_segments=6)
    assert [(len(i) > 8, c) for i, c in s.paths][:1] == [(True, True)]  # the outline: one closed ring
    assert len(s.paths) == 1 + 3 + 2  # the three-way junction and the change of colour stay apart
    # every point of every piece is a point of the ring, and nothing else
    alone = io.load(write(tmp_path, "".join(f'<path fill="none" stroke="black" d="{d}"/>'
                                            f'<path fill="red" d="M50 50 h1 v1 z"/>' for d in pieces), "b.svg"),
                    curve_segments=6)
    assert len(alone.paths) == 16  # filled paths between the pieces: the painting order keeps them apart
    ring = s.vertices[s.paths[0][0]]
    every = np.concatenate([alone.vertices[i] for i, _ in alone.paths[::2]])
    assert len(np.unique(np.round(every, 9), axis=0)) == len(ring)
    assert np.abs(ring[:, None] - every[None]).max(axis=2).min(axis=1).max() < 1e-9


def test_a_filled_ring_that_turns_back_on_itself_loses_the_spike_a_stroke_keeps_it(tmp_path):
    # a square whose right side runs out 2 and straight back (no area), and whose left side ends a hair
    # past the start, to which the closing edge backs up (as in Font Awesome's road and carrot)
    d = "M0.0003 0 H10 V5 H12 H10 V10 H0 V-0.004 Z"
    s = read(tmp_path, f'<path d="{d}"/><path fill="none" stroke="black" d="{d}" transform="translate(20)"/>')
    filled, stroked = (s.vertices[i] for i, _ in s.paths)
    assert not np.any(np.all(np.abs(filled - [12, 5]) < 1e-9, axis=1)) and len(filled) == 5
    assert abs(abs(ring_area(filled)) - 100) < 0.1
    assert np.any(np.all(np.abs(stroked - [32, 5]) < 1e-9, axis=1))  # drawn as a line: kept
    a, b, report = correspond(s, s)  # meshed: the ring no longer touches itself
    assert "as outlines" not in report.summary()


def test_a_filled_ring_through_one_point_twice_is_cut_there(tmp_path):
    # a body with a wheel drawn onto it through one point of its top, as Bootstrap draws carts and bugs
    s = read(tmp_path, '<path d="M0 0 H10 V4 H6 L7 6 L5 6 L6 4 H0 Z"/>')
    rings = [s.vertices[i] for i, _ in s.paths]
    assert sorted(len(r) for r in rings) == [3, 5] and sorted(map(len, s.regions)) == [1, 1]
    np.testing.assert_allclose(sorted(abs(ring_area(r)) for r in rings), [2.0, 40.0])
    for r in rings:  # neither passes through a point twice
        assert len(np.unique(np.round(r, 9), axis=0)) == len(r)
    a, b, report = correspond(s, s)
    assert "as outlines" not in report.summary()


def test_inherited_fill_opacity_and_colour(tmp_path):
    body = ('<g fill="#0000ff" opacity="0.5"><path d="M0 0 L4 0 L4 4"/></g>'
            '<path fill="#ff0000" fill-opacity="0.25" d="M10 0 h4 v4 h-4"/>')
    s = read(tmp_path, body)
    assert [c for _, c in s.paths] == [True, True]
    assert s.regions == [[0], [1]]
    assert s.paint[0].fill == (0.0, 0.0, 1.0, 1.0) and s.paint[0].opacity == 0.5
    assert s.paint[1].fill[:3] == (1.0, 0.0, 0.0)
    assert abs(s.paint[1].fill[3] - 0.25) < 1 / 255


@pytest.mark.parametrize("rule, inner_same, inner_reversed", [
    # nonzero: a ring turning the same way as its container is inside the fill (no hole)
    ("nonzero", "outline", "hole"),
    # evenodd: every nested ring is a hole, whatever its direction
    ("evenodd", "hole", "hole"),
])
def test_fill_rule_decides_holes(tmp_path, rule, inner_same, inner_reversed):
    d = "M0 0 h10 v10 h-10 z M2 2 h2 v2 h-2 z M6 2 v2 h2 v-2 z"
    s = read(tmp_path, f'<path fill-rule="{rule}" d="{d}"/>')
    expect = {"hole": [], "outline": []}
    expect[inner_same].append(1)
    expect[inner_reversed].append(2)
    assert s.regions == [[0] + expect["hole"]]
    for k in expect["outline"]:
        assert s.paint[k].fill is None  # a boundary inside the fill draws nothing filled
    for k in expect["hole"]:
        assert s.paint[k] == s.paint[0]  # holes repeat their region's paint


def test_evenodd_island_in_a_hole_is_its_own_region(tmp_path):
    d = "M0 0 h10 v10 h-10 z M2 2 h6 v6 h-6 z M3 3 h4 v4 h-4 z"
    s = read(tmp_path, f'<path fill-rule="evenodd" d="{d}"/>')
    assert s.regions == [[0, 1], [2]]


def test_separate_elements_are_separate_regions(tmp_path):
    # the same nested squares as two elements: painted on top of each other, no hole
    s = read(tmp_path, '<path d="M0 0 h10 v10 h-10 z"/><path d="M2 2 v2 h2 v-2 z"/>')
    assert s.regions == [[0], [1]]


def test_degenerate_subpaths_are_dropped_with_a_warning(tmp_path):
    body = ('<path id="dot" d="M5 5 L5 5"/><path id="flat" d="M0 0 L1 1 L2 2 z"/>'
            '<path id="ok" d="M0 0 h4 v4 h-4 z"/>')
    with pytest.warns(UserWarning) as record:
        s = read(tmp_path, body)
    text = str(record[0].message)
    assert '<path id="dot">: closed subpath 0 has 1 distinct point(s)' in text
    assert '<path id="flat">: filled subpath 0 encloses no area' in text
    assert len(s.paths) == 1 and s.regions == [[0]]


def test_only_degenerate_subpaths_is_an_error_naming_them(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(FileFormatError, match=r'nothing to read .*<path id="flat">: filled subpath 0'):
            read(tmp_path, '<path id="flat" d="M0 0 L1 1 L2 2 z"/>')


def test_regions_and_paint_read_back_identically(tmp_path):
    body = ('<path fill="#336699" fill-opacity="0.5" stroke="#ff0000" stroke-width="0.25" opacity="0.75" '
            'fill-rule="evenodd" d="M0 0 h10 v10 h-10 z M2 2 h6 v6 h-6 z M3 3 h4 v4 h-4 z"/>'
            '<path fill="none" stroke="#00ff00" d="M0 12 L5 15 L9 12"/>' + HEART)
    s = read(tmp_path, body)
    assert s.regions == [[0, 1], [2], [4]]
    io.save(s, tmp_path / "back.svg")
    back = io.load(tmp_path / "back.svg")
    np.testing.assert_array_equal(back.vertices, s.vertices)
    assert [(p.tolist(), c) for p, c in back.paths] == [(p.tolist(), c) for p, c in s.paths]
    assert back.regions == s.regions
    for p, q in zip(back.paint, s.paint, strict=False):
        assert (p.fill is None) == (q.fill is None) and p.stroke == q.stroke
        assert p.stroke_width == q.stroke_width and p.opacity == q.opacity
        if p.fill is not None:
            np.testing.assert_allclose(p.fill, q.fill, atol=1 / 255)


def test_elements_that_draw_nothing_are_left_out(tmp_path):
    s = read(tmp_path, '<path d="M0 0h24v24H0z" fill="none"/><line x1="0" y1="0" x2="5" y2="5"/>'
                       '<path d="M4 4h8v8h-8z"/>')
    assert len(s.paths) == 1 and s.regions == [[0]]
    np.testing.assert_allclose(s.vertices, [[4, 4], [12, 4], [12, 12], [4, 12]])


def test_what_the_reader_does_not_read_is_named_in_one_warning(tmp_path):
    """Gradient paint, text and images are not drawn silently: one warning names them."""
    pytest.importorskip("svgelements")
    path = tmp_path / "g.svg"
    path.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><defs><linearGradient id="g">'
                    '<stop offset="0" stop-color="red"/></linearGradient></defs>'
                    '<rect id="box" x="1" y="1" width="8" height="8" fill="url(#g)"/>'
                    '<text x="1" y="5">hi</text><image href="a.png" x="0" y="0" width="1" height="1"/></svg>')
    with pytest.warns(UserWarning) as caught:
        shape = io.load(path)
    (w,) = [str(c.message) for c in caught if "does not read" in str(c.message)]
    assert "<text> x1" in w and "<image> x1" in w and "<rect id='box'> fill" in w
    assert shape.n_vertices == 4  # the rectangle itself is still read
    plain = tmp_path / "p.svg"
    plain.write_text('<svg xmlns="http://www.w3.org/2000/svg"><rect x="1" y="1" width="8" height="8"/></svg>')
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        io.load(plain)  # nothing unread: no warning
