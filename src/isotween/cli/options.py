"""Options shared by the commands that compute a sequence, and `emit` that writes it.

Use as decorators on a click command::

    @click.command("interpolate")
    @frames_option
    @solver_options
    @output_options
    def cmd(output, fmt, texture, plot, quiet, **params): ...

and call `check_outputs` before any work, `progress` around the solve, and
`emit` at the end; `emit` reads the rendering controls (`render_options`)
from the command's parameters. Choices and defaults come from the library's
constants (`isotween.interpolate.SOLVERS`, `isotween.render.defaults`, ...).
"""

import contextlib
import math
import os
import sys
import time
from contextlib import contextmanager
from pathlib import Path

import click

from .._defaults import DEFAULT_TOL
from .._validate import is_int
from ..errors import FileFormatError, IncompatibleShapesError, require
from ..io import atomic_path
from ..outputs import FORMATS, output_kind, with_paint, write_output
from ..render.defaults import BACKGROUND, DURATION, FPS, HOLD, SIZE

__all__ = [
    "frames_option",
    "solver_options",
    "solver_options_for",
    "render_options",
    "output_options",
    "solver_kwargs",
    "check_outputs",
    "check_paths",
    "check_render_memory",
    "check_texture",
    "probe_writable",
    "ensure_compatible",
    "progress",
    "emit",
    "summary",
    "timer",
]

SOLVER_KEYS = ("frames", "solver", "init", "scheme", "tol", "max_iter", "method", "times")
#: parameters of `render_options`, passed on to `isotween.write_output`
RENDER_KEYS = ("fps", "duration", "size", "hold", "bounce", "loop", "title", "background")
PAINT_KEYS = ("fill", "stroke", "stroke_width")


def _compose(*decorators):
    def apply(func):
        for decorator in reversed(decorators):
            func = decorator(func)
        return func

    return apply


class SizeType(click.ParamType):
    """``N`` (longest side) or ``WxH`` in pixels."""

    name = "N|WxH"

    def convert(self, value, param, ctx):
        if isinstance(value, (int, tuple)):
            return value
        text = str(value).lower().strip()
        try:
            parts = [int(p) for p in text.split("x")]
        except ValueError:
            parts = []
        if len(parts) not in (1, 2) or min(parts) < 8 or max(parts) > 8192:
            self.fail(f"{value!r} is not a size: give N or WxH in pixels, each from 8 to 8192", param, ctx)
        return parts[0] if len(parts) == 1 else tuple(parts)


class ColoursType(click.ParamType):
    """``COLOUR`` or ``START:END`` (names or #rrggbb); one colour only when ``pair`` is False."""

    def __init__(self, pair=True):
        self.pair = pair
        self.name = "COLOUR[:COLOUR]" if pair else "COLOUR"

    def convert(self, value, param, ctx):
        if not isinstance(value, str):
            return value
        parts = value.split(":")
        if len(parts) > (2 if self.pair else 1) or not all(parts):
            self.fail(f"{value!r}: give one colour{' or START:END' if self.pair else ''}", param, ctx)
        from matplotlib.colors import is_color_like

        bad = [p for p in parts if not is_color_like(p)]
        if bad:
            self.fail(f"{bad[0]!r} is not a colour (use a name like 'red' or '#rrggbb')", param, ctx)
        return parts[0] if len(parts) == 1 else tuple(parts)


frames_option = click.option(
    "--frames", "-n", type=int, default=9, show_default=True,
    help="Number of frames, both inputs included.",
)


