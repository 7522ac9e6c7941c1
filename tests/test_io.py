"""File formats: exact round trips, known geometry, and errors that name file and line."""

import json
import os

import numpy as np
import pytest

import isotween
from isotween import Sequence, Shape, io
from isotween.errors import FileFormatError, IncompatibleShapesError, ParameterError
from isotween.io._files import atomic_path
from isotween.render.defaults import DURATION, FPS

# awkward floats: shortest-repr decimals must survive every text format
AWKWARD = np.array([[1 / 3, -2.5e8], [0.1 + 0.2, 1e-17], [-7.25, 3.0e-5], [2.0, 1 / 7]])


def path_shape():
    """A ring with an awkward outer boundary, a hole, and an open polyline."""
    outer = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [1 / 3, 2.0 + 1e-9]])
    hole = np.array([[1.0, 1.0], [2.0, 1.1], [1.5, 1.7]])
    tail = np.array([[5.0, 0.0], [6.5, 0.25], [7.0, -1 / 7]])
    v = np.vstack([outer, hole, tail])
    paths = [(np.arange(0, 4), True), (np.arange(4, 7), True), (np.arange(7, 10), False)]
    edges = np.vstack(
        [np.column_stack([p, np.roll(p, -1)]) if c else np.column_stack([p[:-1], p[1:]]) for p, c in paths]
    )
    return Shape(v, edges, paths=paths)


def mesh_shape(edge_order="default"):
    """Two triangles and a fan quad, with per-vertex uv."""
    v = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.5]]) + AWKWARD[0]
    f = np.array([[0, 1, 2], [0, 2, 3], [1, 4, 2]])
    uv = (v - v.min(axis=0)) / np.ptp(v, axis=0)
    if edge_order == "default":
        return Shape.from_mesh(v, f, uv=uv)
    edges = Shape.from_mesh(v, f).edges[::-1, ::-1]  # reversed order and direction
    return Shape(v, edges, f, uv=uv)


def soup_shape():
    """Edges in an order that is no chain: each one a separate piece."""
    v = np.vstack([AWKWARD, AWKWARD + 10.0])
    e = np.array([[0, 5], [3, 1], [6, 2], [1, 7], [4, 0], [2, 3]])
    return Shape(v, e)


def same_paths(a, b):
    if a is None or b is None:
        return a is None and b is None
    return len(a) == len(b) and all(np.array_equal(p, q) and c == d for (p, c), (q, d) in zip(a, b, strict=True))


def assert_same_shape(a, b, paths=True):
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.edges, b.edges)
    assert (a.faces is None) == (b.faces is None)
    if a.faces is not None:
        np.testing.assert_array_equal(a.faces, b.faces)
    assert (a.uv is None) == (b.uv is None)
    if a.uv is not None:
        np.testing.assert_array_equal(a.uv, b.uv)
    if paths:
        assert same_paths(a.paths, b.paths)


# ---------------------------------------------------------------- round trips
@pytest.mark.parametrize("ext", [".obj", ".off", ".svg", ".json", ".npz"])
def test_outline_round_trip_is_exact(tmp_path, ext):
    shape = path_shape()
    io.save(shape, tmp_path / f"s{ext}")
    back = io.load(tmp_path / f"s{ext}")
    # SVG is y-down: a y-up shape is written upright, as (x, -y), marked so, and negated back on reading
    assert not back.y_down
    assert_same_shape(back, shape)


@pytest.mark.parametrize("ext", [".json", ".npz"])
def test_regions_and_paint_round_trip(tmp_path, ext):
    # a filled square with a hole, and an unfilled ring drawn with a stroke: saved without its regions the ring
    # would read back as a filled region, without its paint in black
    from isotween.paint import Paint

    square = [[0, 0], [4, 0], [4, 4], [0, 4]]
    hole = [[1, 1], [1, 3], [3, 3], [3, 1]]
    ring = [[6, 0], [8, 0], [8, 2]]
    paint = [Paint(fill=(0.8, 0.2, 0.1, 1.0)), Paint(fill=(0.8, 0.2, 0.1, 1.0)),
             Paint(fill=None, stroke=(0.1, 0.1, 0.1, 0.5), stroke_width=0.3, opacity=0.75)]
    for regions in ([[0, 1]], []):
        shape = Shape.from_paths([square, hole, ring], closed=True, regions=regions,
                                 paint=paint if regions else paint[2:] * 3)
        io.save(shape, tmp_path / f"s{ext}")
        back = io.load(tmp_path / f"s{ext}")
        assert_same_shape(back, shape)
        assert back.regions == shape.regions and back.paint == shape.paint


