"""``isotween transfer``: one shape moved the way another moves (Sec. 5.1)."""

import click

from .options import check_outputs, emit, frames_option, output_options, progress, solver_kwargs, solver_options, timer
from .prepare import keys_options, outline_correspondence_options, report_correspondence


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

    elapsed = timer()
    check_outputs(output, fmt, texture, plot)
    correspondence = keys_options(params)
    with progress(quiet) as callback:
        seq = transfer(source_start, source_end, target_start, callback=callback, **correspondence,
                       **solver_kwargs(params))
    report_correspondence(seq, quiet)
    emit(seq, output, fmt=fmt, texture=texture, quiet=quiet, plot=plot, seconds=elapsed())
