"""Shape as a value: read-only arrays, equality and hash, similarity transforms, SVG repr."""

import copy
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from isotween import Shape, interpolate, transfer
from isotween.errors import ParameterError, ShapeError
from isotween.paint import Paint
from shapes import ellipse, grid_mesh


def test_arrays_are_read_only_and_not_the_callers():
    v = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    mesh = Shape(v, faces=[[0, 1, 2], [1, 3, 2]], uv=v.copy())
    for arr in (mesh.vertices, mesh.edges, mesh.faces, mesh.uv, mesh.components):
        with pytest.raises(ValueError):
            arr[0] = arr[1]
    v[0] = 5.0  # the caller's array stays writeable and apart
    assert mesh.vertices[0].tolist() == [0.0, 0.0]
    moved = mesh.with_vertices(v)
    assert not moved.vertices.flags.writeable
    v[1] = 7.0
    assert moved.vertices[1].tolist() == [1.0, 0.0]
    ring = Shape.from_polygon(v[:3])
    with pytest.raises(ValueError):
        ring.paths[0][0][0] = 2


def test_equality_by_value_with_a_consistent_hash():
    a = Shape.from_polygon([[0, 0], [2, 0], [0, 1]])
    b = Shape.from_polygon(np.array([[0, 0], [2, 0], [0, 1]], dtype=np.float32))
    assert a == b and hash(a) == hash(b) and len({a, b}) == 1
    assert a == copy.deepcopy(a) and {a: 1}[copy.deepcopy(a)] == 1
    negzero = a.with_vertices(a.vertices * [1.0, -1.0])  # -0.0 where y was 0
    assert negzero != a
    flipped_back = negzero.with_vertices(negzero.vertices * [1.0, -1.0])
    assert flipped_back == a and hash(flipped_back) == hash(a)
    assert a.with_vertices(np.where(a.vertices == 0, -0.0, a.vertices)) == a
    assert hash(a.with_vertices(np.where(a.vertices == 0, -0.0, a.vertices))) == hash(a)
    assert a != a.translate([1e-12, 0])
    polyline = Shape.from_polyline(a.vertices)  # same points, one edge less
    assert a != polyline and not a.equals(polyline)
    y_down = Shape(a.vertices, a.edges, paths=a.paths, y_down=True)
    assert a != y_down
    painted = Shape(a.vertices, a.edges, paths=a.paths, regions=[[0]], paint=[Paint(fill=(1, 0, 0))])
    assert painted != Shape(a.vertices, a.edges, paths=a.paths, regions=[[0]], paint=[Paint(fill=(0, 0, 1))])
    assert (a == "a") is False and a != None  # noqa: E711
    assert (a == a.vertices) is False and (a.vertices == a) is False  # never elementwise
    assert np.asarray(a).shape == (3, 2) and np.array_equal(np.asarray(a), a.vertices)


def test_equals_with_tolerance(ellipse_shape):
    s = ellipse_shape
    near = s.translate([3e-9, -3e-9])
    assert not s.equals(near) and s.equals(near, atol=1e-8) and not s.equals(near, atol=1e-9)
    assert not s.equals(s.vertices) and not s.equals(None)


def test_similarity_transforms_against_complex_arithmetic():
    s = ellipse()
    z = s.z
    p = 0.3 - 0.7j
    theta = 1.1
    turned = s.rotate(theta, origin=[p.real, p.imag])
    assert np.allclose(turned.z, np.exp(1j * theta) * (z - p) + p, atol=1e-14)
    assert np.allclose(s.rotate(63.0, degrees=True).z, np.exp(1j * np.deg2rad(63.0)) * z, atol=1e-14)
    c = z.mean()
    assert np.allclose(s.rotate(theta, origin="centroid").z, np.exp(1j * theta) * (z - c) + c, atol=1e-14)
    assert np.allclose(s.scale(2.5, origin=p).z, 2.5 * (z - p) + p, atol=1e-14)
    assert np.allclose(s.scale([2.0, -1.0]).vertices, s.vertices * [2.0, -1.0])
    assert np.array_equal(s.translate(1 + 2j).vertices, s.vertices + [1.0, 2.0])
    m = np.array([[1.0, 0.4, 3.0], [-0.2, 0.9, -1.0], [0.0, 0.0, 1.0]])
    assert np.allclose(s.transform(m).vertices, s.vertices @ m[:2, :2].T + m[:2, 2])
    assert np.allclose(s.transform(m[:2, :2]).vertices, s.vertices @ m[:2, :2].T)
    assert s.rotate(theta).rotate(-theta).equals(s, atol=1e-14)
    assert s.z.tolist() == z.tolist()  # the original is untouched


