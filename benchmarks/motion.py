"""Known motions: drawings whose in-betweens are known, morphed by isotween, flubber and GSAP.

Usage: python benchmarks/motion.py [--cases N] [--frames 21] [--only NAME ...] [--no-others]
[--workers 1] [--timeout 60] [--no-write] [--section "Known motions"]

Every case (issue 20) is a source drawing and a target that is the same drawing moved by a
known motion, so the right in-betweens are known:

- rigid turns by 10 to 180 degrees (plus a translation) of font glyphs (DejaVu Sans and
  Serif, which matplotlib ships; Liberation Serif, Sans and Mono, Debian's
  ``fonts-liberation``) and of filled icons (Bootstrap Icons, Font Awesome solid;
  benchmarks/corpus.py installs them from npm);
- similarities: a turn and a scale from 0.5 to 2;
- isometric bends: a bar (a filled rectangle) bent into circular arcs by 90, 180 and 270
  degrees, or into an S, without stretching its centre line; an open stroked line bent the
  same way.

The motion is applied to the drawing's control points (curves stay curves), and the
target is written with every segment split in two (a different number of points) and every
closed ring starting at a different segment. Both files go to ``benchmarks/.motion/cases``.
Before anything is morphed, each rigid and similarity target is read back with
``isotween.io.load`` and checked against the exact motion of the source (within 0.05 % of
its own diagonal: the reader drops spike tips within its curve tolerance, which scales with
the drawing), so the corpus itself is right.

Each case is morphed into F frames (default 21) by

- isotween with no options, as ``isotween interpolate A.svg B.svg`` runs it (``isotween.morph``
  where the package has it; otherwise the command's own steps: ``make_compatible``, then
  ``interpolate`` with ``fold="fallback"`` for meshes it built), one process per case,
  killed after ``--timeout`` seconds;
- flubber 0.4 (benchmarks/flubber_run.js) on the rings as isotween reads them, with
  maxSegmentLength 1 % of the diagonal (filled drawings only: flubber morphs closed rings);
- GSAP's MorphSVGPlugin (the ``gsap`` npm package, pinned below; benchmarks/gsap_run.js, run
  headless in Node.js) on the two path data strings, with its defaults and a linear ease.

Measures, per case, over all frames (the end frames included), in % :

- stray (rigid and similarity cases): the symmetric Hausdorff distance between the frame's
  outline and the best-fitting rigid (similar) copy of the source outline, as % of the
  source's bounding-box diagonal. The fit starts from the exact answer at that time (the
  source turned by t * angle about the motion's fixed point and scaled by s ** t) and from
  the same turn centred on the frame, each refined by ICP (nearest points both ways, closed-
  form least squares); the lower distance is kept. Outlines are sampled every 1/3000 of the
  diagonal.
- area: the largest | area(t) / ((1 - t) A0 + t A1) - 1 |, the drawing's area under the
  even-odd rule (signed ring areas, each ring's role and orientation taken from frame 0
  where the tool keeps its rings in order: a ring turned inside out counts negative, so a
  swing over 100 % means a ring inverted on the way); for similarities the blend is A0 ** (1 - t) * A1 ** t,
  the area of the exact in-between;
- length: the largest | outline length(t) / ((1 - t) L0 + t L1) - 1 | (all rings and strokes;
  geometric blend for similarities).

A0, A1, L0, L1 are those of the exact drawings. Targets (issue 20): rigid and similarity
cases stray at most 0.5 % in every frame; bends keep area (bars) and length within 2 %.
"""

import argparse
import glob
import json
import multiprocessing as mp
import os
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
import corpus  # noqa: E402
from _results import table, write_section  # noqa: E402

CACHE = HERE / ".motion"
#: npm packages of this benchmark (installed into CACHE); flubber comes with benchmarks/corpus.py
PACKAGES = {"gsap": "3.15.0"}
LIBERATION = "/usr/share/fonts/truetype/liberation"
DIAGONAL = 100.0  # every source drawing is scaled to this bounding-box diagonal
STRAY_TARGET, BEND_TARGET, CORPUS_TOLERANCE = 0.5, 2.0, 0.05  # % of the diagonal / % of the blend
SPACING = DIAGONAL / 3000  # outline sampling of the measures
#: cases whose isotween frames are also drawn as a strip (benchmarks/.motion/strip-*.png)
STRIPS = ("Liberation Serif 'G' 90", "DejaVu Sans '&' 120", "DejaVu Serif 'B' 45", "DejaVu Serif 'a' 180",
          "bootstrap key 170", "bootstrap cup 60", "bar 180", "bar S", "stroke S")
TOOLS = ("isotween", "flubber 0.4", f"GSAP {PACKAGES['gsap']}")


# ---------------------------------------------------------------- drawings
@dataclass
class Drawing:
    """Rings of Bezier segments.

    Attributes
    ----------
    rings : list of list of (k + 1, 2) float arrays
        Each ring is a chain of segments given by their control points (k = 1 line,
        2 quadratic, 3 cubic); a segment starts where the previous one ends.
    closed : list of bool
        Whether each ring is closed (filled drawings: all).
    fill_rule : str
        ``nonzero`` or ``evenodd``.
    stroke : float or None
        Stroke width of an unfilled drawing (``None``: filled).
    """

    rings: list
    closed: list
    fill_rule: str = "nonzero"
    stroke: float | None = None

    def map(self, fn):
        """The drawing with ``fn`` applied to every control point ((k, 2) -> (k, 2))."""
        return Drawing([[fn(s) for s in r] for r in self.rings], list(self.closed), self.fill_rule, self.stroke)


