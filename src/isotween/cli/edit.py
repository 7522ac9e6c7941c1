"""``isotween edit``: frames of a saved sequence replaced, the change carried through its motion (Sec. 5.2)."""

import click

from .options import check_outputs, emit, output_options, timer


@click.command("edit")
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
