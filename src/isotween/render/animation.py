"""Animated outputs: GIF (Pillow) and MP4 (imageio-ffmpeg)."""

import numpy as np

from .. import errors
from ..errors import ParameterError
from ..io._files import atomic_path
from ._frames import SequenceRenderer

__all__ = ["write_gif", "write_mp4"]


def _check_fps(fps):
    if not np.isfinite(fps) or fps <= 0 or fps > 100:
        raise ParameterError(f"fps must be in (0, 100], got {fps!r}")


def write_gif(seq, path, fps=12, size=400, texture=None, loop=True, bounce=False, style="auto"):
    """Write every frame of a sequence as an animated GIF.

    All frames are drawn over the bounding box of the whole sequence, so the
    motion is visible. Identical consecutive images are merged by Pillow into
    one longer frame (the timing stays right).

    Parameters
    ----------
    seq : Sequence
    path : str or os.PathLike
    fps : float
        Frames per second (GIF delays are stored in 1/100 s).
    size : int or (2,) int
        Longest side in pixels, or ``(width, height)``.
    texture : path or (H, W, 3|4) array, optional
        Image warped through every frame (meshes only).
    loop : bool
        Repeat forever; otherwise play once.
    bounce : bool
        Play forward then backward (``2 F - 2`` frames).
    style : str
        See `draw_frame`.
    """
    from PIL import Image

    _check_fps(fps)
    renderer = SequenceRenderer(seq, size, texture=texture, style=style)
    order = list(range(len(renderer)))
    if bounce:
        order += order[-2:0:-1]
    rgb = [renderer.image(k) for k in range(len(renderer))]
    # one palette for the whole animation, from a montage of up to 8 frames
    sample = np.unique(np.linspace(0, len(rgb) - 1, min(8, len(rgb))).round().astype(int))
    montage = Image.fromarray(np.concatenate([rgb[k] for k in sample], axis=0))
    palette = montage.quantize(colors=256, method=Image.Quantize.FASTOCTREE)
    frames = [Image.fromarray(img).quantize(palette=palette, dither=Image.Dither.NONE) for img in rgb]
    images = [frames[k] for k in order]
    options = {"save_all": True, "append_images": images[1:], "duration": max(10, round(1000 / fps)), "disposal": 1}
    if loop:
        options["loop"] = 0
    with atomic_path(path) as tmp:
        images[0].save(tmp, format="GIF", **options)


def write_mp4(seq, path, fps=24, size=480, texture=None, style="auto"):
    """Write every frame of a sequence as an H.264 MP4 video.

    Needs the ``video`` extra (imageio-ffmpeg). Pixel sizes are rounded up to
    even numbers, as the yuv420p encoder requires.

    Parameters
    ----------
    seq : Sequence
    path : str or os.PathLike
    fps : float
    size : int or (2,) int
        Longest side in pixels, or ``(width, height)``.
    texture : path or (H, W, 3|4) array, optional
    style : str
        See `draw_frame`.
    """
    imageio_ffmpeg = errors.require("imageio_ffmpeg", "video")
    _check_fps(fps)
    renderer = SequenceRenderer(seq, size, texture=texture, style=style, even=True)
    with atomic_path(path) as tmp:
        writer = imageio_ffmpeg.write_frames(
            tmp,
            (renderer.width, renderer.height),
            fps=fps,
            codec="libx264",
            pix_fmt_in="rgb24",
            pix_fmt_out="yuv420p",
            macro_block_size=2,
            ffmpeg_log_level="error",
            output_params=["-f", "mp4"],
        )
        writer.send(None)
        try:
            for k in range(len(renderer)):
                writer.send(np.ascontiguousarray(renderer.image(k)))
        finally:
            writer.close()
