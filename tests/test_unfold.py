"""AIAP solved again with edges flipped where a few faces fold: the paper's method, on other triangles."""

import sys

import numpy as np
import pytest

import isotween
from isotween import metrics
from isotween.foldfree.unfold import MOST, folding, unfold
from isotween.interpolate import interpolate
from isotween.pipeline import prepare_pair

T = [[0, 3], [0, 4], [4, 4], [4, 3], [2.5, 3], [2.5, 0], [1.5, 0], [1.5, 3]]
ARROW = [[0, 1], [3, 1], [3, 0], [5, 1.5], [3, 3], [3, 2], [0, 2]]
Z = [[0, 3], [3, 3], [3, 2.4], [0.9, 0.6], [3, 0.6], [3, 0], [0, 0], [0, 0.6], [2.1, 2.4], [0, 2.4]]
TURN = np.linspace(0, 2 * np.pi, 60, endpoint=False)
HEART = np.c_[16 * np.sin(TURN) ** 3, 13 * np.cos(TURN) - 5 * np.cos(2 * TURN) - 2 * np.cos(3 * TURN)
              - np.cos(4 * TURN)] / 8


def drawing(path, ring):
    d = "M" + " L".join(f"{x:.4f} {-y:.4f}" for x, y in np.asarray(ring, float)) + " Z"
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg"><path d="{d}"/></svg>')
    return path


def pair(tmp_path, a, b):
    prepared = prepare_pair(drawing(tmp_path / "a.svg", a), drawing(tmp_path / "b.svg", b))
    return prepared.source, prepared.target


@pytest.fixture
def to_the_end(monkeypatch):
    """AIAP's iterations run to the end with the fold check too.

    Stopped before the first fold, T -> ARROW does not fold, and nothing is left to unfold.
    """
    monkeypatch.setattr(sys.modules["isotween.interpolate"], "_unfolded", lambda shape: lambda z: False)


def test_aiap_stops_before_the_first_iteration_that_folds(tmp_path):
    source, target = pair(tmp_path, T, ARROW)
    converged = interpolate(source, target, frames=21, fold="allow")
    assert metrics.flipped_faces(converged) > 0  # run to the end, AIAP folds a few faces
    seq = interpolate(source, target, frames=21, fold="fallback")
    k = seq.info["stopped"]["iteration"]
    assert seq.method == "aiap" and "fallback" not in seq.info and 1 <= k < seq.info["stopped"]["of"]
    assert metrics.flipped_faces(seq) == 0 and not any(metrics.outline_crossings(seq))
    # the frames are the solver's own k-th iterate, ends exact
    np.testing.assert_array_equal(seq.frames, interpolate(source, target, frames=21, fold="allow", max_iter=k).frames)
    np.testing.assert_array_equal(seq.frames[-1], target.vertices)


def test_a_t_becomes_an_arrow_by_aiap_on_flipped_edges(tmp_path, to_the_end):
    source, target = pair(tmp_path, T, ARROW)
    folded = interpolate(source, target, frames=21, fold="allow")
    assert 0 < len(folding(folded)) <= MOST  # the correspondence's meshes fold a few faces in AIAP's in-betweens
    seq = interpolate(source, target, frames=21, fold="fallback")
    assert "fallback" not in seq.info and "unfolded" in seq.info
    assert metrics.flipped_faces(seq) == 0
    # AIAP's own frames on the new triangles, with the same vertices, outline and ends
    same = interpolate(source.with_faces(seq.shape.faces), target.with_faces(seq.shape.faces), frames=21,
                       fold="allow")
    np.testing.assert_array_equal(same.frames, seq.frames)
    np.testing.assert_array_equal(seq.frames[0], source.vertices)
    np.testing.assert_array_equal(seq.frames[-1], target.vertices)
    assert seq.shape.paths[0][0].tolist() == source.paths[0][0].tolist()
    keys = [set(map(tuple, np.sort(s.faces, axis=1).tolist())) for s in (source, seq.shape)]
    assert 0 < len(keys[0] - keys[1]) <= 2 * MOST  # a few faces changed, the rest of the mesh kept
    assert np.all(seq.shape.face_areas(seq.frames[-1]) > 0)


