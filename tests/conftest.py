"""Shared fixtures: shapes with known exact motions and real AIAP sequences.

The shape builders themselves live in ``shapes.py`` (imported by test modules
directly); the fixtures here are the sequences several test files use.
"""

import sys

import numpy as np
import pytest

from browser import browser  # noqa: F401  (the fixture, shared by the browser tests)
from isotween import Shape, interpolate
from shapes import bend, ellipse, grid_mesh


def pytest_collection_modifyitems(config, items):
    """Every test that uses the ``browser`` fixture carries the ``browser`` marker (``-m "not browser"``)."""
    for item in items:
        if "browser" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.browser)


@pytest.fixture
def shared_only(monkeypatch):
    """The fold check solves AIAP with the shared weights of Eq. (10) alone: where they fold, the repairs run."""
    import isotween.interpolate  # noqa: F401 (the module, not the function the package exports)

    monkeypatch.setattr(sys.modules["isotween.interpolate"], "WEIGHTS", ())


@pytest.fixture
def uniform_meshes(monkeypatch):
    """Compatible meshes as fine inside as at the outline (no `GRADE`): the meshes some fold tests were built on."""
    from isotween.correspondence import compatible_mesh

    monkeypatch.setattr(compatible_mesh, "GRADE", 0.0)


@pytest.fixture(scope="session")
def bent_bar():
    """A real AIAP sequence: a triangulated bar bending by 90 degrees, 7 frames."""
    bar = grid_mesh(13, 4, length=4.0, width=1.0)
    return interpolate(bar, bar.with_vertices(bend(bar.vertices, np.pi / 2)), frames=7)


@pytest.fixture(scope="session")
def ellipse_shape():
    """A 16-gon close to an ellipse (no symmetry that hides index errors)."""
    return ellipse()


@pytest.fixture(scope="session")
def two_components():
    """An edge soup in two pieces: a triangle and an open chain, apart."""
    tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.3, 0.8]])
    chain = np.array([[3.0, 0.0], [3.5, 0.4], [4.0, 0.1], [4.6, 0.5]])
    return Shape.from_paths([tri, chain], closed=[True, False])


def rigid_frames(shape, times, turns=0.3, shift=(2.0, -1.0)):
    """(F, n, 2) frames of ``shape`` turning rigidly about its centroid at constant speed.

    ``turns`` full turns over [0, 1] while the centroid moves linearly by ``shift``.
    Every connected component turns about the centroid of the whole shape; for
    one component this is the motion AIAP reproduces exactly.
    """
    z = shape.z
    c = z.mean()
    t = np.asarray(times, dtype=float)[:, None]
    out = (z - c) * np.exp(2j * np.pi * turns * t) + c + t * complex(*shift)
    return np.stack([out.real, out.imag], axis=-1)


@pytest.fixture(scope="session")
def rigid_motion():
    """The function ``rigid_frames(shape, times, turns=0.3, shift=(2, -1))``."""
    return rigid_frames
