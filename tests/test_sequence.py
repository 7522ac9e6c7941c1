"""Sequence as a container: indexing, equality, shape at any time, output."""

import copy
import html.parser
import json
import re

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from isotween import Sequence, Shape, interpolate, load_sequence, metrics  # noqa: E402
from isotween.errors import FileFormatError, ParameterError  # noqa: E402
from shapes import chain, ellipse  # noqa: E402


@pytest.fixture(scope="module")
def curl():
    """A real AIAP sequence with uneven times: a chain curling by 0.9 turns."""
    a, b = chain(30, 0.9)
    times = np.array([0.0, 0.1, 0.25, 0.5, 0.6, 0.8, 1.0])
    return interpolate(a, b, frames=len(times), times=times)


def test_slices_keep_frames_times_and_metadata(curl):
    part = curl[2:5]
    assert isinstance(part, Sequence)
    assert np.array_equal(part.frames, curl.frames[2:5])
    assert np.array_equal(part.times, curl.times[2:5])
    assert (part.method, part.scheme, part.iterations, part.converged) == (
        curl.method, curl.scheme, curl.iterations, curl.converged)
    assert part.energy == curl.energy and part.shape is curl.shape
    every_other = curl[::2]
    assert np.array_equal(every_other.times, curl.times[::2])
    picked = curl[[0, -1]]
    assert np.array_equal(picked.frames, curl.frames[[0, -1]])
    assert np.array_equal(curl[curl.times > 0.5].times, curl.times[curl.times > 0.5])
    part.frames[0, 0, 0] += 1.0  # a slice owns its frames
    assert curl.frames[2, 0, 0] != part.frames[0, 0, 0]


def test_slices_keep_y_down():
    s = Shape.from_polygon([[0, 0], [1, 0], [0, 1]])
    s = Shape(s.vertices, s.edges, paths=s.paths, y_down=True)
    seq = interpolate(s, s.rotate(0.5), frames=4)
    assert seq.y_down and seq[1:3].y_down and seq[1].y_down


def test_metrics_of_a_slice_blend_between_its_own_ends(curl):
    part = curl[2:6]
    span = (part.times - part.times[0]) / (part.times[-1] - part.times[0])
    same = Sequence(part.frames, part.shape, times=span)
    for metric in (metrics.edge_length_deviation, metrics.area_deviation):
        assert np.array_equal(metric(part, reduce=None), metric(same, reduce=None))
    assert metrics.edge_length_deviation(part, reduce=None)[[0, -1]].tolist() == [0.0, 0.0]


def test_integer_indices_iteration_and_array(curl):
    n = len(curl)
    assert n == 7
    assert np.array_equal(curl[-1].vertices, curl.frames[n - 1])
    assert np.array_equal(curl[-n].vertices, curl.frames[0])
    assert [s.vertices.tolist() for s in curl] == curl.frames.tolist()
    arr = np.asarray(curl)
    assert arr.shape == (n, 30, 2) and arr.dtype == np.float64
    assert np.array_equal(np.asarray(curl, dtype=np.float32), curl.frames.astype(np.float32))
    for bad in (n, -n - 1):
        with pytest.raises(IndexError):
            curl[bad]
    with pytest.raises(IndexError):
        curl[np.array([True, False])]


def test_equality_is_explicit_and_never_raises(curl):
    twin = copy.deepcopy(curl)
    assert curl.equals(twin) and twin.equals(curl)
    assert (curl == twin) is False and (curl == curl) is True  # == is identity
    assert curl != twin
    assert not curl.equals(curl[:-1])
    assert not curl.equals(curl.frames) and not curl.equals(None)
    nudged = copy.deepcopy(curl)
    nudged.frames[3, 4, 1] += 1e-9
    assert not curl.equals(nudged) and curl.equals(nudged, atol=1e-8)
    other_times = copy.deepcopy(curl)
    other_times.times[3] += 1e-3
    assert not curl.equals(other_times)
    assert len({curl, twin}) == 2  # hashed by identity, consistently with ==
    assert (curl == curl.frames) is False and (curl.frames == curl) is False  # never elementwise


def test_copies_and_pickles_after_at(curl):
    import pickle

    curl.at(0.3)
    assert pickle.loads(pickle.dumps(curl)).equals(curl) and copy.deepcopy(curl).equals(curl)


def test_at_is_exact_at_the_frames(curl, two_components):
    for k, t in enumerate(curl.times):
        assert np.array_equal(curl.at(t).vertices, curl.frames[k])
    soup = interpolate(two_components, two_components.rotate(2.0).translate([1, 3]), frames=6)
    for k, t in enumerate(soup.times):
        assert np.array_equal(soup.at(t).vertices, soup.frames[k])
    # each component's centroid moves linearly between the frames
    t = 0.5 * (soup.times[2] + soup.times[3])
    c = soup.shape.components
    mid = soup.at(t).vertices
    for label in range(soup.shape.n_components):
        ends = soup.frames[2:4, c == label].mean(axis=1)
        assert np.allclose(mid[c == label].mean(axis=0), ends.mean(axis=0), atol=1e-12)


