"""``isotween prepare SOURCE TARGET -o DIR``.

A compatible pair written as files, and the correspondence options that `interpolate`, `keyframes` and `transfer` share.
"""

import click

from ..errors import ParameterError
from .options import _compose, ensure_compatible

__all__ = ["correspondence_options", "outline_correspondence_options", "correspondence_kwargs",
           "make_compatible", "keys_options", "report_correspondence", "CORRESPONDENCE_KEYS"]

#: names of the correspondence options among a command's parameters
CORRESPONDENCE_KEYS = ("points", "segment", "rotation", "outline", "mesh_size", "unmatched",
                       "resample_points", "mesh_area", "correspondence", "landmarks", "fit")


def _landmark(ctx, param, values):
    """``X0,Y0:X1,Y1`` strings as ((x0, y0), (x1, y1)) pairs."""
    out = []
    for text in values or ():
        try:
            a, b = text.split(":")
            pair = tuple(tuple(float(v) for v in p.split(",")) for p in (a, b))
            if any(len(p) != 2 for p in pair):
                raise ValueError
        except ValueError:
            raise click.BadParameter(f"{text!r} is not X0,Y0:X1,Y1 (a source point and its target point)") \
                from None
        out.append(pair)
    return out or None

_outline_options = (
    click.option("--points", type=int, default=None, metavar="N",
                 help="Inputs that need correspondence: N points on all rings together "
                      "[default: the larger input's count]."),
    click.option("--segment", type=float, default=None, metavar="LENGTH",
                 help="Instead of --points: enough points that no segment is longer than LENGTH."),
    click.option("--rotation", is_flag=True,
                 help="Keyframes and transfer: factor out rotation when choosing where each ring starts "
                      "(two drawings are aligned as wholes, turn included, without it)."),
    click.option("--unmatched", type=click.Choice(["grow", "split"]), default="grow", show_default=True,
                 help="A region or hole with no partner grows from a small copy at its own place, or "
                      "splits off from the nearest region."),
    click.option("--correspondence", type=click.Choice(["auto", "always", "never"]), default="auto",
                 show_default=True,
                 help="auto: drawings (SVG) are always put in correspondence, other compatible inputs are "
                      "used as they are; always; never (the inputs must be compatible)."),
    click.option("--landmark", "landmarks", multiple=True, callback=_landmark, metavar="X0,Y0:X1,Y1",
                 help="A source point and the target point it must go to (repeatable), like shape hints."),
)

#: keyframes and transfer: every input after the first fitted into the first's box
outline_correspondence_options = _compose(*_outline_options, click.option(
    "--fit", is_flag=True,
    help="Scale and move every input after the first into the first's bounding box first (drawings from icon "
         "sets drawn in different units then move at one size).",
))

correspondence_options = _compose(*_outline_options, click.option(
    "--fit", is_flag=True,
    help="Scale and move the target into the source's bounding box first (drawings from icon sets drawn in "
         "different units then morph at one size).",
), click.option(
    "--outline", is_flag=True, help="Morph outlines only (no triangle meshes for filled regions).",
), click.option(
    "--mesh-size", type=float, default=None, metavar="LENGTH",
    help="Target triangle edge length of the filled regions' meshes [default: the outline's spacing, "
         "at least 1/60 of the drawings' diagonal].",
), click.option(
    "--resample", "resample_points", type=int, default=None, metavar="N",
    help="Older form: resample the outlines to N vertices in all, rings paired in order.",
), click.option(
    "--mesh", "mesh_area", is_flag=False, flag_value="auto", default=None, metavar="[MAX_AREA]",
    help="Older form: triangulate the source outline with Triangle (largest triangle area MAX_AREA) and "
         "map it onto the target outline (needs isotween[mesh]; may flip triangles).",
))


def correspondence_kwargs(params):
    """Pop the correspondence options out of a command's parameters (dict)."""
    return {k: params.pop(k) for k in CORRESPONDENCE_KEYS if k in params}


def _drawing_paths(*paths):
    """Whether any of the paths is a drawing (its point order means nothing)."""
    from ..pipeline import DRAWING_SUFFIXES

    return any(str(p).lower().endswith(DRAWING_SUFFIXES) for p in paths)