def test_transforms_keep_connectivity_and_mirrors_reverse_faces():
    mesh = grid_mesh(4, 3)
    mirrored = mesh.transform([[-1.0, 0.0], [0.0, 1.0]])
    assert np.array_equal(mirrored.faces, mesh.faces) and np.array_equal(mirrored.edges, mesh.edges)
    assert np.allclose(mirrored.face_areas(), -mesh.face_areas())
    assert np.allclose(mesh.rotate(2.0).face_areas(), mesh.face_areas())


@pytest.mark.parametrize("bad", [
    lambda s: s.transform(np.eye(4)),
    lambda s: s.transform([[1, 0, 0], [0, 1, 0], [1, 0, 1]]),
    lambda s: s.transform([[np.nan, 0], [0, 1]]),
    lambda s: s.translate([1, 2, 3]),
    lambda s: s.rotate("90"),
    lambda s: s.scale([1, 2, 3]),
    lambda s: s.rotate(1.0, origin="middle"),
])
def test_bad_transform_arguments(bad):
    with pytest.raises(ParameterError):
        bad(ellipse())


def test_from_paths_is_the_ring_builder():
    outer = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], dtype=float)
    hole = outer[::-1] * 0.5 + 1
    tail = np.array([[5.0, 0.0], [6.0, 1.0], [7.0, 0.0]])
    s = Shape.from_paths([outer, hole, tail], closed=[True, True, False])
    assert s.edges.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4],
                                [8, 9], [9, 10]]
    assert [(p.tolist(), c) for p, c in s.paths] == [([0, 1, 2, 3], True), ([4, 5, 6, 7], True),
                                                     ([8, 9, 10], False)]
    assert Shape.from_paths([outer, hole]) == Shape.from_polygon([outer, hole])
    assert Shape.from_paths([tail], closed=False) == Shape.from_polyline(tail)
    as_complex = Shape.from_paths([outer[:, 0] + 1j * outer[:, 1]], y_down=True)
    assert as_complex.y_down and np.array_equal(as_complex.vertices, outer)
    with pytest.raises(ShapeError, match="ring 1"):
        Shape.from_paths([outer, tail[:2]], closed=True)
    with pytest.raises(ShapeError, match="closed has 1 values for 2 rings"):
        Shape.from_paths([outer, hole], closed=[True])


def test_svg_repr_is_valid_svg_with_the_shape():
    holes = Shape.from_polygon([[[0, 0], [4, 0], [4, 4], [0, 4]], [[1, 1], [1, 2], [2, 2], [2, 1]]])
    root = ET.fromstring(holes._repr_svg_())
    ns = "{http://www.w3.org/2000/svg}"
    assert root.tag == f"{ns}svg" and len(root.get("viewBox").split()) == 4
    fill, edges = root.findall(f"{ns}path")
    assert fill.get("fill-rule") == "evenodd" and fill.get("d").count("M") == 2
    assert edges.get("d").count("M") == holes.n_edges
    # y up: the drawing is mirrored so that y grows upwards on screen
    first = [float(x) for x in edges.get("d")[1:].split(" L")[0].split()]
    assert first == [0.0, -0.0] or first == [0.0, 0.0]
    x0, y0, w, h = (float(x) for x in root.get("viewBox").split())
    assert x0 < 0 and y0 < -4 < 0 < y0 + h
    mesh = ET.fromstring(grid_mesh(3, 3)._repr_svg_())
    assert mesh.findall(f"{ns}path")[0].get("d").count("M") == 8  # one per triangle


def test_interpolate_and_transfer_take_plain_polygon_arrays():
    s = ellipse(20)
    t = s.rotate(1.2).translate([2, 1])
    from_arrays = interpolate(s.vertices, t.vertices.tolist(), frames=5)
    from_shapes = interpolate(s, t, frames=5)
    assert np.array_equal(from_arrays.frames, from_shapes.frames)
    assert from_arrays.shape == s
    moved = transfer(s.vertices, t.vertices, s.scale(2.0).vertices, frames=5)
    assert np.allclose(moved.frames, 2.0 * from_shapes.frames, atol=1e-9)
    with pytest.raises(ShapeError, match="target must be an isotween.Shape or an \\(n, 2\\) polygon array"):
        interpolate(s, np.zeros((3, 3)))
    with pytest.raises(ShapeError, match="source"):
        interpolate("not a shape", t)
