"""Build the example gallery: src/isotween/examples/data/ and docs/gallery/*.png.

    PYTHONPATH=src python3 scripts/build_examples.py [NAME ...]   # all, or only these

Everything comes from data that pip packages ship, no downloads: glyph outlines
of the DejaVu fonts bundled with matplotlib (matplotlib.textpath.TextPath), the
Grace Hopper photograph of matplotlib's sample data, and shapes made here.
Meshes come from `isotween.mesh_pair` (needs the ``mesh`` extra). Every example
is then interpolated once and drawn as a strip of frames into docs/gallery/,
and the default one is also run through ``isotween demo`` for the README's
animation.
"""

import json
import shutil
import tempfile
from pathlib import Path

import matplotlib
import numpy as np
from click.testing import CliRunner
from matplotlib.font_manager import FontProperties
from matplotlib.path import Path as MplPath
from matplotlib.textpath import TextPath
from PIL import Image

import isotween
from isotween import Shape, io
from isotween.cli import main
from isotween.examples import DATA
from isotween.outputs import with_paint
from isotween.render import write_strip

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "docs" / "gallery"


# ---------------------------------------------------------------- shapes
def glyph(char, size=10.0, per_curve=6, weight="bold"):
    """Closed rings of a DejaVu Sans glyph (y up): outer ring first, then holes top to bottom."""
    path = TextPath((0, 0), char, size=size, prop=FontProperties(family="DejaVu Sans", weight=weight))
    rings, ring = [], []
    steps = np.linspace(0, 1, per_curve + 1)[1:]
    for curve, code in path.iter_bezier():
        if code == MplPath.MOVETO:
            if ring:
                rings.append(np.vstack(ring))
            ring = [curve.control_points[-1:]]
        elif code == MplPath.CLOSEPOLY:
            continue
        else:
            ring.append(curve(steps) if len(curve.control_points) > 2 else curve.control_points[-1:])
    if ring:
        rings.append(np.vstack(ring))
    out = []
    for r in rings:
        keep = np.r_[True, np.any(np.abs(np.diff(r, axis=0)) > 1e-9, axis=1)]
        r = r[keep]
        if np.allclose(r[0], r[-1]):
            r = r[:-1]
        out.append(r)
    area = [abs(_area(r)) for r in out]
    outer = int(np.argmax(area))
    holes = sorted((r for i, r in enumerate(out) if i != outer), key=lambda r: -r[:, 1].mean())
    return [out[outer]] + holes


