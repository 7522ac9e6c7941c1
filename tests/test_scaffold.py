"""The scaffold around a drawing's pieces: pieces that would pass through each other are held apart.

A bar turns a quarter round about its centre next to two small squares
that its ends sweep through (a known collision); AIAP turns every piece
rigidly, so its middle frames cross. The fold fallback repairs exactly those
frames inside a scaffold: no outline edge of the drawing crosses another,
no triangle flips, and every other frame is AIAP's, bit for bit.
"""

import numpy as np
import pytest

import isotween
from isotween.foldfree.scaffold import box_around, scaffold, separate_regions
from isotween.geometry import edge_table, triangle_areas
from isotween.metrics import flipped_faces, outline_crossings

pytest.importorskip("shapely")


def rect(x0, y0, x1, y1):
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)


def svg(rings, path):
    d = " ".join("M " + " L ".join(f"{x:.6f} {y:.6f}" for x, y in r) + " Z" for r in rings)
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="-7 -3 10 6"><path d="{d}"/></svg>')
    return str(path)


@pytest.fixture
def turning_bar(tmp_path):
    bar = rect(-2, -0.25, 2, 0.25)
    turned = bar @ np.array([[0.0, 1.0], [-1.0, 0.0]])
    box = rect(1.3, 1.3, 1.9, 1.9)
    # a square on both diagonals, whichever way the bar turns, and a heavy piece that stays
    others = [box, box * [1, -1], np.array([[-6, -2], [-4, -2], [-4.5, 1]], float)]
    return svg([bar, *others], tmp_path / "a.svg"), svg([turned, *others], tmp_path / "b.svg")


def test_pieces_that_would_collide_are_held_apart(turning_bar):
    a, b = turning_bar
    aiap = isotween.interpolate(a, b, frames=9, fold="allow")
    crossed = outline_crossings(aiap)
    assert crossed[1:-1].any() and not flipped_faces(aiap)  # the premise: pieces pass through each other
    seq = isotween.interpolate(a, b, frames=9)
    assert seq.method == "aiap" and "repaired" in seq.info["fallback"]
    assert not outline_crossings(seq).any() and flipped_faces(seq) == 0
    for k in np.flatnonzero(crossed == 0):  # frames with no collision: AIAP's own
        assert np.array_equal(seq.frames[k], aiap.frames[k])


def built(files):
    """The drawing's shape, its positions, the box and the scaffold around its pieces."""
    shape = isotween.interpolate(*files, frames=3, fold="allow").shape
    z = shape.vertices[:, 0] + 1j * shape.vertices[:, 1]
    box = box_around(z[None])
    return shape, z, box, scaffold(shape, z, box)


def test_the_scaffold_tiles_the_box_around_the_pieces(turning_bar):
    shape, z, box, sc = built(turning_bar)
    joint = np.r_[z, sc.source]
    areas = triangle_areas(joint, sc.faces)
    pieces = np.abs(shape.face_areas()).sum()
    width, height = np.ptp(box.real), np.ptp(box.imag)
    assert np.all(areas > 0)
    np.testing.assert_allclose(areas.sum() + pieces, width * height, rtol=1e-9)
    assert np.all(sc.source[sc.fixed] == box)
    # the scaffold follows the pieces: exact where it was built
    np.testing.assert_array_equal(sc.follow(np.stack([z, z + 0.1]))[0], sc.source)