def _solver_option(key):
    from ..baselines import METHODS as BASELINES
    from ..easing import EASINGS
    from ..initialisation import INITIALISERS
    from ..interpolate import SOLVERS
    from ..optimisation.schemes import SCHEMES

    options = {
        "solver": click.option("--solver", type=click.Choice(SOLVERS), default=SOLVERS[0], show_default=True,
                               help="Per-edge local solver (Alg. 2) or one sparse system per iteration (Alg. 1)."),
        "init": click.option("--init", type=click.Choice(INITIALISERS), default=INITIALISERS[0], show_default=True,
                             help="Initial guess: edge-vector interpolation (Eqs. 12-13) or linear blending."),
        "scheme": click.option("--scheme", type=click.Choice(tuple(SCHEMES)), default="midpoint", show_default=True,
                               help="Time discretisation of the energy (Eq. 6)."),
        "tol": click.option("--tol", type=float, default=DEFAULT_TOL, show_default=True,
                            help="Stop when no vertex moves more than tol x bounding-box diagonal (Eq. 11)."),
        "max_iter": click.option("--max-iter", type=int, default=100, show_default=True, help="Iteration limit."),
        "method": click.option("--method", type=click.Choice(("aiap",) + tuple(BASELINES)), default="aiap",
                               show_default=True, help="AIAP, or a baseline method to compare with."),
        "easing": click.option("--easing", type=click.Choice(tuple(EASINGS)), default="linear", show_default=True,
                               help="Spacing of the frames in time."),
    }
    return options[key]


def solver_options_for(*keys):
    """A decorator adding the solver options named by ``keys`` (choices from the library's constants)."""
    return _compose(*(_solver_option(k) for k in keys))


def solver_options(func):
    """A decorator adding every option `isotween.interpolate` takes.

    The choices come from the solver's modules, imported here when a command is
    decorated, not when this module is (``isotween render`` does not load the solver).
    """
    return solver_options_for("solver", "init", "scheme", "tol", "max_iter", "method", "easing")(func)

render_options = _compose(
    click.option("--fps", type=click.FloatRange(0, 100, min_open=True), default=None,
                 help=f"Frames per second of animations [default: {FPS}]."),
    click.option("--size", type=SizeType(), default=None,
                 help=f"Picture size: longest side N or WxH in pixels [default: {SIZE}; strip cells 240]."),
    click.option("--duration", type=click.FloatRange(0, 3600), default=None,
                 help=f"Seconds of motion in animations other than the page; 0 plays one frame per tick "
                      f"[default: {DURATION:g}]."),
    click.option("--hold", type=click.FloatRange(0, 3600), default=None,
                 help=f"Seconds to stay on the first and the last frame [default: {HOLD:g}; the page: 0]."),
    click.option("--bounce/--no-bounce", default=None, help="Play forward then backward [default: no]."),
    click.option("--loop/--no-loop", default=None, help="Repeat forever or play once [default: loop]."),
    click.option("--title", default=None, help="Title of the page, SVG or Lottie [default: the input files]."),
    click.option("--background", type=ColoursType(pair=False), default=None,
                 help=f"Colour behind the shape [default: {BACKGROUND}]."),
    click.option("--fill", type=ColoursType(), default=None,
                 help="Fill colour, or START:END blended in Oklab (replaces the shapes' own paint)."),
    click.option("--stroke", type=ColoursType(), default=None, help="Outline colour, or START:END."),
    click.option("--stroke-width", type=click.FloatRange(0), default=None,
                 help="Outline width in shape units [default: 0.4 % of the bounding-box diagonal]."),
)

output_options = _compose(
    click.option("-o", "--output", "output", required=True,
                 help="Output: .gif .webp .apng .mp4 .svg .html .lottie.json .css .waapi.json (animation), "
                      ".png (strip), "
                      ".npz .json (sequence) or a folder of frames."),
    click.option("--format", "fmt", type=click.Choice(FORMATS), default=None,
                 help="Write one file per frame in this format into the -o folder (lottie: one Lottie .json)."),
    click.option("--texture", default=None, help="Image mapped through the shape's uv in rendered outputs."),
    click.option("--plot", default=None, help="Also plot the energy per iteration to this image file."),
    click.option("--quiet", "-q", is_flag=True, help="No progress bars."),
    render_options,
)


def solver_kwargs(params):
    """The keyword arguments of `isotween.interpolate` among a command's parameters.

    ``easing`` becomes the frame ``times`` (`isotween.easing.eased_times`).
    """
    out = {k: params[k] for k in SOLVER_KEYS if k in params and params[k] is not None}
    easing = params.get("easing")
    if easing and easing != "linear" and "frames" in out:
        from ..easing import eased_times

        out["times"] = eased_times(out["frames"], easing)
    return out