def test_at_is_continuous_between_frames(curl):
    # a Lipschitz bound: moving t by d moves no vertex by more than C d, on both
    # sides of every interior frame and inside the intervals
    size = np.ptp(curl.frames.reshape(-1, 2), axis=0).max()
    for t in list(curl.times[1:-1]) + [0.05, 0.37, 0.9]:
        here = curl.at(t).vertices
        for d in (1e-3, 1e-5, 1e-7):
            for side in (-d, d):
                step = np.abs(curl.at(t + side).vertices - here).max()
                assert step <= 50 * size * d, (t, side, step)


def test_at_recovers_a_rigid_rotation_at_any_time(rigid_motion):
    shape = ellipse(24)
    times = np.array([0.0, 0.15, 0.5, 0.7, 1.0])
    seq = Sequence(rigid_motion(shape, times, turns=0.35), shape, times=times)
    rng = np.random.default_rng(7)
    for t in np.r_[rng.uniform(0, 1, 25), 0.0, 1.0]:
        expected = rigid_motion(shape, [t], turns=0.35)[0]
        assert np.allclose(seq.at(t).vertices, expected, atol=1e-10, rtol=0), t


def test_resample_runs_through_the_frames(curl, rigid_motion):
    back = curl.resample(times=curl.times)
    assert np.array_equal(back.frames, curl.frames)
    shape = ellipse(20)
    seq = Sequence(rigid_motion(shape, np.linspace(0, 1, 5)), shape)
    fine = seq.resample(frames=17)
    assert np.array_equal(fine.times, np.linspace(0, 1, 17))
    assert np.allclose(fine.frames, rigid_motion(shape, fine.times), atol=1e-10, rtol=0)
    assert np.array_equal(fine.info["resampled_from"], seq.times)
    for bad in ({"frames": 1}, {"times": [0.5, 0.2]}, {}):
        with pytest.raises(ParameterError):
            seq.resample(**bad)


def test_at_rejects_times_outside_the_range(curl):
    part = curl[2:5]
    assert np.array_equal(part.at(part.times[0]).vertices, curl.frames[2])
    for t in (-0.1, 1.5, float("nan"), curl.times[1]):
        with pytest.raises(ParameterError, match="outside"):
            part.at(t) if t == curl.times[1] else curl.at(t)


def test_save_round_trip_and_bad_path(curl, tmp_path):
    files = curl.save(tmp_path / "curl.npz")
    back = load_sequence(files[0])
    assert back.equals(curl)
    with pytest.raises(FileFormatError):
        curl.save(tmp_path / "curl.xyz")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["curl.npz"]


def test_plot_draws_the_chosen_frames(curl):
    ax = curl.plot(frames=[0, 3, -1])
    lines = ax.get_lines()
    assert len(lines) == 3
    for line, k in zip(lines, (0, 3, 6), strict=True):
        xy = line.get_xydata()
        xy = xy[np.isfinite(xy).all(axis=1)]
        assert np.allclose(np.unique(xy, axis=0), np.unique(curl.frames[k], axis=0))
    assert len(curl.plot(frames=4).get_lines()) == 4
    with pytest.raises(ParameterError):
        curl.plot(indices=[99])


class _Tags(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags, self.attrs = [], {}

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        self.attrs.setdefault(tag, dict(attrs))


def test_html_repr_embeds_the_viewer_with_the_frames(curl):
    text = curl._repr_html_()
    outer = _Tags()
    outer.feed(text)
    assert outer.tags == ["iframe"]
    page = outer.attrs["iframe"]["srcdoc"]  # unescaped by the parser
    inner = _Tags()
    inner.feed(page)
    assert inner.tags[0] == "html" and "canvas" in inner.tags
    data = json.loads(re.search(r'id="isotween-data">(.*?)</script>', page, re.S).group(1))
    from isotween.render.html import decode_frames

    frames = decode_frames(data["frames"], curl.frames.shape)
    size = np.ptp(curl.frames.reshape(-1, 2), axis=0).max()
    assert np.abs(frames - curl.frames).max() <= size / 65000  # 16-bit levels of the shape's size


def test_repr_is_one_compact_line(curl):
    text = repr(curl)
    assert "\n" not in text and len(text) < 160
    assert "7 frames" in text and "30 vertices" in text


def test_plot_takes_a_count_as_frames_and_picks_with_indices(curl):
    """``frames`` is a count everywhere; picking frames by index is ``indices`` (an index list as frames warns)."""
    picked = curl.plot(indices=[0, 3, -1]).get_lines()
    with pytest.warns(DeprecationWarning, match="indices="):
        old = curl.plot(frames=[0, 3, -1]).get_lines()
    assert len(picked) == len(old) == 3
    for a, b in zip(picked, old, strict=True):
        np.testing.assert_array_equal(a.get_xydata(), b.get_xydata())
    with pytest.raises(ParameterError, match="not both"):
        curl.plot(frames=3, indices=[0])
