"""The geometry kernel (`isotween.geometry`) on known shapes, and a scan that keeps it the only one.

The scan reads every module under ``src/isotween`` and fails when a shoelace
(signed-area) formula appears outside ``geometry.py``. It looks for the two
forms the formula takes:

- a cross product of a vertex array with its cyclic shift, ``np.roll(z, -1)``
  (or ``np.roll(p, -1)`` used as an index) on a line that also takes ``.imag``
  of a ``conj`` product or subtracts two such products
  (``x * np.roll(y, -1) - np.roll(x, -1) * y``), within four lines either side
  (an index array rolled a few lines before the product is caught too);
- the sliced form ``x[:-1] * y[1:] - x[1:] * y[:-1]`` (any names).

A rolled array on its own (edges ``(p, roll(p, -1))``, a turning angle) is not
an area and passes. Use `isotween.geometry.ring_area`, `triangle_areas` or
`ring_centroid` instead of writing the formula again.
"""

import re
from pathlib import Path

import numpy as np
import pytest

from isotween import geometry
from isotween.errors import ShapeError

SRC = Path(__file__).resolve().parents[1] / "src" / "isotween"
KERNEL = SRC / "geometry.py"

ROLL = re.compile(r"roll\([^)]*-\s*1")
CONJ_IMAG = re.compile(r"conj\b.*\.imag|\.imag.*conj\b|\.conj\(\).*\.imag")
CROSS = re.compile(r"\*\s*np\.roll\([^)]*-\s*1[^)]*\)\s*-\s*np\.roll\(|np\.roll\([^)]*-\s*1[^)]*\)\s*\*\s*\w+\s*[-+]")
SLICED = re.compile(r"\[\s*:\s*-1\s*\]\s*\*\s*\w+\[\s*1\s*:\s*\]\s*-\s*\w+\[\s*1\s*:\s*\]\s*\*\s*\w+\[\s*:\s*-1\s*\]")


def shoelace_lines(text):
    """Line numbers of ``text`` that compute a shoelace area (see the module docstring)."""
    hits = []
    lines = text.splitlines()
    for n, line in enumerate(lines, 1):
        code = line.split("#", 1)[0]
        window = " ".join(s.split("#", 1)[0] for s in lines[max(0, n - 5):n + 4])  # formulas split over lines
        rolled = ROLL.search(code)
        if (rolled and (CONJ_IMAG.search(window) or CROSS.search(code))) or SLICED.search(code):
            hits.append(n)
    return hits


@pytest.mark.parametrize("snippet", [
    "a = 0.5 * np.sum((np.conj(z) * np.roll(z, -1)).imag)",
    "a = abs(np.sum((z[p].conj() * z[np.roll(p, -1)]).imag))",
    "area = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)",
    "a = np.sum(x[:-1] * y[1:] - x[1:] * y[:-1])",
    "w = np.roll(z, -1)\ncross = (np.conj(z) * w).imag",
    "nxt = np.concatenate([np.roll(p, -1) for p in loops])\nowner = 1\nz = seq.z\n"
    "cross = 0.5 * (z[:, idx].conj() * z[:, nxt]).imag",
])
def test_the_scan_catches_a_shoelace(snippet):
    assert shoelace_lines(snippet)


@pytest.mark.parametrize("snippet", [
    "e = np.column_stack([p, np.roll(p, -1)])",
    "turn = np.angle(d / np.roll(d, 1))",
    "b = np.roll(f, -1, axis=1).ravel()",
])
def test_the_scan_passes_other_rolls(snippet):
    assert not shoelace_lines(snippet)


def test_no_second_shoelace():
    found = {str(p.relative_to(SRC)): shoelace_lines(p.read_text(encoding="utf-8"))
             for p in sorted(SRC.rglob("*.py")) if p != KERNEL}
    found = {k: v for k, v in found.items() if v}
    assert not found, f"a shoelace area outside isotween/geometry.py (use the kernel): {found}"
    assert shoelace_lines(KERNEL.read_text(encoding="utf-8"))  # the scan still sees the kernel's own


SQUARE = np.array([0, 1, 1 + 1j, 1j])


def test_ring_area_and_orientation_of_a_unit_square():
    assert geometry.ring_area(SQUARE) == 1.0
    assert geometry.ring_area(np.c_[SQUARE.real, SQUARE.imag]) == 1.0
    assert geometry.ring_area(SQUARE[::-1]) == -1.0
    assert geometry.ring_orientation(SQUARE) == 1 and geometry.ring_orientation(SQUARE[::-1]) == -1
    assert geometry.ring_orientation(np.array([0, 1, 2])) == 0
    assert geometry.ring_centroid(3 + 2j + SQUARE) == pytest.approx(3.5 + 2.5j)