def check_outputs(output, fmt=None, texture=None, plot=None):
    """Fail before any computation when an output cannot be written.

    The output kind is remembered for `emit`, so the path is checked once.

    Returns
    -------
    str
        The kind of output (`isotween.outputs.output_kind`).

    Raises
    ------
    FileFormatError
        Unknown output kind, missing folder, missing texture image.
    """
    kind = output_kind(output, fmt)
    ctx = click.get_current_context(silent=True)
    if ctx is not None:
        ctx.meta.setdefault("isotween.kinds", {})[(str(output), fmt)] = kind
    frames = ctx.params.get("frames") if ctx is not None else None
    if is_int(frames):
        check_render_memory(output, fmt, frames)
    probe_writable(output if kind == "frames" and Path(output).is_dir() else Path(output).parent, output)
    if texture is not None:
        check_texture(texture)
    if plot is not None:
        parent = Path(plot).parent
        if not parent.is_dir():
            raise FileFormatError(f"cannot write {plot}: {parent} does not exist")
        if Path(plot).suffix.lower() not in (".png", ".pdf", ".svg"):
            raise FileFormatError(f"{plot}: the energy plot must be a .png, .pdf or .svg file")
        probe_writable(parent, plot)
    return kind


# ---------------------------------------------------------------- early path checks


def probe_writable(folder, target=None):
    """Fail unless a file can be created in ``folder`` (tried, then removed).

    Permission bits do not tell (root, read-only mounts, /proc), so a
    temporary file is created and removed.

    Raises
    ------
    FileFormatError
        Naming ``target`` (or the folder) and the reason.
    """
    import tempfile

    folder = Path(folder)
    name = target if target is not None else folder
    if not folder.is_dir():
        what = "is not a folder" if folder.exists() else "does not exist"
        raise FileFormatError(f"cannot write {name}: {folder} {what}")
    try:
        fd, tmp = tempfile.mkstemp(prefix=".isotween-probe-", dir=folder)
    except OSError as exc:
        raise FileFormatError(f"cannot write {name}: {folder} is not writable ({exc.strerror or exc})") from None
    os.close(fd)
    os.unlink(tmp)


def check_texture(texture):
    """Fail unless ``texture`` is an image file Pillow can read (header checked, not decoded).

    Raises
    ------
    FileFormatError
        Missing file, not an image, or an image too large for memory.
    """
    from ..errors import require
    from ..io._files import check_readable
    from ..resources import check_memory

    try:
        path = check_readable(texture)
    except FileFormatError as exc:
        raise FileFormatError(f"{exc} (the texture image)") from None
    image = require("PIL.Image", "cli")
    try:
        with image.open(path) as im:
            width, height = im.size
            im.verify()
    except Exception as exc:  # Pillow raises many kinds (UnidentifiedImageError, SyntaxError, bombs)
        raise FileFormatError(f"{texture}: not a readable texture image ({type(exc).__name__})") from None
    from ..render.texture import TEXTURE_BYTES_PER_PIXEL

    check_memory(TEXTURE_BYTES_PER_PIXEL * float(width) * height, f"the texture {texture} ({width} x {height} pixels)",
                 advice="use a smaller image")


def check_render_memory(output, fmt, frames, vertices=0):
    """Refuse, before any work, an output whose pixels (or vector ticks) would not fit in memory.

    The same estimate as every writer's (`isotween.resources.output_bytes`),
    with the largest image ``--size`` allows (N x N for a longest side N),
    every frame kept for GIF, WebP and APNG, the picked cells of a strip,
    and the ticks at ``--fps`` with ``--hold`` for Lottie and SVG.

    Raises
    ------
    ResourceError
    """
    from ..outputs import output_kind
    from ..resources import OUTPUT_BYTES, check_output_memory

    kind = output_kind(output, fmt)
    if kind == "frames" and str(fmt or "obj").lower() != "png":
        return
    if kind not in OUTPUT_BYTES:
        return
    ctx = click.get_current_context(silent=True)
    params = ctx.params if ctx is not None else {}
    size = params.get("size") or {"strip": 240, "frames": 600}.get(kind, SIZE)
    width, height = (size, size) if isinstance(size, int) else size
    frames = int(frames)
    if kind == "strip":
        frames = min(8, frames)
    elif kind in ("lottie", "svg"):
        fps, hold = params.get("fps") or FPS, params.get("hold") or 0.0
        frames = (2 * frames if params.get("bounce") else frames) + 2 * round(hold * fps)
    elif kind == "frames":
        frames = 1
    check_output_memory(kind, width, height, frames, output, vertices=vertices)