def _area(r):
    x, y = r[:, 0], r[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def rectangle_outline(width, height, step):
    """Counter-clockwise rectangle outline with vertices about ``step`` apart."""
    nx, ny = max(2, round(width / step)), max(2, round(height / step))
    x, y = np.linspace(0, width, nx + 1)[:-1], np.linspace(0, height, ny + 1)[:-1]
    return np.vstack([np.c_[x, 0 * x], np.c_[0 * y + width, y], np.c_[width - x, 0 * x + height],
                      np.c_[0 * y, height - y]])


def worm_outline(length=8.0, head=0.55, tail=0.3, n=150):
    """A tapered capsule along x from 0 to ``length``: half-width ``tail`` at x=0, ``head`` at the end."""
    t = np.linspace(0, 1, n // 2)
    x = length * t
    w = tail + (head - tail) * t
    cap = np.linspace(-np.pi / 2, np.pi / 2, 14)[1:-1]
    top = np.c_[x, w]
    bottom = np.c_[x, -w][::-1]
    head_cap = np.c_[length + head * np.cos(cap), head * np.sin(cap)]
    tail_cap = np.c_[-tail * np.cos(cap), -tail * np.sin(cap)]
    return np.vstack([bottom[::-1], head_cap, top[::-1], tail_cap])


def bend(points, angle, length):
    """Bend the strip along the x axis from 0 to ``length`` into an arc of ``angle`` radians."""
    R = length / angle
    r = R - points[:, 1]
    return np.c_[r * np.sin(points[:, 0] / R), R - r * np.cos(points[:, 0] / R)]


def curl(n, turns, step, sign=1.0):
    """A chain of ``n`` equal steps whose turning grows linearly (an Euler spiral of ``turns`` turns)."""
    s = np.arange(n - 1) / (n - 2)
    theta = sign * 2 * np.pi * turns * s**2
    d = step * np.exp(1j * theta)
    z = np.concatenate([[0], np.cumsum(d)])
    return np.c_[z.real, z.imag]


def stick_figure(joints, bones, head, ball, per_bone=6, ring=18):
    """An edge soup: a tree of subdivided bones, a head ring and a ball ring (three components)."""
    names = list(joints)
    pts = [np.asarray(joints[k], dtype=float) for k in names]
    edges = []
    for a, b in bones:
        i, j = names.index(a), names.index(b)
        chain = [i]
        for t in np.linspace(0, 1, per_bone + 1)[1:-1]:
            pts.append((1 - t) * pts[i] + t * pts[j])
            chain.append(len(pts) - 1)
        chain.append(j)
        edges += list(zip(chain[:-1], chain[1:], strict=True))
    for centre, radius in (head, ball):
        th = np.linspace(0, 2 * np.pi, ring, endpoint=False) + np.pi / 2
        start = len(pts)
        pts += list(np.c_[centre[0] + radius * np.cos(th), centre[1] + radius * np.sin(th)])
        idx = np.arange(start, start + ring)
        edges += list(zip(idx, np.roll(idx, -1), strict=True))
    return Shape(np.array(pts), np.array(edges))


def posed(lengths, angles, root):
    """Joint positions of a skeleton from bone lengths and absolute bone angles (degrees)."""
    out = {"pelvis": np.asarray(root, dtype=float)}
    for (a, b), length in lengths.items():
        out[b] = out[a] + length * np.array([np.cos(np.deg2rad(angles[b])), np.sin(np.deg2rad(angles[b]))])
    return out


# ---------------------------------------------------------------- examples
def ex_worm():
    outline = worm_outline()
    src = Shape.from_polygon(outline)
    tgt = src.with_vertices(bend(outline, np.deg2rad(300), 8.0))
    pair = isotween.mesh_pair(src, tgt, max_area=0.06)
    return pair.source, pair.target


def ex_bar():
    """A two-row triangle strip whose boundary ring passes through every vertex.

    Every method of `isotween compare` takes it (mesh and outline ones).
    """
    k, length, width = 30, 8.0, 0.5
    x = np.linspace(0.0, length, k)
    flat = np.r_[np.c_[x, 0 * x], np.c_[x, 0 * x + width]]
    b, t = np.arange(k), np.arange(k, 2 * k)
    faces = np.r_[np.c_[b[:-1], b[1:], t[1:]], np.c_[b[:-1], t[1:], t[:-1]]]
    src = Shape(flat, faces=faces, paths=[(np.r_[b, t[::-1]], True)])
    return src, src.with_vertices(bend(flat, np.deg2rad(270), length))


def ex_glyphs():
    return Shape.from_polygon(glyph("S")), Shape.from_polygon(glyph("5"))


def ex_holes():
    return Shape.from_polygon(glyph("B")), Shape.from_polygon(glyph("8"))


def ex_regions():
    """Two drawings with different numbers of regions and holes, stored as they are.

    `load_example` puts them in correspondence with the defaults of `isotween.correspond`.
    """
    return Shape.from_polygon(glyph("j")), Shape.from_polygon(glyph("B"))


def ex_turn():
    """'G' and the same glyph turned by 120 degrees, written with other point counts and ring starts."""
    rings = glyph("G")
    out = []
    for k, r in enumerate(rings):
        z = (r[:, 0] + 1j * r[:, 1]) * np.exp(2j * np.pi / 3) + (9 - 2j)
        knots = np.append(z, z[0])
        cum = np.r_[0, np.cumsum(np.abs(np.diff(knots)))]
        s = np.unique(np.round(np.r_[cum[:-1], np.linspace(0, cum[-1], 2 * len(r) + 7, endpoint=False)], 12))
        w = np.roll(np.interp(s, cum, knots.real) + 1j * np.interp(s, cum, knots.imag), 11 + 5 * k)
        out.append(np.c_[w.real, w.imag])
    return Shape.from_polygon(rings), Shape.from_polygon(out)


def ex_strokes():
    """Line icons: a check mark into a cross, strokes with round caps (the cross's second stroke grows out)."""
    from isotween.paint import Paint

    ink = Paint(fill=None, stroke=(0.11, 0.11, 0.11, 1.0), stroke_width=0.9)
    check = Shape.from_paths([[[1, 6], [4, 3], [10, 9]]], closed=False, regions=[], paint=[ink])
    cross = Shape.from_paths([[[1.5, 10.5], [10.5, 1.5]], [[1.5, 1.5], [10.5, 10.5]]], closed=False, regions=[],
                             paint=[ink, ink])
    return check, cross


def ex_struck():
    """Line icons: a ring, and the ring struck through, drawn as two arcs parted where the slash crosses."""
    from isotween.paint import Paint

    ink = Paint(fill=None, stroke=(0.11, 0.11, 0.11, 1.0), stroke_width=0.9)
    th = np.deg2rad(np.arange(0, 360, 6))
    ring = Shape.from_paths([np.c_[6 + 4 * np.cos(th), 6 + 4 * np.sin(th)]], closed=True, regions=[], paint=[ink])
    arcs = [np.deg2rad(np.linspace(a, a + 140, 36)) for a in (65, 245)]  # gaps of 40 degrees round 45 and 225
    ends = 6 + 5.2 * np.cos(np.deg2rad(45)) * np.array([-1, 1])
    struck = Shape.from_paths([np.c_[6 + 4 * np.cos(a), 6 + 4 * np.sin(a)] for a in arcs] + [np.c_[ends, ends]],
                              closed=False, regions=[], paint=[ink, ink, ink])
    return ring, struck


def ex_plus():
    """A plus into a minus, filled outlines with rounded ends: the minus is the plus's cross bar."""
    plus = ("M 8 1.5 A 0.75 0.75 0 0 1 8.75 2.25 L 8.75 7.25 L 13.75 7.25 A 0.75 0.75 0 0 1 13.75 8.75 "
            "L 8.75 8.75 L 8.75 13.75 A 0.75 0.75 0 0 1 7.25 13.75 L 7.25 8.75 L 2.25 8.75 "
            "A 0.75 0.75 0 0 1 2.25 7.25 L 7.25 7.25 L 7.25 2.25 A 0.75 0.75 0 0 1 8 1.5 Z")
    minus = "M 2.25 7.25 L 13.75 7.25 A 0.75 0.75 0 0 1 13.75 8.75 L 2.25 8.75 A 0.75 0.75 0 0 1 2.25 7.25 Z"
    with tempfile.TemporaryDirectory() as tmp:
        shapes = []
        for name, d in (("plus", plus), ("minus", minus)):
            path = Path(tmp) / f"{name}.svg"
            path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16"><path d="{d}"/></svg>')
            shapes.append(io.load(path))
    return shapes[0], shapes[1]


def _svg_pair(first, second, view="0 0 16 16"):
    """Two drawings read from SVG path data (a list of ``d`` strings each, one filled path per string)."""
    shapes = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, paths in (("a", first), ("b", second)):
            path = Path(tmp) / f"{name}.svg"
            path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{view}">'
                            + "".join(f'<path d="{d}"/>' for d in paths) + "</svg>")
            shapes.append(io.load(path))
    return shapes[0], shapes[1]


def ex_play():
    """Play into pause: a rounded triangle and two rounded bars, the right one only partly inside the triangle."""
    play = ["M 3.5 3.4 A 1 1 0 0 1 5 2.55 L 13.2 7.15 A 1 1 0 0 1 13.2 8.85 L 5 13.45 A 1 1 0 0 1 3.5 12.6 Z"]
    pause = [f"M {x} 4.25 A 1.25 1.25 0 0 1 {x + 1.25} 3 L {x + 2.25} 3 A 1.25 1.25 0 0 1 {x + 3.5} 4.25 "
             f"L {x + 3.5} 11.75 A 1.25 1.25 0 0 1 {x + 2.25} 13 L {x + 1.25} 13 A 1.25 1.25 0 0 1 {x} 11.75 Z"
             for x in (3.5, 8.5)]
    return _svg_pair(play, pause)


def ex_star():
    """A star drawn as an outline (a band round a hole) and filled: the same outer outline, the hole closes."""
    import shapely

    k = np.arange(10)
    r = np.where(k % 2, 3.1, 7.5)  # the tips and the inner corners
    z = 8 + 8.6j - 1j * r * np.exp(1j * np.pi * k / 5)
    star = shapely.Polygon(np.c_[z.real, z.imag]).buffer(0.5, join_style="round").buffer(-0.5)  # rounded tips
    outline = shapely.orient_polygons(star.difference(star.buffer(-1.2, join_style="mitre")))  # the hole winds back

    def d(poly):
        return " ".join("M " + " L ".join(f"{u:.4f} {v:.4f}" for u, v in np.asarray(r.coords)[:-1]) + " Z"
                        for r in [poly.exterior, *poly.interiors])

    return _svg_pair([d(outline)], [d(star)])


def ex_menu():
    """A menu into a close sign: three bars, and an X drawn as one outline (its two bars crossed)."""
    menu = [f"M 2.75 {y} L 13.25 {y} A 0.75 0.75 0 0 1 13.25 {y + 1.5} L 2.75 {y + 1.5} A 0.75 0.75 0 0 1 2.75 {y} Z"
            for y in (3.25, 7.25, 11.25)]
    r = 0.75 / np.sqrt(2)
    a, b, c = 3.5, 12.5, 8.0  # the bars run from (a, a) to (b, b) and from (b, a) to (a, b)
    corners = [(a - r, a + r), (a + r, a - r), (c, c - 2 * r), (b - r, a - r), (b + r, a + r), (c + 2 * r, c),
               (b + r, b - r), (b - r, b + r), (c, c + 2 * r), (a + r, b + r), (a - r, b - r), (c - 2 * r, c)]
    x = ["M " + " L ".join(f"{u:.4f} {v:.4f}" for u, v in corners) + " Z"]
    return _svg_pair(menu, x)


#: a padlock drawn as one filled outline with the shackle's hole, closed and open (shackle lifted, one leg free)
LOCK_BODY = "L 12.5 7 A 1.5 1.5 0 0 1 14 8.5 L 14 13.5 A 1.5 1.5 0 0 1 12.5 15 L 3.5 15 A 1.5 1.5 0 0 1 2 13.5 Z"
LOCK = {
    "closed": "M 2 8.5 A 1.5 1.5 0 0 1 3.5 7 L 3.5 5 A 4.5 4.5 0 0 1 12.5 5 " + LOCK_BODY
              + " M 5 7 L 5 5 A 3 3 0 0 1 11 5 L 11 7 Z",
    "open": "M 2 8.5 A 1.5 1.5 0 0 1 3.5 7 L 3.5 2.5 A 4.5 4.5 0 0 1 12.5 2.5 L 12.5 4.5 L 11 4.5 L 11 2.5 "
            "A 3 3 0 0 0 5 2.5 L 5 7 " + LOCK_BODY,
}


def ex_lock():
    """A padlock opens: the hole inside the closed shackle opens into the open one's notch (read as SVG drawings)."""
    shapes = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("closed", "open"):
            path = Path(tmp) / f"{name}.svg"
            path.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 -3 16 19">'
                            f'<path fill-rule="evenodd" d="{LOCK[name]}"/></svg>')
            shapes.append(io.load(path))
    return shapes[0], shapes[1]


