"""CSS and Web Animations outputs: ``@keyframes`` on the ``d`` property, and the same keys as JSON.

Both draw one SVG ``<path>`` per group (`outline_groups`: a region with its
holes, or an open path) in composition pixels framed like the raster outputs
(``w x h`` from ``size``, `fit_view`), y down. Outlines are Bezier curves with
one command structure for all ticks (`fit_curves`), so browsers interpolate
``path()`` values; keys are kept only where easing between their neighbours
does not reproduce a tick (`reduce_keys`), the eases written as
``cubic-bezier()`` timing functions. Chromium and Firefox animate ``d``.
"""

import html
import json
from pathlib import Path

import numpy as np

from ..io import write_text
from ..paint import sequence_paint
from ._view import bbox_of, fit_view, image_size, sequence_frames, stroke_margin, to_pixels
from .curves import TOLERANCE
from .defaults import FILL, FILL_EDGE, FPS, SIZE, WIRE
from .keys import LINEAR, X1, X2, reduce_keys
from .keys import TOLERANCE as KEY_TOLERANCE
from .paths import PathData, compact, hex_colour, tolerance_digits
from .playback import playback_order

__all__ = ["web_animation", "css_text", "snippet_html", "waapi_data", "write_css", "write_waapi",
           "pixel_frames"]

_COLOUR_TOL = 0.5 / 255  # sRGB step below one level of 8 bits
_ALPHA_TOL = 0.004
_POINTS_TO_PX = 100.0 / 72.0  # the raster outputs draw at 100 dpi


def pixel_frames(seq, size):
    """Frames in composition pixels.

    Parameters
    ----------
    seq : Sequence
    size : int or (2,) int

    Returns
    -------
    px : (F, n, 2) float array
    width, height : int
    unit : float
        Pixels per shape unit.
    """
    frames = sequence_frames(seq)
    box = bbox_of(frames, stroke_margin(sequence_paint(seq)[1]))
    w, h = image_size(box, size)
    x0, x1, _, _ = fit_view(box, w, h)
    return to_pixels(frames, box, w, h, seq.shape.y_down), int(w), int(h), w / (x1 - x0)


def _paint_tracks(track, unit):
    """Numeric paint of one group at every tick: ``name -> (P, D) values, tolerance``."""
    out = {}
    for name in ("fill", "stroke"):
        colours = [getattr(p, name) for p in track]
        if all(c is None for c in colours):
            out[name] = None
            continue
        base = next(c for c in colours if c is not None)
        rgb = np.array([(c if c is not None else base)[:3] for c in colours])
        alpha = np.array([0.0 if c is None else c[3] * p.opacity for c, p in zip(colours, track, strict=True)])
        out[name] = (rgb, _COLOUR_TOL)
        out[f"{name}-opacity"] = (alpha[:, None], _ALPHA_TOL)
    if out["stroke"] is not None:
        width = np.array([p.stroke_width * unit if p.stroke is not None else 0.0 for p in track])
        out["stroke-width"] = (width[:, None], 0.02)
    return out


def _css_value(name, value, digits):
    if name in ("fill", "stroke"):
        return hex_colour(tuple(np.clip(value, 0, 1)) + (1.0,))
    if name == "stroke-width":
        return compact(f"{value[0]:.{digits}f}")
    return compact(f"{value[0]:.3f}")


