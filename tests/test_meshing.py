"""Meshes from outlines.

Compatible meshes by default, the Triangle path with its harmonic target (flips reported), errors, CLI.
"""

import numpy as np
import pytest
from click.testing import CliRunner

from isotween import Shape, io, mesh_pair, resample
from isotween.cli import main
from isotween.errors import IncompatibleShapesError, ShapeError

pytest.importorskip("shapely", minversion="2.1")


def needs_triangle():
    pytest.importorskip("triangle")


def ellipse(k, a, b, centre=0j, reverse=False):
    th = np.linspace(0, 2 * np.pi, k, endpoint=False)
    z = centre + a * np.cos(th) + 1j * b * np.sin(th)
    z = z[::-1] if reverse else z
    return np.c_[z.real, z.imag]


def moved(shape, f):
    z = f(shape.z)
    return shape.with_vertices(np.c_[z.real, z.imag])


@pytest.fixture
def washer():
    """An elliptic outline with an off-centre hole."""
    return Shape.from_polygon([ellipse(90, 3.0, 2.0), ellipse(30, 0.8, 0.6, 0.7 + 0.3j, reverse=True)])


def polygon_area(shape):
    """Even-odd area of the closed rings (outer minus holes), by the shoelace formula."""
    total = [0.5 * np.imag(np.sum(np.conj(z) * np.roll(z, -1))) for z in (shape.z[p] for p, _ in shape.paths)]
    return abs(total[0]) - sum(abs(a) for a in total[1:])


def test_rigid_motion_gives_a_rigidly_moved_mesh(washer):
    rot = np.exp(2.1j)
    src, tgt, flipped = mesh_pair(washer, moved(washer, lambda z: rot * z + (5 - 1j)))
    assert flipped.size == 0
    np.testing.assert_allclose(tgt.face_areas(), src.face_areas(), rtol=0, atol=1e-9)
    np.testing.assert_allclose(tgt.z, rot * src.z + (5 - 1j), atol=1e-9)  # interior vertices too
    assert src.n_vertices > washer.n_vertices  # the interior was filled


def test_default_mesh_fills_the_polygon_and_leaves_the_hole(washer):
    small = washer.with_vertices(washer.vertices * 0.01)
    src, tgt, flipped = mesh_pair(small, small, max_area=5e-6)
    areas = src.face_areas()
    assert np.all(areas > 0) and flipped.size == 0
    np.testing.assert_allclose(areas.sum(), polygon_area(small), rtol=1e-12)
    np.testing.assert_allclose(tgt.vertices, src.vertices, atol=1e-12)  # the same outline: the same mesh
    assert src.n_faces > polygon_area(small) / 5e-6  # max_area sets the mesh size


def test_mesh_fills_the_polygon_and_leaves_the_hole(washer):
    needs_triangle()
    small = washer.with_vertices(washer.vertices * 0.01)  # areas written 5e-06 must still reach Triangle
    src, _, _ = mesh_pair(small, small, max_area=5e-6, min_angle=25, mesher="triangle")
    areas = src.face_areas()
    assert np.all(areas > 0)
    np.testing.assert_allclose(areas.sum(), polygon_area(small), rtol=1e-12)
    assert areas.max() <= 5e-6 * (1 + 1e-9) and src.n_faces > polygon_area(small) / 5e-6
    # interior triangles meet the angle bound (the outline's own vertices may not)
    inner = np.all(src.faces >= washer.n_vertices, axis=1)
    p = src.z[src.faces[inner]]
    sides = np.abs(p - np.roll(p, -1, axis=1))
    a, b, c = sides[:, 0], sides[:, 1], sides[:, 2]
    smallest = np.arccos(np.clip((b**2 + c**2 - a**2) / (2 * b * c), -1, 1))
    angles = np.degrees(np.minimum.reduce([smallest, np.arccos((a**2 + c**2 - b**2) / (2 * a * c)),
                                           np.arccos((a**2 + b**2 - c**2) / (2 * a * b))]))
    assert inner.any() and angles.min() >= 25 - 1e-6