def _svg_path(geometry):
    """SVG path data of a shapely (multi)polygon: every ring a closed polyline."""
    rings = [ring for poly in getattr(geometry, "geoms", [geometry]) for ring in [poly.exterior, *poly.interiors]]
    return " ".join("M " + " L ".join(f"{x:.4f} {y:.4f}" for x, y in np.asarray(r.coords)[:-1]) + " Z" for r in rings)


def ex_slash():
    """An eye, and the same eye struck through: the slash parts the eye, which stays where it is drawn."""
    import shapely

    t = np.linspace(0.0, 1.0, 33)[:, None]
    upper = (1 - t) ** 2 * [0, 8] + 2 * t * (1 - t) * [8, 0.5] + t ** 2 * [16, 8]  # quadratic Beziers
    lens = shapely.Polygon(np.r_[upper, upper[-2:0:-1] * [1, -1] + [0, 16]])
    eye = lens.difference(shapely.Point(8, 8).buffer(3.4, quad_segs=16))
    pupil = shapely.Point(8, 8).buffer(2.0, quad_segs=16)
    line = shapely.LineString([(1.5, 1.5), (14.5, 14.5)])
    gap, bar = line.buffer(1.2, cap_style="flat"), line.buffer(0.55, cap_style="round")
    drawings = {"eye": [eye, pupil], "slashed": [eye.difference(gap), pupil.difference(gap), bar]}
    shapes = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, parts in drawings.items():
            path = Path(tmp) / f"{name}.svg"
            body = "".join(f'<path fill-rule="evenodd" d="{_svg_path(g)}"/>' for g in parts)
            path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16">{body}</svg>')
            shapes.append(io.load(path))
    return shapes[0], shapes[1]


