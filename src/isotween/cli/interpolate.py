"""``isotween interpolate SOURCE TARGET``: the in-betweens of two shape files."""

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
    timer,
)
from .prepare import correspondence_kwargs, correspondence_options, make_compatible


@main.command("interpolate")
@click.argument("source")
@click.argument("target")
@frames_option
@solver_options
@correspondence_options
@output_options
def interpolate_command(source, target, output, fmt, texture, plot, quiet, **params):
    """Interpolate SOURCE into TARGET as-isometrically-as-possible.

    SOURCE and TARGET are shape files (.obj .off .svg .json .npz). Shapes
    that do not share vertex count and connectivity are put in
    correspondence first (regions, holes and polylines paired, outlines
    resampled, filled regions meshed as solids), and one line says what was
    done. The output kind follows -o: an animation (.gif .mp4 .html), a
    strip of frames (.png), a sequence file (.npz .json), or a folder of
    frame files (with --format).
    """
    from .. import interpolate
    from ..io import load

    elapsed = timer()
    check_outputs(output, fmt, texture, plot)
    options = correspondence_kwargs(params)
    src, tgt = make_compatible(load(source), load(target), source, target, quiet=quiet, **options)
    kwargs = solver_kwargs(params)
    with progress(quiet) as callback:
        seq = interpolate(src, tgt, callback=callback, **kwargs)
    emit(seq, output, fmt=fmt, texture=texture, quiet=quiet, plot=plot, seconds=elapsed())
