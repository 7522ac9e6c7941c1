"""A hole that opens into a notch: 'O' into 'C' opens the O where the C has its gap.

The O's hole lies in the C's notch, so the O is cut open along a slit across
its material where the C is empty, and its outer ring, run round the hole,
is matched to the C's outline: no hole shrinks away. At the O's end the
slit is closed again, so frame 0 is the O exactly (same filled area, every
input vertex in place).
"""

import sys
from pathlib import Path

import numpy as np
import pytest

import isotween
from isotween.correspondence import notches
from isotween.geometry import ring_area

ROOT = Path(__file__).resolve().parents[1]
pytest.importorskip("shapely")


def glyph_svg(char, path, style=""):
    pytest.importorskip("matplotlib")
    sys.path.insert(0, str(ROOT / "scripts"))
    from build_examples import glyph

    rings = glyph(char)
    d = " ".join("M " + " L ".join(f"{x:.3f} {-y:.3f}" for x, y in r) + " Z" for r in rings)
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg"><path fill-rule="evenodd" {style} d="{d}"/></svg>')
    return str(path)


def test_o_opens_into_c(tmp_path):
    o, c = glyph_svg("O", tmp_path / "o.svg"), glyph_svg("C", tmp_path / "c.svg")
    seq = isotween.morph(o, c, frames=9)
    assert "1 source hole(s) opened into notches" in seq.info["correspondence"]
    shape = seq.shape
    assert len(shape.paths) == 1 and len(shape.regions) == 1  # one ring: no hole shrinks away
    z0 = seq.frames[0, :, 0] + 1j * seq.frames[0, :, 1]
    ring = z0[shape.paths[0][0]]
    area = abs(ring_area(np.c_[ring.real, ring.imag]))
    drawing = isotween.io.load(o)
    outer, hole = (drawing.vertices[idx] for idx, _ in drawing.paths)
    assert area == pytest.approx(abs(ring_area(outer)) - abs(ring_area(hole)), rel=1e-9)  # the slit closed
    for r in (outer, hole):  # every input vertex of the O is a vertex of frame 0
        pts = r[:, 0] + 1j * r[:, 1]
        assert np.abs(pts[:, None] - z0[None, :]).min(axis=1).max() < 1e-9


def test_a_closed_slit_is_its_centre_line():
    outer = np.array([0, 4, 4 + 4j, 4j], complex)
    hole = np.array([1 + 1j, 1 + 3j, 3 + 3j, 3 + 1j], complex)  # clockwise
    ring, ((oa, ha, hb, ob), (o, h)) = notches._spliced(outer, hole, 1, 3, 0.01)
    inner = abs(ring_area(np.c_[hole.real, hole.imag]))
    assert 16 - inner - 0.02 * abs(h - o) < abs(ring_area(np.c_[ring.real, ring.imag])) < 16 - inner
    side = np.r_[ring, oa + 0.3 * (ha - oa)]  # a vertex resampling put on a side
    closed = notches.close_slits(side, [((oa, ha, hb, ob), (o, h))])
    assert abs(ring_area(np.c_[closed[:-1].real, closed[:-1].imag])) == pytest.approx(16 - inner, rel=1e-9)
    assert closed[-1] == pytest.approx(o + 0.3 * (h - o))


def test_the_gallery_lock_opens_its_shackle_and_keeps_its_body():
    from isotween import examples
    from isotween.metrics import flipped_faces, outline_crossings

    seq = examples.interpolate_example("lock")
    assert "1 source hole(s) opened into notches" in seq.info["correspondence"]
    assert flipped_faces(seq) == 0 and not outline_crossings(seq).any()
    body = np.flatnonzero(seq.frames[0, :, 1] > 13.5)  # the body's lower part, the same in both drawings
    moved = np.linalg.norm(seq.frames[:, body] - seq.frames[0, body], axis=-1).max()
    assert moved < 0.01 * seq.shape.bbox_diagonal()
    lifted = seq.frames[:, :, 1].min(axis=1)  # the shackle's top rises steadily by 2.5 (y down)
    assert np.all(np.diff(lifted) < 0) and lifted[0] - lifted[-1] == pytest.approx(2.5, abs=1e-6)


def test_a_stroked_o_keeps_its_hole(tmp_path):
    # a stroke would draw the closed slit at the O's end: the hole shrinks away instead
    style = 'stroke="black" stroke-width="0.5"'
    o, c = glyph_svg("O", tmp_path / "o.svg", style), glyph_svg("C", tmp_path / "c.svg", style)
    seq = isotween.morph(o, c, frames=5)
    assert "opened into notches" not in seq.info["correspondence"]
    assert len(seq.shape.paths) == 2


