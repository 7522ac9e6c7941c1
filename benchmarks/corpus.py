"""The drawing corpus of the correspondence benchmark: public filled icons, font glyphs, stroked icons.

Icons come from npm packages installed into ``benchmarks/.corpus`` on first use, with
the other tools (flubber, GSAP) (Bootstrap Icons' ``*-fill.svg``, MIT; Font Awesome
Free's solid set, CC BY 4.0; Lucide's stroked line icons from ``lucide-static``, ISC:
``fill="none"``, a 2-unit round stroke), glyphs from the DejaVu fonts that matplotlib ships, written
as filled SVG paths (nonzero rule, quadratic curves kept). Pairs are drawn with a
fixed seed.
"""

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
CACHE = HERE / ".corpus"
PACKAGES = {"bootstrap-icons": "1.13.2", "@fortawesome/fontawesome-free": "7.3.1", "flubber": "0.4.2",
            "lucide-static": "1.62.0", "gsap": "3.15.0"}

#: classic morphs, Bootstrap Icons names (without -fill.svg)
CLASSIC = [
    ("play", "pause"), ("star", "bell"), ("house", "heart"), ("circle", "square"),
    ("triangle", "circle"), ("heart", "star"), ("cloud", "sun"), ("moon", "sun"),
    ("lock", "unlock"), ("volume-up", "volume-mute"), ("mic", "mic-mute"), ("eye", "eye-slash"),
    ("bookmark", "bookmark-star"), ("chat", "envelope"), ("camera", "image"), ("person", "people"),
    ("plus-circle", "x-circle"), ("check-circle", "x-circle"), ("file", "folder"), ("cart", "bag"),
]


def install():
    """Install the npm packages (icons, flubber, GSAP) into the cache folder once."""
    marker = CACHE / "installed.json"
    if marker.exists() and json.loads(marker.read_text()) == PACKAGES:
        return CACHE
    if shutil.which("npm") is None:
        raise SystemExit("the corpus needs npm (Node.js) to install the icon sets and flubber")
    CACHE.mkdir(exist_ok=True)
    (CACHE / "package.json").write_text('{"name": "isotween-corpus", "private": true}\n')
    specs = [f"{name}@{version}" for name, version in PACKAGES.items()]
    subprocess.run(["npm", "install", "--no-audit", "--no-fund", "--silent", *specs], cwd=CACHE, check=True)
    marker.write_text(json.dumps(PACKAGES))
    return CACHE


def icons():
    """Sorted lists of filled icon files: (bootstrap, fontawesome)."""
    root = install() / "node_modules"
    bootstrap = sorted((root / "bootstrap-icons" / "icons").glob("*-fill.svg"))
    awesome = sorted((root / "@fortawesome" / "fontawesome-free" / "svgs" / "solid").glob("*.svg"))
    return bootstrap, awesome


def strokes():
    """Sorted list of Lucide's stroked icon files."""
    return sorted((install() / "node_modules" / "lucide-static" / "icons").glob("*.svg"))


def classic_pairs():
    """The classic morphs that exist in the installed Bootstrap Icons."""
    folder = install() / "node_modules" / "bootstrap-icons" / "icons"
    out = []
    for a, b in CLASSIC:
        fa, fb = folder / f"{a}-fill.svg", folder / f"{b}-fill.svg"
        if fa.exists() and fb.exists():
            out.append((fa, fb))
    return out


def _glyph_d(char, family):
    from matplotlib.font_manager import FontProperties
    from matplotlib.path import Path as MPath
    from matplotlib.textpath import TextPath

    path = TextPath((0, 0), char, size=100, prop=FontProperties(family=family))
    parts = []
    for verts, code in path.iter_segments(curves=True, simplify=False):
        xy = " ".join(f"{x:.3f} {-y:.3f}" for x, y in np.asarray(verts).reshape(-1, 2))
        if code == MPath.MOVETO:
            parts.append(f"M {xy}")
        elif code == MPath.LINETO:
            parts.append(f"L {xy}")
        elif code == MPath.CURVE3:
            parts.append(f"Q {xy}")
        elif code == MPath.CURVE4:
            parts.append(f"C {xy}")
        elif code == MPath.CLOSEPOLY:
            parts.append("Z")
    return " ".join(parts)


GLYPHS = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789&?@%$#"
FAMILIES = ("DejaVu Sans", "DejaVu Serif")


def glyphs():
    """Filled SVG files of the alphanumeric glyphs of two DejaVu families (written once)."""
    folder = CACHE / "glyphs"
    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for family in FAMILIES:
        tag = family.split()[-1].lower()
        for k, char in enumerate(GLYPHS):
            f = folder / f"{tag}-{k:02d}.svg"
            if not f.exists():
                d = _glyph_d(char, family)
                f.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="-10 -110 120 140">'
                             f'<path fill="black" d="{d}"/></svg>\n')
            out.append(f)
    return out


def pairs(n_icons=500, n_glyphs=200, seed=20261123, n_strokes=0):
    """(kind, source file, target file) pairs.

    The classic morphs, random icon pairs (each within one icon set), random glyph pairs,
    random stroked-icon pairs (kind 'stroke', within Lucide); a fixed seed. The stroked pairs
    come last and from their own generator, so the other pairs stay those of earlier runs.
    """
    rng = np.random.default_rng(seed)
    bootstrap, awesome = icons()
    out = [("classic", a, b) for a, b in classic_pairs()]
    for k in range(n_icons):
        pool = bootstrap if k % 2 == 0 else awesome
        i, j = rng.choice(len(pool), size=2, replace=False)
        out.append(("icon", pool[i], pool[j]))
    pool = glyphs()
    for _ in range(n_glyphs):
        i, j = rng.choice(len(pool), size=2, replace=False)
        out.append(("glyph", pool[i], pool[j]))
    if n_strokes:
        rng = np.random.default_rng(seed + 1)
        pool = strokes()
        for _ in range(n_strokes):
            i, j = rng.choice(len(pool), size=2, replace=False)
            out.append(("stroke", pool[i], pool[j]))
    return out
