"""``isotween render SEQUENCE -o OUT``: draw a saved sequence again, as any output."""

import click

from .options import check_outputs, emit, output_options, timer


@click.command("render")
@click.argument("sequence")
@output_options
def render_command(sequence, output, fmt, texture, plot, quiet, **render):
    """Render SEQUENCE (.npz/.json, or a folder of frames) to -o without solving again.

    The output kind follows -o: .gif .webp .apng .mp4 .svg .html
    .lottie.json .css .waapi.json (animations), .png (a strip of frames), .npz .json
    (sequence files) or a folder of frame files (with --format). Colours
    come from the sequence's paint or --fill/--stroke.
    """
    from ..io import load_sequence

    elapsed = timer()
    check_outputs(output, fmt, texture, plot)
    seq = load_sequence(sequence)
    emit(seq, output, fmt=fmt, texture=texture, quiet=quiet, plot=plot, seconds=elapsed())