@pytest.mark.parametrize("ext", [".obj", ".off", ".json", ".npz"])
@pytest.mark.parametrize("make", [mesh_shape, lambda: mesh_shape("custom"), soup_shape],
                         ids=["mesh", "mesh-edge-order", "soup"])
def test_mesh_and_soup_round_trip_is_exact(tmp_path, ext, make):
    shape = make()
    io.save(shape, tmp_path / f"s{ext}")
    back = io.load(tmp_path / f"s{ext}")
    # text mesh formats do not keep paths for a soup (they are chains of the edges)
    assert_same_shape(back, shape, paths=ext in (".json", ".npz"))


def test_svg_writes_mesh_edges_as_a_drawing(tmp_path):
    shape = mesh_shape()
    io.save(shape, tmp_path / "m.svg")
    back = io.load(tmp_path / "m.svg")
    assert not back.y_down  # y-up mesh, written upright and read back as it was
    # every edge of the mesh is drawn: the segments read back are the same set
    def seg(s):
        return {tuple(sorted(map(tuple, s.vertices[e].round(12).tolist()))) for e in s.edges}

    assert seg(back) == seg(shape)


def test_y_down_travels_with_the_shape(tmp_path):
    svg = tmp_path / "a.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg"><polygon points="0,0 4,0 4,1"/></svg>')
    shape = io.load(svg)
    assert shape.y_down and not path_shape().y_down
    for ext in (".json", ".npz"):
        io.save(shape, tmp_path / f"s{ext}")
        assert io.load(tmp_path / f"s{ext}").y_down
        io.save(path_shape(), tmp_path / f"u{ext}")
        assert not io.load(tmp_path / f"u{ext}").y_down
        seq = Sequence(np.stack([shape.vertices, shape.vertices + 1]), shape)
        io.save_sequence(seq, tmp_path / f"q{ext}")
        assert io.load_sequence(tmp_path / f"q{ext}").shape.y_down
    assert shape.with_vertices(shape.vertices * 2).y_down


def test_svg_keeps_y_down_and_user_units(tmp_path):
    shape = Shape.from_polygon([[0.0, 0.0], [10.0, 0.0], [10.0, 5.0]])
    io.save(shape, tmp_path / "t.svg")
    text = (tmp_path / "t.svg").read_text()
    assert 'd="M 0.0 0.0 L 10.0 0.0 L 10.0 -5.0 Z"' in text  # y-up: drawn upright
    io.save(Shape(shape.vertices, shape.edges, paths=shape.paths, y_down=True), tmp_path / "d.svg")
    assert 'd="M 0.0 0.0 L 10.0 0.0 L 10.0 5.0 Z"' in (tmp_path / "d.svg").read_text()  # y-down: as it is


# ---------------------------------------------------------------- SVG reading
SVG = """<?xml version="1.0"?>
<svg xmlns="http://www.w3.org/2000/svg" width="50mm" height="20mm" viewBox="-100 -100 400 200">
  <g transform="translate(10,20)">
    <rect id="box" x="1" y="2" width="3" height="4" transform="scale(2)"/>
  </g>
  <circle cx="5" cy="-3" r="2"/>
  <polyline points="0,0 1,1 2,0" fill="none" stroke="black"/>
  <line x1="0" y1="5" x2="3" y2="9" stroke="black"/>
  <path d="M 0 10 C 1 11 2 11 3 10" style="fill:none;stroke:black"/>
</svg>
"""