def web_animation(seq, fps=FPS, size=SIZE, bounce=False, hold=0.0, loop=True, title=None, background=None,
                  curves=True, reduce=True, tolerance=None, key_tolerance=None):
    """Keys of every drawn group, ready for CSS or the Web Animations API.

    Parameters
    ----------
    seq : Sequence
    fps : float
        Ticks per second (`playback_order`); tick ``k`` plays at ``k / fps``.
    size : int or (2,) int
        Longest side of the drawing in px, or ``(width, height)``.
    bounce : bool
    hold : float
        Seconds on the first and the last frame.
    loop : bool
    title : str, optional
    background : matplotlib colour, optional
    curves : bool
        Bezier curves (else the polylines).
    reduce : bool
        Drop the keys that easing reproduces (else one key per tick).
    tolerance : float, optional
        Of the curves, in pixels (default 0.1 % of the composition's
        diagonal).
    key_tolerance : float, optional
        Of the keys, in pixels (default `keys.TOLERANCE`, 0.25 %, of the
        diagonal).

    Returns
    -------
    dict
        ``width``, ``height``, ``duration`` (seconds of one pass: the ticks
        and one more tick on the last), ``loop``, ``title``,
        ``background`` (``#rrggbb`` or None) and ``groups``: per group
        ``attributes`` (the values that do not change, ``d`` of the first
        tick included) and ``keys``: a list of ``{"offset", "easing",
        property: value}`` with offsets in [0, 1].
    """
    order = playback_order(len(seq), fps, hold, bounce)
    px, w, h, unit = pixel_frames(seq, size)
    if tolerance is None:
        tolerance = TOLERANCE * float(np.hypot(w, h))
    if key_tolerance is None:
        key_tolerance = KEY_TOLERANCE * float(np.hypot(w, h))
    data = PathData(seq, curves=curves, frames=px, tolerance=tolerance, relative=curves or reduce,
                    precision=tolerance_digits(tolerance) if curves or reduce else None)
    digits = data.digits
    ticks = px[np.append(order, order[-1])]  # one more tick: the last frame shows for 1 / fps
    times = np.arange(len(ticks)) / float(fps)
    duration = len(order) / float(fps)
    regions, paints = sequence_paint(seq)
    groups = []
    for g, runs in enumerate(data.runs):
        closed = any(c.closed for c in runs)
        tracks = [(np.concatenate([c.controls(ticks).reshape(len(ticks), -1) for c in runs], axis=1), key_tolerance,
                   True)]
        static, animated = {}, {}
        if paints is None:
            static = ({"fill": FILL, "fill-rule": "evenodd", "stroke": FILL_EDGE,
                       "stroke-width": compact(f"{0.5 * _POINTS_TO_PX:.3f}"), "stroke-linejoin": "round"} if closed else
                      {"fill": "none", "stroke": WIRE, "stroke-width": compact(f"{1.2 * _POINTS_TO_PX:.3f}"),
                       "stroke-linecap": "round", "stroke-linejoin": "round"})
        else:
            track = [paints[int(k)][data.first_path[g]] for k in np.append(order, order[-1])]
            static = {"fill-rule": "evenodd", "stroke-linejoin": "round", "stroke-linecap": "round"}
            for name, value in _paint_tracks(track, unit).items():
                if value is None:
                    static[name] = "none"
                elif np.ptp(value[0], axis=0).max() <= value[1]:
                    static[name] = _css_value(name, value[0][0], digits)
                else:
                    animated[name] = value[0]
                    tracks.append((value[0], value[1], False))
            if static.get("stroke") == "none":
                for name in ("stroke-opacity", "stroke-width"):
                    static.pop(name, None)
        keys, eases = reduce_keys(times, tracks, reduce=reduce)
        moving = np.ptp(tracks[0][0], axis=0).max() > 0 if len(tracks[0][0][0]) else False
        strings = data.strings(ticks[keys])
        attributes = {"d": strings[0][g], **static}
        frames = []
        for j, k in enumerate(keys.tolist()):
            key = {"offset": round(times[k] / duration, 6)}
            if j < len(eases) and not np.allclose(eases[j], LINEAR, atol=1e-4):
                y1, y2 = (round(float(y), 4) for y in eases[j])
                key["easing"] = f"cubic-bezier({X1:.4f},{y1:g},{X2:.4f},{y2:g})"
            if moving:
                key["d"] = strings[j][g]
            for name, values in animated.items():
                key[name] = _css_value(name, values[k], digits)
            frames.append(key)
        groups.append({"attributes": attributes, "keys": frames if (moving or animated) else []})
    return {"width": w, "height": h, "duration": duration, "loop": bool(loop),
            "title": title or f"isotween: {len(seq)} frames, {seq.shape.n_vertices} vertices",
            "background": None if background is None else hex_colour(background), "groups": groups}


def css_text(anim, prefix="isotween"):
    """The ``@keyframes`` rules of `web_animation` (str): class ``{prefix}-g{i}`` animates group ``i``."""
    lines = [f"/* {anim['title']}: {anim['width']} x {anim['height']} px, {anim['duration']:.6g} s."
             f" Each <path class=\"{prefix}-gN\"> of the SVG in the HTML snippet written beside this file"
             " plays keyframes isotween-gN (the d property: Chromium, Firefox). */"]
    count = "infinite" if anim["loop"] else "1 forwards"
    for i, group in enumerate(anim["groups"]):
        if not group["keys"]:
            continue
        name = f"{prefix}-g{i}"
        lines.append(f".{name} {{ animation: {name} {anim['duration']:.6g}s linear {count}; }}")
        lines.append(f"@keyframes {name} {{")
        for key in group["keys"]:
            body = []
            for prop, value in key.items():
                if prop == "offset":
                    continue
                if prop == "easing":
                    body.append(f"animation-timing-function: {value}")
                elif prop == "d":
                    body.append(f'd: path("{value}")')
                else:
                    body.append(f"{prop}: {value}")
            percent = compact(f"{100 * key['offset']:.4f}")
            lines.append(f"  {percent}% {{ {'; '.join(body)}; }}")
        lines.append("}")
    return "\n".join(lines) + "\n"