def check_paths(inputs, outputs):
    """Fail when an output path names one of the input files, or another output.

    Parameters
    ----------
    inputs : iterable of path-like
        Files the command reads.
    outputs : iterable of (option, path-like)
        Paths it writes, with the option that named them.

    Raises
    ------
    FileFormatError
        An output that would overwrite an input or another output of the
        same command, ``-`` (standard output is not written to), a NUL byte
        or a name longer than the file system takes.
    """
    from ..io._files import NAME_MAX, check_path_text

    def same(a, b):
        try:
            return os.path.samefile(a, b)
        except OSError:
            return os.path.abspath(a) == os.path.abspath(b)

    def exists(p):
        try:
            return p is not None and Path(p).exists()
        except (ValueError, TypeError):  # a NUL byte: the loader names it
            return False

    existing = [p for p in inputs if exists(p)]
    seen = []
    for option, out in outputs:
        if out is None:
            continue
        path = check_path_text(out)
        if str(out) == "-":
            raise FileFormatError(f"{option} -: writing to standard output is not supported; name a file or folder")
        size = len(path.name.encode("utf-8", "surrogatepass"))
        if size > NAME_MAX:
            raise FileFormatError(f"{option} {out}: the name is {size} bytes long; file systems take at most "
                                  f"{NAME_MAX}")
        for p in existing:
            if Path(out).exists() and same(out, p):
                raise FileFormatError(
                    f"{option} {out} names an input file; it would be overwritten (choose another name)")
        for other, prev in seen:
            if same(out, prev):
                raise FileFormatError(f"{option} {out} and {other} {prev} name the same file; "
                                      "one would replace the other (choose two names)")
        seen.append((option, out))


def ensure_compatible(source, target, source_path, target_path):
    """`check_compatible` with a message that names both files and the way out.

    Raises
    ------
    IncompatibleShapesError
    """
    from ..correspondence import check_compatible
    from ..interpolate import check_movable

    check_movable(source, str(source_path))
    try:
        check_compatible(source, target, names=[str(source_path), str(target_path)])
    except IncompatibleShapesError as exc:
        raise IncompatibleShapesError(
            f"{source_path} and {target_path} are not compatible: {exc}. Let correspondence run "
            "(--correspondence auto, the default), or make them compatible first with "
            f"`isotween prepare {source_path} {target_path} --points N -o DIR`"
        ) from None


@contextmanager
def progress(quiet=False, total=None, desc="iterations"):
    """A progress bar on stderr; yields the ``callback(iteration, energy, max_move)``.

    It counts iterations and shows the energy and the largest vertex move
    (the convergence measure of Eq. 11), with no time estimate: the solver
    stops when it converges, usually long before the iteration limit
    (``total`` is accepted for compatibility and not shown). The bar appears
    only for runs longer than half a second and never with ``quiet``.
    """
    if quiet:
        yield None
        return
    from tqdm import tqdm

    bar = tqdm(desc=desc, unit="it", file=sys.stderr, leave=False, delay=0.5,
               bar_format="{desc}: {n_fmt} [{elapsed}{postfix}]")

    def callback(iteration, energy, max_move):
        bar.set_postfix(energy=f"{energy:.4g}", move=f"{max_move:.2g}", refresh=False)
        bar.update(1)

    try:
        yield callback
    finally:
        bar.close()


