"""Compatible meshing: `compatible_meshes` on the hard cases of glyph and icon outlines.

Usage: PYTHONPATH=src python3 benchmarks/meshing.py

Each case is a pair of outlines resampled to corresponding rings with
`isotween.resample`, meshed with the default mesh size (the mean edge length
of the source rings) unless the case says otherwise. Columns: ring points (K),
mesh vertices and faces, Steiner (interior) vertices, smallest angle in the
source and target mesh (after the overlay -> after the joint quality step),
flipped or degenerate triangles in source / target, whether the overlay was
needed, flipped target triangles of the Triangle + harmonic map path
(``mesh_pair(..., mesher="triangle")``, for comparison; needs ``triangle``),
and seconds (median of 5 runs, min-max). Overlay crossings: intersection
vertices the overlay made before the quality step. Writes the "Compatible meshing"
section of benchmarks/RESULTS.md.
"""

import os
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
import isotween  # noqa: E402
from _results import repeat, table, write_section  # noqa: E402
from build_examples import glyph  # noqa: E402
from isotween.correspondence.compatible_mesh import compatible_meshes  # noqa: E402
from isotween.errors import ShapeError  # noqa: E402


def rect(x0, y0, x1, y1, n):
    """Counter-clockwise rectangle ring, n points per side."""
    c = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]], dtype=float)
    return np.vstack([np.linspace(c[i], c[i + 1], n, endpoint=False) for i in range(4)])


def grid_icon():
    """A square with a 2 x 2 grid of square windows (4 holes)."""
    return [rect(0, 0, 9, 9, 12)] + [rect(x, y, x + 3, y + 3, 4)[::-1] for y in (1, 5) for x in (1, 5)]


def clipboard():
    """A board with a clip on top (non-convex outline) and 4 slots (holes)."""
    outer = np.array([[0, 0], [8, 0], [8, 10], [5.5, 10], [5.5, 11.2], [2.5, 11.2], [2.5, 10], [0, 10]], float)
    return [outer] + [rect(1.5, y, 6.5, y + 1.0, 4)[::-1] for y in (1.2, 3.4, 5.6, 7.8)]


def bend(rings, angle):
    """Bend along x into a circular arc of total turning ``angle``, rotated by 0.4 rad."""
    allx = np.concatenate([r[:, 0] for r in rings])
    radius = np.ptp(allx) / angle
    out = []
    for r in rings:
        z = (radius + r[:, 1]) * np.exp(1j * (r[:, 0] - allx.min()) / radius + 0.4j)
        out.append(np.c_[z.real, z.imag])
    return out


CASES = [  # name, shapes, ring points, mesh size / mean ring edge, refine_first
    ("'C' -> 'G'", lambda: (glyph("C"), glyph("G")), 120, 1.0, False),
    ("'C' -> 'G', half mesh size", lambda: (glyph("C"), glyph("G")), 120, 0.5, False),
    ("'C' -> 'G', refine_first", lambda: (glyph("C"), glyph("G")), 120, 1.0, True),
    ("'P' -> bent, rotated 'P'", lambda: (glyph("P"), bend(glyph("P"), 2.0)), 130, 1.0, False),
    ("'P' -> 'R'", lambda: (glyph("P"), glyph("R")), 150, 1.0, False),
    ("'P' -> 'R', refine_first", lambda: (glyph("P"), glyph("R")), 150, 1.0, True),
    ("'B' -> '8'", lambda: (glyph("B"), glyph("8")), 180, 1.0, False),
    ("'S' -> '5'", lambda: (glyph("S"), glyph("5")), 160, 1.0, False),
    ("grid icon -> clipboard", lambda: (grid_icon(), clipboard()), 150, 1.0, False),
]


def _min_angles(shape):
    """(F,) smallest corner angle of every face, radians."""
    p = shape.z[shape.faces]
    return np.abs(np.angle((np.roll(p, -2, axis=1) - p) / (np.roll(p, -1, axis=1) - p))).min(axis=1)


def triangle_flips(s, t):
    """Flipped target triangles of the Triangle + harmonic path, or 'n/a'."""
    try:
        import triangle  # noqa: F401
    except ImportError:
        return "n/a"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pair = isotween.mesh_pair(s, t, mesher="triangle")
    return f"{pair.flipped.size} of {pair.source.n_faces}"


def random_pairs(n, holes, seed):
    """``n`` pairs of random star-shaped polygons (source radii 2.6-3.2, target 2.3-3.8).

    Each shape has ``holes`` = (fewest, most) small star-shaped holes, placed independently.
    """
    import shapely

    rng = np.random.default_rng(seed)

    def star(k, lo, hi, c, cw=False):
        th = (np.arange(k) + 0.7 * rng.random(k)) / k * 2 * np.pi * (-1 if cw else 1)
        r = lo + (hi - lo) * rng.random(k)
        return np.c_[r * np.cos(th) + c.real, r * np.sin(th) + c.imag]

    for _ in range(n):
        nh = int(rng.integers(holes[0], holes[1] + 1))
        k = int(rng.integers(20, 60))
        ks = [int(rng.integers(6, 16)) for _ in range(nh)]

        def shape(lo, hi, k=k, ks=ks):
            while True:
                rings = [star(k, lo, hi, 0j)] + [star(kk, 0.2, 0.5, complex(*rng.uniform(-1.6, 1.6, 2)), cw=True)
                                                 for kk in ks]
                if shapely.Polygon(rings[0], rings[1:]).is_valid:
                    return rings

        yield shape(2.6, 3.2), shape(2.3, 3.8)


