"""``isotween edit``: frames of a saved sequence replaced, the change carried through its motion (Sec. 5.2)."""

import click

from .options import check_outputs, emit, output_options, timer


@click.command("edit")
@click.argument("sequence")
@click.option("--frame", "-k", "indices", type=int, multiple=True, required=True,
              help="Index of an edited frame (repeat with --shape for several).")
@click.option("--shape", "shapes", multiple=True, required=True,
              help="The edited frame's shape file, one per --frame.")
@click.option("--free-ends", is_flag=True,
              help="Let the first and last frames change too (the paper's procedure).")
@click.option("--correspondence", type=click.Choice(["auto", "always", "never"]), default="auto",
              show_default=True,
              help="auto: a --shape of other connectivity (a drawing) is brought onto the sequence's; "
                   "always; never (each --shape must be compatible with the sequence).")
@output_options
def edit_command(sequence, indices, shapes, free_ends, correspondence, output, fmt, texture, plot, quiet, **render):
    """Replace frames of SEQUENCE and carry the change through its motion (Sec. 5.2).

    SEQUENCE is a .npz/.json sequence file or a folder of frames. A --shape
    with the sequence's connectivity (a frame written by `isotween render`)
    is used as it is; a drawing of other connectivity is put in
    correspondence with the sequence's frame, whose mesh is kept.
    """
    from .. import edit
    from ..errors import ParameterError
    from ..io import load_sequence

    elapsed = timer()
    if len(indices) != len(shapes):
        raise ParameterError(f"give one --shape per --frame ({len(indices)} frames, {len(shapes)} shapes)")
    check_outputs(output, fmt, texture, plot)
    seq = load_sequence(sequence)
    out = edit(seq, edits=dict(zip(indices, shapes, strict=True)), keep_ends=not free_ends,
               correspondence=correspondence)
    emit(out, output, fmt=fmt, texture=texture, quiet=quiet, plot=plot, seconds=elapsed())