def summary(seq, seconds, written):
    """One line: frames, vertices, iterations, the written sequence's own metrics, wall time, size, outputs.

    The metrics (docs/how-it-works.md, "Metric definitions") are measured on ``seq`` itself, so a transferred
    or edited sequence reports its own numbers, never the solver's of
    another sequence; a metric that does not apply (no faces, no edges) is
    left out rather than printed as nan.
    """
    from .. import metrics

    parts = [f"frames={len(seq)}", f"vertices={seq.shape.n_vertices}", f"edges={seq.shape.n_edges}",
             f"iterations={seq.iterations}", f"converged={'yes' if seq.converged else 'no'}"]
    if seq.shape.n_edges and len(seq) > 1:
        values = {"energy": metrics.isometric_energy(seq), "edge_dev": metrics.edge_length_deviation(seq)}
        for name, value in values.items():
            if math.isfinite(value):
                parts.append(f"{name}={value:.4g}")
    if seq.shape.n_faces:
        parts.append(f"flipped={int(metrics.flipped_faces(seq))}")
    parts.append(f"seconds={seconds:.3f}")
    if written:
        parts.append(f"size={human_size(sum(_bytes(p) for p in written))}")
    return " ".join(parts) + f" -> {', '.join(str(p) for p in written)}"


def _bytes(path):
    """Size of a written file, or of all files in a written folder (0 when missing)."""
    path = Path(path)
    if path.is_dir():
        return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())
    return path.stat().st_size if path.exists() else 0


def human_size(n):
    """Bytes as ``812B``, ``45.3kB``, ``12.1MB`` (powers of 1000).

    Examples
    --------
    >>> human_size(812), human_size(45_300), human_size(12_100_000)
    ('812B', '45.3kB', '12.1MB')
    """
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= scale:
            return f"{n / scale:.1f}{unit}"
    return f"{int(n)}B"


def _input_names(ctx):
    """File names (or the example) among the command's arguments, for a default title."""
    names = []
    for param in ctx.command.params:
        if isinstance(param, click.Argument):
            value = ctx.params.get(param.name)
            for v in value if isinstance(value, (list, tuple)) else [value]:
                if v:
                    names.append(Path(str(v)).name)
    return names


def emit(seq, out, fmt=None, texture=None, quiet=False, plot=None, seconds=None):
    """Write ``seq`` to ``out`` (a path or a list of paths) and print the summary line.

    The rendering controls (`render_options`: fps, size, hold, bounce, loop,
    title, background, fill, stroke, stroke width) are read from the running
    command's parameters, so every command with `output_options` takes them.

    Parameters
    ----------
    seq : Sequence
    out : path-like or list of path-like
    fmt : str, optional
        Frame format for a folder output.
    texture : path-like, optional
    quiet : bool
        No progress bars.
    plot : path-like, optional
        Energy plot (`isotween.render.plot_energy`).
    seconds : float, optional
        Wall time to report (measured from the command's start); defaults
        to the sequence's ``timings['total']``. The time spent writing is
        added.
    """
    started = time.perf_counter()
    ctx = click.get_current_context(silent=True)
    params = ctx.params if ctx is not None else {}
    options = {k: params.get(k) for k in RENDER_KEYS}
    if options["title"] is None and ctx is not None:
        names = _input_names(ctx)
        options["title"] = " \u2192 ".join(names) if names else None
    seq = with_paint(seq, **{k: params.get(k) for k in PAINT_KEYS})
    kinds = ctx.meta.get("isotween.kinds", {}) if ctx is not None else {}
    outs = out if isinstance(out, (list, tuple)) else [out]
    for o in outs:
        check_render_memory(o, fmt, len(seq), seq.shape.n_vertices)
    written = []
    with contextlib.ExitStack() as stack:
        if plot is not None:  # drawn first: a plot that fails leaves no output at all
            render = require("isotween.render", "cli")
            render.plot_energy(seq, stack.enter_context(atomic_path(plot)))
        try:
            for o in outs:
                written += write_output(seq, o, format=fmt, texture=texture, quiet=quiet,
                                        kind=kinds.get((str(o), fmt)), **options)
        except BaseException:
            for p in written:
                Path(p).unlink(missing_ok=True)
            raise
    if plot is not None:
        written.append(Path(plot))
    if seconds is None:
        seconds = float(seq.timings.get("total", 0.0))
    click.echo(summary(seq, seconds + time.perf_counter() - started, written))
    return written


def timer():
    """Seconds since the call, as a function (``elapsed = timer(); ...; elapsed()``)."""
    start = time.perf_counter()
    return lambda: time.perf_counter() - start
