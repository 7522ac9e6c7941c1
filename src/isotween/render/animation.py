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
from .playback import playback_order

__all__ = ["write_gif", "write_mp4", "write_webp", "write_apng", "playback_order", "FPS", "SIZE"]

#: longest a single image may stay on screen in each format (milliseconds): GIF delays are 16-bit counts
#: of 1/100 s, APNG's 16-bit counts of 1/1000 s (as Pillow writes them), WebP's 24-bit milliseconds
FRAME_MS_LIMIT = {"gif": 655_350, "apng": 65_535, "webp": 16_777_215}


def check_timing(kind, durations, order=None, rgb=None):
    """Refuse an animation whose image would stay on screen longer than its format can say.

    Pillow merges consecutive identical images into one longer one, so the
    durations of each run of identical images (same frame, or the same
    pixels) are summed first.

    Parameters
    ----------
    kind : {'gif', 'apng', 'webp'}
    durations : (P,) array_like
        Milliseconds of every tick.
    order : (P,) int array, optional
        Frame of every tick (default: all different).
    rgb : dict, optional
        Frame index -> image, to merge different frames with the same pixels.

    Raises
    ------
    ParameterError
        Naming the longest run, the limit and what to change.
    """
    durations = np.asarray(durations, dtype=np.float64)
    if order is not None and len(order):
        order = np.asarray(order)
        same = order[1:] == order[:-1]
        if rgb is not None:
            changed = np.flatnonzero(~same)
            for i in changed:
                a, b = rgb[int(order[i])], rgb[int(order[i + 1])]
                same[i] = a.shape == b.shape and np.array_equal(a, b)
        starts = np.flatnonzero(np.r_[True, ~same])
        durations = np.add.reduceat(durations, starts) if len(durations) else durations
    longest = float(durations.max(initial=0.0))
    limit = FRAME_MS_LIMIT[kind]
    if not np.isfinite(longest) or longest > limit:
        raise ParameterError(
            f"in a {kind.upper()} file an image can stay at most {limit / 1000:g} s on screen, but one would stay "
            f"{longest / 1000:.4g} s; raise the frame rate (fps) or shorten the hold")


def _render(renderer, order, progress):
    """RGB images of the distinct frames in ``order`` (dict index -> (H, W, 3) uint8)."""
    needed = np.unique(order)
    if progress:
        from tqdm import tqdm

        needed = tqdm(needed, desc="rendering", unit="frame", leave=False, delay=0.5)
    return {int(k): renderer.image(int(k)) for k in needed}


def _pillow_frames(seq, fps, size, texture, bounce, hold, background, style, progress, kind):
    from PIL import Image

    renderer = SequenceRenderer(seq, size, texture=texture, style=style, background=background, kind=kind)
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
    Image, rgb, order = _pillow_frames(seq, fps, size, texture, bounce, hold, background, style, progress, "gif")
    keys = sorted(rgb)
    # one palette for the whole animation, from a montage of up to 16 frames (paint colours included)
    sample = [keys[i] for i in np.unique(np.linspace(0, len(keys) - 1, min(16, len(keys))).round().astype(int))]
    montage = Image.fromarray(np.concatenate([rgb[k] for k in sample], axis=0))
    palette = montage.quantize(colors=256, method=Image.Quantize.FASTOCTREE)
    frames = {k: Image.fromarray(img).quantize(palette=palette, dither=Image.Dither.NONE) for k, img in rgb.items()}
    images = [frames[int(k)] for k in order]
    tick = max(10, round(1000 / fps))
    check_timing("gif", np.full(len(order), float(tick)), order, rgb)
    options = {"save_all": True, "append_images": images[1:], "duration": tick, "disposal": 1}
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
    images, durations = _pillow_images(seq, fps, size, texture, bounce, hold, background, style, progress, "webp")
    with atomic_path(path) as tmp:
        images[0].save(tmp, format="WEBP", save_all=True, append_images=images[1:], duration=durations,
                       loop=0 if loop else 1, lossless=quality >= 100, quality=int(quality), method=4)


