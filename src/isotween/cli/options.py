"""Options shared by the commands that compute a sequence, and `emit` that writes it.

Use as decorators on a click command::

    @main.command("interpolate")
    @frames_option
    @solver_options
    @output_options
    def cmd(frames, solver, init, scheme, tol, max_iter, method,
            output, fmt, texture, plot, quiet): ...

and call `check_outputs` before any work, `progress` around the solve, and
`emit` at the end.
"""

import contextlib
import math
import os
import sys
import time
from contextlib import contextmanager
from pathlib import Path

import click

from ..errors import FileFormatError, IncompatibleShapesError, require
from ..io import FRAME_FORMATS, output_kind, write_output
from ..io._files import atomic_path

__all__ = [
    "frames_option",
    "solver_options",
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

SOLVER_KEYS = ("frames", "solver", "init", "scheme", "tol", "max_iter", "method")


def _compose(*decorators):
    def apply(func):
        for decorator in reversed(decorators):
            func = decorator(func)
        return func

    return apply


frames_option = click.option(
    "--frames", "-n", type=int, default=9, show_default=True,
    help="Number of frames, both inputs included.",
)

solver_options = _compose(
    click.option("--solver", type=click.Choice(["local", "global"]), default="local", show_default=True,
                 help="Per-edge local solver (Alg. 2) or one sparse system per iteration (Alg. 1)."),
    click.option("--init", type=click.Choice(["edge", "linear"]), default="edge", show_default=True,
                 help="Initial guess: edge-vector interpolation (Eqs. 12-13) or linear blending."),
    click.option("--scheme", type=click.Choice(["midpoint", "paper"]), default="midpoint", show_default=True,
                 help="Time discretisation of the energy (Eq. 6)."),
    click.option("--tol", type=float, default=5e-4, show_default=True,
                 help="Stop when no vertex moves more than tol x bounding-box diagonal (Eq. 11)."),
    click.option("--max-iter", type=int, default=100, show_default=True, help="Iteration limit."),
    click.option("--method", default="aiap", show_default=True,
                 help="aiap, or a baseline: linear, intrinsic, arap, arap-baxter, shapespace."),
)

output_options = _compose(
    click.option("-o", "--output", "output", required=True,
                 help="Output: .gif .mp4 .svg .html (animation) .png (strip) .npz .json (sequence) or a folder."),
    click.option("--format", "fmt", type=click.Choice(FRAME_FORMATS), default=None,
                 help="Write one file per frame in this format into the -o folder."),
    click.option("--texture", default=None, help="Image mapped through the shape's uv in rendered outputs."),
    click.option("--plot", default=None, help="Also plot the energy per iteration to this image file."),
    click.option("--quiet", "-q", is_flag=True, help="No progress bar."),
)


def solver_kwargs(params):
    """The keyword arguments of `isotween.interpolate` among a command's parameters."""
    return {k: params[k] for k in SOLVER_KEYS if k in params}


def check_outputs(output, fmt=None, texture=None, plot=None):
    """Fail before any computation when an output cannot be written.

    Raises
    ------
    FileFormatError
        Unknown output kind, missing folder, missing texture image.
    """
    kind = output_kind(output, fmt)
    ctx = click.get_current_context(silent=True)
    frames = ctx.params.get("frames") if ctx is not None else None
    if isinstance(frames, int) and not isinstance(frames, bool):
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
    from ..resources import check_memory

    path = Path(texture)
    if not path.is_file():
        raise FileFormatError(f"{texture}: no such texture image")
    image = require("PIL.Image", "cli")
    try:
        with image.open(path) as im:
            width, height = im.size
            im.verify()
    except Exception as exc:  # Pillow raises many kinds (UnidentifiedImageError, SyntaxError, bombs)
        raise FileFormatError(f"{texture}: not a readable texture image ({type(exc).__name__})") from None
    check_memory(16.0 * width * height, f"the texture {texture} ({width} x {height} pixels)",
                 advice="use a smaller image")


#: peak bytes per frame of a GIF: every frame is drawn (RGBA, 400 x 400 pixels) and kept,
#: with its palette image, until the file is written
GIF_BYTES_PER_FRAME = 5 * 400 * 400


def check_render_memory(output, fmt, frames):
    """Refuse a GIF of more frames than memory holds (`ResourceError`); other kinds stream or store points."""
    from ..resources import check_memory

    if output_kind(output, fmt) == "gif":
        check_memory(GIF_BYTES_PER_FRAME * float(frames), f"rendering {frames} frames into {output}",
                     advice="use fewer frames, or write .mp4, .html or a sequence file")


def check_paths(inputs, outputs):
    """Fail when an output path names one of the input files.

    Parameters
    ----------
    inputs : iterable of path-like
        Files the command reads.
    outputs : iterable of (option, path-like)
        Paths it writes, with the option that named them.

    Raises
    ------
    FileFormatError
    """
    def same(a, b):
        try:
            return os.path.samefile(a, b)
        except OSError:
            return os.path.abspath(a) == os.path.abspath(b)

    existing = [p for p in inputs if p is not None and Path(p).exists()]
    for option, out in outputs:
        if out is None:
            continue
        for p in existing:
            if Path(out).exists() and same(out, p):
                raise FileFormatError(f"{option} {out} names an input file; it would be overwritten (choose another name)")


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
            f"{source_path} and {target_path} are not compatible: {exc}. Make them compatible first, "
            f"e.g. `isotween prepare {source_path} {target_path} --resample N` "
            "(same vertex count N and connectivity for both)"
        ) from None


