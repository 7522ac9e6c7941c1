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
    monkeypatch.setattr(sys.modules["isotween.interpolate"], "_flips", lambda shape: lambda z: 1)


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


def test_a_t_becomes_an_arrow_by_aiap_on_flipped_edges(tmp_path, to_the_end, uniform_meshes):
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


def test_morph_and_the_command_line_say_where_edges_were_flipped(tmp_path, to_the_end, uniform_meshes):
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


def test_where_the_first_iteration_folds_edges_are_flipped_there_and_aiap_stops_before_a_fold(tmp_path, uniform_meshes):
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


# DejaVu Sans 'M' and DejaVu Serif 'h' (Bitstream Vera licence), as matplotlib writes their outlines
SANS_M = ("M 9.812 -72.906 L 24.516 -72.906 L 43.109 -23.297 L 61.812 -72.906 L 76.516 -72.906 L 76.516 -0.000 "
          "L 66.891 -0.000 L 66.891 -64.016 L 48.094 -14.016 L 38.188 -14.016 L 19.391 -64.016 L 19.391 -0.000 "
          "L 9.812 -0.000 L 9.812 -72.906 Z")
SERIF_H = ("M 4.109 -0.000 L 4.109 -5.172 L 12.203 -5.172 L 12.203 -70.797 L 3.609 -70.797 L 3.609 -75.984 "
           "L 21.188 -75.984 L 21.188 -42.672 Q 23.688 -47.953 27.656 -50.641 Q 31.641 -53.328 36.922 -53.328 "
           "Q 45.516 -53.328 49.562 -48.391 Q 53.609 -43.453 53.609 -33.016 L 53.609 -5.172 L 61.625 -5.172 "
           "L 61.625 -0.000 L 36.812 -0.000 L 36.812 -5.172 L 44.578 -5.172 L 44.578 -30.172 Q 44.578 -39.703 "
           "42.250 -43.188 Q 39.938 -46.688 33.984 -46.688 Q 27.734 -46.688 24.453 -42.141 Q 21.188 -37.594 "
           "21.188 -28.906 L 21.188 -5.172 L 29.000 -5.172 L 29.000 -0.000 L 4.109 -0.000 Z")


def glyphs(tmp_path, a, b):
    """The compatible pair `prepare_pair` makes of two glyph outlines (SVG path data, matplotlib's em box)."""
    files = [tmp_path / "a.svg", tmp_path / "b.svg"]
    for file, d in zip(files, (a, b), strict=True):
        file.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="-10 -110 120 140"><path d="{d}"/></svg>')
    prepared = prepare_pair(*files)
    return prepared.source, prepared.target


def test_where_aiap_on_flipped_edges_lets_outlines_cross_it_stops_at_the_most_iterations_that_do_not(tmp_path,
                                                                                                    monkeypatch):
    # the pair's meshes as the overlay makes them (pulled with flips on the way, the initialisation folds nothing)
    monkeypatch.setattr(sys.modules["isotween.correspondence.compatible_mesh"], "PULL_RETRY", -1.0)
    source, target = glyphs(tmp_path, SANS_M, SERIF_H)
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


# DejaVu Sans '2' and '3' (Bitstream Vera licence), as matplotlib writes their outlines
SANS_2 = ("M 19.188 -8.297 L 53.609 -8.297 L 53.609 -0.000 L 7.328 -0.000 L 7.328 -8.297 Q 12.938 -14.109 22.625 "
          "-23.891 Q 32.328 -33.688 34.812 -36.531 Q 39.547 -41.844 41.422 -45.531 Q 43.312 -49.219 43.312 -52.781 "
          "Q 43.312 -58.594 39.234 -62.250 Q 35.156 -65.922 28.609 -65.922 Q 23.969 -65.922 18.812 -64.312 Q 13.672 "
          "-62.703 7.812 -59.422 L 7.812 -69.391 Q 13.766 -71.781 18.938 -73.000 Q 24.125 -74.219 28.422 -74.219 "
          "Q 39.750 -74.219 46.484 -68.547 Q 53.219 -62.891 53.219 -53.422 Q 53.219 -48.922 51.531 -44.891 Q 49.859 "
          "-40.875 45.406 -35.406 Q 44.188 -33.984 37.641 -27.219 Q 31.109 -20.453 19.188 -8.297 Z")