def write_apng(seq, path, fps=FPS, size=SIZE, texture=None, loop=True, bounce=False, style="auto", *,
               hold=0.0, background=BACKGROUND, progress=False):
    """Write a sequence as an animated PNG (APNG, lossless; Pillow).

    Parameters are those of `write_gif`. Plays in every current browser;
    viewers without APNG support show the first frame.
    """
    images, durations = _pillow_images(seq, fps, size, texture, bounce, hold, background, style, progress, "apng")
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
    renderer = SequenceRenderer(seq, size, texture=texture, style=style, even=True, background=background,
                                kind="mp4")
    order = playback_order(len(renderer), fps, hold, bounce)
    with atomic_path(path) as tmp:
        _encode(imageio_ffmpeg.get_ffmpeg_exe(), renderer, order, fps, tmp, path, progress)


def _encode(exe, renderer, order, fps, tmp, path, progress):
    """Stream the frames of ``order`` to ffmpeg (H.264 in MP4); a failing ffmpeg fails the write.

    Frames are drawn as they are sent (one in memory). ffmpeg's messages go
    to a temporary file, and its exit status is checked: a full disk or a
    rejected frame rate raises `FileFormatError` with ffmpeg's last message.
    """
    import subprocess
    import tempfile
    from fractions import Fraction

    from ..errors import FileFormatError

    rate = Fraction(float(fps)).limit_denominator(1001)
    if rate <= 0:
        raise ParameterError(f"fps {fps!r} is too small for a video (at least 1/1001)")
    cmd = [exe, "-y", "-nostdin", "-f", "rawvideo", "-vcodec", "rawvideo", "-s", f"{renderer.width}x{renderer.height}",
           "-pix_fmt", "rgb24", "-r", str(rate), "-i", "-", "-an", "-vcodec", "libx264", "-pix_fmt", "yuv420p",
           "-crf", "25", "-v", "error", "-f", "mp4", str(tmp)]
    ticks = order
    if progress:
        from tqdm import tqdm

        ticks = tqdm(order, desc="rendering", unit="frame", leave=False, delay=0.5)
    with tempfile.TemporaryFile() as log:
        proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=log)
        try:
            last, image = None, None
            for k in ticks:
                if k != last:
                    last, image = k, np.ascontiguousarray(renderer.image(int(k)))
                try:
                    proc.stdin.write(image.tobytes())
                except (BrokenPipeError, OSError):
                    break  # ffmpeg ended early: its status and message say why
            try:
                proc.stdin.close()
            except OSError:
                pass
            code = proc.wait()
        except BaseException:
            proc.kill()
            proc.wait()
            raise
        log.seek(0)
        lines = [line.strip() for line in log.read().decode("utf-8", "replace").splitlines() if line.strip()]
    if code != 0 or lines:
        import signal

        if lines:
            why = lines[-1]
        elif code < 0 and -code in signal.valid_signals():
            why = f"killed by {signal.Signals(-code).name}"
            why += ", the file size limit" if -code == signal.SIGXFSZ else ""
        else:
            why = f"exit status {code}"
        raise FileFormatError(f"cannot write {path}: ffmpeg failed ({why[:200]})")


def _pillow_images(seq, fps, size, texture, bounce, hold, background, style, progress, kind):
    """Pillow images in playing order and their durations (animated WebP and APNG).

    Durations are integer milliseconds whose running sum stays on the 1/fps grid.
    """
    image, rgb, order = _pillow_frames(seq, fps, size, texture, bounce, hold, background, style, progress, kind)
    durations = np.diff(np.round(np.arange(len(order) + 1) * 1000.0 / fps))
    check_timing(kind, durations, order, rgb if kind == "apng" else None)  # Pillow merges identical APNG images
    distinct = {k: image.fromarray(rgb.pop(k)) for k in sorted(rgb)}  # one image per frame, repeated by reference
    images = [distinct[int(k)] for k in order]
    return images, durations.astype(int).tolist()