@contextmanager
def progress(quiet=False, total=None, desc="iterations"):
    """A progress bar on stderr; yields the ``callback(iteration, energy, max_move)``.

    The bar appears only for runs longer than half a second and never with
    ``quiet``.
    """
    if quiet:
        yield None
        return
    from tqdm import tqdm

    bar = tqdm(total=total, desc=desc, unit="it", file=sys.stderr, leave=False, delay=0.5)

    def callback(iteration, energy, max_move):
        bar.set_postfix(energy=f"{energy:.4g}", move=f"{max_move:.2g}", refresh=False)
        bar.update(1)

    try:
        yield callback
    finally:
        bar.close()


def summary(seq, seconds, written):
    """One line: frames, vertices, edges, iterations, converged, energy, seconds, outputs.

    The energy is measured on the frames written (`isotween.metrics.isometric_energy`),
    whatever method made them.
    """
    from ..metrics import isometric_energy

    energy = isometric_energy(seq) if len(seq) >= 2 else math.nan
    return (
        f"frames={len(seq)} vertices={seq.shape.n_vertices} edges={seq.shape.n_edges} "
        f"iterations={seq.iterations} converged={'yes' if seq.converged else 'no'} "
        f"energy={energy:.4g} seconds={seconds:.3f} -> {', '.join(str(p) for p in written)}"
    )


def emit(seq, out, fmt=None, texture=None, quiet=False, plot=None, seconds=None):
    """Write ``seq`` to ``out`` (a path or a list of paths) and print the summary line.

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
        Time to report; defaults to the sequence's ``timings['total']``.
    """
    outs = out if isinstance(out, (list, tuple)) else [out]
    for o in outs:
        check_render_memory(o, fmt, len(seq))
    written = []
    with contextlib.ExitStack() as stack:
        if plot is not None:  # drawn first: a plot that fails leaves no output at all
            render = require("isotween.render", "cli")
            render.plot_energy(seq, stack.enter_context(atomic_path(plot)))
        try:
            for o in outs:
                written += write_output(seq, o, format=fmt, texture=texture, quiet=quiet)
        except BaseException:
            for p in written:
                Path(p).unlink(missing_ok=True)
            raise
    if plot is not None:
        written.append(Path(plot))
    if seconds is None:
        seconds = float(seq.timings.get("total", math.nan))
    click.echo(summary(seq, seconds, written))
    return written


def timer():
    """Seconds since the call, as a function (``elapsed = timer(); ...; elapsed()``)."""
    start = time.perf_counter()
    return lambda: time.perf_counter() - start