def test_triangle_areas_and_angles():
    z = np.array([0, 2, 2j, 2 + 2j])
    f = np.array([[0, 1, 2], [0, 2, 1], [1, 3, 2]])
    assert geometry.triangle_areas(z, f).tolist() == [2.0, -2.0, 2.0]
    assert geometry.triangle_areas(np.c_[z.real, z.imag], f).tolist() == [2.0, -2.0, 2.0]
    ang = geometry.triangle_angles(z, f)
    assert np.allclose(ang.sum(axis=1), np.pi)
    assert np.allclose(np.degrees(ang[0]), [90, 45, 45])
    assert geometry.triangle_angles(np.array([0, 0, 1j]), np.array([[0, 1, 2]]))[0, 0] == 0.0  # degenerate


def test_bbox_diagonal_of_points_either_way():
    assert geometry.bbox_diagonal(np.array([[0.0, 0.0], [3.0, 4.0]])) == 5.0
    assert geometry.bbox_diagonal(np.array([0j]), np.array([3 + 4j])) == 5.0


def square_with_hole():
    """A 4 x 4 square with a 2 x 2 hole, 8 counter-clockwise triangles: (z, faces)."""
    outer = np.array([0, 4, 4 + 4j, 4j])
    inner = np.array([1 + 1j, 3 + 1j, 3 + 3j, 1 + 3j])
    z = np.r_[outer, inner]
    f = []
    for i in range(4):
        j = (i + 1) % 4
        f += [[i, j, 4 + j], [i, 4 + j, 4 + i]]
    return z, np.array(f)


def test_boundary_loops_of_a_square_with_a_hole():
    z, f = square_with_hole()
    assert np.all(geometry.triangle_areas(z, f) > 0)
    loops = geometry.boundary_loops(f, len(z))
    assert sorted(sorted(p.tolist()) for p in loops) == [[0, 1, 2, 3], [4, 5, 6, 7]]
    area = sorted(geometry.ring_area(z[p]) for p in loops)
    assert area == [-4.0, 16.0]  # the outer loop counter-clockwise, the hole clockwise
    a, b, _, _, twin = geometry.edge_table(f)
    outside = twin < 0
    assert outside.sum() == 8 and np.all(twin[twin[~outside]] == np.flatnonzero(~outside))
    assert np.all(a[twin[~outside]] == b[~outside])


def test_boundary_loops_refuse_a_pinch():
    f = np.array([[0, 1, 2], [0, 3, 4]])  # two triangles touching at vertex 0
    with pytest.raises(ShapeError, match="meet at vertex 0"):
        geometry.boundary_loops(f, 5)


def fan():
    """A convex boundary of 6 and 3 interior vertices, triangulated: (z, faces, boundary)."""
    rng = np.random.default_rng(1)
    b = np.exp(2j * np.pi * np.arange(6) / 6)
    z = np.r_[b, 0.3 * (rng.random(3) - 0.5) + 0.3j * (rng.random(3) - 0.5)]
    from scipy.spatial import Delaunay

    f = Delaunay(np.c_[z.real, z.imag]).simplices
    f = np.where((geometry.triangle_areas(z, f) < 0)[:, None], f[:, [0, 2, 1]], f)
    return z, f, np.arange(6)


def test_mean_value_weights_reproduce_affine_maps():
    z, f, b = fan()
    W = geometry.mean_value_weights(z, f)
    inner = np.setdiff1d(np.arange(len(z)), b)
    assert np.allclose(np.asarray(W.sum(axis=1)).ravel(), 1.0)
    for affine in (lambda p: p, lambda p: (2 - 1j) * p + 3, lambda p: 1.5 * p.real + 1j * (p.imag - 0.5 * p.real)):
        w = affine(z)
        assert np.allclose((W @ w)[inner], w[inner], rtol=0, atol=1e-12)
    L = geometry.mean_value_laplacian(z, f)
    assert np.allclose((L @ ((1 + 2j) * z + 5))[inner], 0, atol=1e-12)


def test_convex_map_reproduces_an_affine_map_and_keeps_triangles_positive():
    z, f, b = fan()
    A = lambda p: 2 * p.real + 1j * (p.imag + 0.3 * p.real) - 1  # noqa: E731
    assert np.allclose(geometry.convex_map(z, f, b, A(z[b])), A(z), atol=1e-12)
    out = geometry.convex_map(z, f, b, np.exp(2j * np.pi * np.arange(6) / 6))
    assert np.all(geometry.triangle_areas(out, f) > 0)
