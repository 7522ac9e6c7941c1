"""Rendering: frames on matplotlib axes, PNG strips, GIF/WebP/APNG/MP4/SVG/Lottie animations, an HTML viewer.

Everything draws through matplotlib's Agg backend (no display needed); every
file is written atomically. Submodules load on first use, so that importing
``isotween.render.defaults`` (the shared playback defaults) stays cheap.
"""

import importlib

#: public name -> submodule that defines it
_NAMES = {
    "draw_frame": "frame",
    "write_frame_png": "frame",
    "write_strip": "strip",
    "write_gif": "animation",
    "write_mp4": "animation",
    "write_webp": "animation",
    "write_apng": "animation",
    "playback_order": "playback",
    "write_html": "html",
    "write_svg_animation": "svg_animation",
    "write_lottie": "lottie",
    "write_css": "web",
    "write_waapi": "web",
    "PathData": "paths",
    "fit_curves": "curves",
    "plot_energy": "plots",
    "write_methods_figure": "comparison",
    "write_metrics_figure": "comparison",
    "compared_frames": "comparison",
    "load_texture": "texture",
    "texture_uv": "texture",
    "FPS": "defaults",
    "SIZE": "defaults",
    "BACKGROUND": "defaults",
}

__all__ = list(_NAMES)


def __getattr__(name):
    if name in _NAMES:
        value = getattr(importlib.import_module(f".{_NAMES[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_NAMES))