def _c(z):
    return np.column_stack([z.real, z.imag])


def _z(p):
    return p[..., 0] + 1j * p[..., 1]


def similarity(drawing, a, b):
    """The drawing moved by z -> a z + b (complex a, b): a turn by arg(a), a scale by |a|."""
    return drawing.map(lambda p: _c(a * _z(p) + b))


def bezier(ctrl, t):
    """Points of a Bezier segment ((k + 1, 2) control points) at parameters ``t`` ((m,) array)."""
    pts = np.repeat(ctrl[None], len(t), axis=0).astype(float)
    t = np.asarray(t, float)[:, None]
    for k in range(len(ctrl) - 1, 0, -1):
        pts = pts[:, :k] * (1 - t[:, None]) + pts[:, 1:k + 1] * t[:, None]
    return pts[:, 0]


def split(ctrl, u):
    """The two halves of a Bezier segment split at parameter u (de Casteljau)."""
    left, right, pts = [ctrl[0]], [ctrl[-1]], np.asarray(ctrl, float)
    while len(pts) > 1:
        pts = pts[:-1] * (1 - u) + pts[1:] * u
        left.append(pts[0])
        right.append(pts[-1])
    return np.array(left), np.array(right[::-1])


def resubdivided(drawing, u=0.4):
    """Every segment split in two at parameter ``u``: the same curves with other points."""
    rings = [[h for s in r for h in split(s, u)] for r in drawing.rings]
    return Drawing(rings, list(drawing.closed), drawing.fill_rule, drawing.stroke)


def rolled(drawing, shift=3):
    """Closed ring k starts at its segment ``shift + k`` (modulo its length), not its first."""
    rings = []
    for k, (r, c) in enumerate(zip(drawing.rings, drawing.closed, strict=True)):
        n = len(r)
        s = (shift + k) % n if c and n > 1 else 0
        s = s or (1 if c and n > 1 else 0)
        rings.append(r[s:] + r[:s])
    return Drawing(rings, list(drawing.closed), drawing.fill_rule, drawing.stroke)


def sample(drawing, spacing=SPACING):
    """Polylines of the drawing: [(points (m, 2), closed)], no gap longer than about ``spacing``."""
    out = []
    for r, c in zip(drawing.rings, drawing.closed, strict=True):
        parts = []
        for s in r:
            if len(s) == 2:
                pts = s[:1]
            else:
                rough = np.sum(np.hypot(*np.diff(s, axis=0).T))
                n = max(8, int(np.ceil(rough / spacing)))
                pts = bezier(s, np.arange(n) / n)
            parts.append(pts)
        if not c:
            parts.append(r[-1][-1:])
        out.append((densify(np.vstack(parts), c, spacing), c))
    return out


def densify(points, closed, spacing):
    """A polyline with points added on its edges so that no gap exceeds ``spacing``."""
    nxt = np.roll(points, -1, axis=0) if closed else points[1:]
    start = points if closed else points[:-1]
    if not len(start):
        return points
    n = np.maximum(1, np.ceil(np.hypot(*(nxt - start).T) / spacing).astype(int))
    k = np.repeat(np.arange(len(start)), n)
    f = (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)) / np.repeat(n, n)
    out = start[k] * (1 - f[:, None]) + nxt[k] * f[:, None]
    return out if closed else np.vstack([out, points[-1:]])


def path_data(drawing):
    """SVG path data of the drawing (M, L, Q, C, Z)."""
    cmd = {2: "L", 3: "Q", 4: "C"}
    out = []
    for r, c in zip(drawing.rings, drawing.closed, strict=True):
        out.append("M " + " ".join(f"{v:.6f}" for v in r[0][0]))
        for s in r:
            out.append(cmd[len(s)] + " " + " ".join(f"{v:.6f}" for v in s[1:].ravel()))
        if c:
            out.append("Z")
    return " ".join(out)


def write_svg(drawing, file):
    """Write the drawing as one <path> (filled black, or stroked black when it is a stroke)."""
    pts = np.vstack([s for r in drawing.rings for s in r])
    lo, hi = pts.min(axis=0) - 5, pts.max(axis=0) + 5
    paint = (f'fill="none" stroke="black" stroke-width="{drawing.stroke:g}" stroke-linecap="round"'
             if drawing.stroke else f'fill="black" fill-rule="{drawing.fill_rule}"')
    Path(file).write_text(
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{lo[0]:.3f} {lo[1]:.3f} {hi[0] - lo[0]:.3f} '
        f'{hi[1] - lo[1]:.3f}">\n  <path {paint} d="{path_data(drawing)}"/>\n</svg>\n')


def _closed_ring(segments):
    """A ring closed by a line back to its start where it ends elsewhere."""
    if np.hypot(*(segments[-1][-1] - segments[0][0])) > 1e-9:
        segments.append(np.array([segments[-1][-1], segments[0][0]]))
    return segments


