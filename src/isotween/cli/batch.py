"""``isotween batch MANIFEST -o OUTDIR``: many interpolations, locally or on a Dask cluster."""

import click


@click.command("batch")
@click.argument("manifest")
@click.option("-o", "--output", "outdir", required=True,
              help="Folder for the outputs (relative output paths) and the report (created if missing).")
@click.option("--workers", "-j", type=int, default=None,
              help="Local worker processes [default: all cores].")
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="Run on the Dask cluster of this scheduler (tcp://host:8786; needs isotween[dask]).")
@click.option("--report", default=None,
              help="JSON Lines report, one record per job [default: OUTDIR/batch-report.jsonl].")
@click.option("--force", is_flag=True, help="Run every job, even those finished with the same inputs.")
@click.option("--frames", "-n", type=int, default=None, help="Frames of jobs that do not set them [9].")
@click.option("--resample", type=int, default=None, metavar="N",
              help="Resample both outlines of jobs that do not set it to N vertices.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def batch_command(manifest, outdir, workers, scheduler, report, force, frames, resample, quiet):
    """Run every job of MANIFEST.

    A .csv or .jsonl file with the columns source, target, output and per-job options (frames, solver, init, scheme,
    tol, max_iter, method, resample, mesh, format, correspondence, stagger, strokes), or a folder of pairs
    (sub-folders with source.EXT and target.EXT, or NAME.source.EXT beside NAME.target.EXT).

    Outputs are written atomically; a re-run skips jobs whose output exists
    with the same inputs and options. Failed jobs are listed in the report
    and do not stop the others; the exit status is 1 when any job failed.
    """
    import sys

    from .. import batch
    from .._text import safe_text
    from ..batch import check_jobs, read_manifest
    from . import _fail, _Terminated

    defaults = {k: v for k, v in (("frames", frames), ("resample", resample)) if v is not None}
    total = 0

    def counted():  # the whole manifest is read before anything runs
        nonlocal total
        for job in read_manifest(manifest, defaults):
            total += 1
            yield job

    check_jobs(counted(), outdir)  # two jobs with one output, or an output that is an input: refused
    try:
        result = batch(read_manifest(manifest, defaults), outdir=outdir, workers=workers, scheduler=scheduler,
                       report=report, resume=not force, progress=not quiet, total=total)
    except _Terminated:
        _fail("terminated; finished jobs are in the report, the others did not run", 143)
    except KeyboardInterrupt:
        _fail("interrupted; finished jobs are in the report, the others did not run", 130)
    for rec in result["failures"][:10]:
        click.echo(f"failed: {safe_text(rec['output'])}: {safe_text(rec['error'])}", err=True)
    click.echo(f"jobs={total} done={result['done']} skipped={result['skipped']} failed={result['failed']} "
               f"seconds={result['seconds']:.2f} report={safe_text(result['report'])}")
    if result["failed"]:
        sys.exit(1)
