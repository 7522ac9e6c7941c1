"""Method 'convex' and the fold fallback of `isotween.interpolate`.

The Floater-Gotsman convex-combination morph: no in-between frame folds, the
ends are the inputs, and a folding AIAP result is replaced (by its refinement,
method 'injective': tests/test_injective.py).
"""

import sys
from pathlib import Path

import numpy as np
import pytest

import isotween
from isotween import Shape
from isotween.correspondence import correspond
from isotween.errors import MethodError
from isotween.metrics import flipped_faces, outline_crossings

ROOT = Path(__file__).resolve().parents[1]


def glyph(char):
    pytest.importorskip("matplotlib")
    sys.path.insert(0, str(ROOT / "scripts"))
    from build_examples import glyph as outline

    return Shape.from_polygon(outline(char))


def disc(n, r=1.0, centre=0j):
    z = centre + r * np.exp(2j * np.pi * np.arange(n) / n)
    return np.c_[z.real, z.imag]


def square():
    return Shape.from_polygon([[0, 0], [3, 0], [3, 3], [0, 3]])


def u_shape():
    return Shape.from_polygon([[0, 0], [3, 0], [3, 3], [2, 3], [2, 1], [1, 1], [1, 3], [0, 3]])


def ring_with_hole(centre, n=24):
    return Shape.from_polygon([disc(n, 2.0), disc(n - 8, 0.6, centre)[::-1]])


def pair(name):
    pytest.importorskip("shapely")
    a, b = {
        "W->T": lambda: (glyph("W"), glyph("T")),
        "square->U": lambda: (square(), u_shape()),
        "hole moves": lambda: (ring_with_hole(-1.0), ring_with_hole(1.0 + 0.2j, n=30)),
        "B->D": lambda: (glyph("B"), glyph("D")),
    }[name]()
    src, tgt, _ = correspond(a, b)
    assert src.n_faces > 0 and np.array_equal(src.faces, tgt.faces)
    return src, tgt


@pytest.mark.parametrize("name", ["W->T", "square->U", "hole moves", "B->D"])
def test_convex_never_folds_and_ends_are_the_inputs(name):
    src, tgt = pair(name)
    if name == "hole moves":
        assert [len(r) for r in src.regions] == [2]  # a region with a hole
    seq = isotween.interpolate(src, tgt, frames=9, method="convex")
    assert seq.method == "convex"
    assert flipped_faces(seq, None).tolist() == [0] * 9
    assert outline_crossings(seq, scope="region").tolist() == [0] * 9
    assert np.array_equal(seq.frames[0], src.vertices)  # bit for bit
    assert np.array_equal(seq.frames[-1], tgt.vertices)


def test_where_the_shared_weights_fold_aiap_with_relative_weights_does_not():
    src, tgt = pair("W->T")
    aiap = isotween.interpolate(src, tgt, frames=9)
    assert flipped_faces(aiap) > 0  # the premise: AIAP folds on this pair with the shared weights
    seq = isotween.interpolate(src, tgt, frames=9, fold="fallback")
    assert seq.method == "aiap" and "fallback" not in seq.info and "relative weights" in seq.info["weights"]
    assert flipped_faces(seq) == 0 and not outline_crossings(seq).any()
    # the frames are AIAP's own with those weights (stopped where the fold check stopped it), ends exact
    k = seq.info.get("stopped", {}).get("iteration", 100)
    own = isotween.interpolate(src, tgt, frames=9, assembly="relative", max_iter=k)
    np.testing.assert_array_equal(seq.frames, own.frames)
    assert np.array_equal(seq.frames[0], src.vertices) and np.array_equal(seq.frames[-1], tgt.vertices)


def test_folding_aiap_is_repaired_inside_its_scaffold(shared_only):
    src, tgt = pair("W->T")
    aiap = isotween.interpolate(src, tgt, frames=9)
    assert flipped_faces(aiap) > 0  # the premise: AIAP folds on this pair
    seq = isotween.interpolate(src, tgt, frames=9, fold="fallback")
    assert seq.method == "aiap" and "repaired" in seq.info["fallback"]
    assert flipped_faces(seq) == 0 and not outline_crossings(seq).any()
    assert np.array_equal(seq.frames[0], src.vertices) and np.array_equal(seq.frames[-1], tgt.vertices)