def ex_curls():
    a, b = curl(60, 1.6, 0.12), curl(60, 1.1, 0.12, sign=-1.0)
    straight_a = np.c_[np.arange(60) * 0.12, np.zeros(60)]
    straight_b = straight_a + [0.0, -1.2]
    src = Shape.from_polyline([straight_a, straight_b])
    tgt = Shape.from_polyline([a + [1.0, 0.6], b + [1.0, -2.0]])
    return src, tgt


def ex_hopper():
    with Image.open(DATA / "hopper.jpg") as im:
        w, h = im.size
    width, height = 4.0, 4.0 * h / w
    outline = rectangle_outline(width, height, 0.2)
    src = Shape.from_polygon(outline)
    # a wave across, then the photo's vertical axis bent by 80 degrees
    wave = np.c_[outline[:, 1], width / 2 - outline[:, 0] - 0.2 * np.sin(2.5 * outline[:, 1])]
    bent = bend(wave, np.deg2rad(80), height)
    tgt = src.with_vertices(np.c_[-bent[:, 1], bent[:, 0]])
    pair = isotween.mesh_pair(src, tgt, max_area=0.05)
    uv = (pair.source.vertices - pair.source.vertices.min(axis=0)) / [width, height]
    mesh = Shape(pair.source.vertices, faces=pair.source.faces, uv=uv, paths=pair.source.paths)
    return mesh, mesh.with_vertices(pair.target.vertices)


