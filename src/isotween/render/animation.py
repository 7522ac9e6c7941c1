"""Animated raster outputs: GIF, animated WebP and APNG (Pillow), MP4 (imageio-ffmpeg).

Every writer takes the same playback controls (`playback_order`): frames per
second, a hold at both ends, bounce, loop, size and background.
"""

import numpy as np

from .. import errors
from ..errors import ParameterError
from ..io import atomic_path
from ._frames import SequenceRenderer
from .defaults import BACKGROUND, FPS, SIZE

__all__ = ["write_gif", "write_mp4", "write_webp", "write_apng", "playback_order", "FPS", "SIZE"]


def check_fps(fps):
    """Raise `ParameterError` unless ``fps`` is in (0, 100]."""
    if isinstance(fps, bool) or not isinstance(fps, (int, float, np.number)) or not np.isfinite(fps) \
            or fps <= 0 or fps > 100:
        raise ParameterError(f"fps must be a number in (0, 100], got {fps!r}")


def playback_order(n, fps=FPS, hold=0.0, bounce=False):
    """Which frame is shown at each tick of ``1 / fps`` seconds.

    Parameters
    ----------
    n : int
        Frames in the sequence.
    fps : float
    hold : float
        Seconds the first and the last frame stay on screen (each end; with
        ``bounce`` the turning point holds too), on top of their own tick.
    bounce : bool
        Play forward then backward (``2 n - 2`` ticks before holds).

    Returns
    -------
    (P,) int array
        Frame index of every tick.
    """
    check_fps(fps)
    if not np.isfinite(hold) or hold < 0:
        raise ParameterError(f"hold must be a number of seconds >= 0, got {hold!r}")
    extra = int(round(hold * fps))
    forward = np.arange(n)
    ends = lambda k: np.full(extra, k, dtype=np.int64)  # noqa: E731
    parts = [ends(0), forward, ends(n - 1)]
    if bounce and n > 2:
        parts += [forward[-2:0:-1]]
    return np.concatenate(parts).astype(np.int64)


def _render(renderer, order, progress):
    """RGB images of the distinct frames in ``order`` (dict index -> (H, W, 3) uint8)."""
    needed = np.unique(order)
    if progress:
        from tqdm import tqdm

        needed = tqdm(needed, desc="rendering", unit="frame", leave=False, delay=0.5)
    return {int(k): renderer.image(int(k)) for k in needed}


def _pillow_frames(seq, fps, size, texture, bounce, hold, background, style, progress):
    from PIL import Image

    renderer = SequenceRenderer(seq, size, texture=texture, style=style, background=background)
    order = playback_order(len(renderer), fps, hold, bounce)
    rgb = _render(renderer, order, progress)
    return Image, rgb, order


def write_gif(seq, path, fps=FPS, size=SIZE, texture=None, loop=True, bounce=False, style="auto", *,
              hold=0.0, background=BACKGROUND, progress=False):
    """Write every frame of a sequence as an animated GIF.

    All frames are drawn over the bounding box of the whole sequence, so the
    motion is visible. Identical consecutive images are merged by Pillow into
    one longer frame (the timing stays right). GIF stores delays in 1/100 s.

    Parameters
    ----------
    seq : Sequence
    path : str or os.PathLike
    fps : float
        Frames per second.
    size : int or (2,) int
        Longest side in pixels, or ``(width, height)``.
    texture : path or (H, W, 3|4) array, optional
        Image warped through every frame (meshes only).
    loop : bool
        Repeat forever; otherwise play once.
    bounce : bool
        Play forward then backward.
    style : str
        See `draw_frame`.
    hold : float
        Seconds to stay on the first and last frame.
    background : matplotlib colour
    progress : bool
        Progress bar on stderr while rendering.
    """
    Image, rgb, order = _pillow_frames(seq, fps, size, texture, bounce, hold, background, style, progress)
    keys = sorted(rgb)
    # one palette for the whole animation, from a montage of up to 16 frames (paint colours included)
    sample = [keys[i] for i in np.unique(np.linspace(0, len(keys) - 1, min(16, len(keys))).round().astype(int))]
    montage = Image.fromarray(np.concatenate([rgb[k] for k in sample], axis=0))
    palette = montage.quantize(colors=256, method=Image.Quantize.FASTOCTREE)
    frames = {k: Image.fromarray(img).quantize(palette=palette, dither=Image.Dither.NONE) for k, img in rgb.items()}
    images = [frames[int(k)] for k in order]
    options = {"save_all": True, "append_images": images[1:], "duration": max(10, round(1000 / fps)), "disposal": 1}
    if loop:
        options["loop"] = 0
    with atomic_path(path) as tmp:
        images[0].save(tmp, format="GIF", **options)