def test_folding_aiap_that_cannot_be_repaired_falls_back_to_the_injective_morph(monkeypatch, shared_only):
    from isotween.foldfree import repair

    monkeypatch.setattr(repair, "WORK", 0)  # every repair gives up at once
    src, tgt = pair("W->T")
    seq = isotween.interpolate(src, tgt, frames=9, fold="fallback")
    assert seq.method == "injective"
    assert "folded" in seq.info["fallback"] and "injective" in seq.info["fallback"]
    assert flipped_faces(seq) == 0 and not outline_crossings(seq, scope="region").any()
    assert np.array_equal(seq.frames[-1], tgt.vertices)


def test_rigid_pair_does_not_fall_back_and_convex_recovers_the_rigid_motion():
    src, _ = pair("square->U")
    tgt = src.rotate(2.0, origin=(1.0, 2.0)).translate([5.0, -3.0])
    seq = isotween.interpolate(src, tgt, frames=7, fold="fallback")
    assert seq.method == "aiap" and "fallback" not in seq.info
    convex = isotween.interpolate(src, tgt, frames=7, method="convex")
    # the rigid part is taken out first: every frame is a rotation about the centroid
    # by t * 2 rad, the centroid moving on a straight line (a known exact motion)
    cs, ct = src.z.mean(), tgt.z.mean()
    t = convex.times[:, None]
    expected = (src.z - cs) * np.exp(2j * t) + cs + t * (ct - cs)
    assert np.abs(convex.z - expected).max() < 1e-9 * src.bbox_diagonal()


def test_convex_cannot_be_built_keeps_the_first_result_and_says_why():
    # a square with a centre vertex pushed out of it: the target mesh itself folds
    v = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1, 1]], float)
    faces = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    src = Shape.from_mesh(v, faces)
    w = v.copy()
    w[4] = [3.0, 1.0]
    tgt = Shape.from_mesh(w, faces)
    seq = isotween.interpolate(src, tgt, frames=9, fold="fallback")
    assert seq.method == "aiap"
    assert "kept" in seq.info["fallback"] and "flipped against the source" in seq.info["fallback"]
    assert "injective" in seq.info["fallback"] and "convex" in seq.info["fallback"]


def test_bad_input_raises_method_error():
    line = Shape.from_polyline([[0, 0], [1, 0], [2, 1]])
    with pytest.raises(MethodError, match="solid regions"):
        isotween.interpolate(line, line.translate([1, 0]), method="convex")
    # a mesh plus a loose polyline vertex
    v = np.array([[0, 0], [1, 0], [0, 1], [3, 3]], float)
    mesh = Shape(v, edges=[[0, 1], [1, 2], [2, 0], [2, 3]], faces=[[0, 1, 2]])
    with pytest.raises(MethodError, match="vertex 3"):
        isotween.interpolate(mesh, mesh.translate([1, 0]), method="convex")
    with pytest.raises(isotween.errors.ParameterError, match="fold"):
        isotween.interpolate(mesh, mesh, fold="never")


def test_cli_falls_back_and_says_so(tmp_path, shared_only):
    pytest.importorskip("shapely")
    from click.testing import CliRunner

    from isotween.cli import main

    def svg(shape, name):
        d = " ".join("M " + " L ".join(f"{x:.4f} {-y:.4f}" for x, y in shape.vertices[p]) + " Z"
                     for p, _ in shape.paths)
        path = tmp_path / name
        path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg"><path fill="black" d="{d}"/></svg>')
        return str(path)

    out = tmp_path / "out.npz"
    result = CliRunner().invoke(main, ["interpolate", svg(glyph("W"), "w.svg"), svg(glyph("T"), "t.svg"),
                                       "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "fold check" in result.output and "repaired with no flip" in result.output
    seq = isotween.io.load_sequence(str(out))
    assert seq.method == "aiap" and flipped_faces(seq) == 0


def test_components_move_independently():
    src, tgt = pair("square->U")
    n = src.n_vertices

    def two(a, b):
        return Shape(np.r_[a.vertices, b.vertices], faces=np.r_[a.faces, b.faces + n])

    moved_src, moved_tgt = src.translate([10.0, 0.0]), tgt.rotate(1.0).translate([10.0, 4.0])
    both = isotween.interpolate(two(src, moved_src), two(tgt, moved_tgt), frames=5, method="convex")
    alone = [isotween.interpolate(s, t, frames=5, method="convex").frames for s, t in
             ((src, tgt), (moved_src, moved_tgt))]
    assert len(both.info["components"]) == 2
    np.testing.assert_allclose(both.frames, np.concatenate(alone, axis=1), rtol=0, atol=1e-12 * 20)
