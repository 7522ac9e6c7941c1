"""Hostile inputs.

Every one gets the exact error class (library) or exit code and one ``error:`` line (command line), with no traceback
and no file left behind.

Signals: SIGINT and SIGTERM during the solve and during rendering keep the old
output and leave no temporary file.
"""

import io as _io
import os
import signal
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import isotween
from isotween import Shape, interpolate, io
from isotween.cli import main
from isotween.correspondence import mesh_pair
from isotween.errors import (
    FileFormatError,
    IncompatibleShapesError,
    MethodError,
    ParameterError,
    ResourceError,
    ShapeError,
)
from isotween.paint import Paint
from isotween.resources import memory_limit, parse_size

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
RING = [[0, 1], [1, 2], [2, 3], [3, 0]]


def square():
    return Shape.from_polygon(SQUARE)


def wide():
    return square().with_vertices(SQUARE * [2.0, 1.0])


def points_only(n=2):
    return Shape(np.arange(2 * n, dtype=float).reshape(n, 2))


def sequence():
    return interpolate(square(), wide(), frames=5)


def nan_sequence():
    seq = sequence()
    seq.frames[2, 1, 0] = np.nan
    return seq


def ellipse_points(k=40, a=2.0, b=1.0):
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    return np.c_[a * np.cos(t), b * np.sin(t)]


def big_square():
    return Shape.from_polygon(SQUARE * 10)


# ------------------------------------------------------------------ library: values at the edge
API = [
    ("vertices-strings", lambda: Shape([["0", "0"], ["1", "0"]]), ShapeError),
    ("vertices-ragged", lambda: Shape([[0, 0], [1]]), ShapeError),
    ("vertices-nan", lambda: Shape([[0, 0], [np.nan, 1]]), ShapeError),
    ("vertices-inf", lambda: Shape([[0, 0], [np.inf, 1]]), ShapeError),
    ("vertices-1e200", lambda: Shape([[0, 0], [1e200, 0]], [[0, 1]]), ShapeError),
    ("vertices-3-columns", lambda: Shape(np.zeros((3, 3))), ShapeError),
    ("vertices-flat", lambda: Shape([0.0, 1.0, 2.0]), ShapeError),
    ("vertices-bool", lambda: Shape([[True, False], [False, True]]), ShapeError),
    ("vertices-objects", lambda: Shape([[None, 0], [1, 2]]), ShapeError),
    ("vertices-complex", lambda: Shape(np.zeros((2, 2), dtype=complex)), ShapeError),
    ("edge-out-of-range", lambda: Shape(SQUARE, [[0, 4]]), ShapeError),
    ("edge-negative", lambda: Shape(SQUARE, [[0, -1]]), ShapeError),
    ("edge-10e30", lambda: Shape(SQUARE, [[0, 10**30]]), ShapeError),
    ("edge-fraction", lambda: Shape(SQUARE, [[0, 1.5]]), ShapeError),
    ("edge-nan", lambda: Shape(SQUARE, [[0, np.nan]]), ShapeError),
    ("edge-ragged", lambda: Shape(SQUARE, [[0, 1], [2]]), ShapeError),
    ("edge-strings", lambda: Shape(SQUARE, [["0", "1"]]), ShapeError),
    ("edge-width-3", lambda: Shape(SQUARE, [[0, 1, 2]]), ShapeError),
    ("edge-self-loop", lambda: Shape(SQUARE, [[2, 2]]), ShapeError),
    ("edge-duplicate", lambda: Shape(SQUARE, [[0, 1], [1, 0]]), ShapeError),
    ("duplicates-option", lambda: Shape(SQUARE, RING, duplicates="drop"), ShapeError),
    ("face-out-of-range", lambda: Shape(SQUARE, faces=[[0, 1, 9]]), ShapeError),
    ("face-repeats-vertex", lambda: Shape(SQUARE, faces=[[0, 1, 1]]), ShapeError),
    ("uv-wrong-size", lambda: Shape(SQUARE, RING, uv=[[0, 0]]), ShapeError),
    ("uv-nan", lambda: Shape(SQUARE, RING, uv=[[0, 0], [1, 0], [1, np.nan], [0, 1]]), ShapeError),
    ("uv-strings", lambda: Shape(SQUARE, RING, uv=[["a", "b"]] * 4), ShapeError),
    ("paths-out-of-range", lambda: Shape(SQUARE, RING, paths=[([0, 1, 7], True)]), ShapeError),
    ("paths-not-pairs", lambda: Shape(SQUARE, RING, paths=[[0, 1, 2]]), ShapeError),
    ("paths-closed-string", lambda: Shape(SQUARE, RING, paths=[([0, 1, 2], "yes")]), ShapeError),
    ("paths-2d-indices", lambda: Shape(SQUARE, RING, paths=[([[0, 1], [2, 3]], True)]), ShapeError),
    ("paths-a-string", lambda: Shape(SQUARE, RING, paths="0123"), ShapeError),
    ("regions-without-paths", lambda: Shape(SQUARE, RING, regions=[[0]]), ShapeError),
    ("paint-wrong-length", lambda: Shape(SQUARE, RING, paths=[([0, 1, 2, 3], True)],
                                         paint=[Paint(), Paint()]), ShapeError),
    ("with-vertices-nan", lambda: square().with_vertices(np.where(SQUARE == 1, np.nan, SQUARE)), ShapeError),
    ("with-vertices-shape", lambda: square().with_vertices(SQUARE[:3]), ShapeError),
    ("with-vertices-strings", lambda: square().with_vertices(SQUARE.astype(str)), ShapeError),
    ("with-vertices-1e200", lambda: square().with_vertices(SQUARE * 1e200), ShapeError),
    ("from-polygon-empty", lambda: Shape.from_polygon([]), ShapeError),
    ("from-polygon-two-points", lambda: Shape.from_polygon([[0, 0], [1, 0]]), ShapeError),
    ("from-polygon-ragged", lambda: Shape.from_polygon([[0, 0], [1], [2, 2]]), ShapeError),
    ("from-polygon-string", lambda: Shape.from_polygon("abc"), ShapeError),
    ("from-polygon-empty-ring", lambda: Shape.from_polygon([SQUARE, []]), ShapeError),
    ("from-polyline-one-point", lambda: Shape.from_polyline([[0, 0]]), ShapeError),
    ("interpolate-no-edges", lambda: interpolate(points_only(), points_only()), ShapeError),
    ("interpolate-one-vertex", lambda: interpolate(points_only(1), points_only(1)), ShapeError),
    ("interpolate-flat-array", lambda: interpolate(np.ravel(SQUARE), SQUARE), ShapeError),
    ("frames-1", lambda: interpolate(square(), wide(), frames=1), ParameterError),
    ("frames-fraction", lambda: interpolate(square(), wide(), frames=1.5), ParameterError),
    ("frames-bool", lambda: interpolate(square(), wide(), frames=True), ParameterError),
    ("frames-1e9", lambda: interpolate(square(), wide(), frames=10**9), ResourceError),
    ("frames-10e30", lambda: interpolate(square(), wide(), frames=10**30), ResourceError),
    ("max-memory-small", lambda: interpolate(square(), wide(), frames=100, max_memory=1000), ResourceError),
    ("max-memory-negative", lambda: interpolate(square(), wide(), max_memory=-1), ParameterError),
    ("tol-nan", lambda: interpolate(square(), wide(), tol=float("nan")), ParameterError),
    ("tol-negative", lambda: interpolate(square(), wide(), tol=-1.0), ParameterError),
    ("tol-string", lambda: interpolate(square(), wide(), tol="small"), ParameterError),
    ("tol-inf", lambda: interpolate(square(), wide(), tol=float("inf")), ParameterError),
    ("max-iter-0", lambda: interpolate(square(), wide(), max_iter=0), ParameterError),
    ("max-iter-fraction", lambda: interpolate(square(), wide(), max_iter=2.5), ParameterError),
    ("solver-unknown", lambda: interpolate(square(), wide(), solver="magic"), ParameterError),
    ("init-unknown", lambda: interpolate(square(), wide(), init="magic"), ParameterError),
    ("scheme-unknown", lambda: interpolate(square(), wide(), scheme="magic"), ParameterError),
    ("times-wrong-length", lambda: interpolate(square(), wide(), frames=3, times=[0, 1]), ParameterError),
    ("times-decreasing", lambda: interpolate(square(), wide(), frames=3, times=[0, 0.7, 0.2]), ParameterError),
    ("times-nan", lambda: interpolate(square(), wide(), frames=3, times=[0, np.nan, 1]), ParameterError),
    # polygons of other counts are morphed (correspondence runs); refused when it is switched off
    ("incompatible-counts", lambda: interpolate(square(), Shape.from_polygon(SQUARE[:3]), correspondence="never"),
     IncompatibleShapesError),
    ("zero-length-edge", lambda: interpolate(square(), square().with_vertices(SQUARE * [1, 0])), ShapeError),
    ("method-unknown", lambda: interpolate(square(), wide(), method="morph"), MethodError),
    ("shapespace-no-edges", lambda: interpolate(points_only(), points_only(), method="shapespace"), ShapeError),
    ("transfer-no-edges", lambda: isotween.transfer(points_only(), points_only(), points_only()), ShapeError),
    ("transfer-incompatible", lambda: isotween.transfer(square(), wide(), Shape.from_polygon(SQUARE[:3]),
                                                        correspondence="never"), IncompatibleShapesError),
    ("interpolate-correspondence-unknown", lambda: interpolate(square(), wide(), correspondence="maybe"),
     ParameterError),
    ("transfer-frames-1e9", lambda: isotween.transfer(square(), wide(), square(), frames=10**9), ResourceError),
    ("edit-frame-out-of-range", lambda: isotween.edit(sequence(), frame=9, shape=square()), ParameterError),
    ("edit-frame-fraction", lambda: isotween.edit(sequence(), frame=1.5, shape=square()), ParameterError),
    ("edit-not-a-sequence", lambda: isotween.edit(square(), frame=1, shape=square()), ParameterError),
    ("edit-nan-frames", lambda: isotween.edit(nan_sequence(), frame=1, shape=square()), ParameterError),
    ("edit-edits-a-list", lambda: isotween.edit(sequence(), edits=[square()]), ParameterError),
    ("edit-nan-shape", lambda: isotween.edit(sequence(), frame=1, shape=np.full_like(SQUARE, np.nan)), ShapeError),
    ("keyframes-one", lambda: isotween.interpolate_keyframes([square()]), ParameterError),
    ("keyframes-times-strings", lambda: isotween.interpolate_keyframes([square(), wide()], times=["a", "b"]),
     ParameterError),
    ("keyframes-smooth-nan", lambda: isotween.interpolate_keyframes([square(), wide()], smooth=float("nan")),
     ParameterError),
    ("keyframes-frames-1e9", lambda: isotween.interpolate_keyframes([square(), wide()], frames=10**9), ResourceError),
    ("keyframes-no-edges", lambda: isotween.interpolate_keyframes([points_only(), points_only()]), ShapeError),
    ("mesh-max-area-unreachable", lambda: mesh_pair(big_square(), big_square(), max_area=1, mesher="triangle"),
     ParameterError),
    ("mesh-max-area-tiny", lambda: mesh_pair(big_square(), big_square(), max_area=1e-12), ResourceError),
    ("mesh-max-area-negative", lambda: mesh_pair(big_square(), big_square(), max_area=-1), ParameterError),
    ("max-memory-size-text", lambda: parse_size("lots"), ParameterError),
    ("max-memory-size-zero", lambda: parse_size("0"), ParameterError),
]