def glyph(char, font_file):
    """A glyph of a font file as a filled drawing (y down, as SVG)."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.path import Path as MPath
    from matplotlib.textpath import TextPath

    tp = TextPath((0, 0), char, size=100, prop=FontProperties(fname=font_file))
    rings, ring, cur = [], None, None
    for verts, code in tp.iter_segments(curves=True, simplify=False):
        v = np.asarray(verts, float).reshape(-1, 2) * [1, -1]
        if code == MPath.MOVETO:
            if ring:
                rings.append(_closed_ring(ring))
            ring, cur = [], v[-1]
        elif code == MPath.CLOSEPOLY:
            if ring:
                rings.append(_closed_ring(ring))
            ring = None
        else:
            ring.append(np.vstack([cur, v]))
            cur = v[-1]
    if ring:
        rings.append(_closed_ring(ring))
    return _without_flat_rings(Drawing(rings, [True] * len(rings), "nonzero"))


def icon(file):
    """A filled icon (all its elements share one fill rule) as a drawing; arcs become cubics."""
    import svgelements as se

    rings, rules = [], set()
    for el in se.SVG.parse(str(file)).elements():
        if not isinstance(el, se.Shape):
            continue
        rules.add(str(el.values.get("fill-rule", "nonzero")))
        p = se.Path(el)
        p.approximate_arcs_with_cubics()
        ring = None
        for seg in p.segments():
            if isinstance(seg, se.Move):
                if ring:
                    rings.append(_closed_ring(ring))
                ring = []
                continue
            if isinstance(seg, se.Close):
                if ring:
                    rings.append(_closed_ring(ring))
                ring = None
                continue
            if ring is None:
                ring = []
            if isinstance(seg, se.Line):
                ctrl = [seg.start, seg.end]
            elif isinstance(seg, se.QuadraticBezier):
                ctrl = [seg.start, seg.control, seg.end]
            elif isinstance(seg, se.CubicBezier):
                ctrl = [seg.start, seg.control1, seg.control2, seg.end]
            else:
                raise ValueError(f"{file}: unexpected segment {type(seg).__name__}")
            ctrl = np.array([[q.x, q.y] for q in ctrl], float)
            if len(ctrl) > 2 or np.hypot(*(ctrl[1] - ctrl[0])) > 1e-12:
                ring.append(ctrl)
        if ring:
            rings.append(_closed_ring(ring))
    if len(rules) != 1:
        raise ValueError(f"{file}: elements with different fill rules {sorted(rules)}")
    return _without_flat_rings(Drawing(rings, [True] * len(rings), rules.pop()))


def _without_flat_rings(drawing):
    """The filled drawing without rings of zero area (they paint nothing; readers may drop them)."""
    scale = _diag(drawing) ** 2
    keep = [k for k, (p, _) in enumerate(sample(drawing, 1e-3 * np.sqrt(scale))) if abs(ring_area(p)) > 1e-6 * scale]
    return Drawing([drawing.rings[k] for k in keep], [True] * len(keep), drawing.fill_rule, drawing.stroke)


def normalised(drawing):
    """The drawing scaled to a bounding-box diagonal of DIAGONAL, its box's corner at the origin."""
    pts = np.vstack([p for p, _ in sample(drawing, 1e-3 * _diag(drawing))])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    k = DIAGONAL / np.hypot(*(hi - lo))
    return drawing.map(lambda p: (p - lo) * k)


def _diag(drawing):
    pts = np.vstack([s for r in drawing.rings for s in r])
    return float(np.hypot(*np.ptp(pts, axis=0)))


def bent(turns, length=100.0, width=10.0, stroke=False):
    """A bar (or a stroke) along a centre line of pieces (length, turning angle in radians).

    The centre line keeps its length: each piece is a straight segment (angle 0) or a circular
    arc; the bar's sides are the arcs offset by half the width on either side.
    """
    pieces, p, h = [], 0j, 1 + 0j
    for frac, angle in turns:
        ell = frac * length
        pieces.append((p, h, ell, angle))
        if angle:
            k = angle / ell
            p = p + (h * 1j / k) * (1 - np.exp(1j * angle))
            h = h * np.exp(1j * angle)
        else:
            p = p + h * ell

    def side(d):
        segs = []
        for q, hd, ell, angle in pieces:
            n = 1j * hd
            if not angle:
                segs.append(_c(np.array([q + d * n, q + hd * ell + d * n])))
                continue
            k = angle / ell
            centre, v = q + n / k, (d - 1 / k) * n
            m = int(np.ceil(abs(angle) / (np.pi / 4)))
            step = angle / m
            t = 4 / 3 * np.tan(step / 4)
            for _ in range(m):
                w = v * np.exp(1j * step)
                segs.append(_c(np.array([centre + v, centre + v + t * 1j * v, centre + w - t * 1j * w, centre + w])))
                v = w
        return segs

    if stroke:
        return Drawing([side(0.0)], [False], stroke=width)
    left, right = side(width / 2), side(-width / 2)
    ring = left + [np.array([left[-1][-1], right[-1][-1]])] + [s[::-1] for s in right[::-1]]
    ring.append(np.array([right[0][0], left[0][0]]))
    return Drawing([ring], [True])


# ---------------------------------------------------------------- cases
@dataclass
class Case:
    """One known motion: the drawings, and for rigid and similarity cases z -> a z + b."""

    name: str
    kind: str  # rigid, similarity, bend
    source: Drawing
    target: Drawing
    a: complex = 1
    b: complex = 0
    files: tuple = field(default=())


def fonts():
    """Font files by name: DejaVu from matplotlib, Liberation from Debian's fonts-liberation."""
    import matplotlib

    ttf = Path(matplotlib.get_data_path()) / "fonts" / "ttf"
    out = {"DejaVu Sans": ttf / "DejaVuSans.ttf", "DejaVu Serif": ttf / "DejaVuSerif.ttf"}
    for name in ("Serif", "Sans", "Mono"):
        found = glob.glob(f"{LIBERATION}/Liberation{name}-Regular.ttf") or glob.glob(
            f"/usr/share/fonts/**/Liberation{name}-Regular.ttf", recursive=True)
        if not found:
            raise SystemExit("benchmarks/motion.py needs Debian's Liberation fonts: apt-get install fonts-liberation")
        out[f"Liberation {name}"] = Path(found[0])
    return out


