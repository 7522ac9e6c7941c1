"""``isotween keyframes``: AIAP through several keyframes at once."""

import click

from .options import check_outputs, emit, output_options, progress, solver_options_for, timer
from .prepare import keys_options, outline_correspondence_options, report_correspondence


@click.command("keyframes")
@click.argument("keyframes", nargs=-1, required=True)
@click.option("--frames", "-n", type=int, default=None,
              help="Total number of frames, keyframes included [default: 8 per segment + 1].")
@click.option("--times", default=None, help="Keyframe times, comma separated, from 0 to 1.")
@click.option("--easing", type=click.Choice(["linear", "ease-in", "ease-out", "ease-in-out"]),
              default="linear", show_default=True, help="Spacing of the frames in time.")
@click.option("--smooth", type=float, default=1.0, show_default=True,
              help="How strongly velocities turn smoothly through interior keyframes.")
@solver_options_for("solver", "init", "scheme", "tol", "max_iter", "method")
@outline_correspondence_options
@output_options
def keyframes_command(keyframes, frames, times, easing, smooth, solver, init, scheme, tol, max_iter, method,
                      output, fmt, texture, plot, quiet, **params):
    """AIAP through every KEYFRAME file at once (at least two).

    With --solver global or another --method, each segment between
    consecutive keyframes is interpolated on its own.

    Keyframes that do not share connectivity are first put in
    correspondence together as outlines (each paired with the first, one
    point count per ring), and one line says what was done.
    """
    from .. import interpolate_keyframes
    from ..errors import ParameterError

    elapsed = timer()
    check_outputs(output, fmt, texture, plot)
    if times is not None:
        try:
            times = [float(x) for x in times.split(",")]
        except ValueError:
            raise ParameterError(f"--times must be numbers separated by commas, got {times!r}") from None
    correspondence = keys_options(params)
    with progress(quiet) as callback:
        seq = interpolate_keyframes(list(keyframes), times=times, frames=frames, easing=easing, smooth=smooth,
                                    init=init, scheme=scheme, tol=tol, max_iter=max_iter, callback=callback,
                                    solver=solver, method=method, **correspondence)
    report_correspondence(seq, quiet)
    emit(seq, output, fmt=fmt, texture=texture, quiet=quiet, plot=plot, seconds=elapsed())