def test_morph_and_the_command_line_say_where_edges_were_flipped(tmp_path, to_the_end):
    from click.testing import CliRunner

    from isotween.cli import main

    a, b = drawing(tmp_path / "a.svg", T), drawing(tmp_path / "b.svg", ARROW)
    seq = isotween.morph(a, b, frames=21)
    assert "fallback" not in seq.info and seq.info["unfolded"].startswith("aiap folded")
    out = tmp_path / "out.npz"
    result = CliRunner().invoke(main, ["interpolate", str(a), str(b), "--frames", "21", "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert f"fold check: {seq.info['unfolded']}" in result.output and "repaired" not in result.output
    saved = isotween.io.load_sequence(str(out))
    assert saved.method == "aiap" and metrics.flipped_faces(saved) == 0


@pytest.mark.parametrize("a, b", [(Z, HEART), (T, ARROW)])
def test_unfolding_never_folds_more(tmp_path, a, b):
    source, target = pair(tmp_path, a, b)
    seq = interpolate(source, target, frames=21, fold="allow")
    tried = []

    def solve(faces):
        tried.append(faces)
        return interpolate(source.with_faces(faces), target.with_faces(faces), frames=21, fold="allow")

    out = unfold(seq, solve)
    assert len(folding(out)) <= len(folding(seq))
    assert (out is seq) == (len(folding(out)) == len(folding(seq)))
    assert tried  # edges were flipped and AIAP solved again


@pytest.mark.parametrize("last_clean", [1, 2, 6, 19])
def test_the_fold_check_finds_the_most_iterations_whose_outlines_do_not_cross(last_clean):
    from types import SimpleNamespace

    from isotween.interpolate import _fewer_iterations

    calls = []

    def fewer(j):  # AIAP stopped after j iterations: its outlines cross from iteration last_clean + 1 on
        calls.append(j)
        return SimpleNamespace(iterations=j, info={}, crossing=j > last_clean)

    seq = _fewer_iterations(20, fewer, lambda s: not s.crossing)
    assert seq.iterations == last_clean and seq.info["stopped"] == {
        "iteration": last_clean, "of": last_clean + 1, "why": "outlines cross"}
    assert len(calls) <= 1 + int(np.ceil(np.log2(20)))  # a bisection, not a walk through every count
    assert _fewer_iterations(20, fewer, lambda s: False) is None  # where the first crosses: nothing


# Bootstrap Icons (MIT licence, The Bootstrap Authors): truck-front-fill and cloud-lightning-fill
TRUCK = ("M3.5 0A2.5 2.5 0 0 0 1 2.5v9c0 .818.393 1.544 1 2v2a.5.5 0 0 0 .5.5h2a.5.5 0 0 0 .5-.5V14h6v1.5a.5.5 0 0 0 "
         ".5.5h2a.5.5 0 0 0 .5-.5v-2c.607-.456 1-1.182 1-2v-9A2.5 2.5 0 0 0 12.5 0zM3 3a1 1 0 0 1 1-1h8a1 1 0 0 1 1 "
         "1v3.9c0 .625-.562 1.092-1.17.994C10.925 7.747 9.208 7.5 8 7.5s-2.925.247-3.83.394A1.008 1.008 0 0 1 3 "
         "6.9zm1 9a1 1 0 1 1 0-2 1 1 0 0 1 0 2m8 0a1 1 0 1 1 0-2 1 1 0 0 1 0 2m-5-2h2a1 1 0 1 1 0 2H7a1 1 0 1 1 0-2")
CLOUD = ("M7.053 11.276A.5.5 0 0 1 7.5 11h1a.5.5 0 0 1 .474.658l-.28.842H9.5a.5.5 0 0 1 .39.812l-2 2.5a.5.5 0 0 "
         "1-.875-.433L7.36 14H6.5a.5.5 0 0 1-.447-.724zm6.352-7.249a5.001 5.001 0 0 0-9.499-1.004A3.5 3.5 0 1 0 3.5 "
         "10H13a3 3 0 0 0 .405-5.973")


def test_where_the_first_iteration_folds_edges_are_flipped_there_and_aiap_stops_before_a_fold(tmp_path):
    from isotween.pipeline import STAGGER, unmatched_spans

    files = []
    for name, d in (("truck", TRUCK), ("cloud", CLOUD)):
        files.append(tmp_path / f"{name}.svg")
        files[-1].write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16"><path d="{d}"/></svg>')
    prepared = prepare_pair(*files)
    source, target = prepared.source, prepared.target
    spans = unmatched_spans(source, prepared.report, STAGGER)  # the lightning comes in late, as `morph` has it
    first = interpolate(source, target, frames=21, fold="allow", max_iter=1, spans=spans)
    assert 0 < len(folding(first)) <= MOST  # the assembled initialisation folds a few faces already
    seq = interpolate(source, target, frames=21, fold="fallback", spans=spans)
    assert seq.method == "aiap" and "fallback" not in seq.info and "unfolded" in seq.info
    assert metrics.flipped_faces(seq) == 0
    # AIAP's own k-th iterate on the flipped faces (the same vertices and ends)
    k = seq.info["stopped"]["iteration"]
    own = interpolate(source.with_faces(seq.shape.faces), target.with_faces(seq.shape.faces), frames=21,
                      fold="allow", max_iter=k, spans=spans)
    np.testing.assert_array_equal(own.frames, seq.frames)
    np.testing.assert_array_equal(seq.frames[-1], target.vertices)


# DejaVu Sans 'N' and DejaVu Serif 'J' (Bitstream Vera licence), as matplotlib writes their outlines
SANS_N = ("M 9.812 -72.906 L 23.094 -72.906 L 55.422 -11.922 L 55.422 -72.906 L 64.984 -72.906 L 64.984 -0.000 "
          "L 51.703 -0.000 L 19.391 -60.984 L 19.391 -0.000 L 9.812 -0.000 L 9.812 -72.906 Z")
SERIF_J = ("M -8.406 17.484 L -8.406 6.000 L -2.828 6.000 Q -2.688 10.844 -0.531 13.203 Q 1.609 15.578 5.906 15.578 "
           "Q 11.719 15.578 14.016 11.906 Q 16.312 8.250 16.312 -2.391 L 16.312 -67.672 L 4.984 -67.672 "
           "L 4.984 -72.906 L 35.500 -72.906 L 35.500 -67.672 L 26.219 -67.672 L 26.219 -2.000 "
           "Q 26.219 10.062 21.375 15.422 Q 16.547 20.797 5.812 20.797 Q 2.344 20.797 -1.234 19.969 "
           "Q -4.828 19.141 -8.406 17.484 Z")


def test_where_aiap_on_flipped_edges_lets_outlines_cross_it_stops_at_the_most_iterations_that_do_not(tmp_path):
    files = []
    for name, d in (("n", SANS_N), ("j", SERIF_J)):
        files.append(tmp_path / f"{name}.svg")
        files[-1].write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="-10 -110 120 140">'
                             f'<path d="{d}"/></svg>')
    prepared = prepare_pair(*files)
    source, target = prepared.source, prepared.target
    first = interpolate(source, target, frames=21, fold="allow", max_iter=1)
    assert 0 < len(folding(first)) <= MOST  # the initialisation folds a few faces
    seq = interpolate(source, target, frames=21, fold="fallback")
    assert seq.method == "aiap" and "fallback" not in seq.info and "unfolded" in seq.info
    assert seq.info["stopped"]["why"] == "outlines cross"
    assert metrics.flipped_faces(seq) == 0 and metrics.outline_crossings(seq).sum() == 0
    # one iteration more, on the same triangles, lets the outline cross itself
    k = seq.info["stopped"]["iteration"]
    more = interpolate(source.with_faces(seq.shape.faces), target.with_faces(seq.shape.faces), frames=21,
                       fold="allow", max_iter=k + 1)
    assert metrics.outline_crossings(more).sum() > 0
    own = interpolate(source.with_faces(seq.shape.faces), target.with_faces(seq.shape.faces), frames=21,
                      fold="allow", max_iter=k)
    np.testing.assert_array_equal(own.frames, seq.frames)
