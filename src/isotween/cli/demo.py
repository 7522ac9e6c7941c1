"""``isotween demo [NAME]``: run a built-in example and write an animation."""

from pathlib import Path

import click

from ..errors import FileFormatError, MissingDependencyError, ParameterError
from ..outputs import with_paint, write_output
from .options import SOLVER_KEYS, progress, render_options, summary, timer


@click.command("demo")
@click.argument("name", required=False)
@click.option("-o", "--output", "outdir", default="isotween-demo", show_default=True,
              help="Folder for NAME.gif and NAME.html (created if missing).")
@click.option("--list", "list_names", is_flag=True,
              help="List the built-in examples (name and what it shows) and exit.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
@render_options
def demo_command(name, outdir, list_names, quiet, fill, stroke, stroke_width, **render):
    """Interpolate the built-in example NAME (default: the first one).

    Writes OUTDIR/NAME.gif and OUTDIR/NAME.html.
    """
    try:
        from .. import examples
    except ImportError:
        raise MissingDependencyError("the built-in examples (isotween.examples) are not installed") from None

    names = list(examples.names())
    if list_names:
        width = max(map(len, names), default=0)
        click.echo("\n".join(f"{n:<{width}}  {examples.describe(n)}" for n in names))
        return
    if not names:
        raise ParameterError("no built-in examples are installed")
    name = name or names[0]
    if name not in names:
        raise ParameterError(f"unknown example '{name}'; available: {', '.join(names)}")
    folder = Path(outdir)
    if folder.exists() and not folder.is_dir():
        raise FileFormatError(f"cannot write to {folder}: it is a file, not a folder")
    if not folder.parent.is_dir():
        raise FileFormatError(f"cannot create {folder}: {folder.parent} does not exist")
    elapsed = timer()
    options = examples.example_options(name)
    kwargs = {k: options[k] for k in SOLVER_KEYS if k in options}
    texture = options.get("texture")
    with progress(quiet) as callback:
        seq = examples.interpolate_example(name, callback=callback, **kwargs)
    colours = {k: v for k, v in (("fill", fill), ("stroke", stroke), ("stroke_width", stroke_width)) if v is not None}
    seq = with_paint(seq, **(colours or examples.example_paint(name)))
    render["title"] = render["title"] or f"isotween demo: {name}"
    created = not folder.exists()
    folder.mkdir(exist_ok=True)
    written = []
    try:
        for out in (folder / f"{name}.gif", folder / f"{name}.html"):
            written += write_output(seq, out, texture=texture, quiet=quiet, **render)
    except BaseException:
        for p in written:
            p.unlink(missing_ok=True)
        if created and not any(folder.iterdir()):
            folder.rmdir()
        raise
    click.echo(summary(seq, elapsed(), written))
