"""``isotween transfer``: one shape moved the way another moves (Sec. 5.1)."""

import click

from .options import check_outputs, emit, frames_option, output_options, progress, solver_kwargs, solver_options, timer
from .prepare import correspondence_kwargs, make_keys_compatible, outline_correspondence_options


@click.command("transfer")
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