def test_svg_known_geometry(tmp_path):
    (tmp_path / "k.svg").write_text(SVG)
    s = io.load(tmp_path / "k.svg", curve_segments=16)
    kinds = [(len(p), c) for p, c in s.paths]
    # rect: 4 corners closed; circle: 4 arcs x 16 closed; polyline 3 open; line 2 open; cubic 1 + 16 open
    assert kinds == [(4, True), (64, True), (3, False), (2, False), (17, False)]
    rect = s.vertices[s.paths[0][0]]
    # scale(2) then translate(10, 20); viewBox and mm size ignored, y kept pointing down
    np.testing.assert_allclose(rect, [[12, 24], [18, 24], [18, 32], [12, 32]], atol=1e-12)
    circle = s.vertices[s.paths[1][0]]
    np.testing.assert_allclose(np.hypot(*(circle - [5, -3]).T), 2.0, atol=1e-9)
    ang = np.unwrap(np.arctan2(*(circle - [5, -3]).T[::-1]))
    assert np.all(np.abs(np.diff(ang)) > 0.05)  # distinct, evenly spread (2 pi / 64 ~ 0.098)
    np.testing.assert_allclose(s.vertices[s.paths[3][0]], [[0, 5], [3, 9]])
    cubic = s.vertices[s.paths[4][0]]
    np.testing.assert_allclose(cubic[[0, -1]], [[0, 10], [3, 10]], atol=1e-12)
    np.testing.assert_allclose(cubic[8], [1.5, 10.75], atol=1e-12)  # B(1/2) = (p0 + 3 p1 + 3 p2 + p3) / 8
    assert s.n_edges == 4 + 64 + 2 + 1 + 16


def test_svg_curves_flattened_to_a_tolerance_of_the_diagonal(tmp_path):
    """By default every curve's polyline stays within CURVE_TOLERANCE of the diagonal, not far finer."""
    from isotween.io.svg import CURVE_TOLERANCE

    for r in (2.0, 200.0):
        (tmp_path / "c.svg").write_text(f'<svg xmlns="http://www.w3.org/2000/svg"><rect x="0" y="0" width="{4 * r}" '
                                        f'height="1" fill="black"/><circle cx="{2 * r}" cy="{2 * r}" r="{r}" '
                                        'fill="black"/></svg>')
        s = io.load(tmp_path / "c.svg")
        tol = CURVE_TOLERANCE * s.bbox_diagonal()
        z = s.z[s.paths[1][0]] - (2 * r + 2j * r)
        np.testing.assert_allclose(np.abs(z), r, atol=1e-9 * r)  # on the circle
        sagitta = r - np.abs(0.5 * (z + np.roll(z, -1)))  # chord midpoints: the farthest from the arc
        assert sagitta.max() <= tol and sagitta.max() > tol / 8  # within tolerance, not far finer
    assert len(z) == len(io.load(tmp_path / "c.svg", curve_segments=None).paths[1][0])  # scale-free count


def test_svg_curve_segments_option(tmp_path):
    (tmp_path / "k.svg").write_text(SVG)
    s = io.load(tmp_path / "k.svg", curve_segments=4)
    assert [len(p) for p, _ in s.paths] == [4, 16, 3, 2, 5]


def test_svg_explicit_closing_point_is_not_duplicated(tmp_path):
    (tmp_path / "z.svg").write_text(
        '<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 L2 0 L2 2 L0 0 Z M 5 5 l 1 0 l 0 1 z"/></svg>'
    )
    s = io.load(tmp_path / "z.svg")
    assert [(len(p), c) for p, c in s.paths] == [(3, True), (3, True)]
    np.testing.assert_allclose(s.vertices[3:], [[5, 5], [6, 5], [6, 6]])