#: (font, character, degrees) rigid turns of glyphs
GLYPH_TURNS = [
    ("Liberation Serif", "G", 90), ("DejaVu Sans", "&", 120), ("DejaVu Serif", "B", 45),
    ("Liberation Sans", "%", 150), ("DejaVu Sans", "R", 10), ("Liberation Mono", "k", 30),
    ("DejaVu Serif", "a", 180), ("Liberation Sans", "e", 75), ("DejaVu Sans", "4", 135),
    ("Liberation Serif", "Q", 60), ("DejaVu Serif", "@", 20), ("Liberation Mono", "8", 165),
]
#: (icon set, name, degrees) rigid turns of icons
ICON_TURNS = [
    ("bootstrap", "key", 170), ("bootstrap", "cup", 60), ("bootstrap", "lock", 100),
    ("bootstrap", "house", 30), ("bootstrap", "star", 50), ("bootstrap", "bell", 15),
    ("bootstrap", "puzzle", 90), ("fontawesome", "key", 45), ("fontawesome", "mug-saucer", 120),
    ("fontawesome", "lock", 180), ("fontawesome", "anchor", 75), ("fontawesome", "gear", 25),
]
#: (source kind, font or set, character or name, degrees, scale) similarities
SIMILARITIES = [
    ("glyph", "DejaVu Sans", "S", 30, 0.5), ("glyph", "Liberation Serif", "g", 90, 2.0),
    ("icon", "bootstrap", "heart", 45, 1.5), ("icon", "fontawesome", "dragon", 160, 0.7),
    ("glyph", "DejaVu Serif", "3", 120, 1.25), ("icon", "fontawesome", "bicycle", 10, 1.8),
]
#: (name, turns of the centre line [(fraction of its length, degrees)], width, stroke)
BENDS = [
    ("bar 90", [(1, 90)], 10, False), ("bar 180", [(1, 180)], 10, False), ("bar 270", [(1, 270)], 10, False),
    ("thick bar 90", [(1, 90)], 20, False), ("thick bar 180", [(1, 180)], 20, False),
    ("bar S", [(0.5, 90), (0.5, -90)], 10, False),
    ("stroke 90", [(1, 90)], 4, True), ("stroke 180", [(1, 180)], 4, True), ("stroke 270", [(1, 270)], 4, True),
    ("stroke S", [(0.5, 120), (0.5, -120)], 4, True),
]


def _icon_file(kind, name):
    root = corpus.install() / "node_modules"
    if kind == "bootstrap":
        return root / "bootstrap-icons" / "icons" / f"{name}-fill.svg"
    return root / "@fortawesome" / "fontawesome-free" / "svgs" / "solid" / f"{name}.svg"


def _moved(name, kind, source, degrees, scale, k):
    """A case whose target is ``source`` turned by ``degrees`` about its box centre, scaled, shifted."""
    a = scale * np.exp(1j * np.radians(degrees))
    centre = DIAGONAL / 2 * (1 + 1j) / np.sqrt(2)
    shift = 0.15 * DIAGONAL * np.exp(1j * (0.7 + 1.3 * k))  # a translation as well, different per case
    b = centre - a * centre + shift
    target = rolled(resubdivided(similarity(source, a, b), 0.4 if k % 2 else 0.5), shift=3 + k)
    return Case(name, kind, source, target, a, b)


def cases():
    """The benchmark's cases, in a fixed order (rigid turns, similarities, bends)."""
    font = fonts()
    out, k = [], 0
    for family, char, deg in GLYPH_TURNS:
        out.append(_moved(f"{family} '{char}' {deg}", "rigid", normalised(glyph(char, font[family])), deg, 1.0, k))
        k += 1
    for kind, name, deg in ICON_TURNS:
        out.append(_moved(f"{kind} {name} {deg}", "rigid", normalised(icon(_icon_file(kind, name))), deg, 1.0, k))
        k += 1
    for src, where, what, deg, scale in SIMILARITIES:
        d = glyph(what, font[where]) if src == "glyph" else icon(_icon_file(where, what))
        label = f"{where} '{what}'" if src == "glyph" else f"{where} {what}"
        out.append(_moved(f"{label} {deg} x{scale:g}", "similarity", normalised(d), deg, scale, k))
        k += 1
    for name, turns, width, stroke in BENDS:
        straight = bent([(f, 0) for f, _ in turns], width=width, stroke=stroke)
        curved = bent([(f, np.radians(d)) for f, d in turns], width=width, stroke=stroke)
        out.append(Case(name, "bend", straight, rolled(curved, shift=2)))
    return out


def write_cases(selected):
    """Write the source and target SVG of every case into CACHE/cases; (source, target) paths."""
    folder = CACHE / "cases"
    folder.mkdir(parents=True, exist_ok=True)
    for case in selected:
        stem = "".join(ch if ch.isalnum() else "-" for ch in case.name).strip("-")
        case.files = (folder / f"{stem}-a.svg", folder / f"{stem}-b.svg")
        write_svg(case.source, case.files[0])
        write_svg(case.target, case.files[1])