def svg_markup(anim, prefix="isotween"):
    """The inline ``<svg>`` the CSS animates (str)."""
    w, h = anim["width"], anim["height"]
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" class="{prefix}" viewBox="0 0 {w} {h}" width="{w}" '
           f'height="{h}">']
    if anim["background"]:
        out.append(f'  <rect width="{w}" height="{h}" fill="{anim["background"]}"/>')
    for i, group in enumerate(anim["groups"]):
        attrs = " ".join(f'{k}="{html.escape(v)}"' for k, v in group["attributes"].items())
        out.append(f'  <path class="{prefix}-g{i}" {attrs}/>')
    out.append("</svg>")
    return "\n".join(out)


def snippet_html(anim, css_href, prefix="isotween"):
    """A page that shows the animation: the SVG and a link to the CSS file."""
    return ("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">"
            f"<title>{html.escape(anim['title'])}</title>\n"
            f'<link rel="stylesheet" href="{html.escape(css_href)}">\n'
            "<style>body { margin: 0 }</style></head>\n<body>\n" + svg_markup(anim, prefix) + "\n</body></html>\n")


_CAMEL = {"fill-opacity": "fillOpacity", "stroke-opacity": "strokeOpacity", "stroke-width": "strokeWidth"}


def waapi_data(anim):
    """The animation for ``element.animate(keyframes, timing)``, JSON-ready.

    Returns
    -------
    dict
        ``width``, ``height``, ``background``, ``title``, ``timing``
        (``duration`` in ms, ``iterations``: None for Infinity, ``fill``)
        and ``paths``: per path its ``attributes`` and ``keyframes``
        (Web Animations form: ``offset``, ``easing``, ``d: 'path("...")'``,
        camelCase paint properties).
    """
    paths = []
    for group in anim["groups"]:
        frames = []
        for key in group["keys"]:
            frame = {}
            for prop, value in key.items():
                frame[_CAMEL.get(prop, prop)] = f'path("{value}")' if prop == "d" else value
            frames.append(frame)
        paths.append({"attributes": group["attributes"], "keyframes": frames})
    return {"width": anim["width"], "height": anim["height"], "background": anim["background"],
            "title": anim["title"],
            "timing": {"duration": round(1000 * anim["duration"], 3), "iterations": None if anim["loop"] else 1,
                       "fill": "forwards", "easing": "linear"},
            "paths": paths}


def write_css(seq, path, fps=FPS, size=SIZE, bounce=False, hold=0.0, loop=True, title=None, background=None,
              curves=True, reduce=True):
    """Write a CSS animation (``.css``) and the HTML page that uses it (``.html`` beside it).

    Parameters are those of `web_animation`. The page is named after the CSS
    file (``out.css`` -> ``out.html``) and links it.

    Returns
    -------
    list of Path
        The CSS file and the page.
    """
    path = Path(path)
    anim = web_animation(seq, fps=fps, size=size, bounce=bounce, hold=hold, loop=loop, title=title,
                         background=background, curves=curves, reduce=reduce)
    page = path.with_suffix(".html")
    write_text(path, css_text(anim))
    write_text(page, snippet_html(anim, path.name))
    return [path, page]


def write_waapi(seq, path, fps=FPS, size=SIZE, bounce=False, hold=0.0, loop=True, title=None, background=None,
                curves=True, reduce=True):
    """Write the Web Animations JSON (``.waapi.json``, `waapi_data`); parameters of `web_animation`."""
    anim = web_animation(seq, fps=fps, size=size, bounce=bounce, hold=hold, loop=loop, title=title,
                         background=background, curves=curves, reduce=reduce)
    write_text(path, json.dumps(waapi_data(anim), separators=(",", ":"), allow_nan=False))
    return [Path(path)]