@pytest.mark.parametrize(
    "body, expected",
    [
        ('<path id="wig" d="M 0 0 L 1 qq"/>', '<path id="wig">: malformed path data'),
        ('<rect x="0" y="0" width="3" height="4"/><polygon points="0,0 1,1 2"/>', "<polygon> number 1"),
        ('<polygon points="0,0 1,1"/>', "closed subpath 0 has 2 distinct point(s)"),
        ('<circle cx="a" cy="0" r="1"/>', 'cx="a" is not a length'),
        ("<text>hi</text>", "nothing to read"),
    ],
)
def test_svg_errors_name_the_element(tmp_path, body, expected):
    (tmp_path / "b.svg").write_text(f'<svg xmlns="http://www.w3.org/2000/svg">{body}</svg>')
    with pytest.raises(FileFormatError, match="b.svg") as err:
        io.load(tmp_path / "b.svg")
    assert expected in str(err.value)


def test_svg_xml_error_names_the_line(tmp_path):
    (tmp_path / "x.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg">\n<rect x="1"\n</svg>\n')
    with pytest.raises(FileFormatError, match=r"x\.svg, line 3: malformed XML"):
        io.load(tmp_path / "x.svg")


# ---------------------------------------------------------------- OBJ reading
def test_obj_polygons_lines_negative_indices_and_uv_pairs(tmp_path):
    (tmp_path / "q.obj").write_text(
        "# quad and a tail\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2\n"
        "vt 0.5 0.5\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
        "f 1/2/1 2/3/1 3/4/1 -2/5/1\nl 3/4 -1/1\n"
    )
    s = io.load(tmp_path / "q.obj")
    np.testing.assert_array_equal(s.faces, [[0, 1, 2], [0, 2, 3]])  # fan of the quad
    # l edges first, then the face sides not listed
    np.testing.assert_array_equal(s.edges[0], [2, 4])
    assert {tuple(sorted(e)) for e in s.edges.tolist()} == {(0, 1), (1, 2), (0, 2), (2, 3), (0, 3), (2, 4)}
    np.testing.assert_array_equal(s.uv, [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]])
    assert s.paths is None  # a mesh keeps no paths


def test_obj_lines_become_paths(tmp_path):
    (tmp_path / "l.obj").write_text("v 0 0\nv 1 0\nv 1 1\nv 5 5\nv 6 5\nl 1 2 3 1\nl 4 5\n")
    s = io.load(tmp_path / "l.obj")
    assert same_paths(s.paths, [(np.array([0, 1, 2]), True), (np.array([3, 4]), False)])
    np.testing.assert_array_equal(s.edges, [[0, 1], [1, 2], [2, 0], [3, 4]])


@pytest.mark.parametrize(
    "text, expected",
    [
        ("v 0 0 0\nv 1 0 0\nv 0 1 0.5\nf 1 2 3\n", "line 3: vertex 3 has z = 0.5"),
        ("v 0 0\nv 1 x\n", "line 2: 'x' is not a number"),
        ("v 0 0\nv 1 0\nv 0 1\nf 1 2 4\n", "line 4: face refers to vertex 4"),
        ("v 0 0\nv 1 0\nv 0 1\nf 1 2 0\n", "line 4: vertex index 0"),
        ("v 0 0\nv 1 0\nv 0 1\n\nf 1 2\n", "line 5: 'f' needs at least 3 vertices"),
        ("v 0 0\nv 1 0\nv 0 1\nf 1 2 2\n", "line 4: face repeats vertex 2"),
        ("v 0 0\nv 1 0\nvt 0 0\nvt 1 1\nl 1/1 2/2\nl 1/2 2/2\n", "line 6: vertex 1 has two different texture"),
        ("v 0 0\nv 1 0\nl 1 1 2\n", "line 3: line repeats vertex 1"),
        ("# nothing\n", "no vertices"),
    ],
)
def test_obj_errors_name_file_and_line(tmp_path, text, expected):
    (tmp_path / "bad.obj").write_text(text)
    with pytest.raises(FileFormatError, match="bad.obj") as err:
        io.load(tmp_path / "bad.obj")
    assert expected in str(err.value)