def ex_soup():
    lengths = {("pelvis", "neck"): 2.0, ("neck", "l_elbow"): 1.1, ("l_elbow", "l_hand"): 1.0,
               ("neck", "r_elbow"): 1.1, ("r_elbow", "r_hand"): 1.0, ("pelvis", "l_knee"): 1.3,
               ("l_knee", "l_foot"): 1.3, ("pelvis", "r_knee"): 1.3, ("r_knee", "r_foot"): 1.3}
    bones = list(lengths)
    stand = {"neck": 90, "l_elbow": 240, "l_hand": 265, "r_elbow": 300, "r_hand": 275,
             "l_knee": 255, "l_foot": 268, "r_knee": 285, "r_foot": 272}
    kick = {"neck": 100, "l_elbow": 150, "l_hand": 100, "r_elbow": 10, "r_hand": 70,
            "l_knee": 250, "l_foot": 270, "r_knee": 340, "r_foot": 10}
    shapes = []
    for angles, ball in ((stand, ((2.2, -2.4), 0.35)), (kick, ((5.2, 1.5), 0.35))):
        joints = posed(lengths, angles, (0.0, 0.0))
        neck = joints["neck"]
        direction = (neck - joints["pelvis"]) / np.linalg.norm(neck - joints["pelvis"])
        head = (tuple(neck + 0.55 * direction), 0.45)
        shapes.append(stick_figure(joints, bones, head, ball))
    return shapes[0], shapes[1]


EXAMPLES = [
    ("worm", "a worm meshed from its outline curls up by 300 degrees, head against tail",
     ex_worm, None, {"frames": 17}),
    ("bar", "a triangle strip curls by 270 degrees; every method of `isotween compare` takes it",
     ex_bar, None, {"frames": 13}),
    ("glyphs", "'S' into '5': DejaVu Sans glyph outlines with different point counts, resampled",
     ex_glyphs, 160, {"frames": 13}),
    ("holes", "'B' into '8': a polygon with two holes (outer ring and holes paired in order)",
     ex_holes, 200, {"frames": 13}),
    ("regions", "'j' into 'B' with no options: the stem becomes the B, the dot shrinks away, two holes open",
     ex_regions, "correspond", {"frames": 13}),
    ("turn", "'G' turned by 120 degrees, written with other point counts and starts: with no options every "
             "in-between is the turned glyph", ex_turn, "correspond", {"frames": 13}),
    ("strokes", "line icons with no options: a check mark becomes a cross, its second stroke growing out of the first",
     ex_strokes, "correspond", {"frames": 13}),
    ("struck", "a ring struck through with no options: the ring opens where the slash comes in, each arc staying "
               "where it is drawn", ex_struck, "correspond", {"frames": 13}),
    ("plus", "a plus into a minus with no options: the arms retract into the bar, which stays where it is drawn",
     ex_plus, "correspond", {"frames": 13}),
    ("play", "play into pause with no options: the triangle parts into the two bars",
     ex_play, "correspond", {"frames": 13}),
    ("menu", "a menu into a close sign with no options: the X is taken as its two crossed bars, which the menu's "
             "top and bottom bars turn into while the middle one fades", ex_menu, "correspond", {"frames": 13}),
    ("star", "an outline star fills with no options: the outline stays where it is while the hole closes",
     ex_star, "correspond", {"frames": 13}),
    ("lock", "a padlock opens with no options: the hole inside the shackle opens into the open lock's notch",
     ex_lock, "correspond", {"frames": 13}),
    ("slash", "an eye struck through with no options: the slash parts the eye, each half staying where it is drawn",
     ex_slash, "correspond", {"frames": 13}),
    ("curls", "two open polylines curling into spirals, one by 1.6 turns, one by 1.1 the other way",
     ex_curls, None, {"frames": 17}),
    ("hopper", "a textured mesh: Grace Hopper's photograph bends and waves",
     ex_hopper, None, {"frames": 13}),
    ("soup", "an edge soup of three components: a stick figure kicks a ball",
     ex_soup, None, {"frames": 13}),
]