def random_rows():
    """Success counts on random polygon pairs, without and with holes."""
    rows = []
    for name, holes in (("random star polygons, no hole", (0, 0)), ("random star polygons, 1-3 holes", (1, 3))):
        done = flips = refused = 0
        angles, seconds, messages = [], [], set()
        for src, tgt in random_pairs(40, holes, seed=11):
            try:
                res = compatible_meshes(src, tgt, mesh_size=0.35)
            except ShapeError as exc:
                refused += 1
                messages.add("a hole with no straight cut in both shapes" if "straight cuts" in str(exc) else str(exc))
                continue
            done += 1
            flips += int(np.sum(res.source.face_areas() <= 0) + np.sum(res.target.face_areas() <= 0))
            angles.append(min(res.info["min_angle_source"], res.info["min_angle_target"]))
            seconds.append(res.info["seconds"])
        rows.append([name, done + refused, done, refused, flips, f"{np.median(angles):.1f}",
                     f"{np.median(seconds):.3f}", "; ".join(sorted(messages)) or "-"])
        print(" | ".join(str(c) for c in rows[-1]), flush=True)
    return table(["pairs", "tried", "meshed", "refused", "flips (both meshes, all pairs)",
                  "median smallest angle (deg)", "median seconds", "refusal"], rows)


def main():
    load_before = os.getloadavg()[0]
    rows = []
    for name, make, points, scale, first in CASES:
        a, b = make()
        s, t = isotween.resample(a, b, points=points)
        src = [s.vertices[p] for p, _ in s.paths]
        tgt = [t.vertices[p] for p, _ in t.paths]
        edge = float(np.mean(np.concatenate([np.linalg.norm(np.diff(np.r_[r, r[:1]], axis=0), axis=1)
                                             for r in src])))
        med, lo, hi, res = repeat(lambda src=src, tgt=tgt, size=scale * edge, first=first:
                                  compatible_meshes(src, tgt, mesh_size=size, refine_first=first), 5)
        i = res.info
        flips = f"{np.sum(res.source.face_areas() <= 0)} / {np.sum(res.target.face_areas() <= 0)}"
        small = np.degrees(np.minimum(_min_angles(res.source), _min_angles(res.target)))
        rows.append([
            name, i["ring_vertices"], i["vertices"], i["faces"], i["steiner"], i["crossings"],
            f"{i['min_angle_before_source']:.2f} -> {i['min_angle_source']:.1f}",
            f"{i['min_angle_before_target']:.2f} -> {i['min_angle_target']:.1f}",
            f"{np.sum(small < 10)} / {np.sum(small < 20)}",
            flips, "yes" if i["overlay"] else "no", triangle_flips(s, t), f"{med:.3f} ({lo:.3f}-{hi:.3f})",
        ])
        print(" | ".join(str(c) for c in rows[-1]), flush=True)
    header = ["case", "ring points", "vertices", "faces", "Steiner", "overlay crossings", "min angle src (deg)",
              "min angle tgt (deg)", "faces < 10 / < 20 deg (either mesh)", "flips src / tgt", "overlay",
              "Triangle path: flipped tgt",
              "seconds, median of 5 (min-max)"]
    body = table(header, rows)
    print(body)
    note = (
        "`compatible_meshes`: shapely constrained Delaunay triangulation of each polygon; the refined source "
        "mesh mapped onto the target by mean-value weights where that flips nothing, else pulled onto the "
        "target outline with no flip (where the pull gets stuck near it, again with edges flipped on the way, "
        "then the quality step), and the map made least distorted (overlay: no: low distortion is the "
        "aim there, not angles); else the two triangulations overlaid in the unit disc and refined in both, "
        "then joint edge collapses and flips and smoothing, every step keeping both meshes valid (overlay: "
        "yes). "
        "Rings from `isotween.resample` of DejaVu Sans Bold glyphs (matplotlib) and two icons drawn in the "
        "script; mesh size: the mean ring edge length (times 0.5 where the case says so). "
        "Min angle: before -> after the last step (the overlay's quality step, or the least-distorted map, "
        "which moves only the target). `refine_first` rows overlay the refined source mesh instead of the "
        "plain one (the default refines after the overlay). "
        "The Triangle column is the earlier "
        "default (Triangle mesh of the source, cotangent harmonic map onto the target), for comparison. "
        f"The machine was shared with other jobs while this ran (1-minute load average {load_before:.1f} "
        f"before and {os.getloadavg()[0]:.1f} after, on {os.cpu_count()} cores): times are upper bounds."
    )
    rand = random_rows()
    note2 = ("Random pairs (fixed seed 11, mesh size 0.35, one run each): holes are placed independently in "
             "source and target, so a hole may have to travel across the shape. A refusal is the ShapeError "
             "for a hole that no straight cut joins to the outer ring or to another hole in both shapes "
             "(polyline cuts are not implemented).")
    write_section("Compatible meshing", note + "\n\n" + body + "\n\n" + note2 + "\n\n" + rand,
                  "PYTHONPATH=src python3 benchmarks/meshing.py")


if __name__ == "__main__":
    main()
