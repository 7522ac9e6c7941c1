"""Memory guards: estimate what a run needs and refuse it before allocating.

The limit is the memory available now (``MemAvailable`` in /proc/meminfo, or
the physical memory where that file does not exist), unless a caller gives
``max_memory`` (bytes) or runs inside :func:`memory_limit` (the command
line's ``--max-memory``).
"""

import contextlib
import contextvars
import os

from .errors import ParameterError, ResourceError

__all__ = ["available_memory", "memory_limit", "check_memory", "solve_bytes", "parse_size", "format_size",
           "output_bytes", "check_output_memory", "OUTPUT_BYTES"]

_LIMIT = contextvars.ContextVar("isotween_memory_limit", default=None)
_UNITS = {"": 1, "b": 1, "k": 1 << 10, "kb": 1 << 10, "m": 1 << 20, "mb": 1 << 20,
          "g": 1 << 30, "gb": 1 << 30, "t": 1 << 40, "tb": 1 << 40}


def available_memory():
    """Bytes of memory available to a new allocation (int).

    ``MemAvailable`` from /proc/meminfo (Linux); elsewhere the physical
    memory (``os.sysconf``); 8 GiB when neither can be read. A limit on the
    address space (``ulimit -v``, ``RLIMIT_AS``) lowers it to what is left
    of that limit.
    """
    free = _meminfo("/proc/meminfo", "MemAvailable:")
    if free is None:
        try:
            free = int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
        except (AttributeError, ValueError, OSError):
            free = 8 << 30
    try:
        import resource

        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    except (ImportError, OSError, ValueError):
        soft = -1
    if soft not in (-1, getattr(resource, "RLIM_INFINITY", -1)):
        used = _meminfo("/proc/self/status", "VmSize:") or 0
        free = min(free, max(soft - used, 0))
    return free


def _meminfo(path, key):
    """Bytes of the ``key`` line (in kB) of a /proc file, or None."""
    try:
        with open(path, encoding="ascii") as fh:
            for line in fh:
                if line.startswith(key):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def parse_size(text):
    """Bytes of a size such as ``512M``, ``4G``, ``2.5GB`` or ``1000000`` (int).

    Raises
    ------
    ParameterError
        Not a positive size.
    """
    s = str(text).strip().lower().replace(" ", "")
    num = s.rstrip("kmgtb")
    unit = s[len(num):]
    try:
        value = float(num) * _UNITS[unit]
    except (ValueError, KeyError):
        raise ParameterError(f"--max-memory takes a size such as 512M, 4G or 2.5GB, got {text!r}") from None
    if not value > 0 or value != value or value == float("inf"):
        raise ParameterError(f"--max-memory must be a positive size, got {text!r}")
    return int(value)


def format_size(nbytes):
    """``nbytes`` in the largest fitting binary unit, e.g. ``'15.7 GiB'``."""
    value = float(nbytes)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if value < 1024 or unit == "PiB":
            return f"{value:.0f} {unit}" if unit == "B" else f"{value:.1f} {unit}"
        value /= 1024
    return f"{value:.1f} PiB"  # pragma: no cover


@contextlib.contextmanager
def memory_limit(nbytes):
    """Within the block, `check_memory` uses ``nbytes`` as the limit (None: available memory)."""
    token = _LIMIT.set(nbytes)
    try:
        yield
    finally:
        _LIMIT.reset(token)


def check_memory(nbytes, what, max_memory=None, advice="use fewer frames or vertices"):
    """Raise `ResourceError` when ``nbytes`` exceed the memory limit.

    Parameters
    ----------
    nbytes : int or float
        Estimated peak bytes of the step.
    what : str
        The step, as the message names it (e.g. ``"interpolating 1000000000 frames of 4 vertices"``).
    max_memory : int, optional
        Limit in bytes; default the :func:`memory_limit` in force, else
        :func:`available_memory`.
    advice : str
        What to change, as the message suggests it.
    """
    if max_memory is not None and (isinstance(max_memory, bool) or not max_memory > 0):
        raise ParameterError(f"max_memory must be a positive number of bytes, got {max_memory!r}")
    limit = max_memory if max_memory is not None else _LIMIT.get()
    source = "the limit" if limit is not None else "the available memory"
    if limit is None:
        limit = available_memory()
    if nbytes > limit:
        raise ResourceError(
            f"{what} needs about {format_size(nbytes)}, more than {source} ({format_size(limit)}); "
            f"{advice}, or raise the limit with --max-memory (max_memory=)"
        )


def solve_bytes(frames, n_vertices, n_edges):
    """Estimated peak bytes of an interpolation (float).

    Per frame: the vertex positions (complex, current and previous), the
    output frames, and about five complex arrays over the edges (current,
    next, fitted speeds, normal equations). Measured peaks (numpy path, a
    ring, 2,000-20,000 frames) were 131-134 bytes per frame and vertex
    against 144 estimated here; the numba path needs less (69-84).
    """
    return float(frames) * (64.0 * n_vertices + 80.0 * n_edges)


#: peak bytes of writing each kind of output, as (per pixel of every frame kept in memory, per pixel once,
#: per vertex of every tick). Measured peaks over the interpreter's (800 x 420 px, 40-60 frames, Pillow 11,
#: matplotlib 3.9) per pixel and frame: GIF 8.2, WebP 8.7, APNG 11.0; MP4 (2000 x 1040 px, frames streamed to
#: ffmpeg, x264's look-ahead included) 220 per pixel; Lottie 2,290 and SVG 226 bytes per vertex and tick.
#: The once-only part is the drawing canvas (RGBA, with matplotlib's buffers) and the encoder's.
OUTPUT_BYTES = {
    "gif": (10, 64, 0),
    "webp": (10, 64, 0),
    "apng": (12, 64, 0),
    "mp4": (0, 240, 0),  # frames stream to ffmpeg, one at a time
    "strip": (8, 48, 0),  # the sheet of the picked cells
    "frames": (0, 48, 0),  # one PNG per frame, one at a time
    "image": (0, 48, 0),
    "lottie": (0, 0, 2500),
    "svg": (0, 0, 300),
}


def output_bytes(kind, width, height, frames, vertices=0):
    """Estimated peak bytes of writing ``frames`` images of ``width`` x ``height`` pixels as ``kind`` (float).

    Parameters
    ----------
    kind : str
        A key of `OUTPUT_BYTES` (other kinds: 0).
    width, height : int
        Pixels of one image (for a strip: of one cell).
    frames : int
        Images kept in memory (distinct frames; picked cells of a strip), or
        ticks of a vector animation.
    vertices : int
        Vertices per frame (vector animations).
    """
    per_frame, once, per_vertex = OUTPUT_BYTES.get(kind, (0, 0, 0))
    pixels = float(width) * float(height)
    return pixels * (per_frame * float(frames) + once) + per_vertex * float(frames) * float(vertices)


def check_output_memory(kind, width, height, frames, what, vertices=0):
    """`check_memory` of `output_bytes`, naming the image size and frame count.

    Raises
    ------
    ResourceError
    """
    nbytes = output_bytes(kind, width, height, frames, vertices)
    if OUTPUT_BYTES.get(kind, (0, 0, 0))[2]:
        step = f"writing {frames} ticks of {vertices} vertices into {what}"
        advice = "use fewer frames or vertices, a lower fps or a shorter hold"
    else:
        step = f"rendering {frames} frames of {width} x {height} pixels into {what}"
        advice = "use fewer frames or a smaller size" + (
            ", or write .mp4, .html or a sequence file" if kind in ("gif", "webp", "apng", "strip") else "")
    check_memory(nbytes, step, advice=advice)