def test_a_scaffold_carried_along_stays_a_tiling_and_becomes_delaunay_again(turning_bar):
    shape, z, box, sc = built(turning_bar)
    # the bar slides along its length, the scaffold following: still positive, no longer Delaunay
    slid = np.where((np.abs(z.imag) < 0.3) & (np.abs(z.real) < 2.1), z + 0.8, z)
    moved = sc.follow(np.stack([z, slid]))[1]
    joint = np.r_[slid, moved]
    assert np.all(triangle_areas(joint, sc.faces) > 0)
    again = sc.moved(joint)
    assert not np.array_equal(again.faces, sc.faces)  # the premise: edges flipped
    np.testing.assert_array_equal(again.source, moved)
    areas = triangle_areas(joint, again.faces)
    assert np.all(areas > 0)
    pieces = np.abs(triangle_areas(slid, shape.faces)).sum()
    np.testing.assert_allclose(areas.sum() + pieces, np.ptp(box.real) * np.ptp(box.imag), rtol=1e-9)
    # no edge between two of its triangles has the fourth vertex inside the first's circumcircle
    u, v, w, _, twin = edge_table(again.faces)
    inner = twin >= 0
    p = joint[np.stack([u[inner], v[inner], w[inner]], axis=1)] - joint[w[twin[inner]]][:, None]
    lift = np.stack([p.real, p.imag, np.abs(p) ** 2], axis=2)
    assert np.all(np.linalg.det(lift) <= 1e-9 * np.abs(p).max(axis=1) ** 4)


def test_a_piece_that_starts_on_another_is_left_out():
    small = rect(0.4, 0.4, 0.6, 0.6)
    big = rect(0, 0, 2, 2)
    moved = small + [3.0, 0.0]
    shape = isotween.Shape.from_paths([big, small], regions=[[0], [1]])
    z0 = shape.vertices[:, 0] + 1j * shape.vertices[:, 1]
    z1 = np.r_[z0[:4], moved[:, 0] + 1j * moved[:, 1]]
    assert separate_regions(shape, np.stack([z0, z1])) == [0]  # the small square splits off the big one
    assert separate_regions(shape, np.stack([z1, z1])) == [0, 1]


def test_a_scaffold_geos_cannot_triangulate_is_a_shape_error_and_the_morph_goes_on(turning_bar, monkeypatch):
    import shapely

    a, b = turning_bar
    shape = isotween.interpolate(a, b, frames=3, fold="allow").shape
    z = shape.vertices[:, 0] + 1j * shape.vertices[:, 1]
    real = shapely.constrained_delaunay_triangles

    def refuse(polygon, **kw):  # as GEOS does on rings that nearly touch
        raise shapely.errors.GEOSException("IllegalStateException: Unable to find a convex corner")

    monkeypatch.setattr(shapely, "constrained_delaunay_triangles", refuse)
    with pytest.raises(isotween.errors.ShapeError, match="too close to degenerate to triangulate"):
        scaffold(shape, z, box_around(z[None]))
    # in the fold repair (meshes made before): no scaffold, so the collisions are kept, said, and nothing raises
    monkeypatch.setattr(shapely, "constrained_delaunay_triangles", real)
    aiap = isotween.interpolate(a, b, frames=9, fold="allow")
    monkeypatch.setattr(shapely, "constrained_delaunay_triangles", refuse)
    seq = isotween.interpolate(aiap.shape, aiap.shape.with_vertices(aiap.frames[-1]), frames=9, fold="fallback")
    assert "no scaffold could hold them apart" in seq.info["collisions"]
    np.testing.assert_array_equal(seq.frames, aiap.frames)


def test_of_two_crossed_bars_one_is_left_out():
    # an X taken as its two bars: they overlap where they cross, though neither starts inside the other; touching
    # along an edge (the parts of a cut region) is no overlap
    across, upright, beside = rect(0, 1, 3, 2), rect(1, 0, 2, 3), rect(3, 1, 4, 2)
    shape = isotween.Shape.from_paths([across, upright, beside], regions=[[0], [1], [2]])
    z = shape.vertices[:, 0] + 1j * shape.vertices[:, 1]
    assert separate_regions(shape, np.stack([z, z])) == [0, 2]  # alike, the later bar is left out
    wider = np.r_[z[:4], z[4:8] + np.array([0, 0.5, 0.5, 0]), z[8:]]  # the upright bar made wider
    assert separate_regions(shape, np.stack([wider, wider])) == [1, 2]
