"""``isotween compare SOURCE TARGET``: every method side by side, with a report."""

import click

from .._defaults import DEFAULT_TOL
from ..errors import ParameterError
from .options import frames_option, timer


@click.command("compare")
@click.argument("source", required=False)
@click.argument("target", required=False)
@click.option("--example", default=None, help="Compare on a built-in example (isotween demo --list) instead of files.")
@click.option("--methods", default="aiap,linear,intrinsic,arap,arap-baxter,shapespace,convex,injective",
              show_default=True,
              help="Comma-separated methods to compare.")
@frames_option
@click.option("--tol", type=float, default=DEFAULT_TOL, show_default=True,
              help="Stopping rule of the iterative methods (Eq. 11).")
@click.option("--max-iter", type=int, default=100, show_default=True, help="Iteration limit.")
@click.option("-o", "--output", "report_dir", required=True,
              help="Report folder (created if missing): methods.png, metrics.png, table.md, table.csv.")
def compare_command(source, target, example, methods, frames, tol, max_iter, report_dir):
    """Interpolate SOURCE into TARGET (or a built-in --example) with several methods and compare them.

    Prints the table (Markdown) and writes the report folder. A method that
    cannot take these shapes (ARAP without triangles, intrinsic without
    polygons) is listed as skipped with the reason; the others still run.
    """
    from ..compare import compare, table_markdown
    elapsed = timer()
    if example is not None:
        if source or target:
            raise ParameterError("give either SOURCE and TARGET files or --example NAME, not both")
        from ..examples import load_example

        src, tgt, _ = load_example(example)
    elif source and target:
        from ..pipeline import prepare_pair

        prepared = prepare_pair(source, target)
        if prepared.report is not None:
            click.echo(prepared.summary())
        src, tgt = prepared.source, prepared.target
    else:
        raise ParameterError("compare needs SOURCE and TARGET files, or --example NAME (see isotween demo --list)")
    names = [m.strip() for m in methods.split(",") if m.strip()]
    rows = compare(src, tgt, methods=names, frames=frames, report_dir=report_dir, tol=tol, max_iter=max_iter)
    click.echo(table_markdown(rows), nl=False)
    click.echo(f"{len(rows)} methods, {sum(r['status'] == 'ok' for r in rows)} run, "
               f"seconds={elapsed():.3f} -> {report_dir}")