def make_compatible(src, tgt, source_path, target_path, quiet=False, points=None, segment=None,
                    rotation=False, outline=False, mesh_size=None, unmatched="grow",
                    resample_points=None, mesh_area=None, correspondence="auto", landmarks=None,
                    fit=False, prepared=False):
    """A loaded pair made compatible by the library as the options ask; its report printed, then checked.

    Without ``--resample``/``--mesh``: `isotween.pipeline.prepare_pair`
    (correspondence as its policy says), whose one-line report is printed
    (unless ``quiet``). With them: `isotween.pipeline.prepare_steps` (the
    older explicit steps), whose warnings go to stderr.

    Returns
    -------
    (Shape, Shape), or with ``prepared`` an `isotween.pipeline.Prepared`
    """
    from ..correspondence.resample import check_points
    from ..pipeline import prepare_pair, prepare_steps

    for value in (points, resample_points):  # refused before any geometry library allocates them
        if isinstance(value, int) and value > 0:
            check_points(value, 2, "putting in correspondence")
    if resample_points is None and mesh_area is None:
        options = {k: v for k, v in (("points", points), ("segment", segment), ("rotation", rotation),
                                     ("outline", outline), ("mesh_size", mesh_size), ("landmarks", landmarks))
                   if v not in (None, False)}
        if unmatched != "grow":
            options["unmatched"] = unmatched
        result = prepare_pair(src, tgt, correspondence=correspondence, fit=fit, **options,
                              names=(source_path, target_path), _drawing=_drawing_paths(source_path, target_path))
        if result.report is not None and not quiet:
            click.echo(result.summary())
    else:
        if fit:
            raise ParameterError("--fit goes with correspondence, not with --resample or --mesh")
        if resample_points is None:
            ensure_compatible(src, tgt, source_path, target_path)
        result = prepare_steps(src, tgt, resample=resample_points, mesh=mesh_area, rotation=rotation)
    for note in result.notes:
        click.echo(note, err=True)
    ensure_compatible(result.source, result.target, source_path, target_path)
    return result if prepared else (result.source, result.target)


def keys_options(params):
    """Pop a keyframes or transfer command's options: ``correspondence``, ``correspond_options``, ``fit``.

    What `interpolate_keyframes` and `transfer` take; they run
    `isotween.pipeline.prepare_keys` themselves.
    """
    options = correspondence_kwargs(params)
    if options.pop("landmarks", None):
        raise ParameterError("--landmark is for two drawings (interpolate, prepare)")
    policy = options.pop("correspondence", "auto")
    fit = bool(options.pop("fit", False))
    given = {k: v for k, v in options.items() if v not in (None, False) and not (k == "unmatched" and v == "grow")}
    if "unmatched" in given:
        given["unmatched"] = options["unmatched"]
    return {"correspondence": policy, "correspond_options": given or None, "fit": fit}


def report_correspondence(seq, quiet=False):
    """Print the one line on the correspondence that a library call ran (none when it ran none)."""
    if seq.info.get("correspondence") and not quiet:
        click.echo(seq.info["correspondence"])


@click.command("prepare")
@click.argument("source")
@click.argument("target")
@click.option("-o", "--output", "outdir", required=True,
              help="Folder for source.FORMAT and target.FORMAT (created if missing).")
@click.option("--format", "fmt", type=click.Choice(["obj", "off", "svg", "json", "npz"]), default="obj",
              show_default=True, help="File format of the two shapes.")
@click.option("--quiet", "-q", is_flag=True, help="No correspondence report.")
@correspondence_options
def prepare_command(source, target, outdir, fmt, quiet, **params):
    """Make SOURCE and TARGET compatible and write them into OUTDIR.

    The files are OUTDIR/source.FORMAT and OUTDIR/target.FORMAT, ready for
    `isotween interpolate`.

    Give the correspondence options (--points, --segment, --outline,
    --mesh-size, ...) or the older --resample N and/or --mesh.
    """
    from ..io import load, save
    from ..io._files import atomic_dir

    options = correspondence_kwargs(params)
    defaults = {"points": None, "segment": None, "rotation": False, "outline": False, "mesh_size": None,
                "unmatched": "grow", "resample_points": None, "mesh_area": None, "correspondence": "auto",
                "landmarks": None, "fit": False}
    if options == defaults:
        raise ParameterError("nothing to prepare: give --points N, --segment, --outline, --mesh-size or --fit "
                             "(correspondence), or give --resample N and/or --mesh")
    src, tgt = make_compatible(load(source), load(target), source, target, quiet=quiet, **options)
    with atomic_dir(outdir) as tmp:
        for shape, name in ((src, "source"), (tgt, "target")):
            save(shape, tmp / f"{name}.{fmt}")
    click.echo(f"vertices={src.n_vertices} edges={src.n_edges} faces={src.n_faces} -> "
               f"{outdir}/source.{fmt}, {outdir}/target.{fmt}")
