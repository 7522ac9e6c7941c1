"""``isotween transfer``, ``isotween edit`` and ``isotween keyframes``."""

import click

from . import main
from .options import (
    check_outputs,
    emit,
    frames_option,
    output_options,
    progress,
    solver_kwargs,
    solver_options,
    solver_options_for,
    timer,
)
from .prepare import correspondence_kwargs, make_keys_compatible, outline_correspondence_options


@main.command("transfer")
@click.argument("source_start")
@click.argument("source_end")
@click.argument("target_start")
@frames_option
@solver_options
@outline_correspondence_options
@output_options
def transfer_command(source_start, source_end, target_start, output, fmt, texture, plot, quiet, **params):
    """Move TARGET_START the way SOURCE_START moves into SOURCE_END (Sec. 5.1).

    Shapes that do not share connectivity are first put in correspondence
    together as outlines, and one line says what was done.
    """
    from .. import transfer
    from ..io import load

    elapsed = timer()
    check_outputs(output, fmt, texture, plot)
    paths = (source_start, source_end, target_start)
    shapes = make_keys_compatible([load(p) for p in paths], paths, quiet=quiet, role="input",
                                  **correspondence_kwargs(params))
    with progress(quiet) as callback:
        seq = transfer(*shapes, callback=callback, **solver_kwargs(params))
    emit(seq, output, fmt=fmt, texture=texture, quiet=quiet, plot=plot, seconds=elapsed())


@main.command("edit")
@click.argument("sequence")
@click.option("--frame", "-k", "frames", type=int, multiple=True, required=True,
              help="Index of an edited frame (repeat with --shape for several).")
@click.option("--shape", "shapes", multiple=True, required=True,
              help="The edited frame's shape file, one per --frame.")
@click.option("--free-ends", is_flag=True,
              help="Let the first and last frames change too (the paper's procedure).")
@output_options
def edit_command(sequence, frames, shapes, free_ends, output, fmt, texture, plot, quiet, **render):
    """Replace frames of SEQUENCE and carry the change through its motion (Sec. 5.2).

    SEQUENCE is a .npz/.json sequence file or a folder of frames.
    """
    from .. import edit
    from ..errors import ParameterError
    from ..io import load, load_sequence

    elapsed = timer()
    if len(frames) != len(shapes):
        raise ParameterError(f"give one --shape per --frame ({len(frames)} frames, {len(shapes)} shapes)")
    check_outputs(output, fmt, texture, plot)
    seq = load_sequence(sequence)
    out = edit(seq, edits={k: load(p) for k, p in zip(frames, shapes, strict=True)}, keep_ends=not free_ends)
    emit(out, output, fmt=fmt, texture=texture, quiet=quiet, plot=plot, seconds=elapsed())


@main.command("keyframes")
@click.argument("keyframes", nargs=-1, required=True)
@click.option("--frames", "-n", type=int, default=None,
              help="Total number of frames, keyframes included [default: 8 per segment + 1].")
@click.option("--times", default=None, help="Keyframe times, comma separated, from 0 to 1.")
@click.option("--easing", type=click.Choice(["linear", "ease-in", "ease-out", "ease-in-out"]),
              default="linear", show_default=True, help="Spacing of the frames in time.")
@click.option("--smooth", type=float, default=1.0, show_default=True,
              help="How strongly velocities turn smoothly through interior keyframes.")
@solver_options_for("init", "scheme", "tol", "max_iter")
@outline_correspondence_options
@output_options
def keyframes_command(keyframes, frames, times, easing, smooth, init, scheme, tol, max_iter,
                      output, fmt, texture, plot, quiet, **params):
    """AIAP through every KEYFRAME file at once (at least two).

    Keyframes that do not share connectivity are first put in
    correspondence together as outlines (each paired with the first, one
    point count per ring), and one line says what was done.
    """
    from .. import interpolate_keyframes
    from ..errors import ParameterError
    from ..io import load

    elapsed = timer()
    check_outputs(output, fmt, texture, plot)
    if times is not None:
        try:
            times = [float(x) for x in times.split(",")]
        except ValueError:
            raise ParameterError(f"--times must be numbers separated by commas, got {times!r}") from None
    shapes = make_keys_compatible([load(p) for p in keyframes], keyframes, quiet=quiet,
                                  **correspondence_kwargs(params))
    with progress(quiet) as callback:
        seq = interpolate_keyframes(shapes, times=times, frames=frames, easing=easing, smooth=smooth,
                                    init=init, scheme=scheme, tol=tol, max_iter=max_iter, callback=callback)
    emit(seq, output, fmt=fmt, texture=texture, quiet=quiet, plot=plot, seconds=elapsed())