@pytest.mark.parametrize("make, error", [c[1:] for c in API], ids=[c[0] for c in API])
def test_library_refuses(make, error):
    with pytest.raises(error) as info:
        make()
    assert type(info.value) is error
    assert str(info.value) and "\n" not in str(info.value)


def test_huge_coordinates_give_no_runtime_warning():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ShapeError, match="beyond"):
            Shape([[0.0, 0.0], [1e200, 0.0]], [[0, 1]])


# ------------------------------------------------------------------ loaders: files
def _npz_bytes(**arrays):
    buf = _io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def _lying_npz(name="vertices"):
    """A tiny .npz whose header claims a (1e12, 2) array."""
    buf = _io.BytesIO()
    np.save(buf, np.zeros((1, 2)))
    raw = buf.getvalue().replace(b"(1, 2)", b"(1000000000000, 2)")
    out = _io.BytesIO()
    with zipfile.ZipFile(out, "w") as z:
        z.writestr(f"{name}.npy", raw)
    return out.getvalue()


def _corrupt_deflate():
    """A compressed .npz whose deflate stream is damaged (zlib.error while reading)."""
    buf = _io.BytesIO()
    np.savez_compressed(buf, vertices=np.arange(2000.0).reshape(-1, 2))
    raw = bytearray(buf.getvalue())
    start = raw.index(b"vertices.npy") + len("vertices.npy") + 40
    raw[start:start + 60] = bytes(60)
    return bytes(raw)


def _zip(name, data):
    out = _io.BytesIO()
    with zipfile.ZipFile(out, "w") as z:
        z.writestr(name, data)
    return out.getvalue()


SVG = '<svg xmlns="http://www.w3.org/2000/svg">{}</svg>'
LAUGHS = ('<?xml version="1.0"?>\n<!DOCTYPE svg [\n<!ENTITY a "aaaaaaaaaa">\n'
          + "".join(f'<!ENTITY {c} "{("&" + p + ";") * 10}">\n' for p, c in zip("abcdefgh", "bcdefghi", strict=True))
          + ']>\n<svg xmlns="http://www.w3.org/2000/svg"><polygon id="&i;" points="0,0 1,0 1,1"/></svg>')