def check_corpus(selected):
    """Assert that every rigid and similarity target, read back by isotween, is the exact motion."""
    import isotween

    for case in selected:
        if case.kind == "bend":
            for f in ("area", "length"):
                m0, m1 = measures(sample(case.source))[f], measures(sample(case.target))[f]
                assert np.isnan(m0) or abs(m1 / m0 - 1) < 1e-3, f"{case.name}: the bend changes the {f}"
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:  # curves sampled finely: this checks the file, not the reader's default sampling
                from isotween.io.svg import read_svg

                loaded = read_svg(case.files[1], curve_segments=64)
            except (ImportError, TypeError):
                loaded = isotween.io.load(case.files[1])
        polys = [(loaded.vertices[p], c) for p, c in loaded.paths]
        exact = sample(similarity(case.source, case.a, case.b))
        d = hausdorff(np.vstack([densify(p, c, SPACING) for p, c in polys]), np.vstack([p for p, _ in exact]))
        size = DIAGONAL * max(1.0, abs(case.a))  # the target's own diagonal (the reader's tolerances scale with it)
        assert 100 * d / size <= CORPUS_TOLERANCE, (
            f"{case.name}: the written target is {100 * d / size:.3f} % of its diagonal off the exact motion")


# ---------------------------------------------------------------- measures
def hausdorff(p, q):
    """Symmetric Hausdorff distance of two point sets (dense samples of outlines)."""
    return max(cKDTree(q).query(p)[0].max(), cKDTree(p).query(q)[0].max())


def ring_area(p):
    """Signed (shoelace) area of a closed polygon (m, 2)."""
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _depths(rings):
    """How many other rings contain a point of each ring."""
    from matplotlib.path import Path as MPath

    out = np.zeros(len(rings), int)
    for j, r in enumerate(rings):
        probe = r[:1]
        for k, other in enumerate(rings):
            if k != j and len(other) > 2 and MPath(other).contains_points(probe)[0]:
                out[j] += 1
    return out


def roles(polys):
    """Sign of each closed ring's area in the even-odd area of a frame: (-1)**depth * orientation."""
    rings = [p for p, c in polys if c]
    signs = np.array([np.sign(ring_area(r)) or 1.0 for r in rings])
    return (-1.0) ** _depths(rings) * signs


def measures(polys, role=None):
    """Area (even-odd, rings weighted by ``role``, default the frame's own) and outline length."""
    rings = [p for p, c in polys if c]
    if role is None or len(role) != len(rings):
        role = roles(polys)
    area = float(sum(w * ring_area(r) for w, r in zip(role, rings, strict=True))) if rings else float("nan")
    length = sum(float(np.sum(np.hypot(*np.diff(np.vstack([p, p[:1]]) if c else p, axis=0).T))) for p, c in polys)
    return {"area": area, "length": length}


def _fit(src, frame_tree, frame, a, b, scale, iterations=15):
    """ICP from z -> a z + b: (a, b) of the best rigid (similar) fit of ``src`` onto ``frame`` found."""
    zs, zf = _z(src), _z(frame)
    w = np.concatenate([np.full(len(zs), 1 / len(zs)), np.full(len(zf), 1 / len(zf))])
    for _ in range(iterations):
        moved = a * zs + b
        _, i1 = frame_tree.query(_c(moved))
        _, i2 = cKDTree(_c(moved)).query(frame)
        z = np.concatenate([zs, zs[i2]])
        f = np.concatenate([zf[i1], zf])
        zm, fm = np.sum(w * z) / w.sum(), np.sum(w * f) / w.sum()
        cross = np.sum(w * np.conj(z - zm) * (f - fm))
        new = cross / np.sum(w * np.abs(z - zm) ** 2) if scale else np.exp(1j * np.angle(cross))
        nb = fm - new * zm
        done = abs(new - a) < 1e-7 and abs(nb - b) < 1e-7 * DIAGONAL
        a, b = new, nb
        if done:
            break
    return a, b


#: turns added to the exact answer's angle when starting the fit (ICP finds the nearest local optimum, and a
#: 180-degree motion may turn either way): every 15 degrees, so that some start is near the global optimum
START_TURNS = np.radians(np.arange(0, 360, 15))


def stray(case, frame_polys, t, src_fine, src_coarse):
    """Distance (% of the diagonal) from a frame at time t to the best rigid (similar) copy of the source.

    ICP on coarse samples from the exact answer at time t (about the motion's fixed point) and
    from its angle plus each of START_TURNS with the centroids matched; the fits are then measured
    on fine samples, the best first, and the lowest distance is returned.
    """
    fine = np.vstack([densify(p, c, SPACING) for p, c in frame_polys])
    coarse = np.vstack([densify(p, c, 20 * SPACING) for p, c in frame_polys])
    tree, fine_tree = cKDTree(coarse), cKDTree(fine)
    angle, s = np.angle(case.a), abs(case.a)
    at = s ** t * np.exp(1j * t * angle)
    bt = case.b / (1 - case.a) * (1 - at) if abs(1 - case.a) > 1e-12 else t * case.b
    zc, fc = np.mean(_z(src_coarse)), np.mean(_z(coarse))
    starts = [(at, bt)] + [(at * np.exp(1j * d), fc - at * np.exp(1j * d) * zc) for d in START_TURNS]
    scored = []
    for a0, b0 in starts:
        a, b = _fit(src_coarse, tree, coarse, a0, b0, case.kind == "similarity")
        moved = _c(a * _z(src_coarse) + b)
        scored.append((max(tree.query(moved)[0].max(), cKDTree(moved).query(coarse)[0].max()), a, b))
        if scored[-1][0] < 0.002 * DIAGONAL:  # a fit this close cannot be beaten by more than the sampling
            break
    best = np.inf
    for _, a, b in sorted(scored, key=lambda x: x[0])[:2]:
        moved = _c(a * _z(src_fine) + b)
        best = min(best, max(fine_tree.query(moved)[0].max(), cKDTree(moved).query(fine)[0].max()))
    return 100 * best / DIAGONAL