# ---------------------------------------------------------------- OFF reading
def test_off_polygons_edges_and_texture(tmp_path):
    (tmp_path / "q.off").write_text(
        "STOFF\n# comment\n5 3 0\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n3 3 0 0.5 0.5\n"
        "4 0 1 2 3 255 0 0\n2 2 4\n2 4 3\n"
    )
    s = io.load(tmp_path / "q.off")
    np.testing.assert_array_equal(s.faces, [[0, 1, 2], [0, 2, 3]])
    np.testing.assert_array_equal(s.edges[:2], [[2, 4], [4, 3]])
    assert s.n_edges == 7
    np.testing.assert_array_equal(s.uv[4], [0.5, 0.5])


def test_off_edge_runs_become_paths(tmp_path):
    (tmp_path / "r.off").write_text("OFF 4 4 4\n0 0 0\n1 0 0\n1 1 0\n9 9 0\n2 0 1\n2 1 2\n2 2 0\n2 2 3\n")
    s = io.load(tmp_path / "r.off")
    assert same_paths(s.paths, [(np.array([0, 1, 2]), True), (np.array([2, 3]), False)])


@pytest.mark.parametrize(
    "text, expected",
    [
        ("PLY\n", "line 1: expected the header 'OFF'"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1\n3 0 1 2\n", "line 5: expected 'x y z'"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 2\n3 0 1 2\n", "line 5: vertex 2 has z = 2.0"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "line 6: face refers to vertex 3"),
        ("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "announced"),
    ],
)
def test_off_errors_name_file_and_line(tmp_path, text, expected):
    (tmp_path / "bad.off").write_text(text)
    with pytest.raises(FileFormatError, match="bad.off") as err:
        io.load(tmp_path / "bad.off")
    assert expected in str(err.value)


# ---------------------------------------------------------------- JSON / NPZ
def test_json_paths_only_give_the_edges(tmp_path):
    doc = {"vertices": [[0, 0], [1, 0], [1, 1], [3, 3], [4, 3]],
           "paths": [{"indices": [0, 1, 2], "closed": True}, {"indices": [3, 4], "closed": False}]}
    (tmp_path / "p.json").write_text(json.dumps(doc))
    s = io.load(tmp_path / "p.json")
    np.testing.assert_array_equal(s.edges, [[0, 1], [1, 2], [2, 0], [3, 4]])


@pytest.mark.parametrize(
    "text, expected",
    [
        ('{"vertices": [\n [0, 0],\n [1, 0],\n [1]\n]}', "line 4: vertices[2]: expected a list of 2 numbers"),
        ('{"vertices": [[0, 0], [1, 0]],\n "edges": [[0, 1], [1, 5]]}', "line 2: edges[1]: vertex index out of range"),
        ('{"vertices": [[0, 0], [1, 0]]\n "edges": []}', "line 2: invalid JSON"),
        ('{"vertices": [[0, 0], [1, "a"]]}', "vertices[1]: expected numbers"),
        ('{"edges": []}', "missing the required key 'vertices'"),
        ('{"vertices": [[0, 0], [1, 0]],\n "paths": [\n {"indices": [0, 1], "closed": true}]}',
         "line 3: paths[0].indices: a closed path needs 3"),
        ("[1, 2]", "expected a JSON object"),
        ('{"vertices": [[0, 0], [1, 0], [0, 1]],\n "paths": [{"indices": [0, 1, 2], "closed": true}],\n'
         ' "paint": [{"fill": "pink"}]}', "paint"),
        ('{"vertices": [[0, 0], [1, 0], [0, 1]],\n "paths": [{"indices": [0, 1, 2], "closed": true}],\n'
         ' "regions": [[1]]}', "region 0 names path 1"),
        ('{"vertices": [[0, 0], [1, 0], [0, 1]],\n "regions": "all"}', "regions: expected a list of lists"),
    ],
)
def test_json_errors_name_file_and_line(tmp_path, text, expected):
    (tmp_path / "bad.json").write_text(text)
    with pytest.raises(FileFormatError, match="bad.json") as err:
        io.load(tmp_path / "bad.json")
    assert expected in str(err.value)


def test_npz_errors_name_the_array(tmp_path):
    np.savez(tmp_path / "a.npz", edges=np.zeros((0, 2), int))
    with pytest.raises(FileFormatError, match="a.npz: missing the array 'vertices'"):
        io.load(tmp_path / "a.npz")
    np.savez(tmp_path / "b.npz", vertices=np.zeros((3, 3)))
    with pytest.raises(FileFormatError, match=r"array 'vertices' must hold numbers of shape \(k, 2\)"):
        io.load(tmp_path / "b.npz")
    np.savez(tmp_path / "d.npz", vertices=np.eye(3, 2), path_indices=np.arange(3), path_sizes=[3],
             path_closed=[True], paint=np.array("[1]"))
    with pytest.raises(FileFormatError, match="d.npz: array 'paint' is not a list of paints"):
        io.load(tmp_path / "d.npz")
    (tmp_path / "c.npz").write_text("not a zip")
    with pytest.raises(FileFormatError, match="c.npz: not a valid .npz"):
        io.load(tmp_path / "c.npz")


# ---------------------------------------------------------------- paths and writing
def test_missing_file_and_unknown_extension_name_the_file(tmp_path):
    with pytest.raises(FileFormatError, match="nope.obj: no such file"):
        io.load(tmp_path / "nope.obj")
    (tmp_path / "a.xyz").write_text("1 2")
    with pytest.raises(FileFormatError, match=r"a\.xyz: cannot read '\.xyz'"):
        io.load(tmp_path / "a.xyz")
    with pytest.raises(FileFormatError, match=r"a\.ply: cannot write '\.ply'"):
        io.save(path_shape(), tmp_path / "a.ply")


def test_unwritable_output_raises_and_leaves_nothing(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(FileFormatError, match="is not a folder"):
        io.save(path_shape(), tmp_path / "file" / "s.obj")
    with pytest.raises(FileFormatError, match="does not exist"):
        io.save(path_shape(), tmp_path / "missing" / "s.obj")
    assert sorted(os.listdir(tmp_path)) == ["file"]


def test_failed_write_keeps_the_old_file_and_leaves_no_temp(tmp_path):
    target = tmp_path / "out.json"
    target.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            tmp.write_text("partial")
            raise RuntimeError("writer failed")
    assert target.read_text() == "old"
    assert os.listdir(tmp_path) == ["out.json"]


# ---------------------------------------------------------------- sequences
def blend_sequence(shape, frames=5):
    """Rotation of ``shape`` by up to 90 degrees about the origin (a known motion)."""
    t = np.linspace(0.0, 1.0, frames)
    z = shape.z[None, :] * np.exp(0.5j * np.pi * t)[:, None]
    return Sequence(
        np.stack([z.real, z.imag], axis=-1), shape, times=t, scheme="paper",
        energy=[0.5, 0.25, 1 / 3], iterations=3, converged=False,
        timings={"init": 0.01, "solve": 0.2}, method="aiap", info={"note": "hand-made", "w": np.arange(3)},
    )


@pytest.mark.parametrize("ext", [".npz", ".json"])
def test_sequence_file_round_trip_is_exact(tmp_path, ext):
    seq = blend_sequence(mesh_shape("custom"))
    io.save_sequence(seq, tmp_path / f"seq{ext}")
    back = io.load_sequence(tmp_path / f"seq{ext}")
    np.testing.assert_array_equal(back.frames, seq.frames)
    np.testing.assert_array_equal(back.times, seq.times)
    assert back.energy == seq.energy
    assert (back.iterations, back.converged, back.method, back.scheme) == (3, False, "aiap", "paper")
    assert back.timings == seq.timings
    assert back.info == {"note": "hand-made", "w": [0, 1, 2]}
    assert_same_shape(back.shape, seq.shape)
    assert io.is_sequence_file(tmp_path / f"seq{ext}")


def test_sequence_keeps_source_vertices_that_differ_from_frame_zero(tmp_path):
    seq = blend_sequence(path_shape())
    seq.frames[0] += 1.0
    io.save_sequence(seq, tmp_path / "s.json")
    back = io.load_sequence(tmp_path / "s.json")
    np.testing.assert_array_equal(back.shape.vertices, seq.shape.vertices)
    assert_same_shape(back.shape, seq.shape)


def test_loading_a_shape_file_as_sequence_and_back_is_refused(tmp_path):
    io.save(path_shape(), tmp_path / "s.json")
    with pytest.raises(FileFormatError, match="missing the key 'frames'"):
        io.load_sequence(tmp_path / "s.json")
    io.save_sequence(blend_sequence(path_shape()), tmp_path / "q.npz")
    with pytest.raises(FileFormatError, match="is a sequence file"):
        io.load(tmp_path / "q.npz")


@pytest.mark.parametrize("fmt", ["obj", "off", "svg", "json", "npz"])
def test_frame_folder_round_trip(tmp_path, fmt):
    seq = blend_sequence(path_shape(), frames=4)
    files = io.write_frames(seq, tmp_path / "frames", format=fmt)
    assert [f.name for f in files] == [f"frame_{k:04d}.{fmt}" for k in range(4)]
    back = io.load_sequence(tmp_path / "frames")
    assert not back.shape.y_down  # y-up frames, in SVG written upright and read back as they were
    np.testing.assert_array_equal(back.frames, seq.frames)
    assert_same_shape(back.shape, seq.shape)


def test_frame_folder_sorts_numbers_by_value_and_drops_stale_frames(tmp_path):
    seq = blend_sequence(path_shape(), frames=12)
    folder = tmp_path / "f"
    folder.mkdir()
    for k in range(12):  # unpadded names: frame_10 must come after frame_9
        io.save(seq[k], folder / f"frame_{k}.json")
    np.testing.assert_array_equal(io.load_sequence(folder).frames, seq.frames)
    out = tmp_path / "g"
    io.write_frames(seq, out, format="json")
    io.write_frames(blend_sequence(path_shape(), frames=3), out, format="json")
    assert sorted(os.listdir(out)) == ["frame_0000.json", "frame_0001.json", "frame_0002.json"]


def test_frame_folder_with_different_connectivity_names_the_file(tmp_path):
    folder = tmp_path / "f"
    folder.mkdir()
    io.save(path_shape(), folder / "a.json")
    io.save(Shape.from_polygon([[0, 0], [1, 0], [0, 1]]), folder / "b.json")
    with pytest.raises(IncompatibleShapesError, match="b.json"):
        io.load_sequence(folder)


def test_failing_frame_writes_leave_no_folder(tmp_path):
    seq = blend_sequence(path_shape(), frames=3)
    with pytest.raises(ParameterError):
        io.write_frames(seq, tmp_path / "new", format="ply")
    (tmp_path / "file").write_text("x")
    with pytest.raises(FileFormatError):
        io.write_frames(seq, tmp_path / "file", format="obj")
    assert sorted(os.listdir(tmp_path)) == ["file"]


# ---------------------------------------------------------------- write_output
def test_write_output_dispatches_on_the_name(tmp_path):
    seq = blend_sequence(path_shape(), frames=3)
    assert isotween.write_output(seq, tmp_path / "s.npz") == [tmp_path / "s.npz"]
    np.testing.assert_array_equal(io.load_sequence(tmp_path / "s.npz").frames, seq.frames)
    written = isotween.write_output(seq, tmp_path / "frames", format="svg")
    assert [p.name for p in written] == ["frame_0000.svg", "frame_0001.svg", "frame_0002.svg"]
    np.testing.assert_array_equal(io.load_sequence(tmp_path / "frames").frames, seq.frames)  # as written
    written = isotween.write_output(seq, tmp_path / "plain")  # no extension: a folder of OBJ frames
    assert written[0].name == "frame_0000.obj"


@pytest.mark.parametrize(
    "name, fmt, error, expected",
    [
        ("s.obj", None, FileFormatError, "holds one shape, not a sequence"),
        ("s.foo", None, FileFormatError, "unknown output kind '.foo'"),
        ("s.gif", "obj", ParameterError, "names a .gif file"),
        ("d", "ply", ParameterError, "unknown format"),
        ("missing/s.npz", None, FileFormatError, "does not exist"),
    ],
)
def test_write_output_refuses_before_writing(tmp_path, name, fmt, error, expected):
    seq = blend_sequence(path_shape(), frames=3)
    with pytest.raises(error, match=expected):
        isotween.write_output(seq, tmp_path / name, format=fmt)
    assert os.listdir(tmp_path) == []


def test_write_output_rendered_kinds(tmp_path):
    pytest.importorskip("isotween.render")
    from PIL import Image

    seq = blend_sequence(path_shape(), frames=4)
    isotween.write_output(seq, tmp_path / "a.gif")
    with Image.open(tmp_path / "a.gif") as im:  # 1 s of motion at 24 fps by default, resampled from 4 frames
        assert im.n_frames == round(DURATION * FPS) + 1
    isotween.write_output(seq, tmp_path / "b.gif", duration=0, hold=0)
    with Image.open(tmp_path / "b.gif") as im:  # duration 0: the frames themselves
        assert im.n_frames == 4
    isotween.write_output(seq, tmp_path / "a.png")
    with Image.open(tmp_path / "a.png") as im:
        assert im.format == "PNG"
    isotween.write_output(seq, tmp_path / "a.html")
    assert "<html" in (tmp_path / "a.html").read_text().lower()
    isotween.write_output(seq, tmp_path / "pngs", format="png")
    assert sorted(os.listdir(tmp_path / "pngs")) == [f"frame_{k:04d}.png" for k in range(4)]


def test_malformed_sequence_files_name_the_problem(tmp_path):
    np.savez(tmp_path / "a.npz", frames=np.zeros((3, 4)))
    with pytest.raises(FileFormatError, match=r"a\.npz: array 'frames' must have shape \(frames, n, 2\)"):
        io.load_sequence(tmp_path / "a.npz")
    np.savez(tmp_path / "b.npz", frames=np.zeros((2, 3, 2)), edges=np.array([[0, 1]]), energy=np.array(["x"]))
    with pytest.raises(FileFormatError, match="array 'energy' must be a 1-d array of numbers"):
        io.load_sequence(tmp_path / "b.npz")
    (tmp_path / "c.json").write_text('{"frames": [\n[[0, 0], [1, 0]],\n[[0, 0]]\n]}')
    with pytest.raises(FileFormatError, match=r"c\.json, line 3: frames\[1\]: has 1 points, frame 0 has 2"):
        io.load_sequence(tmp_path / "c.json")
    (tmp_path / "d.json").write_text('{"frames": [[[0, 0], [1, 0]]], "iterations": "many"}')
    with pytest.raises(FileFormatError, match="iterations: has the wrong type"):
        io.load_sequence(tmp_path / "d.json")


def test_svg_cubic_flattened_within_tolerance_where_it_bends_most_at_an_end(tmp_path):
    """A cubic whose second derivative peaks at an end point (where no inner probe sees it) stays in tolerance."""
    from isotween.io.svg import CURVE_TOLERANCE

    p = np.array([0, -31.2 + 31.2j, -31.2 + 81.9j, 113.1j]) + (440 + 0j)  # as in Font Awesome's carrot
    (tmp_path / "c.svg").write_text(
        '<svg xmlns="http://www.w3.org/2000/svg"><path d="M440 0 c-31.2 31.2 -31.2 81.9 0 113.1 L600 113.1 '
        'L600 0 Z"/></svg>')
    s = io.load(tmp_path / "c.svg")
    tol = CURVE_TOLERANCE * s.bbox_diagonal()
    ring = s.z[s.paths[0][0]]
    t = np.linspace(0, 1, 4001)[:, None]
    curve = ((1 - t) ** 3 * p[0] + 3 * (1 - t) ** 2 * t * p[1] + 3 * (1 - t) * t ** 2 * p[2] + t ** 3 * p[3]).ravel()
    a, b = ring, np.roll(ring, -1)  # every edge of the flattened ring; distance of each curve point to the nearest
    u = np.clip(((curve[:, None] - a) * np.conj(b - a)).real / np.abs(b - a) ** 2, 0, 1)
    gap = np.abs(curve[:, None] - (a + u * (b - a))).min(axis=1)
    assert gap.max() <= tol
