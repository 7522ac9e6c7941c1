"""Paper vs midpoint time discretisation: edge-length deviation (SPEC.md's cases).

Usage: python benchmarks/schemes.py
"""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import isotween  # noqa: E402
from _results import table, write_section  # noqa: E402
from cases import mesh_pair  # noqa: E402
from isotween import Shape, metrics  # noqa: E402


def chain(n, turns):
    step = 2 * np.pi * turns / (n - 1)
    s = np.arange(n) * step
    chord = 2 * np.sin(step / 2)
    return (Shape.from_polyline(np.c_[np.arange(n) * chord, np.zeros(n)]),
            Shape.from_polyline(np.c_[np.sin(s), 1 - np.cos(s)]))


def main():
    cases = [
        ("open chain, 100 vertices, straight -> curled 0.9 turn", chain(100, 0.9), 9),
        ("open chain, 100 vertices, curled 1.8 turns", chain(100, 1.8), 9),
        ("open chain, 100 vertices, curled 1.8 turns", chain(100, 1.8), 45),
        ("triangulated bar, 240 vertices, bent 180 deg", mesh_pair(60, 4), 9),
        ("triangulated bar, 240 vertices, bent 180 deg", mesh_pair(60, 4), 205),
    ]
    rows = []
    for name, (src, tgt), m in cases:
        row = [name, m]
        for scheme in ("paper", "midpoint"):
            seq = isotween.interpolate(src, tgt, frames=m + 1, scheme=scheme, tol=1e-6, max_iter=500)
            row += [f"{100 * metrics.edge_length_deviation(seq):.2f} %", seq.iterations]
            if metrics.flipped_faces(seq):
                row[-1] = f"{seq.iterations} ({metrics.flipped_faces(seq)} flips)"
        rows.append(row)
    body = ("Maximum relative deviation of an edge's length from the blend of its end lengths "
            "(`edge_length_deviation`), converged with tol = 1e-6; m = frame intervals.\n\n"
            + table(["case", "m", "paper", "iters", "midpoint", "iters"], rows)
            + "\n\nThe midpoint scheme keeps lengths where the paper's stretches them, so it is the default.")
    print(body)
    write_section("Time discretisation", body, "python benchmarks/schemes.py")


if __name__ == "__main__":
    main()
