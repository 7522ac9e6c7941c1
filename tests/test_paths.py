"""Path strings at any time: svgelements reads them back to the frame within the curve tolerance."""

import numpy as np
import pytest
import svgelements

import isotween
from isotween.errors import ParameterError
from isotween.examples import load_example
from isotween.outputs import with_paint
from isotween.render.curves import TOLERANCE
from test_curves import polyline_distance


@pytest.fixture(scope="module")
def holes():
    source, target, options = load_example("holes")
    options.pop("texture", None)
    return with_paint(isotween.interpolate(source, target, **options), fill=("red", "blue"), stroke="black")


@pytest.fixture(scope="module")
def curls():
    source, target, options = load_example("curls")
    return isotween.interpolate(source, target, **options)


def parsed_points(d, per_segment=400):
    """(m, 2) points sampled along every drawn segment of a path string."""
    u = np.linspace(0.0, 1.0, per_segment)
    out = [np.array(seg.npoint(u)) for seg in svgelements.Path(d).segments() if not isinstance(seg, svgelements.Move)]
    return np.concatenate(out)


def frame_runs(seq, t, group):
    """Polylines (k, 2) of a group's runs at time t, y down."""
    xy = seq.at(t).vertices.copy()
    if not seq.shape.y_down:
        xy[:, 1] *= -1
    return [xy[np.append(idx, idx[0]) if closed else idx] for idx, closed in group]


@pytest.mark.parametrize("name", ["holes", "curls"])
@pytest.mark.parametrize("curves", [True, False])
def test_path_strings_read_back_to_the_frame_at_any_time(request, name, curves):
    seq = request.getfixturevalue(name)
    diag = np.hypot(*np.ptp(seq.frames.reshape(-1, 2), axis=0))
    tol = TOLERANCE * diag
    from isotween.render.paths import PathData

    groups = PathData(seq).groups
    rng = np.random.default_rng(7)
    for t in [0.0, 1.0, *rng.uniform(0, 1, 4)]:
        strings = seq.path_data(float(t), curves=curves)
        assert len(strings) == len(groups)
        for d, group in zip(strings, groups, strict=True):
            points = parsed_points(d)
            runs = frame_runs(seq, float(t), group)
            # every point of the curves lies near the frame's outline ...
            near = np.min([polyline_distance(points[None], r[None])[0] for r in runs], axis=0)
            assert near.max() <= 1.5 * tol, (t, near.max() / diag)
            # ... and every vertex of the outline near the curves
            vertices = np.concatenate(runs)
            gap = np.linalg.norm(vertices[:, None] - points[None], axis=-1).min(axis=1)
            assert gap.max() <= 1.5 * tol, (t, gap.max() / diag)
        if curves:
            assert sum(d.count("C") + d.count("L") for d in strings) < seq.shape.n_vertices / 2


@pytest.mark.parametrize("name", ["holes", "curls"])
@pytest.mark.parametrize("curves", [True, False])
def test_relative_strings_read_back_as_the_absolute_ones(request, name, curves):
    # what the animated SVG and CSS write: m between subpaths, a command letter only where it changes
    seq = request.getfixturevalue(name)
    from isotween.render.outline import edge_chains
    from isotween.render.paths import PathData, RunStrings, polylines, svg_frames

    relative = PathData(seq, curves=curves, precision=3, relative=True)
    absolute = PathData(seq, curves=curves, precision=3)
    for t in (0.0, 0.37, 1.0):
        for r, a in zip(relative(t), absolute(t), strict=True):
            assert r[0] == "M" and r.count("m") >= a.count("M") - 1
            np.testing.assert_allclose(parsed_points(r, 5), parsed_points(a, 5), atol=2e-3)
    # open chains of edges (the wireframe of the animated SVG)
    chains = polylines([(w, False) for w in edge_chains(seq.shape.edges)])
    frames = svg_frames(seq)[[0, -1]]
    for r, a in zip(RunStrings(chains, 2, relative=True).strings(frames), RunStrings(chains, 2).strings(frames),
                    strict=True):
        np.testing.assert_allclose(parsed_points(r, 3), parsed_points(a, 3), atol=2e-2)


def test_the_same_commands_at_every_time(curls):
    letters = [[("".join(c for c in d if c.isalpha())) for d in curls.path_data(t)] for t in (0.0, 0.37, 1.0)]
    assert letters[0] == letters[1] == letters[2]


def test_to_svg_reads_back_as_the_shape_with_its_paint(holes, tmp_path):
    t = 0.5
    assert holes.to_svg(t, background="white").count("<rect") == 1
    text = holes.to_svg(t)
    path = tmp_path / "mid.svg"
    path.write_text(text)
    back = isotween.io.load(path)
    # the paint at t = 0.5 is the Oklab blend of red and blue; the outline within the tolerance
    from isotween.paint import sequence_paint

    assert back.paint is not None and len(back.paint) >= len(holes.shape.paths)
    mid = holes.resample(times=[0.0, 0.5, 1.0])
    want = sequence_paint(mid)[1][1][0].fill
    np.testing.assert_allclose(back.paint[0].fill[:3], want[:3], atol=1 / 255)
    diag = np.hypot(*np.ptp(holes.frames.reshape(-1, 2), axis=0))
    [ring] = frame_runs(holes, t, [holes.shape.paths[0]])  # y down, as SVG is read
    got = back.vertices[back.paths[0][0]]
    assert polyline_distance(got[None], ring[None]).max() <= 1.5 * TOLERANCE * diag


def test_bad_precision_and_time_are_parameter_errors(curls):
    with pytest.raises(ParameterError, match="precision"):
        curls.path_data(0.5, precision=-1)
    with pytest.raises(ParameterError, match="outside"):
        curls.path_data(1.5)
