"""``isotween prepare SOURCE TARGET -o DIR``: a compatible pair written as files,
and the ``--resample`` / ``--mesh`` options that `interpolate` shares."""

import warnings

import click

from ..errors import ParameterError
from . import main
from .options import _compose, ensure_compatible

__all__ = ["correspondence_options", "make_compatible"]

correspondence_options = _compose(click.option(
    "--resample", "resample_points", type=int, default=None, metavar="N",
    help="Resample both outlines to N vertices in all (arc length, best start and orientation).",
), click.option(
    "--mesh", "mesh_area", is_flag=False, flag_value="auto", default=None, metavar="[MAX_AREA]",
    help="Triangulate the source outline (largest triangle area MAX_AREA; default: none, triangles "
         "grow from the outline inwards) and map the mesh onto the target outline (needs isotween[mesh]).",
))


def make_compatible(src, tgt, source_path, target_path, resample_points=None, mesh_area=None):
    """Resample and/or mesh a loaded pair as the options ask, then check compatibility.

    Prints a warning line on stderr when the target mesh has flipped triangles.

    Returns
    -------
    (Shape, Shape)
    """
    from ..correspondence import mesh_pair, resample

    if resample_points is not None:
        src, tgt = resample(src, tgt, points=resample_points)
    if mesh_area is not None:
        if mesh_area == "auto":
            max_area = None
        else:
            try:
                max_area = float(mesh_area)
            except ValueError:
                raise ParameterError(f"--mesh takes a largest triangle area (a number), got {mesh_area!r}") from None
        ensure_compatible(src, tgt, source_path, target_path)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            src, tgt, flipped = mesh_pair(src, tgt, max_area=max_area)
        if flipped.size:
            click.echo(f"warning: the target mesh has {flipped.size} flipped triangle(s) of "
                       f"{src.n_faces} (first: triangle {flipped[0]})", err=True)
    ensure_compatible(src, tgt, source_path, target_path)
    return src, tgt


@main.command("prepare")
@click.argument("source")
@click.argument("target")
@click.option("-o", "--output", "outdir", required=True,
              help="Folder for source.FORMAT and target.FORMAT (created if missing).")
@click.option("--format", "fmt", type=click.Choice(["obj", "off", "svg", "json", "npz"]), default="obj",
              show_default=True, help="File format of the two shapes.")
@correspondence_options
def prepare_command(source, target, outdir, fmt, resample_points, mesh_area):
    """Make SOURCE and TARGET compatible and write them as OUTDIR/source.FORMAT
    and OUTDIR/target.FORMAT, ready for `isotween interpolate`.

    Give --resample N (outlines with different point counts) and/or --mesh
    (a triangle mesh from the outlines).
    """
    from ..io import load, save
    from ..io._files import atomic_dir

    if resample_points is None and mesh_area is None:
        raise ParameterError("nothing to prepare: give --resample N and/or --mesh")
    src, tgt = make_compatible(load(source), load(target), source, target, resample_points, mesh_area)
    with atomic_dir(outdir) as tmp:
        for shape, name in ((src, "source"), (tgt, "target")):
            save(shape, tmp / f"{name}.{fmt}")
    click.echo(f"vertices={src.n_vertices} edges={src.n_edges} faces={src.n_faces} -> "
               f"{outdir}/source.{fmt}, {outdir}/target.{fmt}")
