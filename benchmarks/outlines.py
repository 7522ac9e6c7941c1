"""Outline correspondence: time of `resample` and `mesh_pair` against the outline size.

Usage: python benchmarks/outlines.py

resample: an outline with a hole (two rings, 1.5 N and 0.8 N input vertices, wavy
so that no start is trivially best) against a rotated, re-started, reversed
copy with other point counts, resampled to N points. mesh_pair: the same
outline resampled to N points, triangulated with the default sizes (no area
bound: triangles grow from the outline inwards) and mapped onto a bent copy.
Medians of 5 runs.

Any two drawings (public icons and glyphs, with flubber side by side) are measured by
``python benchmarks/correspondence.py``; its section in RESULTS.md is "Any two drawings".
"""

import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import isotween  # noqa: E402
from _results import repeat, table, write_section  # noqa: E402


def outline(k_outer, k_hole, turn=0.0, start=0, reverse=False):
    """Wavy outer ring and an off-centre hole, rotated by ``turn``, re-started and reversed."""
    rings = []
    for k, radius, centre, sign in ((k_outer, 3.0, 0j, 1), (k_hole, 0.9, 0.8 + 0.3j, -1)):
        th = np.linspace(0, 2 * np.pi, k, endpoint=False)
        z = centre + radius * (1 + 0.15 * np.sin(5 * th)) * np.exp(sign * 1j * th)
        z = np.roll(z[::-1] if reverse else z, start) * np.exp(1j * turn)
        rings.append(np.c_[z.real, 0.7 * z.imag])
    return rings


def bent(shape):
    z = shape.z + 4.0
    w = np.abs(z) * np.exp(1j * 1.6 * np.angle(z))  # opens the angle around the origin
    return shape.with_vertices(np.c_[w.real, w.imag])


def main():
    rows_r, rows_m = [], []
    for n in (200, 1000, 5000, 20000):
        src = outline(int(1.5 * n * 0.8), int(1.5 * n * 0.2))
        tgt = outline(int(0.8 * n * 0.8), int(0.8 * n * 0.2), turn=2.0, start=n // 7, reverse=True)
        med, lo, hi, _ = repeat(lambda src=src, tgt=tgt, n=n: isotween.resample(src, tgt, points=n, rotation=True), 5)
        rows_r.append([n, len(np.vstack(src)), len(np.vstack(tgt)), f"{1e3 * med:.1f}",
                       f"{1e3 * lo:.1f} - {1e3 * hi:.1f}"])
    for n in (200, 1000, 5000, 20000):
        a, _ = isotween.resample(outline(n, n // 3), outline(n, n // 3), points=n)
        b = bent(a)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            med, lo, hi, pair = repeat(lambda a=a, b=b: isotween.mesh_pair(a, b), 5)
        rows_m.append([n, pair.source.n_vertices, pair.source.n_faces, len(pair.flipped),
                       f"{1e3 * med:.1f}", f"{1e3 * lo:.1f} - {1e3 * hi:.1f}"])
    body = (
        "`resample` (two rings, rotation factored out; ms):\n\n"
        + table(["points N", "source vertices", "target vertices", "median", "min - max"], rows_r)
        + "\n\n`mesh_pair` (outline of N points, default sizes, bent target; ms):\n\n"
        + table(["outline N", "mesh vertices", "triangles", "flipped", "median", "min - max"], rows_m)
    )
    print(body)
    write_section("Outline correspondence", body, "python benchmarks/outlines.py")


if __name__ == "__main__":
    main()