def blend(case, v0, v1, t):
    """The value at time t between the ends' v0 and v1: linear; geometric for similarities.

    The exact in-between of a similarity scales by s ** t, so its area and length follow
    v0 ** (1 - t) * v1 ** t, which the linear blend would count as a swing.
    """
    if case.kind == "similarity":
        return v0 ** (1 - t) * v1 ** t
    return (1 - t) * v0 + t * v1


def evaluate(case, frames, times, keeps_order=True):
    """Measures of one tool's frames ([frame] -> [(points, closed)]) on a case."""
    e0, e1 = measures(sample(case.source)), measures(sample(case.target))
    role = roles(frames[0])  # where the tool reorders its rings, the last frame gets its own (below)
    out = {"stray": float("nan"), "area": float("nan"), "length": float("nan")}
    areas, lengths, strays = [], [], []
    if case.kind != "bend":
        src_fine = np.vstack([p for p, _ in sample(case.source)])
        src_coarse = np.vstack([p for p, _ in sample(case.source, 20 * SPACING)])
    for k, (polys, t) in enumerate(zip(frames, times, strict=True)):
        last = k == len(frames) - 1
        m = measures(polys, None if (last and not keeps_order) else role)
        if not np.isnan(e0["area"]):
            areas.append(abs(m["area"] / blend(case, e0["area"], e1["area"], t) - 1))
        lengths.append(abs(m["length"] / blend(case, e0["length"], e1["length"], t) - 1))
        if case.kind != "bend":
            strays.append(stray(case, polys, t, src_fine, src_coarse))
    if areas:
        out["area"] = 100 * max(areas)
    out["length"] = 100 * max(lengths)
    if strays:
        out["stray"] = max(strays)
        out["strays"] = strays
    out["met"] = meets(case, out)
    return out


def meets(case, r):
    """Whether a tool's measures meet issue 20's target on the case."""
    if case.kind == "bend":
        return bool((np.isnan(r["area"]) or r["area"] <= BEND_TARGET) and r["length"] <= BEND_TARGET)
    return bool(r["stray"] <= STRAY_TARGET)


# ---------------------------------------------------------------- isotween
def _isotween_job(source, target, frames, strip, conn):
    """One case through isotween with no options (in its own process); sends the frames back."""
    out = {}
    try:
        import isotween

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t0 = time.perf_counter()
            a, b = isotween.io.load(source), isotween.io.load(target)
            if hasattr(isotween, "morph"):
                seq = isotween.morph(a, b, frames=frames)
            else:  # what `isotween interpolate A.svg B.svg` does (src/isotween/cli/interpolate.py)
                from isotween.cli.prepare import make_compatible

                src, tgt = make_compatible(a, b, source, target, quiet=True)
                kwargs = {"fold": "fallback"} if not a.n_faces and src.n_faces else {}
                seq = isotween.interpolate(src, tgt, frames=frames, **kwargs)
            out["seconds"] = time.perf_counter() - t0
        arr = np.asarray(seq)
        out["frames"] = [[(arr[k][np.asarray(p)], bool(c)) for p, c in seq.shape.paths] for k in range(len(arr))]
        out["times"] = np.asarray(seq.times, float).tolist()
        out["method"] = seq.method
        out["fallback"] = str(seq.info.get("fallback", ""))
        out["ok"] = True
        if strip:  # drawn within the case's time limit, but not timed
            isotween.render.write_strip(seq, strip, frames=np.linspace(0, len(arr) - 1, 7).round().astype(int))
            out["strip"] = strip
    except Exception as exc:  # noqa: BLE001 - every failure is a measured outcome
        out = {"ok": False, "error": f"{type(exc).__name__}: {exc}"[:300]}
    conn.send(out)
    conn.close()


def strip_file(case):
    """Where the strip of isotween's frames of a case goes."""
    return CACHE / f"strip-{case.files[0].stem[:-2]}.png"


def run_isotween(selected, frames, workers, timeout, strips):
    """Frames of isotween for every case: {name: result}, at most ``workers`` processes at a time."""
    ctx = mp.get_context("fork")
    pending, running, results = list(selected), {}, {}
    while pending or running:
        while pending and len(running) < workers:
            case = pending.pop(0)
            recv, send = ctx.Pipe(duplex=False)
            strip = str(strip_file(case)) if case.name in strips else None
            proc = ctx.Process(target=_isotween_job, args=(str(case.files[0]), str(case.files[1]), frames, strip, send))
            proc.start()
            send.close()
            running[case.name] = (proc, recv, time.monotonic())
        for name, (proc, recv, started) in list(running.items()):
            if recv.poll(0.05):
                try:
                    results[name] = recv.recv()
                except EOFError:
                    results[name] = {"ok": False, "error": f"worker died (exit code {proc.exitcode})"}
            elif time.monotonic() - started > timeout:
                proc.kill()
                results[name] = {"ok": False, "error": f"timeout: no result within {timeout:g} s"}
            elif not proc.is_alive() and not recv.poll(0.2):
                results[name] = {"ok": False, "error": f"worker died (exit code {proc.exitcode})"}
            else:
                continue
            proc.join()
            recv.close()
            del running[name]
            r = results[name]
            print(f"  isotween {name}: " + (f"{r['seconds']:.1f} s, {r['method']}" if r["ok"] else r["error"]),
                  flush=True)
    return results


