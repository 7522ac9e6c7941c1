"""``isotween interpolate SOURCE TARGET``: the in-betweens of two shape files."""

import click

from ..pipeline import STROKES
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


@click.command("interpolate")
@click.argument("source")
@click.argument("target")
@frames_option
@solver_options
@correspondence_options
@click.option("--stagger", type=float, default=None, metavar="SHARE",
              help="A piece with no partner in the other drawing leaves within this first share of the morph, "
                   "and one that appears comes in within the last (where the pieces cannot be kept apart so, 0.2 "
                   "then 0.1 are tried); 1: both over the whole morph. A stroke that would pass through another "
                   "path is drawn off within this share (at most half) and on within the last [default: 0.5].")
@click.option("--strokes", "strokes", type=click.Choice(STROKES), default=STROKES[0],
              show_default=True,
              help="untangle: a stroke that would pass through another path is drawn off and on instead; "
                   "morph: every stroke morphs.")
@output_options
def interpolate_command(source, target, output, fmt, texture, plot, quiet, stagger, strokes, **params):
    """Interpolate SOURCE into TARGET as-isometrically-as-possible.

    SOURCE and TARGET are shape files (.obj .off .svg .json .npz). Shapes
    that do not share vertex count and connectivity are put in
    correspondence first (regions, holes and polylines paired, outlines
    resampled, filled regions meshed as solids), and one line says what was
    done; if the in-betweens of meshes built so then fold (a flipped triangle
    or a self-crossing outline), the fold-free morph of method 'injective'
    (the convex-combination morph made nearly isometric) is written instead,
    and one line says so. The output
    kind follows -o: an animation (.gif .mp4 .html), a strip of frames
    (.png), a sequence file (.npz .json), or a folder of frame files (with
    --format).
    """
    from .. import interpolate
    from ..io import load

    elapsed = timer()
    check_outputs(output, fmt, texture, plot)
    options = correspondence_kwargs(params)
    from ..interpolate import fold_notes
    from ..pipeline import STAGGER, check_stagger, finish, stagger_shares, unmatched_spans

    stagger = check_stagger(STAGGER if stagger is None else stagger)  # before any work
    prepared = make_compatible(load(source), load(target), source, target, quiet=quiet, prepared=True, **options)
    kwargs = solver_kwargs(params)
    if prepared.built_meshes:  # meshes built here: a folding result falls back to the fold-free morph
        kwargs.setdefault("fold", "fallback")
    spans = unmatched_spans(prepared.source, prepared.report, stagger, prepared.target)
    with progress(quiet) as callback:
        seq = interpolate(prepared.source, prepared.target, callback=callback, correspondence="never", spans=spans,
                          **kwargs)
    finish(seq, prepared.report, stagger, strokes)  # no specks at the ends; strokes kept from crossing
    for note in [] if quiet else fold_notes(seq):  # AIAP stopped before a fold, edges flipped, a repair or
        click.echo(f"fold check: {note}")             # the fold-free morph
    if "spans" in seq.info and not quiet:  # the staggering was shortened or dropped to keep the pieces apart
        share = stagger_shares(stagger)[seq.info["spans"]["used"]]
        click.echo(f"stagger: {share:g} instead of {stagger:g}: {seq.info['spans']['why']}")
    if "strokes" in seq.info and not quiet:
        click.echo(f"strokes: {seq.info['strokes']}")
    emit(seq, output, fmt=fmt, texture=texture, quiet=quiet, plot=plot, seconds=elapsed())
