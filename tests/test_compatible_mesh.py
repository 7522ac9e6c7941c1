"""Compatible meshes of two corresponding polygons: no flipped triangle in either, by construction."""

import numpy as np
import pytest

from isotween import resample
from isotween.correspondence.compatible_mesh import compatible_meshes
from isotween.errors import IncompatibleShapesError, ParameterError, ResourceError, ShapeError

pytest.importorskip("shapely", minversion="2.1")


# ---------------------------------------------------------------- shapes
def glyph(char, size=10.0, per_curve=6):
    """Closed rings of a DejaVu Sans Bold glyph (as scripts/build_examples.py): outer ring, then holes."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.path import Path
    from matplotlib.textpath import TextPath

    path = TextPath((0, 0), char, size=size, prop=FontProperties(family="DejaVu Sans", weight="bold"))
    rings, ring = [], []
    steps = np.linspace(0, 1, per_curve + 1)[1:]
    for curve, code in path.iter_bezier():
        if code == Path.MOVETO:
            if ring:
                rings.append(np.vstack(ring))
            ring = [curve.control_points[-1:]]
        elif code != Path.CLOSEPOLY:
            ring.append(curve(steps) if len(curve.control_points) > 2 else curve.control_points[-1:])
    rings.append(np.vstack(ring))
    out = []
    for r in rings:
        r = r[np.r_[True, np.any(np.abs(np.diff(r, axis=0)) > 1e-9, axis=1)]]
        out.append(r[:-1] if np.allclose(r[0], r[-1]) else r)
    out.sort(key=lambda r: -abs(signed_area(r)))
    return out


def signed_area(r):
    z = r[:, 0] + 1j * r[:, 1]
    return 0.5 * np.sum((np.conj(z) * np.roll(z, -1)).imag)


def polygon_area(rings):
    return abs(signed_area(rings[0])) - sum(abs(signed_area(r)) for r in rings[1:])


def rect(x0, y0, x1, y1, n):
    """Counter-clockwise rectangle ring, n points per side."""
    corners = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]], dtype=float)
    pts = [np.linspace(corners[i], corners[i + 1], n, endpoint=False) for i in range(4)]
    return np.vstack(pts)


def grid_icon():
    """A square with a 2 x 2 grid of square windows (4 holes)."""
    holes = [rect(x, y, x + 3, y + 3, 4)[::-1] for y in (1, 5) for x in (1, 5)]
    return [rect(0, 0, 9, 9, 12)] + holes


def clipboard():
    """A board with a clip on top (non-convex outline) and 4 slots (holes)."""
    outer = np.array([[0, 0], [8, 0], [8, 10], [5.5, 10], [5.5, 11.2], [2.5, 11.2], [2.5, 10], [0, 10]], float)
    holes = [rect(1.5, y, 6.5, y + 1.0, 4)[::-1] for y in (1.2, 3.4, 5.6, 7.8)]
    return [outer] + holes


def rings_of(shape):
    return [shape.vertices[p] for p, _ in shape.paths]


def pair(src, tgt, points):
    s, t = resample(src, tgt, points=points)
    return rings_of(s), rings_of(t)


def bend(rings, angle):
    """Bend along x (a circular arc of total turning ``angle``) and rotate by 0.4 rad."""
    out = []
    allx = np.concatenate([r[:, 0] for r in rings])
    length = np.ptp(allx)
    radius = length / angle
    for r in rings:
        phi = (r[:, 0] - allx.min()) / radius
        z = (radius + r[:, 1]) * np.exp(1j * phi) * np.exp(0.4j)
        out.append(np.c_[z.real, z.imag])
    return out


def check(result, src, tgt):
    """The properties every result must have."""
    s, t = result.source, result.target
    np.testing.assert_array_equal(s.faces, t.faces)
    K = sum(len(r) for r in src)
    np.testing.assert_array_equal(s.vertices[:K], np.vstack(src))  # the outlines exactly, in order
    np.testing.assert_array_equal(t.vertices[:K], np.vstack(tgt))
    a_s, a_t = s.face_areas(), t.face_areas()
    assert np.sum(a_s <= 0) == 0 and np.sum(a_t <= 0) == 0  # no flipped or degenerate triangle
    np.testing.assert_allclose(a_s.sum(), polygon_area(src), rtol=1e-9)
    np.testing.assert_allclose(a_t.sum(), polygon_area(tgt), rtol=1e-9)
    assert len(np.unique(s.faces, axis=0)) == s.n_faces
    # every vertex is used and the boundary edges are exactly the ring edges
    assert np.array_equal(np.unique(s.faces), np.arange(s.n_vertices))
    e = np.sort(s.faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    keys, counts = np.unique(e[:, 0] * s.n_vertices + e[:, 1], return_counts=True)
    assert counts.max() == 2
    ring_edges = np.vstack([np.c_[p, np.roll(p, -1)] for p, _ in s.paths])
    ring_keys = np.sort(np.sort(ring_edges, axis=1) @ np.array([s.n_vertices, 1]))
    np.testing.assert_array_equal(np.sort(keys[counts == 1]), ring_keys)
    return a_s, a_t


# ---------------------------------------------------------------- the hard cases
@pytest.mark.parametrize("case", ["C-G", "P-bent-P", "B-8", "grid-clipboard", "m-v"])
def test_hard_cases_have_no_flipped_triangle(case):
    pytest.importorskip("matplotlib")
    if case == "C-G":
        src, tgt = pair(glyph("C"), glyph("G"), 120)
    elif case == "P-bent-P":
        p = glyph("P")
        src, tgt = pair(p, bend(p, 2.0), 130)
    elif case == "B-8":
        src, tgt = pair(glyph("B"), glyph("8"), 180)
    elif case == "m-v":  # straight strokes resampled: nearly collinear ring vertices
        src, tgt = pair(glyph("m"), glyph("v"), 102)
    else:
        src, tgt = pair(grid_icon(), clipboard(), 150)
    result = compatible_meshes(src, tgt)
    check(result, src, tgt)
    info = result.info
    assert info["faces"] == result.source.n_faces and info["vertices"] == result.source.n_vertices
    assert info["steiner"] == info["vertices"] - sum(len(r) for r in src)
    assert len(info["cuts"]) == len(src) - 1
    assert info["min_angle_source"] > 0 and info["min_angle_target"] > 0


@pytest.mark.slow
def test_random_star_polygons_never_flip():
    rng = np.random.default_rng(7)
    overlays = [0, 0]
    for i in range(24):
        k = int(rng.integers(6, 24))

        def star(lo, hi, k=k):
            th = (np.arange(k) + 0.8 * rng.random(k)) / k * 2 * np.pi
            r = lo + (hi - lo) * rng.random(k)
            return np.c_[r * np.cos(th), r * np.sin(th)] + rng.normal(size=2)

        src, tgt = star(1.0, 2.0), star(0.2, 2.5)
        if rng.random() < 0.5:  # clockwise input: the output keeps the input order
            src, tgt = src[::-1], tgt[::-1]
        result = compatible_meshes([src], [tgt], mesh_size=rng.uniform(0.45, 0.8), refine_first=i % 2 == 1,
                                   pull=False)
        check(result, [src], [tgt])
        overlays[i % 2] += result.info["overlay"]
    assert min(overlays) >= 6  # both overlay variants were exercised, not only the direct map


def test_holes_one_and_two():
    def ellipse(k, a, b, c=0j, cw=False):
        th = np.linspace(0, 2 * np.pi, k, endpoint=False) * (-1 if cw else 1)
        z = c + a * np.cos(th) + 1j * b * np.sin(th)
        return np.c_[z.real, z.imag]

    th = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    flower = (2.5 + np.cos(5 * th)) * np.exp(1j * th)
    flower = np.c_[flower.real, flower.imag]
    one = ([ellipse(60, 3, 2), ellipse(20, 0.8, 0.6, 0.7 + 0.3j, True)],
           [flower, ellipse(20, 0.5, 0.9, -0.3j, True)])
    two = ([ellipse(60, 3, 2), ellipse(20, 0.6, 0.5, 1.4, True), ellipse(16, 0.5, 0.5, -1.2, True)],
           [flower, ellipse(20, 0.4, 0.5, 0.4j, True), ellipse(16, 0.3, 0.3, -0.5 - 0.5j, True)])
    for src, tgt in (one, two):
        result = compatible_meshes(src, tgt, mesh_size=0.3)
        check(result, src, tgt)
        assert len(result.info["cuts"]) == len(src) - 1


def test_affine_target_gives_the_affine_image():
    p = [r * 0.1 for r in glyph("P")] if _has_matplotlib() else None
    if p is None:
        pytest.skip("matplotlib missing")
    A = np.array([[1.3, 0.4], [-0.2, 0.8]])
    tgt = [r @ A.T + [3.0, -1.0] for r in p]
    result = compatible_meshes(p, tgt)
    check(result, p, tgt)
    expected = result.source.vertices @ A.T + [3.0, -1.0]
    np.testing.assert_allclose(result.target.vertices, expected, rtol=0, atol=1e-9)
    assert result.info["steiner"] > 0  # interior vertices too


def _has_matplotlib():
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


def test_similar_shapes_share_the_source_mesh():
    """A rotated, scaled copy: the target mesh is the source mesh moved (no overlay needed)."""
    th = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    z = (2 + 0.6 * np.cos(3 * th)) * np.exp(1j * th)
    src = np.c_[z.real, z.imag]
    w = 0.5 * np.exp(1.1j) * z + 4
    result = compatible_meshes([src], [np.c_[w.real, w.imag]])
    assert not result.info["overlay"]
    moved = 0.5 * np.exp(1.1j) * result.source.z + 4
    np.testing.assert_allclose(result.target.z, moved, atol=1e-9)


# ---------------------------------------------------------------- bad input
def test_bad_input_is_named():
    square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    bowtie = np.array([[0, 0], [4, 4], [4, 0], [0, 4]], float)
    with pytest.raises(ShapeError, match=r"source outline touches or crosses itself at \(2, 2\): edge 0-1 of ring 0"):
        compatible_meshes([bowtie], [square])
    hole_out = [square, np.array([[5, 1], [5, 2], [6, 2], [6, 1]], float)]
    hole_in = [square, np.array([[1, 1], [1, 2], [2, 2], [2, 1]], float)]
    with pytest.raises(ShapeError, match="ring 1 of the target .a hole. lies outside ring 0"):
        compatible_meshes(hole_in, hole_out)
    with pytest.raises(IncompatibleShapesError, match="the source has 2 ring.s. but the target has 1"):
        compatible_meshes(hole_in, [square])
    with pytest.raises(IncompatibleShapesError, match="ring 0 has 4 vertices in the source but 5"):
        compatible_meshes([square], [np.r_[square, [[-1, 2]]]])
    with pytest.raises(IncompatibleShapesError, match="ring 0 runs counter-clockwise in the source but clockwise"):
        compatible_meshes([square], [square[::-1]])
    with pytest.raises(ShapeError, match="vertices 1 and 2 of ring 0 of the target coincide"):
        compatible_meshes([square], [np.array([[0, 0], [4, 0], [4, 0], [0, 4]], float)])
    with pytest.raises(ShapeError, match="ring 0 of the source has 2 vertices"):
        compatible_meshes([square[:2]], [square[:2]])


def test_too_fine_a_mesh_is_refused_before_meshing():
    square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    with pytest.raises(ResourceError, match=r"mesh_size=0.001 would make about 3.7e\+07 triangles.*at least 0.0043"):
        compatible_meshes([square], [square], mesh_size=1e-3)  # 16 / (sqrt(3)/4 * 1e-6) = 3.7e7
    with pytest.raises(ParameterError, match="mesh_size must be a positive number"):
        compatible_meshes([square], [square], mesh_size=-1.0)


def test_a_hole_cut_to_another_hole():
    """A centre hole walled in by two arc-shaped holes whose gaps turn by 90 degrees.

    No straight cut reaches the outer ring in both shapes, so the centre hole is cut to an arc hole.
    """
    def circle(k, r, cw=False):
        th = np.linspace(0, 2 * np.pi, k, endpoint=False) * (-1 if cw else 1)
        return np.c_[r * np.cos(th), r * np.sin(th)]

    def arc(a0, a1, turn):
        th = np.radians(np.linspace(a0, a1, 12) + turn)
        z = np.r_[2.5 * np.exp(1j * th), 1.5 * np.exp(1j * th[::-1])][::-1]  # clockwise
        return np.c_[z.real, z.imag]

    src = [circle(64, 4.0), arc(10, 170, 0), arc(190, 350, 0), circle(16, 0.6, cw=True)]
    tgt = [circle(64, 4.0), arc(10, 170, 90), arc(190, 350, 90), circle(16, 0.6, cw=True)]
    result = compatible_meshes(src, tgt, mesh_size=0.4, pull=False)
    check(result, src, tgt)
    joined_to = {h: u for h, u, _, _, _ in result.info["cuts"]}
    assert joined_to[3] >= 64  # the centre hole hangs from a hole, not from the outer ring
    assert len(result.info["cuts"]) == 3 and result.info["overlay"]  # the cut disc was overlaid


def test_smoothing_keeps_both_meshes_valid_and_the_boundary_fixed():
    # the colour-class smoothing on its own, from random valid meshes of random stars: no face of
    # either mesh may lose its positive area, no ring vertex may move, the connectivity is kept,
    # and every colour class is an independent set
    from isotween.correspondence import _quality as cm
    from isotween.geometry import triangle_areas

    rng = np.random.default_rng(11)
    moved = 0
    for i in range(8):
        k = int(rng.integers(8, 20))
        th = (np.arange(k) + 0.8 * rng.random(k)) / k * 2 * np.pi
        src = np.c_[np.cos(th), np.sin(th)] * rng.uniform(1.0, 2.0, (k, 1))
        tgt = np.c_[np.cos(th), np.sin(th)] * rng.uniform(0.3, 2.5, (k, 1)) + rng.normal(size=2)
        m = compatible_meshes([src], [tgt], mesh_size=0.5, refine_first=True)
        z, w, f = m.source.z, m.target.z, m.source.faces
        colour = cm._colour_classes(f, len(z), k, seed=i)
        same = colour[f[:, [0, 1, 2]]] == colour[f[:, [1, 2, 0]]]
        assert not np.any(same & (colour[f] >= 0)), "two neighbours in one colour class"
        assert np.all(colour[:k] == -1) and np.all(colour[k:] >= 0)
        for joint in (False, True):
            z2, w2, n = cm._smooth(z, w, f, k, (0.0, 0.0), joint)
            moved += n
            assert np.array_equal(z2[:k], z[:k]) and np.array_equal(w2[:k], w[:k])
            assert np.all(triangle_areas(z2, f) > 0) and np.all(triangle_areas(w2, f) > 0)
            # a vertex only moves when the smallest angle around it grows: the mesh minimum never drops
            before = np.minimum(cm._sine(z, f), cm._sine(w, f)).min() if joint else cm._sine(z, f).min()
            after = np.minimum(cm._sine(z2, f), cm._sine(w2, f)).min() if joint else cm._sine(z2, f).min()
            assert after >= before - 1e-12
    assert moved > 0  # the smoothing had work to do


def test_a_ring_chord_that_leaves_the_target_is_cut_instead_of_overlaying():
    # a 12-gon meshed with no interior vertex has chords between ring vertices; denting vertex 3 past the
    # chord (2, 4) turns the ear (2, 3, 4) over in the target: no map of that mesh can keep it. Cutting the
    # chord at its midpoint lets the source mesh be pulled onto the target, with no overlay.
    theta = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    src = np.c_[np.cos(theta), np.sin(theta)]
    tgt = src.copy()
    tgt[3] *= 0.3
    s, t, info = compatible_meshes(src, tgt, mesh_size=10.0)
    assert not info["overlay"]
    assert np.all(s.face_areas() > 0) and np.all(t.face_areas() > 0)
    assert np.array_equal(t.vertices[:12], tgt)  # the ring exactly where it was asked
    ring_pairs = np.sort(s.faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    side = np.diff(ring_pairs, axis=1)[:, 0]
    chord = (ring_pairs[:, 1] < 12) & (side != 1) & (side != 11)
    assert not np.any(chord & np.isin(ring_pairs, [3]).any(axis=1))  # the ear's chord is gone


def test_split_edges_keeps_orientation_and_area():
    from isotween.correspondence._disc import _split_edges
    from isotween.geometry import triangle_areas

    rng = np.random.default_rng(4)
    z = rng.random(60) + 1j * rng.random(60)
    from scipy.spatial import Delaunay

    f = Delaunay(np.c_[z.real, z.imag]).simplices
    f = np.where((triangle_areas(z, f) < 0)[:, None], f[:, ::-1], f)
    edges = np.unique(np.sort(f[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0)
    cut = edges[rng.random(len(edges)) < 0.5]
    f2 = _split_edges(f, cut, len(z))
    z2 = np.r_[z, z[cut].mean(axis=1)]
    a = triangle_areas(z2, f2)
    assert np.all(a > 0) and np.isclose(a.sum(), triangle_areas(z, f).sum())
    # every cut side is gone, its midpoint a vertex of the faces on its side(s)
    sides = np.sort(f2[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    assert not (np.isin(sides @ [1000, 1], cut @ [1000, 1])).any()
    assert np.all(np.bincount(f2.ravel(), minlength=len(z2))[len(z):] >= 2)


def test_the_overlay_is_coarsened_and_stays_valid():
    # grid icon -> clipboard needs the overlay: its intersection vertices mostly merge away, both meshes valid
    from isotween.correspondence import compatible_mesh as cm

    src, tgt = pair(grid_icon(), clipboard(), 150)
    coarse = compatible_meshes(src, tgt)
    assert coarse.info["overlay"]
    check(coarse, src, tgt)
    try:
        cm.COARSEN = False
        dense = compatible_meshes(src, tgt)
    finally:
        cm.COARSEN = True
    check(dense, src, tgt)
    assert coarse.info["vertices"] < 0.75 * dense.info["vertices"]  # the quality step's collapses alone leave more
    assert coarse.info["vertices"] < sum(len(r) for r in src) + coarse.info["crossings"] / 2


def test_fans_that_cross_too_often_are_flipped_to_cross_less_and_stay_a_triangulation():
    # two fans of a convex 60-gon from opposite corners: every pair of their diagonals that interleaves crosses
    from isotween.correspondence import _overlay
    from isotween.geometry import edge_table, triangle_areas

    n = 60
    w = np.exp(2j * np.pi * np.arange(n) / n)
    fan = lambda apex: np.array([[apex, (apex + k) % n, (apex + k + 1) % n] for k in range(1, n - 1)])  # noqa: E731
    source, target, pos = fan(0), fan(n // 2), np.arange(n)

    def chords(f):
        a, b, _, _, twin = edge_table(f)
        h = np.flatnonzero(twin > np.arange(len(a)))
        return np.sort(np.c_[a[h], b[h]], axis=1)

    def crossings(f):
        (p, q), (r, s) = chords(source).T[:, :, None], chords(f).T[:, None, :]
        return int(np.count_nonzero(((p < r) & (r < q) & (q < s)) | ((r < p) & (p < s) & (s < q))))

    before = crossings(target)
    assert before > n
    assert _overlay._fewer_crossings(target, source, pos, w, budget=before / n) is target  # within the budget
    flipped = _overlay._fewer_crossings(target, source, pos, w, budget=1)
    assert crossings(flipped) < before / 4
    areas = triangle_areas(w, flipped)
    assert np.all(areas > 0) and np.isclose(areas.sum(), triangle_areas(w, target).sum())
    assert {tuple(e) for e in chords(flipped)}.isdisjoint({(k, (k + 1) % n) for k in range(n - 1)})  # sides kept


# DejaVu Serif 'W' and 'V' (Bitstream Vera licence), as matplotlib writes their outlines
SERIF_W = ("M 76.219 -0.000 L 68.219 -0.000 L 51.516 -59.281 L 34.812 -0.000 L 26.812 -0.000 L 7.719 -67.672 "
           "L 0.484 -67.672 L 0.484 -72.906 L 27.094 -72.906 L 27.094 -67.672 L 18.016 -67.672 L 33.203 -13.812 "
           "L 49.812 -72.906 L 57.719 -72.906 L 74.609 -13.188 L 89.891 -67.672 L 81.500 -67.672 L 81.500 -72.906 "
           "L 102.484 -72.906 L 102.484 -67.672 L 95.312 -67.672 L 76.219 -0.000 Z")
SERIF_V = ("M 17.484 -67.672 L 39.016 -11.719 L 60.500 -67.672 L 52.297 -67.672 L 52.297 -72.906 L 73.688 -72.906 "
           "L 73.688 -67.672 L 66.609 -67.672 L 40.578 -0.000 L 32.172 -0.000 L 6.297 -67.672 L -0.984 -67.672 "
           "L -0.984 -72.906 L 25.594 -72.906 L 25.594 -67.672 L 17.484 -67.672 Z")


def test_a_pull_stuck_near_the_outline_flips_edges_on_the_way_instead_of_overlaying(tmp_path, monkeypatch):
    # a serif W pulled onto a V: with the source's connectivity the arms squeeze triangles flat before the
    # ring reaches the outline; flipping their edges between the pull's weights lets it through
    import isotween.correspondence.compatible_mesh as cm
    from isotween.pipeline import prepare_pair

    files = [tmp_path / "w.svg", tmp_path / "v.svg"]
    for file, d in zip(files, (SERIF_W, SERIF_V), strict=True):
        file.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="-10 -110 120 140"><path d="{d}"/></svg>')
    prepared = prepare_pair(*files)
    rings = [[shape.vertices[shape.paths[0][0]]] for shape in (prepared.source, prepared.target)]
    K = len(rings[0][0])
    monkeypatch.setattr(cm, "PULL_RETRY", -1.0)  # no second pull: the overlay
    assert compatible_meshes(*rings).info["overlay"]
    monkeypatch.undo()
    s, t, info = compatible_meshes(*rings)
    assert not info["overlay"]
    assert np.all(s.face_areas() > 0) and np.all(t.face_areas() > 0)
    assert np.array_equal(t.vertices[:K], rings[1][0])  # the ring exactly where it was asked


def test_the_mesh_follows_the_outline_near_it_and_coarsens_inside(monkeypatch):
    # a disc of 160 outline points and a turned, scaled copy: triangles near the outline keep its edge length,
    # inside they may grow with their distance from it (GRADE), and the map is still the similarity
    import shapely

    from isotween.correspondence import compatible_mesh as cm

    theta = np.linspace(0, 2 * np.pi, 160, endpoint=False)
    src = np.c_[np.cos(theta), np.sin(theta)]
    turn = 1.5 * np.exp(0.7j)
    z = turn * (src @ [1, 1j]) + (2 - 1j)
    s, t, _ = compatible_meshes(src, np.c_[z.real, z.imag])
    np.testing.assert_allclose(t.vertices @ [1, 1j], turn * (s.vertices @ [1, 1j]) + (2 - 1j), atol=1e-9)
    size = np.abs(np.diff(np.r_[src @ [1, 1j], src[0] @ [1, 1j]])).mean()
    outline = shapely.LinearRing(src)
    far = shapely.distance(shapely.points(s.vertices), outline)[s.faces].min(axis=1)  # (F,) of its vertices
    area = s.face_areas()
    assert np.all(area <= 1.5 * np.sqrt(3) / 4 * np.maximum(size, cm.GRADE * far) ** 2 * (1 + 1e-9))
    assert np.median(area[far > 0.5]) > 4 * np.median(area[far == 0])  # inside, much larger than at the outline
    monkeypatch.setattr(cm, "GRADE", 0.0)  # no grading: as fine inside as at the outline, many more triangles
    uniform, _, _ = compatible_meshes(src, np.c_[z.real, z.imag])
    assert uniform.n_faces > 2 * s.n_faces
    assert np.median(uniform.face_areas()[shapely.distance(shapely.points(uniform.vertices), outline)[
        uniform.faces].min(axis=1) > 0.5]) < 2 * np.median(area[far == 0])