def test_bent_outline_is_the_target_boundary_exactly():
    t = np.linspace(0, 6, 40)
    bar = np.vstack([np.c_[t, 0 * t - 0.5], np.c_[t[::-1], 0 * t + 0.5]])
    bent = np.exp(1j * (bar[:, 0] / 6) * np.pi) * (bar[:, 1] - 3) * 1j  # a half ring
    src_outline = Shape.from_polygon(bar)
    tgt_outline = src_outline.with_vertices(np.c_[bent.real, bent.imag])
    src, tgt, flipped = mesh_pair(src_outline, tgt_outline)
    n = src_outline.n_vertices
    np.testing.assert_array_equal(src.vertices[:n], src_outline.vertices)
    np.testing.assert_array_equal(tgt.vertices[:n], tgt_outline.vertices)
    assert tgt.faces is src.faces and src.paths is not None and len(src.paths[0][0]) == n
    assert flipped.size == 0 and np.all(tgt.face_areas() > 0)


def test_default_mesher_has_no_flips_where_the_harmonic_map_folds():
    # a disc into a five-petal flower: the cotangent map of the source mesh flips triangles
    th = np.linspace(0, 2 * np.pi, 80, endpoint=False)
    flower = (2.5 + 1.2 * np.cos(5 * th)) * np.exp(1j * th)
    disc = Shape.from_polygon(ellipse(80, 2.5, 2.5))
    target = disc.with_vertices(np.c_[flower.real, flower.imag])
    if pytest.importorskip("triangle"):
        with pytest.warns(UserWarning, match="flipped triangle"):
            assert mesh_pair(disc, target, mesher="triangle").flipped.size > 0
    src, tgt, flipped = mesh_pair(disc, target)
    assert flipped.size == 0 and np.all(src.face_areas() > 0) and np.all(tgt.face_areas() > 0)
    np.testing.assert_array_equal(tgt.vertices[:80], target.vertices)


def test_flipped_target_triangles_are_reported(washer):
    needs_triangle()
    # push part of the outer boundary through the hole: the map folds
    z = washer.z.copy()
    z[:8] = z[:8] - 4.5
    target = washer.with_vertices(np.c_[z.real, z.imag])
    with pytest.raises(ShapeError, match="target outline touches or crosses itself"):
        mesh_pair(washer, target)  # the default mesher refuses the crossing target outline
    with pytest.warns(UserWarning, match="flipped triangle"):
        src, tgt, flipped = mesh_pair(washer, target, mesher="triangle")
    expected = np.flatnonzero(np.sign(tgt.face_areas()) != np.sign(src.face_areas()))
    assert flipped.size > 0
    np.testing.assert_array_equal(flipped, expected)


# ---------------------------------------------------------------- errors
def test_self_touching_outline():
    eight = Shape.from_polygon([[0, 0], [1, 1], [2, 0], [2, 2], [1, 1], [0, 2]])
    with pytest.raises(ShapeError, match=r"touches itself at \(1, 1\): vertex 1 of ring 0 and vertex 4 of ring 0"):
        mesh_pair(eight, eight)
    t_junction = Shape.from_polygon([[0, 0], [4, 0], [4, 4], [2, 0], [0, 4]])
    with pytest.raises(ShapeError, match=r"touches or crosses itself at \(2, 0\): edge 0-1 of ring 0"):
        mesh_pair(t_junction, t_junction)
    if pytest.importorskip("triangle"):
        with pytest.raises(ShapeError, match=r"touches itself at \(2, 0\)"):
            mesh_pair(t_junction, t_junction, mesher="triangle")


def test_crossing_outline():
    bowtie = Shape.from_polygon([[0, 0], [2, 2], [2, 0], [0, 2]])
    with pytest.raises(ShapeError, match=r"touches or crosses itself at \(1, 1\): edge 0-1 of ring 0 meets edge 2-3"):
        mesh_pair(bowtie, bowtie)
    if pytest.importorskip("triangle"):
        with pytest.raises(ShapeError, match=r"crosses itself near \(1, 1\)"):
            mesh_pair(bowtie, bowtie, mesher="triangle")