SANS_3 = ("M 40.578 -39.312 Q 47.656 -37.797 51.625 -33.000 Q 55.609 -28.219 55.609 -21.188 Q 55.609 -10.406 48.188 "
          "-4.484 Q 40.766 1.422 27.094 1.422 Q 22.516 1.422 17.656 0.516 Q 12.797 -0.391 7.625 -2.203 L 7.625 "
          "-11.719 Q 11.719 -9.328 16.594 -8.109 Q 21.484 -6.891 26.812 -6.891 Q 36.078 -6.891 40.938 -10.547 Q "
          "45.797 -14.203 45.797 -21.188 Q 45.797 -27.641 41.281 -31.266 Q 36.766 -34.906 28.719 -34.906 L 20.219 "
          "-34.906 L 20.219 -43.016 L 29.109 -43.016 Q 36.375 -43.016 40.234 -45.922 Q 44.094 -48.828 44.094 -54.297 "
          "Q 44.094 -59.906 40.109 -62.906 Q 36.141 -65.922 28.719 -65.922 Q 24.656 -65.922 20.016 -65.031 Q 15.375 "
          "-64.156 9.812 -62.312 L 9.812 -71.094 Q 15.438 -72.656 20.344 -73.438 Q 25.250 -74.219 29.594 -74.219 Q "
          "40.828 -74.219 47.359 -69.109 Q 53.906 -64.016 53.906 -55.328 Q 53.906 -49.266 50.438 -45.094 Q 46.969 "
          "-40.922 40.578 -39.312 Z")


def test_where_later_iterations_fold_more_than_the_first_the_first_is_repaired(tmp_path, shared_only):
    source, target = glyphs(tmp_path, SANS_2, SANS_3)
    first = interpolate(source, target, frames=21, fold="allow", max_iter=1)
    last = interpolate(source, target, frames=21, fold="allow")
    assert 0 < len(folding(first)) < len(folding(last))  # the iterations fold more faces than the first
    seq = interpolate(source, target, frames=21, fold="fallback")
    assert seq.method == "aiap" and "folded at iteration 1 of " in seq.info["fallback"]
    assert metrics.flipped_faces(seq) == 0
    np.testing.assert_array_equal(seq.frames[0], source.vertices)
    np.testing.assert_array_equal(seq.frames[-1], target.vertices)
    # the frames the repair left alone are AIAP's first iteration on the same triangles, bit for bit
    own = interpolate(source.with_faces(seq.shape.faces), target.with_faces(seq.shape.faces), frames=21,
                      fold="allow", max_iter=1)
    kept = np.setdiff1d(np.arange(21), seq.info["repair"]["frames"])
    assert 0 < len(kept) < 21
    np.testing.assert_array_equal(seq.frames[kept], own.frames[kept])
    # and the repaired frames stay within 2 % of the diagonal of its own (those of the last iteration: 4.9 %)
    assert seq.info["repair"]["deviation"] < 0.02 * source.bbox_diagonal()


def test_where_the_first_iteration_folds_the_iterations_stop_once_the_folds_spread(tmp_path):
    from isotween.interpolate import _flips
    from isotween.optimisation.local_solver import GROW
    from isotween.optimisation.problem import DEFAULT_TOL
    from isotween.optimisation.solve import solve
    from isotween.problems import keyed_problem

    source, target = glyphs(tmp_path, SANS_2, SANS_3)
    count = _flips(source)

    def run(j):  # j iterations on their own: the first j iterations of any longer run, (21, n) complex
        return interpolate(source, target, frames=21, fold="allow", max_iter=j).frames.view(complex)[..., 0]

    first = count(run(1).T)
    assert first > 0  # the first iteration folds
    spread, now = next((j, n) for j in range(2, 40) if (n := count(run(j).T)) > GROW * first)  # and the folds spread
    problem = keyed_problem([source, target], np.linspace(0, 1, 21), np.array([0, 20]), init="edge",
                            scheme="midpoint", tol=DEFAULT_TOL, max_iter=100)
    result = solve(problem, folds=count)
    assert result.info["spread"] == {"iteration": spread, "first": first, "now": now}
    assert result.iterations == len(result.energy) == spread and not result.converged
    np.testing.assert_allclose(result.z.T, run(spread))