def build_texture():
    """A small copy of matplotlib's sample photograph (public domain, US Navy)."""
    sample = Path(matplotlib.get_data_path()) / "sample_data" / "grace_hopper.jpg"
    out = DATA / "hopper.jpg"
    with Image.open(sample) as im:
        im.convert("RGB").resize((192, 225), Image.LANCZOS).save(out, quality=85)
    return out


#: colours of the examples drawn in colour (`isotween.outputs.with_paint` arguments)
PAINT = {"holes": {"fill": ["#c0392b", "#1f5fa8"], "stroke": "#1b1b1b", "stroke_width": 0.06}}


def main_build(only=None):
    """Build every example, or with ``only`` (a list of names) just those.

    The other examples' data files and strips are kept as they are.
    """
    if only:
        unknown = set(only) - {e[0] for e in EXAMPLES}
        if unknown:
            raise SystemExit(f"unknown example(s): {', '.join(sorted(unknown))}")
    else:
        for old in DATA.glob("*"):
            old.unlink()
    texture = DATA / "hopper.jpg" if only else build_texture()
    index = []
    for name, description, make, points, options in EXAMPLES:
        if only and name not in only:
            index.append(next(e for e in json.loads((DATA / "index.json").read_text())["examples"]
                              if e["name"] == name))
            continue
        src, tgt = make()
        io.save(src, DATA / f"{name}-source.npz")
        io.save(tgt, DATA / f"{name}-target.npz")
        entry = {"name": name, "description": description, "source": f"{name}-source.npz",
                 "target": f"{name}-target.npz", "options": options}
        if points == "correspond":
            entry["correspond"] = {}
        elif points:
            entry["resample"] = points
        if name == "hopper":
            entry["texture"] = texture.name
        if name in PAINT:
            entry["paint"] = PAINT[name]
        index.append(entry)
    (DATA / "index.json").write_text(json.dumps({"examples": index}, indent=1) + "\n")
    isotween.examples._index.cache_clear()

    GALLERY.mkdir(parents=True, exist_ok=True)
    for name in isotween.examples.names():
        if only and name not in only:
            continue
        texture = isotween.examples.example_options(name).get("texture")
        seq = with_paint(isotween.examples.interpolate_example(name), **isotween.examples.example_paint(name))
        src = seq.shape
        picked = np.unique(np.round(np.linspace(0, len(seq) - 1, 6)).astype(int))
        write_strip(seq, GALLERY / f"{name}.png", frames=picked, texture=texture, cell=200)
        if (GALLERY / f"{name}.png").stat().st_size > 140 * 1024:  # the README budget is 150 KiB a strip
            with Image.open(GALLERY / f"{name}.png") as im:
                small = im.convert("RGB").quantize(colors=64, method=Image.Quantize.MEDIANCUT)
            small.save(GALLERY / f"{name}.png", optimize=True)
        print(f"{name}: {src.n_vertices} vertices, {src.n_edges} edges, {src.n_faces} faces, "
              f"{len(seq)} frames, {(GALLERY / f'{name}.png').stat().st_size // 1024} KiB strip")
    default = isotween.examples.names()[0]
    if only and default not in only:
        return
    with tempfile.TemporaryDirectory() as tmp:
        result = CliRunner().invoke(main, ["demo", "-o", tmp, "-q"])
        assert result.exit_code == 0, result.output
        shutil.copy(Path(tmp) / f"{default}.gif", GALLERY / "demo.gif")
    print(f"isotween demo: {(GALLERY / 'demo.gif').stat().st_size // 1024} KiB GIF")


if __name__ == "__main__":
    import sys

    main_build(sys.argv[1:])