FILES = [
    ("obj-huge-index", "a.obj", "v 0 0\nv 1 0\nv 0 1\nf 1 2 99999999999999999999999\n", "line 4"),
    ("obj-huge-negative-index", "a.obj", "v 0 0\nv 1 0\nl 1 -99999999999999999999999\n", "line 3"),
    ("obj-nan-vertex", "a.obj", "v 0 0\nv nan 0\nl 1 2\n", "line 2"),
    ("obj-inf-vertex", "a.obj", "v 0 0\nv 1e400 0\nl 1 2\n", "line 2"),
    ("obj-1e200-vertex", "a.obj", "v 0 0\nv 1e200 0\nl 1 2\n", "line 2"),
    ("obj-z", "a.obj", "v 0 0 1\nv 1 0 0\nl 1 2\n", "line 1"),
    ("obj-index-zero", "a.obj", "v 0 0\nv 1 0\nl 0 1\n", "line 3"),
    ("obj-word", "a.obj", "v 0 zero\n", "line 1"),
    ("obj-no-vertices", "a.obj", "# empty\n", "no vertices"),
    ("obj-not-utf8", "a.obj", b"v 0 0\n\xff\xfe\n", "UTF-8"),
    ("obj-vt-nan", "a.obj", "v 0 0\nv 1 0\nvt 0 0\nvt nan 0\nl 1/1 2/2\n", "uv"),
    ("off-huge-count", "a.off", "OFF\n100000000000000000000000000000 0 0\n", "line 2"),
    ("off-huge-face-index", "a.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999999999999999\n", "line 6"),
    ("off-truncated", "a.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n", "ends after"),
    ("off-bad-header", "a.off", "FOO\n", "header"),
    ("off-negative-count", "a.off", "OFF\n-3 0 0\n", "line 2"),
    ("off-nan-vertex", "a.off", "OFF\n2 1 0\n0 0 0\nnan 0 0\n2 0 1\n", "line 4"),
    ("json-deep", "a.json", '{"vertices": ' + "[" * 100000 + "]" * 100000 + "}", "nested"),
    ("json-edge-10e30", "a.json", '{"vertices": [[0, 0], [1, 0]], "edges": [[0, %d]]}' % 10**30, "edges[0]"),
    ("json-vertex-1e400", "a.json", '{"vertices": [[0, 0], [1e400, 0]]}', "vertices[1]"),
    ("json-vertex-10e400", "a.json", '{"vertices": [[0, 0], [%d, 0]]}' % 10**400, "vertices[1]"),
    ("json-nan", "a.json", '{"vertices": [[0, 0], [NaN, 0]]}', "vertices[1]"),
    ("json-not-object", "a.json", "[1, 2]", "JSON object"),
    ("json-no-vertices", "a.json", '{"edges": []}', "vertices"),
    ("json-ragged", "a.json", '{"vertices": [[0, 0], [1]]}', "vertices[1]"),
    ("json-string-number", "a.json", '{"vertices": [[0, "0"]]}', "vertices[0]"),
    ("json-edge-fraction", "a.json", '{"vertices": [[0, 0], [1, 0]], "edges": [[0, 0.5]]}', "edges[0]"),
    ("json-uv-size", "a.json", '{"vertices": [[0, 0], [1, 0]], "edges": [[0, 1]], "uv": [[0, 0]]}', "uv"),
    ("json-path-out-of-range", "a.json", '{"vertices": [[0, 0], [1, 0]], "paths": [{"indices": [0, 5]}]}', "paths"),
    ("json-invalid", "a.json", '{"vertices": [[0, 0],', "line 1"),
    ("json-huge-digits", "a.json", '{"vertices": [[0, ' + "9" * 5000 + "]]}", "a.json"),
    ("npz-lying-header", "a.npz", _lying_npz(), "declares shape"),
    ("npz-not-zip", "a.npz", b"PK\x03\x04 not really", "not a valid .npz"),
    ("npz-object-array", "a.npz", _npz_bytes(vertices=np.array([[0, 0], [1, None]], dtype=object)), "objects"),
    ("npz-string-vertices", "a.npz", _npz_bytes(vertices=np.array([["0", "0"], ["1", "0"]])), "vertices"),
    ("npz-no-vertices", "a.npz", _npz_bytes(edges=np.array([[0, 1]])), "vertices"),
    ("npz-edge-out-of-range", "a.npz", _npz_bytes(vertices=SQUARE, edges=np.array([[0, 9]])), "out of range"),
    ("npz-nan-vertex", "a.npz", _npz_bytes(vertices=np.array([[0, 0], [np.nan, 0]]), edges=np.array([[0, 1]])),
     "non-finite"),
    ("npz-other-member", "a.npz", _zip("notes.txt", b"hello"), "notes.txt"),
    ("npz-corrupt-deflate", "a.npz", _corrupt_deflate(), "not a valid .npz"),
    ("svg-entity-file", "a.svg", '<?xml version="1.0"?>\n<!DOCTYPE svg [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
     + SVG.format('<polygon id="&x;" points="0,0 1,0 1,1"/>'), "entity"),
    ("svg-billion-laughs", "a.svg", LAUGHS, "entity"),
    ("svg-parameter-entity", "a.svg",
     '<?xml version="1.0"?>\n<!DOCTYPE svg [<!ENTITY % p SYSTEM "http://example.invalid/x.dtd"> %p;]>\n'
     + SVG.format('<polygon points="0,0 1,0 1,1"/>'), "entity"),
    ("svg-external-dtd", "a.svg", '<?xml version="1.0"?>\n<!DOCTYPE svg SYSTEM "http://example.invalid/evil.dtd">\n'
     + SVG.format('<polygon points="0,0 1,0 1,1"/>'), "DTD"),
    ("svg-external-use", "a.svg", '<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink">'
     '<use xlink:href="other.svg#p"/></svg>', "outside this file"),
    ("svg-url-use", "a.svg", SVG.format('<use href="http://example.invalid/a.svg#p"/>'), "outside this file"),
    ("svg-inf", "a.svg", SVG.format('<path d="M 0 0 L 1e400 0 L 5 5 Z"/>'), "non-finite"),
    ("svg-1e200", "a.svg", SVG.format('<path d="M 0 0 L 1e200 0 L 5 5 Z"/>'), "beyond"),
    ("svg-backtracking-points", "a.svg", SVG.format('<polyline points="0,50 103 0.6944444444444443 L 1.0 1.0"/>'),
     "malformed points"),
    ("svg-deep-groups", "a.svg", SVG.format("<g>" * 100000 + "</g>" * 100000), "nested deeper"),
    ("svg-unknown-encoding", "a.svg", '<?xml version="1.0" encoding="UTF-1e400"?><svg/>', "encoding"),
    ("svg-foreign-namespace", "a.svg", '<svg xmlns="http://example.com/svg"><polygon points="0,0 1,0 1,1"/></svg>',
     "not an SVG"),
    ("svg-path-without-start", "a.svg", SVG.format('<path d="L 0 0 S 5 5 10 0 T 20 0"/>'), "geometry"),
    ("svg-malformed", "a.svg", "<svg", "line 1"),
    ("svg-not-svg", "a.svg", "<html/>", "not <svg>"),
    ("svg-empty-drawing", "a.svg", SVG.format(""), "nothing to read"),
    ("svg-bad-path", "a.svg", SVG.format('<path d="M 0 0 L x y"/>'), "malformed path"),
    ("unknown-extension", "a.xyz", "v 0 0\n", "cannot read"),
]


def _write(path, content):
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)


def _listing(folder):
    return sorted(str(p.relative_to(folder)) for p in Path(folder).rglob("*"))


@pytest.mark.parametrize("name, content, needle", [c[1:] for c in FILES], ids=[c[0] for c in FILES])
def test_loader_refuses(tmp_path, name, content, needle):
    path = tmp_path / name
    _write(path, content)
    with pytest.raises(FileFormatError) as info:
        io.load(path)
    assert type(info.value) is FileFormatError
    message = str(info.value)
    assert message.startswith(str(path)) and needle in message and "\n" not in message
    assert _listing(tmp_path) == [name]


def test_svg_links_are_not_followed(tmp_path):
    """An <image> or <a> link to a local file or URL is not read: only the polygon counts."""
    secret = tmp_path / "secret.svg"
    secret.write_text(SVG.format('<polygon points="0,0 100,0 100,100"/>'))
    path = tmp_path / "a.svg"
    path.write_text('<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink">'
                    f'<image xlink:href="{secret.as_uri()}" width="5" height="5"/>'
                    '<image href="http://example.invalid/x.png" width="5" height="5"/>'
                    '<polygon points="0,0 1,0 1,1"/></svg>')
    shape = io.load(path)
    assert shape.n_vertices == 3 and shape.vertices.max() == 1.0


def test_svg_internal_use_still_works(tmp_path):
    path = tmp_path / "a.svg"
    path.write_text(SVG.format('<defs><polygon id="p" points="0,0 1,0 1,1"/></defs><use href="#p" x="5"/>'))
    shape = io.load(path)
    np.testing.assert_allclose(shape.vertices, [[5, 0], [6, 0], [6, 1]])


def test_svg_standard_doctype_is_accepted(tmp_path):
    path = tmp_path / "a.svg"
    path.write_text('<?xml version="1.0"?>\n<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN" '
                    '"http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd">\n'
                    + SVG.format('<polygon points="0,0 1,0 1,1"/>'))
    assert io.load(path).n_vertices == 3


@pytest.mark.parametrize("value, error", [(1.5, ParameterError), (0, ParameterError), ("4", ParameterError),
                                          (10**9, ParameterError)])
def test_svg_curve_segments_refused(tmp_path, value, error):
    path = tmp_path / "a.svg"
    path.write_text(SVG.format('<circle cx="0" cy="0" r="1"/>'))
    with pytest.raises(error):
        io.load(path, curve_segments=value)


@pytest.mark.parametrize("ext", [".obj", ".off", ".json", ".svg"])
def test_text_file_too_large_for_the_limit(tmp_path, ext):
    path = tmp_path / f"a{ext}"
    io.save(Shape.from_polygon(ellipse_points(1000)), path)
    with memory_limit(1000), pytest.raises(ResourceError, match="reading"):
        io.load(path)


def test_frame_folder_too_large_for_the_limit(tmp_path):
    for k in range(3):
        io.save(square(), tmp_path / f"f{k}.npz")
    with memory_limit(500), pytest.raises(ResourceError, match="3 frame files"):
        io.load_sequence(tmp_path)
    assert len(io.load_sequence(tmp_path)) == 3


def test_npz_honest_but_too_large_for_the_limit(tmp_path):
    path = tmp_path / "a.npz"
    io.save(Shape.from_polygon(ellipse_points(1000)), path)
    with memory_limit(1000), pytest.raises(ResourceError, match="reading"):
        io.load(path)
    assert io.load(path).n_vertices == 1000  # the default limit is the available memory


SEQUENCE_FILES = [
    ("npz-nan-frame", "s.npz", lambda: _npz_bytes(frames=np.full((2, 4, 2), np.nan), edges=np.array(RING)),
     "non-finite"),
    ("npz-lying-frames", "s.npz", lambda: _lying_npz("frames"), "declares"),
    ("json-ragged-frames", "s.json", lambda: '{"frames": [[[0, 0], [1, 0]], [[0, 0]]]}', "frames[1]"),
    ("json-deep-frames", "s.json", lambda: '{"frames": ' + "[" * 5000 + "]" * 5000 + "}", "nested"),
]


@pytest.mark.parametrize("name, make, needle", [c[1:] for c in SEQUENCE_FILES], ids=[c[0] for c in SEQUENCE_FILES])
def test_sequence_loader_refuses(tmp_path, name, make, needle):
    path = tmp_path / name
    _write(path, make())
    with pytest.raises(FileFormatError) as info:
        io.load_sequence(path)
    assert needle in str(info.value)