def write_webp(seq, path, fps=FPS, size=SIZE, texture=None, loop=True, bounce=False, style="auto", *,
               hold=0.0, background=BACKGROUND, progress=False, quality=90):
    """Write a sequence as an animated WebP (Pillow; lossy at ``quality``, or lossless at 100).

    Parameters are those of `write_gif`; ``quality`` in [0, 100].
    """
    if not 0 <= quality <= 100:
        raise ParameterError(f"quality must be in [0, 100], got {quality!r}")
    images, durations = _pillow_images(seq, fps, size, texture, bounce, hold, background, style, progress)
    with atomic_path(path) as tmp:
        images[0].save(tmp, format="WEBP", save_all=True, append_images=images[1:], duration=durations,
                       loop=0 if loop else 1, lossless=quality >= 100, quality=int(quality), method=4)


def write_apng(seq, path, fps=FPS, size=SIZE, texture=None, loop=True, bounce=False, style="auto", *,
               hold=0.0, background=BACKGROUND, progress=False):
    """Write a sequence as an animated PNG (APNG, lossless; Pillow).

    Parameters are those of `write_gif`. Plays in every current browser;
    viewers without APNG support show the first frame.
    """
    images, durations = _pillow_images(seq, fps, size, texture, bounce, hold, background, style, progress)
    with atomic_path(path) as tmp:
        images[0].save(tmp, format="PNG", save_all=True, append_images=images[1:], duration=durations,
                       loop=0 if loop else 1, disposal=0, blend=0)


def write_mp4(seq, path, fps=FPS, size=SIZE, texture=None, style="auto", *, bounce=False, hold=0.0,
              background=BACKGROUND, progress=False, loop=True):
    """Write every frame of a sequence as an H.264 MP4 video.

    Needs the ``video`` extra (imageio-ffmpeg). Pixel sizes are rounded up to
    even numbers, as the yuv420p encoder requires. ``loop`` is accepted for a
    common signature; whether a video repeats is up to its player.

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
    bounce, hold, background, progress
        See `write_gif`.
    """
    imageio_ffmpeg = errors.require("imageio_ffmpeg", "video")
    renderer = SequenceRenderer(seq, size, texture=texture, style=style, even=True, background=background)
    order = playback_order(len(renderer), fps, hold, bounce)
    rgb = _render(renderer, order, progress)
    with atomic_path(path) as tmp:
        writer = imageio_ffmpeg.write_frames(
            str(tmp),
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
            for k in order:
                writer.send(np.ascontiguousarray(rgb[int(k)]))
        finally:
            writer.close()


def _pillow_images(seq, fps, size, texture, bounce, hold, background, style, progress):
    """Pillow images in playing order and their durations (animated WebP and APNG).

    Durations are integer milliseconds whose running sum stays on the 1/fps grid.
    """
    image, rgb, order = _pillow_frames(seq, fps, size, texture, bounce, hold, background, style, progress)
    images = [image.fromarray(rgb[int(k)]) for k in order]
    durations = np.diff(np.round(np.arange(len(images) + 1) * 1000.0 / fps)).astype(int).tolist()
    return images, durations