def test_open_or_incompatible_outlines(washer):
    line = Shape.from_polyline(ellipse(10, 1, 1))
    with pytest.raises(ShapeError, match="ring 0 of the source is an open polyline"):
        mesh_pair(line, line)
    with pytest.raises(IncompatibleShapesError, match="vertices"):
        mesh_pair(washer, Shape.from_polygon(ellipse(20, 1, 1)))


# ---------------------------------------------------------------- command line
def _drawn(shape):
    """The y-down shape an SVG file shows for a y-up ``shape``: (x, -y)."""
    return Shape(shape.vertices * [1, -1] + 0.0, shape.edges, paths=shape.paths, y_down=True)


def svg_pair(tmp_path):
    """Two outlines with holes and different point counts, as plain (y-down) SVG files."""
    io.save(_drawn(Shape.from_polygon([ellipse(70, 3, 2), ellipse(20, 0.8, 0.8, reverse=True)])), tmp_path / "a.svg")
    io.save(_drawn(Shape.from_polygon([ellipse(45, 2, 3, 1j), ellipse(33, 0.5, 1, 1.2j, reverse=True)])),
            tmp_path / "b.svg")
    return tmp_path / "a.svg", tmp_path / "b.svg"


def test_cli_mesh_on_the_fly_matches_prepare(tmp_path):
    a, b = svg_pair(tmp_path)
    run = CliRunner().invoke
    result = run(main, ["prepare", str(a), str(b), "--resample", "80", "--mesh", "-o", str(tmp_path / "p")])
    assert result.exit_code == 0, result.output
    src, tgt = io.load(tmp_path / "p" / "source.obj"), io.load(tmp_path / "p" / "target.obj")
    outlines = resample(io.load(a), io.load(b), points=80)
    expected = mesh_pair(*outlines)
    np.testing.assert_array_equal(src.faces, expected.source.faces)
    assert expected.source.y_down and expected.target.y_down  # drawn like the SVG files
    # OBJ is y-up: the y-down meshes are written with y negated (drawn the same way) and read back y-down
    np.testing.assert_array_equal(tgt.vertices, expected.target.vertices)
    assert tgt.y_down
    result = run(main, ["interpolate", str(a), str(b), "--resample", "80", "--mesh", "-n", "5",
                        "-o", str(tmp_path / "s.npz"), "-q"])
    assert result.exit_code == 0, result.output
    seq = __import__("isotween").io.load_sequence(tmp_path / "s.npz")
    np.testing.assert_array_equal(seq.shape.faces, expected.source.faces)
    np.testing.assert_allclose(seq.frames[-1], expected.target.vertices, atol=1e-12)


def test_cli_refuses_a_crossing_target_outline(tmp_path, washer):
    z = washer.z.copy()
    z[:8] = z[:8] - 4.5  # as in test_flipped_target_triangles_are_reported
    io.save(washer, tmp_path / "a.svg")
    io.save(washer.with_vertices(np.c_[z.real, z.imag]), tmp_path / "b.svg")
    result = CliRunner().invoke(main, ["prepare", str(tmp_path / "a.svg"), str(tmp_path / "b.svg"),
                                       "--mesh", "-o", str(tmp_path / "p")])
    assert result.exit_code == 2 and "target outline touches or crosses itself" in result.stderr, result.output
    assert not (tmp_path / "p").exists()


def test_cli_errors_leave_no_output(tmp_path):
    a, b = svg_pair(tmp_path)
    run = CliRunner().invoke
    for args, needle in [
        (["prepare", a, b, "-o", tmp_path / "p"], "give --resample N and/or --mesh"),
        (["prepare", a, b, "--mesh", "-o", tmp_path / "p"], "not compatible"),
        (["prepare", a, b, "--resample", "80", "--mesh", "big", "-o", tmp_path / "p"], "'big'"),
        (["interpolate", a, b, "--resample", "2", "-o", tmp_path / "s.npz"], "points=2 is too few"),
    ]:
        result = run(main, [str(x) for x in args])
        assert result.exit_code == 2 and needle in result.stderr, result.output
        assert not (tmp_path / "p").exists() and not (tmp_path / "s.npz").exists()