def test_fuzzing_a_few_hundred_mutated_files():
    """The harness of benchmarks/fuzz.py on 300 inputs: only shapes, sequences or IsotweenErrors."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("fuzz", Path(__file__).parents[1] / "benchmarks" / "fuzz.py")
    fuzz = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(fuzz)
    counts, _, bugs, _ = fuzz.run(300, workers=1, seed=12)
    assert sum(counts.values()) == 300
    assert not bugs, sorted(bugs)
    assert {o.split()[0] for _, o in counts} <= {"shape", "sequence", "manifest", "error"}


# ------------------------------------------------------------------ command line
@pytest.fixture
def files(tmp_path):
    """Input files of the command-line cases, in their own folder."""
    d = tmp_path / "in"
    d.mkdir()
    io.save(square(), d / "sq.json")
    io.save(wide(), d / "wide.json")
    (d / "pts.obj").write_text("v 0 0\nv 1 0\n")
    (d / "one.obj").write_text("v 0 0\n")
    (d / "zero.obj").write_text("# nothing\n")
    (d / "big.obj").write_text("v 0 0\nv 1 0\nv 0 1\nf 1 2 99999999999999999999999\n")
    (d / "deep.json").write_text('{"vertices": ' + "[" * 100000 + "]" * 100000 + "}")
    (d / "lie.npz").write_bytes(_lying_npz())
    (d / "notimage.png").write_text("not an image")
    for name, (a, b) in (("e1", (2, 1)), ("e2", (1, 2))):
        io.save(Shape.from_polygon(ellipse_points(40, a, b)), d / f"{name}.svg")
    io.save_sequence(sequence(), d / "seq.npz")
    return d


CLI = [
    ("no-edges", ["interpolate", "{in}/pts.obj", "{in}/pts.obj", "-o", "{out}/o.gif"], "pts.obj"),
    ("one-vertex", ["interpolate", "{in}/one.obj", "{in}/one.obj", "-o", "{out}/o.gif"], "one.obj"),
    ("zero-vertices", ["interpolate", "{in}/zero.obj", "{in}/zero.obj", "-o", "{out}/o.gif"], "zero.obj"),
    ("huge-obj-index", ["interpolate", "{in}/big.obj", "{in}/big.obj", "-o", "{out}/o.npz"], "line 4"),
    ("deep-json", ["interpolate", "{in}/deep.json", "{in}/sq.json", "-o", "{out}/o.npz"], "deep.json"),
    ("lying-npz", ["interpolate", "{in}/lie.npz", "{in}/sq.json", "-o", "{out}/o.npz"], "lie.npz"),
    ("frames-1e9", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--frames", "1000000000", "-o", "{out}/o.npz"],
     "GiB"),
    ("frames-1", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--frames", "1", "-o", "{out}/o.npz"], "frames"),
    ("frames-text", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--frames", "many", "-o", "{out}/o.npz"],
     "--frames"),
    ("mesh-1e-9", ["interpolate", "{in}/e1.svg", "{in}/e2.svg", "--resample", "40", "--mesh", "1e-9",
                   "-o", "{out}/o.npz"], "max_area"),
    ("mesh-zero", ["interpolate", "{in}/e1.svg", "{in}/e2.svg", "--resample", "40", "--mesh", "0",
                       "-o", "{out}/o.npz"], "max_area"),
    ("resample-0", ["interpolate", "{in}/e1.svg", "{in}/e2.svg", "--resample", "0", "-o", "{out}/o.npz"], ""),
    ("max-memory-small", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--max-memory", "1K",
                          "-o", "{out}/o.npz"], "limit"),
    ("gif-100000-frames", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--frames", "100000",
                           "-o", "{out}/o.gif"], "rendering 100000 frames"),
    ("max-memory-text", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--max-memory", "lots",
                         "-o", "{out}/o.npz"], "--max-memory"),
    ("output-is-input", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{in}/wide.json"], "input"),
    ("output-unwritable", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "/proc/o.npz"], "/proc"),
    ("output-missing-folder", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{out}/no/o.npz"],
     "does not exist"),
    ("output-unknown-kind", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{out}/o.xyz"], "o.xyz"),
    ("output-obj", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{out}/o.obj"], "one shape"),
    ("format-with-file", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--format", "obj", "-o", "{out}/o.gif"],
     "--format"),
    ("plot-unwritable", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{out}/o.npz",
                         "--plot", "/proc/e.png"], "/proc"),
    ("plot-kind", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{out}/o.npz", "--plot", "{out}/e.txt"],
     "e.txt"),
    ("texture-not-image", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{out}/o.gif",
                           "--texture", "{in}/notimage.png"], "notimage.png"),
    ("texture-missing", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{out}/o.gif",
                         "--texture", "{in}/none.png"], "none.png"),
    ("tol-nan", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--tol", "nan", "-o", "{out}/o.npz"], "tol"),
    ("tol-negative", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--tol", "-1", "-o", "{out}/o.npz"], "tol"),
    ("max-iter-0", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--max-iter", "0", "-o", "{out}/o.npz"],
     "max_iter"),
    ("method-unknown", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--method", "morph", "-o", "{out}/o.npz"],
     "morph"),
    ("missing-input", ["interpolate", "{in}/none.json", "{in}/wide.json", "-o", "{out}/o.npz"], "none.json"),
    ("transfer-no-edges", ["transfer", "{in}/pts.obj", "{in}/pts.obj", "{in}/pts.obj", "-o", "{out}/o.npz"],
     "no edges"),
    ("transfer-frames-1e9", ["transfer", "{in}/sq.json", "{in}/wide.json", "{in}/sq.json", "--frames", "1000000000",
                             "-o", "{out}/o.npz"], "GiB"),
    ("transfer-output-is-input", ["transfer", "{in}/sq.json", "{in}/wide.json", "{in}/sq.json",
                                  "-o", "{in}/sq.json"], "input"),
    ("edit-frame-out-of-range", ["edit", "{in}/seq.npz", "-k", "99", "--shape", "{in}/sq.json",
                                 "-o", "{out}/o.npz"], "99"),
    ("edit-unpaired", ["edit", "{in}/seq.npz", "-k", "1", "-k", "2", "--shape", "{in}/sq.json",
                       "-o", "{out}/o.npz"], "--shape"),
    ("edit-output-is-input", ["edit", "{in}/seq.npz", "-k", "1", "--shape", "{in}/sq.json", "-o", "{in}/seq.npz"],
     "input"),
    ("edit-lying-sequence", ["edit", "{in}/lie.npz", "-k", "1", "--shape", "{in}/sq.json", "-o", "{out}/o.npz"],
     "lie.npz"),
    ("keyframes-one", ["keyframes", "{in}/sq.json", "-o", "{out}/o.npz"], "two"),
    ("keyframes-times", ["keyframes", "{in}/sq.json", "{in}/wide.json", "--times", "0,x", "-o", "{out}/o.npz"],
     "--times"),
    ("keyframes-smooth-nan", ["keyframes", "{in}/sq.json", "{in}/wide.json", "--smooth", "nan",
                              "-o", "{out}/o.npz"], "smooth"),
    ("keyframes-frames-1e9", ["keyframes", "{in}/sq.json", "{in}/wide.json", "--frames", "1000000000",
                              "-o", "{out}/o.npz"], "GiB"),
    ("info-deep-json", ["info", "{in}/deep.json"], "deep.json"),
    ("info-lying-npz", ["info", "{in}/lie.npz"], "lie.npz"),
    ("info-missing", ["info", "{in}/none.obj"], "none.obj"),
    ("prepare-nothing", ["prepare", "{in}/e1.svg", "{in}/e2.svg", "-o", "{out}/p"], "nothing to prepare"),
    ("prepare-mesh-1e-9", ["prepare", "{in}/e1.svg", "{in}/e2.svg", "--resample", "40", "--mesh", "1e-9",
                           "-o", "{out}/p"], "max_area"),
    ("prepare-unwritable", ["prepare", "{in}/e1.svg", "{in}/e2.svg", "--resample", "40", "-o", "/proc/p"], "/proc"),
    ("compare-unwritable", ["compare", "{in}/sq.json", "{in}/wide.json", "-o", "/proc/r"], "/proc"),
    ("compare-one-file", ["compare", "{in}/sq.json", "-o", "{out}/r"], "SOURCE and TARGET"),
    ("demo-proc", ["demo", "-o", "/proc/x"], "/proc"),
    ("demo-unknown", ["demo", "nothing-like-it", "-o", "{out}/d"], "nothing-like-it"),
]


@pytest.mark.parametrize("args, needle", [c[1:] for c in CLI], ids=[c[0] for c in CLI])
def test_command_line_refuses(files, tmp_path, args, needle):
    out = tmp_path / "out"
    out.mkdir()
    before = _listing(tmp_path)
    result = CliRunner().invoke(main, [a.format(**{"in": files, "out": out}) for a in args])
    assert result.exit_code == 2, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert "Traceback" not in result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and needle in lines[0], result.stderr
    assert _listing(tmp_path) == before  # nothing written, no temp file, inputs untouched


def test_command_line_max_memory_lets_a_run_through(files, tmp_path):
    args = ["interpolate", str(files / "sq.json"), str(files / "wide.json"), "-o", str(tmp_path / "o.npz"), "-q"]
    assert CliRunner().invoke(main, args + ["--max-memory", "1K"]).exit_code == 2
    result = CliRunner().invoke(main, args + ["--max-memory", "1G"])
    assert result.exit_code == 0 and (tmp_path / "o.npz").is_file()


def test_summary_reports_the_written_sequence(files, tmp_path):
    """Transfer and edit print the energy of the frames they wrote, not of another run (nor nan)."""
    from isotween.metrics import isometric_energy

    out = tmp_path / "t.npz"
    io.save(square().with_vertices(SQUARE * 3 + 1), files / "big_sq.json")
    result = CliRunner().invoke(main, ["transfer", str(files / "sq.json"), str(files / "wide.json"),
                                       str(files / "big_sq.json"), "-o", str(out), "-q"])
    assert result.exit_code == 0, result.output
    written = io.load_sequence(out)
    energy = float(result.stdout.split("energy=")[1].split()[0])
    assert energy == pytest.approx(isometric_energy(written), rel=1e-3)
    assert written.energy == pytest.approx([isometric_energy(written)])
    edited = tmp_path / "e.npz"
    result = CliRunner().invoke(main, ["edit", str(files / "seq.npz"), "-k", "2", "--shape", str(files / "sq.json"),
                                       "-o", str(edited), "-q"])
    assert result.exit_code == 0, result.output
    energy = result.stdout.split("energy=")[1].split()[0]
    assert energy != "nan" and float(energy) == pytest.approx(isometric_energy(io.load_sequence(edited)), rel=1e-3)


# ------------------------------------------------------------------ signals
def _wait_for(condition, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.02)
    return False


@pytest.mark.slow
@pytest.mark.parametrize("stage", ["solve", "render"])
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_signal_keeps_the_old_output(files, tmp_path, stage, sig):
    import threading

    out = tmp_path / "o.gif"
    out.write_bytes(b"old output")
    before = _listing(tmp_path)
    if stage == "solve":  # a long solve: many frames and vertices, a tolerance never met
        args = ["--resample", "400", "--frames", "400", "--tol", "1e-14", "--max-iter", "100000"]
    else:  # a quick solve, then many frames to draw
        args = ["--resample", "40", "--frames", "400"]
    src = str(Path(isotween.__file__).parents[1])
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (src, os.environ.get("PYTHONPATH")) if p))
    proc = subprocess.Popen([sys.executable, "-m", "isotween", "interpolate", str(files / "e1.svg"),
                             str(files / "e2.svg"), *args, "-o", str(out)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                            # a shell that ran the tests in the background ignores SIGINT: restore it
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    err = []
    reader = threading.Thread(target=lambda: err.extend(iter(lambda: proc.stderr.read(64), b"")), daemon=True)
    reader.start()
    try:
        if stage == "solve":  # the progress bar shows after half a second of iterations
            started = _wait_for(lambda: proc.poll() is not None or b"iterations" in b"".join(err), 60)
        else:  # the temporary file of the animation exists
            started = _wait_for(lambda: proc.poll() is not None or len(_listing(tmp_path)) > len(before), 60)
        assert started and proc.poll() is None, "the run ended before the signal"
        proc.send_signal(sig)
        proc.wait(timeout=60)
        reader.join(timeout=10)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    text = b"".join(err).decode()
    # 130 / 143; where the process ends by the signal itself after its message (seen once in a CI run after the
    # "interrupted" line, cause not found) a shell reports the same status, 128 + the signal's number
    assert proc.returncode in ((130, -signal.SIGINT) if sig == signal.SIGINT else (143, -signal.SIGTERM)), text
    assert text.replace("\r", "\n").strip().splitlines()[-1].startswith("error: ") and "Traceback" not in text
    assert out.read_bytes() == b"old output"
    assert _listing(tmp_path) == before


# ------------------------------------------------------------------ round 3 (issue 25)
def painted_square(width=1.0):
    from isotween.outputs import with_paint

    return with_paint(sequence(), stroke="red", stroke_width=width)


def _replace(seq, **fields):
    from dataclasses import replace

    return replace(seq, **fields)


API_3 = [
    ("at-10e400", lambda: sequence().at(10**400), ParameterError),
    ("report-empty-sequence", lambda: isotween.metrics.report(sequence()[3:3]), ParameterError),
    ("resample-frames-1e8", lambda: sequence().resample(frames=10**8), ResourceError),
    ("resample-points-1e12", lambda: isotween.resample(square(), wide(), points=10**12), ResourceError),
    ("load-nul-path", lambda: io.load("a\0b.json"), FileFormatError),
    ("save-nul-path", lambda: sequence().save("a\0b.gif"), FileFormatError),
    ("save-dash", lambda: sequence().save("-"), FileFormatError),
    ("save-sequence-nan-frames", lambda: io.save_sequence(nan_sequence(), "/nonexistent/x.npz"), FileFormatError),
    ("save-sequence-wrong-vertex-count", lambda: io.save_sequence(_replace(sequence(), frames=sequence().frames[:, :3]),
                                                                  "/nonexistent/x.npz"), FileFormatError),
    ("save-sequence-nan-energy", lambda: io.save_sequence(_replace(sequence(), energy=[np.nan]), "/nonexistent/x.json"),
     FileFormatError),
    ("write-output-not-a-sequence", lambda: isotween.write_output(square(), "/nonexistent/x.gif"), FileFormatError),
]


@pytest.mark.parametrize("make, error", [c[1:] for c in API_3], ids=[c[0] for c in API_3])
def test_library_refuses_round_3(make, error):
    with pytest.raises(error) as info:
        make()
    assert type(info.value) is error
    assert str(info.value) and "\n" not in str(info.value)


#: (id, output name, sequence, options, error, text in the message); nothing may be written
WRITES = [
    ("html-nan-energy", "x.html", lambda: _replace(sequence(), energy=[np.nan]), {}, FileFormatError, "energy[0]"),
    ("html-keyframes-strings", "x.html", lambda: _replace(sequence(), info={"keyframe_indices": ["x"]}), {},
     FileFormatError, "keyframe_indices"),
    ("html-paint-regions-out-of-range", "x.html",
     lambda: _replace(painted_square(), info={**painted_square().info,
                                              "paint": {**painted_square().info["paint"], "regions": [[7]]}}),
     {}, FileFormatError, "paint.regions"),
    ("lottie-stroke-1e308", "x.lottie.json", lambda: painted_square(1e308), {}, FileFormatError, "is inf"),
    ("gif-size-60000", "x.gif", sequence, {"size": 60000}, ResourceError, "60000 x"),
    ("mp4-size-8192-small-limit", "x.mp4", sequence, {"size": 8192, "max_memory": True}, ResourceError, "8192 x"),
    ("gif-hold-1e300", "x.gif", sequence, {"hold": 1e300}, ParameterError, "hold"),
    ("gif-fps-1e-300", "x.gif", sequence, {"fps": 1e-300}, ParameterError, "655.35 s"),
    ("gif-hold-700-fps-1", "x.gif", sequence, {"hold": 700, "fps": 1}, ParameterError, "655.35 s"),
    ("apng-hold-100-fps-1", "x.apng", sequence, {"hold": 100, "fps": 1}, ParameterError, "65.535 s"),
    ("lottie-many-ticks-small-limit", "x.lottie.json", sequence, {"hold": 3600, "fps": 100, "max_memory": True},
     ResourceError, "ticks"),
]


@pytest.mark.parametrize("name, make, options, error, needle", [c[1:] for c in WRITES], ids=[c[0] for c in WRITES])
def test_writers_refuse(tmp_path, name, make, options, error, needle):
    options = dict(options)
    limited = options.pop("max_memory", False)
    with memory_limit(50 << 20 if limited else None), pytest.raises(error) as info:
        isotween.write_output(make(), tmp_path / name, quiet=True, **options)
    assert type(info.value) is error and needle in str(info.value) and "\n" not in str(info.value)
    assert _listing(tmp_path) == []


def test_html_title_cannot_end_the_data_block(tmp_path):
    import json
    import re

    title = '<!--<script></script><b>\u2028x'
    out = tmp_path / "x.html"
    sequence().save(out, title=title)
    page = out.read_text(encoding="utf-8")
    block = re.search(r'<script type="application/json" id="isotween-data">(.*?)</script>', page, re.S).group(1)
    assert "<" not in block and ">" not in block and "\u2028" not in block
    assert json.loads(block)["title"] == "<!--<script></script><b> x"  # U+2028 is a line break: a space
    assert "<title>&lt;!--&lt;script&gt;" in page


@pytest.mark.parametrize("ext", [".svg", ".html", ".lottie.json"])
def test_titles_with_control_characters_and_undecodable_bytes(tmp_path, ext):
    import xml.etree.ElementTree as ET

    out = tmp_path / f"x{ext}"
    sequence().save(out, title="a\x01b\x1bc\udcffd\ne")
    text = out.read_text(encoding="utf-8")  # valid UTF-8
    if ext == ".svg":
        title = ET.parse(out).getroot().find("{http://www.w3.org/2000/svg}title").text  # valid XML
        assert title == "abc\ufffdd e"
    assert "\x01" not in text and "\x1b" not in text


def test_long_legal_output_name_is_written(tmp_path):
    out = tmp_path / ("n" * 246 + ".npz")  # 250 bytes: legal, though the temporary name would not be
    io.save_sequence(sequence(), out)
    assert _listing(tmp_path) == [out.name]


# sequence files whose info disagrees with their frames: refused at load, naming the field
def _sequence_npz(**changes):
    import json

    seq = sequence()
    arrays = {"frames": seq.frames, "edges": seq.shape.edges, "times": seq.times,
              "energy": np.asarray(seq.energy, dtype=float), "info": np.array(json.dumps({}))}
    arrays.update(changes)
    return _npz_bytes(**arrays)


SEQUENCE_INFO = [
    ("keyframes-strings", lambda: _sequence_npz(info=np.array('{"keyframe_indices": ["x"]}')), "keyframe_indices"),
    ("keyframes-out-of-range", lambda: _sequence_npz(info=np.array('{"keyframe_indices": [99]}')),
     "keyframe_indices"),
    ("nan-energy", lambda: _sequence_npz(energy=np.array([np.nan])), "energy[0]"),
    ("nan-times", lambda: _sequence_npz(times=np.array([0, np.nan, 0.5, 0.7, 1.0])), "times"),
    ("decreasing-times", lambda: _sequence_npz(times=np.array([0, 0.5, 0.2, 0.7, 1.0])), "times"),
    ("info-a-list", lambda: _sequence_npz(info=np.array("[1, 2]")), "info"),
    ("paint-regions-out-of-range", lambda: _sequence_npz(info=np.array(
        '{"paint": {"times": [0, 1], "keys": [[{}], [{}]], "regions": [[5]]}}')), "paint"),
    ("paint-keys-a-number", lambda: _sequence_npz(info=np.array('{"paint": {"times": [0, 1], "keys": 3}}')),
     "paint"),
]


@pytest.mark.parametrize("make, needle", [c[1:] for c in SEQUENCE_INFO], ids=[c[0] for c in SEQUENCE_INFO])
def test_sequence_info_refused_at_load(tmp_path, make, needle):
    path = tmp_path / "s.npz"
    path.write_bytes(make())
    with pytest.raises(FileFormatError) as info:
        io.load_sequence(path)
    assert type(info.value) is FileFormatError and str(info.value).startswith(str(path)) and needle in str(info.value)
    result = CliRunner().invoke(main, ["render", str(path), "-o", str(tmp_path / "o.html")])
    assert result.exit_code == 2 and result.stderr.count("\n") == 1 and needle in result.stderr
    assert _listing(tmp_path) == ["s.npz"]


# inputs that are not regular files: one clear error, no hang
@pytest.fixture
def odd_inputs(tmp_path):
    d = tmp_path / "odd"
    d.mkdir()
    os.mkfifo(d / "fifo.svg")
    os.mkfifo(d / "fifo.png")
    os.mkfifo(d / "fifo.csv")
    (d / "zero.obj").symlink_to("/dev/zero")
    (d / "folder.json").mkdir()
    return d


@pytest.mark.parametrize("name, needle", [("fifo.svg", "pipe"), ("zero.obj", "device"), ("folder.json", "folder")])
def test_inputs_must_be_regular_files(odd_inputs, name, needle):
    with pytest.raises(FileFormatError, match=needle):
        io.load(odd_inputs / name)
    result = CliRunner().invoke(main, ["info", str(odd_inputs / name)])
    assert result.exit_code == 2 and result.stderr.count("\n") == 1 and needle in result.stderr


def test_texture_and_manifest_fifos_are_refused(odd_inputs, files, tmp_path):
    result = CliRunner().invoke(main, ["interpolate", str(files / "sq.json"), str(files / "wide.json"), "-o",
                                       str(tmp_path / "o.gif"), "--texture", str(odd_inputs / "fifo.png")])
    assert result.exit_code == 2 and "pipe" in result.stderr and result.stderr.count("\n") == 1
    result = CliRunner().invoke(main, ["batch", str(odd_inputs / "fifo.csv"), "-o", str(tmp_path / "b")])
    assert result.exit_code == 2 and "pipe" in result.stderr and not (tmp_path / "b").exists()


# SVG drawings that would expand beyond memory
def _use_bomb(levels=8, copies=10):
    body = '<defs><rect id="l0" width="1" height="1"/>'
    for k in range(1, levels + 1):
        body += f'<g id="l{k}">' + "".join(f'<use href="#l{k - 1}" x="{i}"/>' for i in range(copies)) + "</g>"
    return SVG.format(body + f'</defs><use href="#l{levels}"/>')


def test_svg_use_bomb_is_refused_before_expanding(tmp_path):
    """8 levels of 10 copies: 10^8 rects counted (not expanded) and refused; 10^4 refused by the memory estimate."""
    def expanded(levels, copies=10):  # <svg>, <defs>, each level once in <defs>, the <use> of the top level
        counts = [1]
        for _ in range(levels):
            counts.append(1 + copies * (1 + counts[-1]))
        return 2 + sum(counts) + 1 + counts[-1]

    path = tmp_path / "bomb.svg"
    path.write_text(_use_bomb())
    with pytest.raises(FileFormatError, match=f"{expanded(8)} elements after <use> expansion; at most 250000"):
        io.load(path)
    path.write_text(_use_bomb(levels=4))
    with memory_limit(50 << 20), pytest.raises(ResourceError, match=f"{expanded(4)} elements after <use> expansion"):
        io.load(path)


def test_svg_use_cycle_is_refused(tmp_path):
    path = tmp_path / "cycle.svg"
    path.write_text(SVG.format('<g id="a"><rect width="1" height="1"/><use href="#a" x="2"/></g>'))
    with pytest.raises(FileFormatError, match="endless copy"):
        io.load(path)


def test_svg_small_use_graph_still_reads(tmp_path):
    path = tmp_path / "uses.svg"
    path.write_text(_use_bomb(levels=2, copies=3))
    assert io.load(path).n_vertices == 4 * 9


def test_winding_numbers_need_no_dense_matrix():
    """15,000 small squares: the sweep tests a few pairs per edge, never 15,000 x 60,000 of them."""
    import tracemalloc

    from isotween.correspondence.regions import fill_regions, winding_numbers

    rings = [np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float) + [2 * (i % 125), 2 * (i // 125)]
             for i in range(15000)]
    tracemalloc.start()
    regions, outline = fill_regions(rings, "nonzero")
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert len(regions) == 15000 and not outline
    assert peak < 200 << 20  # the dense test needed 7 GB
    probes = np.array([[0.5, 0.5], [1.5, 0.5], [-1.0, 0.5]])
    w = winding_numbers(probes, rings[:2])
    assert w.tolist() == [[1, 0], [0, 0], [0, 0]]


# command line, round 3
CLI_3 = [
    ("output-is-plot", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{out}/x.svg", "--plot", "{out}/x.svg"],
     "name the same file"),
    ("output-dash", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "-"], "standard output"),
    ("output-name-too-long", ["interpolate", "{in}/sq.json", "{in}/wide.json", "-o", "{out}/" + "n" * 300 + ".npz"],
     "at most 255"),
    ("gif-fps-1e-300", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--fps", "1e-300", "-o", "{out}/o.gif"],
     "655.35 s"),
    ("gif-hold-700", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--hold", "700", "--fps", "1",
                      "-o", "{out}/o.gif"], "655.35 s"),
    ("gif-300-frames-4000-px", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--frames", "300", "--size", "4000",
                                "-o", "{out}/o.gif"], "4000 x 4000"),
    ("mp4-size-small-limit", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--size", "2000", "--max-memory", "100M",
                              "-o", "{out}/o.mp4"], "2000 x 2000"),
    ("webp-frames-small-limit", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--frames", "3000",
                                 "--max-memory", "1G", "-o", "{out}/o.webp"], "3000 frames"),
    ("lottie-frames-small-limit", ["interpolate", "{in}/sq.json", "{in}/wide.json", "--frames", "100000", "-q",
                                   "--max-memory", "100M", "-o", "{out}/o.lottie.json"], "ticks"),
    ("lottie-stroke-1e308", ["interpolate", "{in}/stroke.svg", "{in}/stroke.svg", "-o", "{out}/o.lottie.json"],
     "is inf"),
    ("points-1e7", ["interpolate", "{in}/e1.svg", "{in}/e2.svg", "--points", "10000000", "--max-memory", "1G",
                    "-o", "{out}/o.npz"], "10000000 points"),
    ("use-bomb", ["info", "{in}/bomb.svg"], "elements after <use> expansion"),
    ("newline-in-name", ["info", "{in}/no\nerror: forged.json"], "no\\nerror: forged.json"),
    ("ansi-in-name", ["info", "{in}/\x1b[2J.json"], "\\x1b[2J.json"),
    ("newline-in-svg-id", ["info", "{in}/id.svg"], 'id="a\\nerror: b"'),
    ("warning-then-error", ["interpolate", "{in}/degenerate.svg", "{in}/none.json", "-o", "{out}/o.npz"],
     "none.json"),
]


@pytest.fixture
def files_3(files):
    (files / "stroke.svg").write_text(SVG.format(
        '<path d="M0 0 L10 0 L10 10 Z" fill="none" stroke="red" stroke-width="1e308"/>'))
    (files / "bomb.svg").write_text(_use_bomb())
    (files / "id.svg").write_text(SVG.format('<path id="a&#10;error: b" d="M 0 0 L x y"/>'))
    (files / "degenerate.svg").write_text(SVG.format('<polygon points="0,0 1,1"/><polygon points="0,0 1,0 1,1"/>'))
    return files


@pytest.mark.parametrize("args, needle", [c[1:] for c in CLI_3], ids=[c[0] for c in CLI_3])
def test_command_line_refuses_round_3(files_3, tmp_path, args, needle):
    out = tmp_path / "out"
    out.mkdir()
    before = _listing(tmp_path)
    result = CliRunner().invoke(main, [a.format(**{"in": files_3, "out": out}) for a in args])
    assert result.exit_code == 2, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and needle in lines[0], result.stderr
    assert "\x1b" not in result.stderr and "Traceback" not in result.output
    assert _listing(tmp_path) == before


def test_warnings_are_one_line_each_after_a_successful_command(files_3, tmp_path):
    result = CliRunner().invoke(main, ["info", str(files_3 / "degenerate.svg")])
    assert result.exit_code == 0
    (line,) = result.stderr.splitlines()
    assert line.startswith("warning: ") and "dropped 1 degenerate subpath" in line and ".py" not in line


@pytest.mark.parametrize("ext, kind", [(".mp4", "ffmpeg"), (".gif", "File too large")])
def test_full_disk_keeps_the_old_output(files, tmp_path, ext, kind):
    """A writer that runs out of room (here: a file size limit) fails the run in one line; the old file stays."""
    import resource

    pytest.importorskip("imageio_ffmpeg")
    out = tmp_path / f"o{ext}"
    out.write_bytes(b"old output")
    before = _listing(tmp_path)
    src = str(Path(isotween.__file__).parents[1])
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (src, os.environ.get("PYTHONPATH")) if p))

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))

    proc = subprocess.run([sys.executable, "-m", "isotween", "interpolate", str(files / "e1.svg"),
                           str(files / "e2.svg"), "--resample", "40", "-q", "-o", str(out)],
                          capture_output=True, env=env, preexec_fn=limit, timeout=300)
    err = proc.stderr.decode()
    assert proc.returncode == 2, err
    (line,) = err.splitlines()
    assert line.startswith(f"error: cannot write {out}") and kind in line
    assert out.read_bytes() == b"old output" and _listing(tmp_path) == before


# ------------------------------------------------------------------ batch, round 3
@pytest.fixture
def pair(tmp_path):
    d = tmp_path / "jobs"
    d.mkdir()
    io.save(square(), d / "a.json")
    io.save(wide(), d / "b.json")
    return d


def _batch(manifest, outdir, *more):
    return CliRunner().invoke(main, ["batch", str(manifest), "-o", str(outdir), "-j", "1", "-q", *more])


def _failed(report):
    import json

    return {r["line"]: r["error"] for r in map(json.loads, open(report, encoding="utf-8")) if r["status"] == "failed"}


def test_batch_outputs_stay_inside_the_output_folder(pair, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (out / "link.npz").symlink_to(victim)
    (out / "dirlink").symlink_to(elsewhere)
    manifest = pair / "m.csv"
    manifest.write_text("source,target,output\n"
                        "a.json,b.json,../../../x.npz\n"
                        f"a.json,b.json,{tmp_path / 'abs.npz'}\n"
                        "a.json,b.json,dirlink/y.npz\n"
                        "a.json,b.json,link.npz\n"
                        "a.json,b.json,sub/ok.npz\n")
    before = _listing(tmp_path)
    result = _batch(manifest, out)
    assert result.exit_code == 1 and "jobs=5 done=1 skipped=0 failed=4" in result.stdout
    failed = _failed(out / "batch-report.jsonl")
    assert sorted(failed) == [2, 3, 4, 5]
    assert "'..' would leave the output folder" in failed[2] and "absolute path" in failed[3]
    assert "goes through the symbolic link" in failed[4] and "is the symbolic link" in failed[5]
    assert all(f"line {k}" in failed[k] for k in failed)
    assert victim.read_text() == "keep me" and list(elsewhere.iterdir()) == []
    assert sorted(set(_listing(tmp_path)) - set(before)) == ["out/batch-report.jsonl", "out/sub", "out/sub/ok.npz"]
    assert len(result.stderr.splitlines()) == 4


@pytest.mark.parametrize("rows, needle", [
    ("a.json,b.json,same.npz\na.json,b.json,same.npz\n", "line 3 and line 2 both write"),
    ("a.json,b.json,./same.npz\na.json,b.json,same.npz\n", "both write"),
    ("a.json,b.json,../jobs/b.json\n", None),  # outside the folder: that job fails alone
    ("a.json,b.json,b.json\n", "is an input of line 2"),
    ("a.json,b.json,x.npz\nx.npz,b.json,y.npz\n", "is an input of line 3"),
])
def test_batch_colliding_outputs_are_refused_before_anything_runs(pair, tmp_path, rows, needle):
    manifest = pair / "m.csv"
    manifest.write_text("source,target,output\n" + rows)
    if needle is None:  # the output folder is the inputs' folder here
        result = _batch(manifest, pair)
        assert result.exit_code == 1 and io.load(pair / "b.json").equals(wide())
        return
    before = _listing(tmp_path)
    result = _batch(manifest, pair)
    assert result.exit_code == 2 and result.stderr.count("\n") == 1 and needle in result.stderr, result.stderr
    assert _listing(tmp_path) == before and io.load(pair / "b.json").equals(wide())


def test_library_batch_refuses_colliding_jobs_and_records_malformed_ones(pair, tmp_path):
    jobs = [{"source": pair / "a.json", "target": pair / "b.json", "output": "o.npz"}] * 2
    with pytest.raises(FileFormatError, match="both write"):
        isotween.batch(jobs, outdir=tmp_path / "o1", workers=1)
    assert not (tmp_path / "o1").exists()
    bad = [{"source": 5, "target": pair / "b.json", "output": "a.npz"},
           {"source": pair / "a.json", "target": pair / "b.json", "output": 7},
           {"source": pair / "a.json", "target": pair / "b.json", "output": "c.npz", "options": ["frames", 3]},
           {"source": pair / "a.json", "target": pair / "b.json", "output": "d.npz", "options": {"frames": "many"}},
           {"source": pair / "a.json", "target": pair / "b.json", "output": "e\0.npz"},
           {"source": pair / "a.json", "target": pair / "b.json", "output": "ok.npz"}]
    res = isotween.batch(iter(bad), outdir=tmp_path / "o2", workers=1)
    assert (res["done"], res["failed"]) == (1, 5)
    errors = [r["error"] for r in res["failures"]]
    assert [e.split(":")[0] for e in errors] == ["ParameterError"] * 4 + ["FileFormatError"]
    assert "source must be a path" in errors[0] and "output must be a path" in errors[1]
    assert "options must be a dict" in errors[2] and "option frames has the wrong type" in errors[3]
    assert "NUL" in errors[4]


MANIFESTS = [
    ("nul-in-path", "m.csv", "source,target,output\na\0.json,b.json,x.npz\na.json,b.json,ok.npz\n", 1,
     "NUL byte"),
    ("jsonl-options-list", "m.jsonl", '{"source": "a.json", "target": "b.json", "output": "x.npz", "options": [1]}\n'
     '{"source": "a.json", "target": "b.json", "output": "ok.npz"}\n', 1, "options must be a JSON object"),
    ("jsonl-options-string", "m.jsonl", '{"source": "a.json", "target": "b.json", "output": "x.npz", '
     '"options": "fast"}\n{"source": "a.json", "target": "b.json", "output": "ok.npz"}\n', 1,
     "options must be a JSON object"),
    ("jsonl-not-json", "m.jsonl", '{"source": \n{"source": "a.json", "target": "b.json", "output": "ok.npz"}\n', 1,
     "not JSON"),
    ("jsonl-huge-int", "m.jsonl", '{"source": "a.json", "target": "b.json", "output": "x.npz", "frames": 1e999}\n'
     '{"source": "a.json", "target": "b.json", "output": "ok.npz"}\n', 1, "wrong type"),
    ("csv-extra-cells", "m.csv", "source,target,output\na.json,b.json,x.npz,9\na.json,b.json,ok.npz\n", 1,
     "more cells"),
    ("fifo-source", "m.csv", "source,target,output\nfifo.json,b.json,x.npz\na.json,b.json,ok.npz\n", 1, "pipe"),
    ("bom-csv", "m.csv", "\ufeffsource,target,output\na.json,b.json,ok.npz\n", 0, None),
]


@pytest.mark.parametrize("name, text, code, needle", [c[1:] for c in MANIFESTS], ids=[c[0] for c in MANIFESTS])
def test_batch_malformed_rows_fail_alone(pair, tmp_path, name, text, code, needle):
    os.mkfifo(pair / "fifo.json")
    (pair / name).write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    result = _batch(pair / name, out)
    assert result.exit_code == code, result.output
    assert (out / "ok.npz").is_file() and "Traceback" not in result.output
    if needle:
        (line,) = result.stderr.splitlines()
        assert line.startswith("failed: ") and needle in line
        assert "done=1" in result.stdout and "failed=1" in result.stdout
    assert sorted(p.name for p in out.iterdir()) == ["batch-report.jsonl", "ok.npz"]


@pytest.mark.parametrize("content, needle", [(b"source,target,output\n\xff\xfe,b,c\n", "UTF-8"),
                                             (b"\xef\xbb\xbfsource,target\n", "missing column(s) output")])
def test_batch_unreadable_manifest_is_one_line_and_leaves_nothing(pair, tmp_path, content, needle):
    (pair / "m.csv").write_bytes(content)
    result = _batch(pair / "m.csv", tmp_path / "out")
    assert result.exit_code == 2 and result.stderr.count("\n") == 1 and needle in result.stderr
    assert not (tmp_path / "out").exists()


def _long_batch(tmp_path):
    """A manifest of eight jobs that each run for minutes (a tolerance never met), and the command to run it."""
    d = tmp_path / "long"
    d.mkdir()
    io.save(Shape.from_polygon(ellipse_points(300, 1, 1)), d / "e1.json")
    io.save(Shape.from_polygon(ellipse_points(300, 2, 1)), d / "e2.json")
    (d / "m.csv").write_text("source,target,output,frames,tol,max_iter\n" + "".join(
        f"e1.json,e2.json,o{i}.npz,300,1e-14,100000\n" for i in range(8)))
    src = str(Path(isotween.__file__).parents[1])
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (src, os.environ.get("PYTHONPATH")) if p))
    cmd = [sys.executable, "-m", "isotween", "batch", str(d / "m.csv"), "-o", str(tmp_path / "out"), "-j", "2", "-q"]
    return cmd, env


def _children(pid):
    out = subprocess.run(["ps", "-o", "pid=", "--ppid", str(pid)], capture_output=True, text=True).stdout
    return [int(p) for p in out.split()]


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("how", ["ctrl-c", "ctrl-c-while-workers-start", "kill-9"])
def test_batch_workers_end_with_the_run(tmp_path, how):
    """Ctrl-C (to the whole process group) ends the run with one line; after kill -9 of the parent the workers end.

    Ctrl-C may come while the workers still import their kernels: they hold it until they ignore it.
    """
    cmd, env = _long_batch(tmp_path)
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                            preexec_fn=lambda: (signal.signal(signal.SIGINT, signal.SIG_DFL), os.setpgrp()))
    try:
        assert _wait_for(lambda: len(_children(proc.pid)) >= 2 or proc.poll() is not None, 120)
        workers = _children(proc.pid)
        if how != "ctrl-c-while-workers-start":
            time.sleep(1.0)  # the workers have started their jobs
        if how.startswith("ctrl-c"):
            os.killpg(proc.pid, signal.SIGINT)
        else:
            os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=60)
        assert _wait_for(lambda: not any(_alive(w) for w in workers), 60), "workers outlived the run"
        err = proc.stderr.read().decode()
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    if how.startswith("ctrl-c"):
        assert proc.returncode == 130
        assert err.splitlines() == ["error: interrupted; finished jobs are in the report, the others did not run"]
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["batch-report.jsonl"]


@pytest.mark.parametrize("ext", [".svg", ".html", ".lottie.json"])
def test_input_names_that_are_not_utf8_make_valid_titles(files, tmp_path, ext):
    """The default title holds the input names; bytes that are not UTF-8 become U+FFFD."""
    odd = files / os.fsdecode(b"sq\xff\x1b.json")
    odd.write_bytes((files / "sq.json").read_bytes())
    out = tmp_path / f"o{ext}"
    result = CliRunner().invoke(main, ["interpolate", str(odd), str(files / "wide.json"), "-q", "-o", str(out)])
    assert result.exit_code == 0, result.output
    text = out.read_text(encoding="utf-8")
    if ext == ".lottie.json":
        import json

        text = json.loads(text)["nm"]
    assert "sq\ufffd.json \u2192 wide.json" in text and "\x1b" not in text


def test_output_that_is_a_symbolic_link_replaces_the_link_not_its_target(files, tmp_path):
    victim = tmp_path / "victim.npz"
    victim.write_bytes(b"keep me")
    link = tmp_path / "o.npz"
    link.symlink_to(victim)
    result = CliRunner().invoke(main, ["interpolate", str(files / "sq.json"), str(files / "wide.json"), "-q",
                                       "-o", str(link)])
    assert result.exit_code == 0, result.output
    assert victim.read_bytes() == b"keep me" and not link.is_symlink() and len(io.load_sequence(link)) == 9


@pytest.mark.parametrize("chunk", [1, 7, 1 << 20])
def test_winding_numbers_match_the_dense_crossing_count(monkeypatch, chunk):
    """The sweep gives the dense test's numbers (points on vertices and edges included), whatever the chunk."""
    from isotween import geometry

    def dense(points, rings):
        a = np.vstack(rings)
        b = np.vstack([np.roll(r, -1, axis=0) for r in rings])
        owner = np.repeat(np.arange(len(rings)), [len(r) for r in rings])
        px, py = points[:, 0:1], points[:, 1:2]
        cross = (b[:, 0] - a[:, 0]) * (py - a[:, 1]) - (px - a[:, 0]) * (b[:, 1] - a[:, 1])
        w = ((a[:, 1] <= py) & (b[:, 1] > py) & (cross > 0)).astype(int) \
            - ((a[:, 1] > py) & (b[:, 1] <= py) & (cross < 0)).astype(int)
        return np.array([w[:, owner == r].sum(axis=1) for r in range(len(rings))]).T

    monkeypatch.setattr(geometry, "WINDING_CHUNK", chunk)
    rng = np.random.default_rng(3)
    for _ in range(60):
        rings = [np.round(rng.normal(size=(rng.integers(3, 9), 2)) * 3) / 2 for _ in range(rng.integers(1, 6))]
        points = np.vstack([np.round(rng.normal(size=(20, 2)) * 3) / 2, np.vstack(rings)[:4]])
        np.testing.assert_array_equal(geometry.winding_numbers(points, rings), dense(points, rings))


@pytest.mark.parametrize("signal_error, code", [("_Terminated", 143), ("KeyboardInterrupt", 130)])
def test_a_signal_inside_an_import_exits_as_that_signal(tmp_path, monkeypatch, signal_error, code):
    # Python wraps an exception raised while a class body is set up (a module being imported
    # when SIGTERM arrives) in a RuntimeError; the command still ends as the signal, in one line
    from isotween import cli

    def load(*args, **kwargs):
        try:
            raise getattr(cli, signal_error, KeyboardInterrupt)()
        except BaseException as exc:
            raise RuntimeError("Error calling __set_name__") from exc

    monkeypatch.setattr(isotween.io, "load", load)
    shape = tmp_path / "a.json"
    isotween.io.save(isotween.Shape.from_polygon([[0, 0], [1, 0], [0, 1]]), shape)
    result = CliRunner().invoke(cli.main, ["info", str(shape)])
    assert result.exit_code == code and "Traceback" not in result.output
