"""Properties of AIAP interpolation on generated shapes (hypothesis, fixed seed).

- the ends equal the inputs bit for bit;
- a rigid target keeps every edge length (midpoint scheme);
- similarity transforms of both inputs transform the result the same way;
- two runs give the same frames bit for bit;
- the numba and numpy paths, run with tol=1e-9, take the same iterations and
  agree to 1e-10 of the bounding-box diagonal (the README's statement).
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from isotween import Shape, interpolate
from isotween.optimisation import backend

SETTINGS = dict(derandomize=True, database=None, deadline=None, suppress_health_check=[HealthCheck.too_slow])

unit = st.floats(min_value=-1.0, max_value=1.0, allow_nan=False, allow_infinity=False)


@st.composite
def shape_pair(draw, max_vertices=12):
    """A closed ring or an open chain and a deformation of it (no coincident vertices)."""
    n = draw(st.integers(min_value=4, max_value=max_vertices))
    closed = draw(st.booleans())
    radius = 1.0 + 0.3 * np.array(draw(st.lists(unit, min_size=n, max_size=n)))
    if closed:  # a star-shaped polygon: angles increase, radii vary
        angle = 2 * np.pi * (np.arange(n) + 0.3 * np.array(draw(st.lists(unit, min_size=n, max_size=n)))) / n
        z = radius * np.exp(1j * angle)
        w = z * (1.0 + 0.4 * np.array(draw(st.lists(unit, min_size=n, max_size=n)))) * np.exp(0.5j * draw(unit))
    else:  # a chain with bounded turning
        turn = 0.5 * np.array(draw(st.lists(unit, min_size=n - 1, max_size=n - 1)))
        z = np.concatenate([[0], np.cumsum(radius[:-1] * np.exp(1j * np.cumsum(turn)))])
        bend = 1.2 * np.array(draw(st.lists(unit, min_size=n - 1, max_size=n - 1)))
        w = np.concatenate([[0], np.cumsum(radius[:-1] * np.exp(1j * np.cumsum(turn + bend)))])
    make = Shape.from_polygon if closed else Shape.from_polyline
    a = make(np.column_stack([z.real, z.imag]))
    return a, a.with_vertices(np.column_stack([w.real, w.imag]))


def similarity(shape, scale, angle, shift):
    z = scale * np.exp(1j * angle) * shape.z + shift
    return shape.with_vertices(np.column_stack([z.real, z.imag]))


def diagonal(seq):
    return float(np.hypot(*np.ptp(seq.frames.reshape(-1, 2), axis=0)))


@settings(max_examples=40, **SETTINGS)
@given(shape_pair(), st.integers(min_value=2, max_value=12), st.sampled_from(["local", "global"]))
def test_ends_equal_the_inputs_bit_for_bit(pair, frames, solver):
    a, b = pair
    seq = interpolate(a, b, frames=frames, solver=solver)
    assert np.array_equal(seq.frames[0], a.vertices) and np.array_equal(seq.frames[-1], b.vertices)


@settings(max_examples=30, **SETTINGS)
@given(shape_pair(), unit, unit, unit, st.integers(min_value=3, max_value=12))
def test_rigid_target_keeps_every_edge_length(pair, turn, dx, dy, frames):
    a, _ = pair
    b = similarity(a, 1.0, 3.0 * turn, 5 * dx + 5j * dy)
    seq = interpolate(a, b, frames=frames, scheme="midpoint")
    lengths = np.abs(seq.edge_vectors())
    assert np.max(np.abs(lengths / lengths[0] - 1.0)) < 1e-9


@settings(max_examples=30, **SETTINGS)
@given(shape_pair(), st.floats(min_value=0.01, max_value=100.0), unit, unit, unit)
def test_similarity_equivariance(pair, scale, turn, dx, dy):
    a, b = pair
    angle, shift = np.pi * turn, 10 * dx + 10j * dy
    seq = interpolate(a, b, frames=7, tol=1e-12, max_iter=6)
    moved = interpolate(similarity(a, scale, angle, shift), similarity(b, scale, angle, shift),
                        frames=7, tol=1e-12, max_iter=6)
    expected = scale * np.exp(1j * angle) * seq.z + shift
    assert np.max(np.abs(moved.z - expected)) < 1e-9 * scale * diagonal(seq)


@settings(max_examples=20, **SETTINGS)
@given(shape_pair(), st.sampled_from(["local", "global"]), st.sampled_from(["midpoint", "paper"]))
def test_runs_are_deterministic(pair, solver, scheme):
    a, b = pair
    first = interpolate(a, b, frames=9, solver=solver, scheme=scheme)
    second = interpolate(a, b, frames=9, solver=solver, scheme=scheme)
    assert np.array_equal(first.frames, second.frames) and first.energy == second.energy


@pytest.mark.skipif("numba" not in backend.available(), reason="numba missing")
@settings(max_examples=20, **SETTINGS)
@given(shape_pair(), st.integers(min_value=3, max_value=12))
def test_numba_and_numpy_paths_agree_at_a_tight_tolerance(pair, frames):
    """At tol=1e-9 both paths take the same iterations and agree to 1e-10 of the diagonal.

    Chains converge in two iterations; rings approach it slowly and run to max_iter.
    """
    a, b = pair
    runs = {}
    for enabled in (True, False):
        with backend.use("numba" if enabled else "numpy"):
            runs[enabled] = interpolate(a, b, frames=frames, tol=1e-9, max_iter=300)
    fast, reference = runs[True], runs[False]
    assert fast.iterations == reference.iterations and fast.converged == reference.converged
    assert np.max(np.abs(fast.z - reference.z)) <= 1e-10 * diagonal(reference)