#: a padlock closed, and open with its shackle moved aside (its left leg on the body's right, its right leg free)
CLOSED_LOCK = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16"><path fill-rule="evenodd" '
               'd="M3 7H5V3A3 3 0 0 1 11 3V7H13V16H3Z M6 7H10V3A2 2 0 0 0 6 3Z"/></svg>')
OPEN_LOCK = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16">'
             '<path d="M1 7H8V3A3 3 0 0 1 14 3V6H13V3A2 2 0 0 0 9 3V7H11V16H1Z"/></svg>')


#: a padlock whose shackle's legs run into the body's rounded corners, closed and open (its shackle moved right)
LEGS_LOCK = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16"><path fill-rule="evenodd" '
             'd="M4 6.2V4A4 4 0 0 1 12 4V6.2A2.4 2.4 0 0 1 14 8.6V13.6A2.4 2.4 0 0 1 11.6 16H4.4A2.4 2.4 0 0 1 2 13.6'
             'V8.6A2.4 2.4 0 0 1 4 6.2Z M5 6H11V4A3 3 0 0 0 5 4Z"/></svg>')
LEGS_OPEN = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16"><path d="M2.4 6H8V4A4 4 0 0 1 16 4V6.4H15V4'
             'A3 3 0 0 0 9 4V6H9.6A2.4 2.4 0 0 1 12 8.4V13.6A2.4 2.4 0 0 1 9.6 16H2.4A2.4 2.4 0 0 1 0 13.6V8.4'
             'A2.4 2.4 0 0 1 2.4 6Z"/></svg>')


@pytest.mark.parametrize("closed_svg,open_svg", [(CLOSED_LOCK, OPEN_LOCK), (LEGS_LOCK, LEGS_OPEN)],
                         ids=["notch moved aside", "legs into the corners"])
def test_a_lock_opens_its_shackle_as_one_piece(tmp_path, closed_svg, open_svg):
    # the first: the shackle's hole lies beside the open lock's hook, not in it, and opens into the hook's notch
    # all the same; the second: a slit across the free leg a little above the body (as similar a ring) would
    # leave a stub on the body that must melt into it and fold the morph, so the leg is cut where it meets the body
    from isotween.metrics import area_deviation, edge_length_deviation, flipped_faces, outline_crossings

    closed, open_ = tmp_path / "closed.svg", tmp_path / "open.svg"
    closed.write_text(closed_svg)
    open_.write_text(open_svg)
    seq = isotween.morph(closed, open_, frames=11)
    assert "1 source hole(s) opened into notches" in seq.info["correspondence"]
    assert seq.method == "aiap" and "fallback" not in seq.info  # the paper's method, nothing folds
    assert flipped_faces(seq) == 0 and not outline_crossings(seq, visible=True).any()
    # lengths and area kept: a hole that shrank away would fill the shackle (area up by the hole's)
    assert edge_length_deviation(seq) < 0.1 and area_deviation(seq) < 2.0


def test_a_ring_into_a_crescent_ring_pairs_the_holes(tmp_path):
    # the ring's hole lies in the crescent's bay, but the crescent has a hole of its own to pair it with: no
    # slit opens (a slit opened in both would part the outline in the in-betweens)
    shapely = pytest.importorskip("shapely")

    def svg(poly, name):
        rings = [poly.exterior, *poly.interiors]
        d = " ".join("M " + " L ".join(f"{x:.4f} {y:.4f}" for x, y in r.coords[:-1]) + " Z" for r in rings)
        text = f'<svg xmlns="http://www.w3.org/2000/svg"><path fill-rule="evenodd" d="{d}"/></svg>'
        (tmp_path / name).write_text(text)
        return str(tmp_path / name)

    disc = shapely.Point(0, 0).buffer(4, 32)
    ring = disc.difference(shapely.Point(0, 0).buffer(3.4, 32))
    crescent = disc.difference(shapely.Point(1.5, -1).buffer(3.6, 32))
    outline = crescent.difference(crescent.buffer(-0.5, 32))
    seq = isotween.morph(svg(ring, "ring.svg"), svg(outline, "crescent.svg"), frames=9)
    assert "holes 1 paired" in seq.info["correspondence"] and "notch" not in seq.info["correspondence"]
    assert len(seq.shape.paths) == 2
