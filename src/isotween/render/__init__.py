"""Rendering: frames on matplotlib axes, PNG strips, GIF/WebP/APNG/MP4/SVG/Lottie animations, an HTML viewer.

Everything draws through matplotlib's Agg backend (no display needed); every
file is written atomically.
"""

from .animation import FPS, SIZE, playback_order, write_apng, write_gif, write_mp4, write_webp
from .frame import draw_frame, write_frame_png
from .html import write_html
from .lottie import write_lottie
from .plots import plot_energy
from .strip import write_strip
from .svg_animation import write_svg_animation
from .texture import load_texture, texture_uv

__all__ = [
    "draw_frame",
    "write_frame_png",
    "write_strip",
    "write_gif",
    "write_mp4",
    "write_webp",
    "write_apng",
    "playback_order",
    "FPS",
    "SIZE",
    "write_html",
    "write_lottie",
    "write_svg_animation",
    "plot_energy",
    "load_texture",
    "texture_uv",
]