# ---------------------------------------------------------------- flubber and GSAP
def install():
    """Install GSAP into CACHE once (pinned), and the corpus' packages (icons, flubber)."""
    corpus.install()
    marker = CACHE / "installed.json"
    if marker.exists() and json.loads(marker.read_text()) == PACKAGES:
        return CACHE
    if shutil.which("npm") is None or shutil.which("node") is None:
        raise SystemExit("benchmarks/motion.py needs Node.js and npm for GSAP and flubber (or give --no-others)")
    CACHE.mkdir(exist_ok=True)
    (CACHE / "package.json").write_text('{"name": "isotween-motion", "private": true}\n')
    specs = [f"{name}@{version}" for name, version in PACKAGES.items()]
    subprocess.run(["npm", "install", "--no-audit", "--no-fund", "--silent", "--save-exact", *specs], cwd=CACHE,
                   check=True)
    marker.write_text(json.dumps(PACKAGES))
    return CACHE


def _node(script, payload, frames, timeout):
    """Run a Node.js runner on one JSON payload; its JSON lines, or an error dict."""
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as fh:
        json.dump(payload, fh)
    try:
        proc = subprocess.run(["node", str(HERE / script), fh.name, str(frames)], capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        return [{"ok": False, "error": f"timeout: no result within {timeout:g} s"}]
    finally:
        os.unlink(fh.name)
    if proc.returncode:
        return [{"ok": False, "error": proc.stderr.strip().splitlines()[-1][:300] if proc.stderr else "node failed"}]
    return [json.loads(line) for line in proc.stdout.splitlines() if line.strip()]


def run_flubber(case, frames, timeout):
    """Frames of flubber of a filled case ([frame] -> [(points, closed)]), or an error."""
    import isotween

    if not all(case.source.closed):
        return {"ok": False, "error": "n/a: flubber morphs closed rings only"}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a, b = isotween.io.load(case.files[0]), isotween.io.load(case.files[1])
    item = {"id": 0, "a": [a.vertices[p].tolist() for p, _ in a.paths],
            "b": [b.vertices[p].tolist() for p, _ in b.paths], "seg": 0.01 * DIAGONAL}
    r = _node("flubber_run.js", [item], frames, timeout)[0]
    if not r["ok"]:
        return {"ok": False, "error": r["error"]}
    out = [[(np.asarray(ring, float), True) for ring in f] for f in r["frames"]]
    return {"ok": True, "frames": out, "seconds": r["seconds"], "mode": r["mode"]}


def run_gsap(case, frames, timeout):
    """GSAP MorphSVGPlugin's frames of a case, sampled from its cubic Beziers, or an error."""
    payload = {"a": path_data(case.source), "b": path_data(case.target), "modules": str(CACHE / "node_modules")}
    r = _node("gsap_run.js", payload, frames, timeout)[0]
    if not r["ok"]:
        return {"ok": False, "error": r["error"]}
    out = []
    for f in r["frames"]:
        polys = []
        for seg in f:
            pts = np.asarray(seg["points"], float).reshape(-1, 2)
            n = (len(pts) - 1) // 3
            if n < 1:
                continue
            curve = np.vstack([bezier(pts[3 * i:3 * i + 4], np.arange(16) / 16) for i in range(n)] + [pts[-1:]])
            closed = seg["closed"] or np.hypot(*(pts[-1] - pts[0])) < 1e-6 * DIAGONAL
            polys.append((curve[:-1] if closed else curve, bool(closed)))
        out.append(polys)
    return {"ok": True, "frames": out, "seconds": r["seconds"]}


# ---------------------------------------------------------------- report
def _fmt(v, digits=2):
    return "-" if v is None or (isinstance(v, float) and np.isnan(v)) else f"{v:.{digits}f}"


def summary_rows(selected, results):
    """One row per tool: targets met and medians, for the rigid/similarity and the bend cases."""
    rows = []
    for tool in TOOLS:
        rs = {c.name: results[c.name].get(tool) for c in selected}
        moved = [c for c in selected if c.kind != "bend" and rs[c.name] is not None]
        bends = [c for c in selected if c.kind == "bend" and rs[c.name] is not None]
        if not moved and not bends:
            continue
        ok_moved = [rs[c.name] for c in moved if rs[c.name]["ok"]]
        ok_bends = [rs[c.name] for c in bends if rs[c.name]["ok"]]
        failed = [c.name for c in moved + bends if not rs[c.name]["ok"] and not rs[c.name]["error"].startswith("n/a")]
        secs = [r["seconds"] for r in ok_moved + ok_bends]

        def med(values):
            values = [v for v in values if not np.isnan(v)]
            return _fmt(float(np.median(values))) if values else "-"

        rows.append([
            tool,
            f"{sum(r['met'] for r in ok_moved)} of {len(moved)}",
            med([r["stray"] for r in ok_moved]),
            med([r["area"] for r in ok_moved]),
            f"{sum(r['met'] for r in ok_bends)} of {len(bends)}" if bends else "-",
            med([r["area"] for r in ok_bends]),
            med([r["length"] for r in ok_bends]),
            len(failed),
            _fmt(float(np.median(secs)), 2) if secs else "-",
        ])
    return rows


def case_rows(selected, results):
    """One row per case: stray, area and length deviation of each tool, and whether it meets the target."""
    rows = []
    for c in selected:
        row = [c.name, c.kind]
        for tool in TOOLS:
            r = results[c.name].get(tool)
            if r is None:
                continue
            if not r["ok"]:
                row.append(r["error"].split(":")[0][:24])
                continue
            parts = [] if c.kind == "bend" else [f"stray {_fmt(r['stray'])}"]
            if not np.isnan(r["area"]):
                parts.append(f"area {_fmt(r['area'], 1)}")
            if c.kind == "bend":
                parts.append(f"length {_fmt(r['length'], 1)}")
            row.append(", ".join(parts) + (" ✓" if r["met"] else " ✗"))
        rows.append(row)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases", type=int, default=None, help="only the first N cases (default: all)")
    parser.add_argument("--frames", type=int, default=21)
    parser.add_argument("--only", action="append", default=None,
                        help="only the cases whose name contains this text (case-insensitive; repeat for several)")
    parser.add_argument("--no-others", action="store_true", help="isotween only: skip flubber and GSAP")
    parser.add_argument("--workers", type=int, default=1, help="isotween processes at a time")
    parser.add_argument("--timeout", type=float, default=60, help="seconds per case and tool before it fails")
    parser.add_argument("--no-write", action="store_true", help="print only; leave RESULTS.md alone")
    parser.add_argument("--section", default="Known motions", help="the RESULTS.md section to write")
    args = parser.parse_args()

    CACHE.mkdir(exist_ok=True)
    if not args.no_others:
        install()
    selected = cases()
    if args.only:
        selected = [c for c in selected if any(o.lower() in c.name.lower() for o in args.only)]
    if args.cases:
        selected = selected[:args.cases]
    if not selected:
        raise SystemExit("no case selected")
    write_cases(selected)
    check_corpus(selected)
    print(f"{len(selected)} cases written to {CACHE / 'cases'}; every rigid and similarity target read back "
          f"within {CORPUS_TOLERANCE} % of its diagonal of the exact motion", flush=True)

    strips = {c.name for c in selected if c.name in STRIPS}
    t0 = time.perf_counter()
    ours = run_isotween(selected, args.frames, args.workers, args.timeout, strips)
    wall = time.perf_counter() - t0
    load = os.getloadavg()[1]  # the machine's load over the last 5 minutes of isotween's runs
    results = {}
    times = np.linspace(0, 1, args.frames)
    for c in selected:
        res = results[c.name] = {}
        r = ours[c.name]
        res[TOOLS[0]] = ({**evaluate(c, r["frames"], r["times"]), "ok": True, "seconds": r["seconds"],
                          "method": r["method"], "fallback": r["fallback"]} if r["ok"] else r)
        if not args.no_others:
            for tool, run, keeps in ((TOOLS[1], run_flubber, True), (TOOLS[2], run_gsap, False)):
                o = run(c, args.frames, args.timeout)
                res[tool] = {**evaluate(c, o["frames"], times, keeps), "ok": True, "seconds": o["seconds"]} \
                    if o["ok"] else o
        line = "; ".join(f"{t}: " + (case_rows([c], {c.name: {t: v}})[0][2]) for t, v in res.items())
        print(f"{c.name}: {line}", flush=True)

    tools = TOOLS[:1] if args.no_others else TOOLS
    n_moved = sum(c.kind != "bend" for c in selected)
    fallback = sum(1 for c in selected if ours[c.name]["ok"] and ours[c.name]["method"] != "aiap")
    body = [
        f"{len(selected)} cases ({n_moved} rigid turns and similarities, {len(selected) - n_moved} bends), "
        f"{args.frames} frames each, no options. Stray: the largest distance over all frames from the frame to "
        "the best rigid (similar) copy of the source, % of the source's bounding-box diagonal (target: at most "
        f"{STRAY_TARGET} %). Area: the largest deviation of the area from the blend of the two ends' areas, % "
        "(signed area: a ring turned inside out counts negative, so over 100 % means a ring inverted); "
        f"length: the same for the outline length (bends' target: both within {BEND_TARGET} %; strokes: length "
        "only). isotween: one process per case, "
        f"at most {args.timeout:g} s each, {wall:.0f} s wall in all ({os.cpu_count()} cores, load average {load:.1f} "
        "at the end); the fold-free fallback replaced AIAP on "
        f"{fallback} of {len(selected)} cases. "
        + ("" if args.no_others else
           "flubber: rings as isotween reads them, maxSegmentLength 1 % of the diagonal (no strokes: it morphs "
           "closed rings only). GSAP: MorphSVGPlugin with its defaults on the two path data strings, linear ease, "
           "headless in Node.js. Times: seconds per case (isotween from reading the files to the last frame)."),
        "",
        table(["tool", "rigid+similar met", "median stray %", "median area swing %", "bends met",
               "median bend area %", "median bend length %", "failures", "median s"],
              summary_rows(selected, results)),
        "",
        table(["case", "motion", *tools], case_rows(selected, results)),
    ]
    failures = [(c.name, t, r["error"]) for c in selected for t, r in results[c.name].items()
                if not r["ok"] and not r["error"].startswith("n/a")]
    if failures:
        body += ["", "Failures:", ""] + [f"- {t}, {n}: {e[:200]}" for n, t, e in failures]
    drawn = [f"benchmarks/.motion/{Path(ours[c.name]['strip']).name}" for c in selected if ours[c.name].get("strip")]
    if drawn:
        body += ["", "Strips of isotween's frames: " + ", ".join(drawn) + "."]
    text = "\n".join(body)
    print(text)
    details = CACHE / "motion.json"
    details.write_text(json.dumps({c.name: {t: {k: v for k, v in r.items() if k != "frames"}
                                            for t, r in results[c.name].items()} for c in selected}, default=str))
    print(f"per-case details: {details}")
    if not args.no_write:
        write_section(args.section, text, " ".join(["python benchmarks/motion.py", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
