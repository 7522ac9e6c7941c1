"""Batches: outputs equal single runs (serial, processes, Dask), resume, failures recorded."""

import json

import numpy as np
import pytest
from click.testing import CliRunner

import isotween
from isotween import Shape, io
from isotween.batch import read_manifest
from isotween.cli import main
from isotween.errors import FileFormatError


def curl(n, turns):
    """An open chain of n unit-spaced vertices turning `turns` times in all."""
    angle = np.linspace(0.0, 2 * np.pi * turns, n - 1)
    z = np.concatenate([[0], np.cumsum(np.exp(1j * angle))])
    return Shape.from_polyline(np.column_stack([z.real, z.imag]))


@pytest.fixture
def pairs(tmp_path):
    """Three compatible pairs and one bad pair (its target file is not JSON) as .json files."""
    folder = tmp_path / "in"
    folder.mkdir()
    names = []
    for i, turns in enumerate((0.3, 0.6, 0.9)):
        io.save(curl(10 + i, 0.0), folder / f"p{i}.source.json")
        io.save(curl(10 + i, turns), folder / f"p{i}.target.json")
        names.append(f"p{i}")
    io.save(curl(10, 0.0), folder / "bad.source.json")
    (folder / "bad.target.json").write_text("{ not json")  # a pair of other vertex counts would be corresponded
    return folder, names


def jobs_of(folder, names, **options):
    return [{"source": folder / f"{n}.source.json", "target": folder / f"{n}.target.json",
             "output": f"{n}.npz", "options": dict(options)} for n in names]


def records(report):
    return [json.loads(line) for line in open(report, encoding="utf-8")]


def test_serial_batch_equals_interpolate(pairs, tmp_path):
    folder, names = pairs
    res = isotween.batch(jobs_of(folder, names, frames=7), outdir=tmp_path / "out", workers=1)
    assert (res["done"], res["failed"], res["skipped"]) == (3, 0, 0)
    for n in names:
        expected = isotween.interpolate(io.load(folder / f"{n}.source.json"),
                                        io.load(folder / f"{n}.target.json"), frames=7)
        got = io.load_sequence(tmp_path / "out" / f"{n}.npz")
        assert got.frames.shape == (7, expected.frames.shape[1], 2)
        np.testing.assert_array_equal(got.frames, expected.frames)


@pytest.mark.slow
def test_processes_and_dask_equal_serial_and_bad_job_is_reported(pairs, tmp_path):
    distributed = pytest.importorskip("distributed")
    folder, names = pairs
    jobs = jobs_of(folder, names + ["bad"], frames=9)
    serial = isotween.batch(jobs, outdir=tmp_path / "serial", workers=1)
    local = isotween.batch(jobs, outdir=tmp_path / "local", workers=2, window=2)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        dask = isotween.batch(jobs, outdir=tmp_path / "dask", client=client, window=2)
    for res in (serial, local, dask):
        assert (res["done"], res["failed"]) == (3, 1)
        (bad,) = res["failures"]
        assert bad["output"].endswith("bad.npz") and "FileFormatError" in bad["error"]
    for n in names:
        ref = io.load_sequence(tmp_path / "serial" / f"{n}.npz").frames
        for run in ("local", "dask"):
            np.testing.assert_array_equal(io.load_sequence(tmp_path / run / f"{n}.npz").frames, ref)
    for run in ("serial", "local", "dask"):  # no output, no temporary file of the bad job
        assert sorted(p.name for p in (tmp_path / run).iterdir()) == sorted(
            [f"{n}.npz" for n in names] + ["batch-report.jsonl"])
        assert {r["status"] for r in records(tmp_path / run / "batch-report.jsonl")} == {"done", "failed"}


def test_resume_skips_finished_jobs_and_reruns_changed_ones(pairs, tmp_path):
    folder, names = pairs
    out = tmp_path / "out"
    jobs = jobs_of(folder, names, frames=5)
    assert isotween.batch(jobs, outdir=out, workers=1)["done"] == 3
    stamps = {n: (out / f"{n}.npz").stat().st_mtime_ns for n in names}
    again = isotween.batch(jobs, outdir=out, workers=1)
    assert (again["done"], again["skipped"]) == (0, 3)
    assert all((out / f"{n}.npz").stat().st_mtime_ns == stamps[n] for n in names)
    io.save(curl(10, 0.4), folder / "p0.target.json")  # new input contents
    jobs[1]["options"]["frames"] = 6  # new options
    (out / "p2.npz").unlink()  # lost output
    third = isotween.batch(jobs, outdir=out, workers=1)
    assert (third["done"], third["skipped"]) == (3, 0)
    assert len(io.load_sequence(out / "p1.npz")) == 6
    assert isotween.batch(jobs, outdir=out, workers=1, resume=False)["done"] == 3


def test_manifests_csv_jsonl_and_folder_give_the_same_jobs(pairs, tmp_path):
    folder, names = pairs
    csv = folder / "jobs.csv"
    csv.write_text("source,target,output,frames,tol\n" + "".join(
        f"{n}.source.json,{n}.target.json,{n}.npz,{5 + i},\n" for i, n in enumerate(names)))
    jsonl = folder / "jobs.jsonl"
    jsonl.write_text("".join(json.dumps({"source": f"{n}.source.json", "target": f"{n}.target.json",
                                         "output": f"{n}.npz", "options": {"frames": 5 + i}}) + "\n"
                             for i, n in enumerate(names)))
    a, b = list(read_manifest(csv)), list(read_manifest(jsonl))
    assert [(j["source"], j["target"], j["output"], j["options"]) for j in a] == \
           [(j["source"], j["target"], j["output"], j["options"]) for j in b]
    assert [j["options"] for j in a] == [{"frames": 5}, {"frames": 6}, {"frames": 7}]
    folder_jobs = list(read_manifest(folder, {"frames": 5}))
    assert sorted(j["output"] for j in folder_jobs) == sorted(f"{n}.npz" for n in names + ["bad"])


@pytest.mark.parametrize("text, needle", [
    ("source,target\na.json,b.json\n", "line 1: missing column(s) output"),
    ("source,target,output,speed\na,b,c,1\n", "unknown column(s) speed"),
])
def test_bad_manifest_is_one_line_error_naming_the_line(tmp_path, text, needle):
    manifest = tmp_path / "jobs.csv"
    manifest.write_text(text)
    with pytest.raises(FileFormatError, match="line"):
        list(read_manifest(manifest))
    result = CliRunner().invoke(main, ["batch", str(manifest), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0] and str(manifest) in lines[0]
    assert not (tmp_path / "out").exists()


def test_bad_manifest_row_fails_alone(pairs, tmp_path):
    """A row with a bad option value is recorded as failed, naming its line; the other rows run."""
    folder, names = pairs
    manifest = folder / "jobs.csv"
    manifest.write_text("source,target,output,frames\n"
                        f"{names[0]}.source.json,{names[0]}.target.json,a.npz,many\n"
                        f"{names[1]}.source.json,{names[1]}.target.json,b.npz,5\n")
    result = CliRunner().invoke(main, ["batch", str(manifest), "-o", str(tmp_path / "out"), "-j", "1", "-q"])
    assert result.exit_code == 1
    assert "jobs=2 done=1 skipped=0 failed=1" in result.stdout
    (line,) = result.stderr.strip().splitlines()
    assert line.startswith("failed: ") and "line 2: bad value 'many' for option frames" in line
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["b.npz", "batch-report.jsonl"]


def test_cli_batch_summary_and_exit_status(pairs, tmp_path):
    folder, names = pairs
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["batch", str(folder), "-o", str(out), "-j", "1", "-n", "5", "-q"])
    assert result.exit_code == 1  # the bad pair failed
    assert "jobs=4 done=3 skipped=0 failed=1" in result.stdout
    assert "failed: " in result.stderr and "bad.npz" in result.stderr
    assert all(len(io.load_sequence(out / f"{n}.npz")) == 5 for n in names)
    (folder / "bad.source.json").unlink()
    (folder / "bad.target.json").unlink()
    again = CliRunner().invoke(main, ["batch", str(folder), "-o", str(out), "-j", "1", "-n", "5", "-q"])
    assert again.exit_code == 0 and "jobs=3 done=0 skipped=3 failed=0" in again.stdout


def test_jobs_are_pulled_lazily_within_the_window(pairs, tmp_path):
    """The client holds at most `window` unfinished jobs.

    When job i is taken from the iterator, at least i - (window - 1) records are already in the report.
    """
    folder, names = pairs
    out = tmp_path / "out"
    jobs = jobs_of(folder, names * 3, frames=5)
    for i, job in enumerate(jobs):
        job["output"] = f"{i}.npz"
    seen = []

    def lazily():
        for i, job in enumerate(jobs):
            report = out / "batch-report.jsonl"
            seen.append((i, len(records(report)) if report.exists() else 0))
            yield job

    res = isotween.batch(lazily(), outdir=out, workers=2, window=3)
    assert res["done"] == len(jobs) == len(seen)
    assert all(i - finished <= 2 for i, finished in seen)
    assert max(i - finished for i, finished in seen) >= 1  # jobs run side by side


def test_local_workers_run_single_threaded_after_jobs_in_this_process(pairs, tmp_path):
    """Workers run numba and the BLAS on one thread each (two workers share two cores).

    They start even after this process has run jobs itself and so started numba's OpenMP pool, which
    does not survive a fork (workers forked from here were terminated).
    """
    from isotween.batch import _Local, threads_in_use

    folder, names = pairs
    serial = isotween.batch(jobs_of(folder, names, frames=7), outdir=tmp_path / "serial", workers=1)
    local = isotween.batch(jobs_of(folder, names, frames=7), outdir=tmp_path / "local", workers=2)
    assert serial["done"] == local["done"] == 3
    for n in names:
        np.testing.assert_array_equal(io.load_sequence(tmp_path / "local" / f"{n}.npz").frames,
                                      io.load_sequence(tmp_path / "serial" / f"{n}.npz").frames)
    for rec in records(tmp_path / "local" / "batch-report.jsonl"):
        assert rec["cpu_seconds"] >= 0.0  # recorded; one thread per worker is asserted below, not timed
    here = threads_in_use()
    runner = _Local(2)
    try:
        seen = [f.result() for f in [runner.pool.submit(threads_in_use) for _ in range(4)]]
    finally:
        runner.close()
    expected = {k: (None if v is None else 1) for k, v in here.items()}
    assert seen == [expected] * 4
    assert threads_in_use() == here  # this process keeps its own settings


def test_batch_morphs_any_two_drawings_as_interpolate_does(tmp_path):
    """Manifest and folder modes take drawings that do not share connectivity (the library's pipeline)."""
    pytest.importorskip("svgelements")
    folder = tmp_path / "pairs"
    (folder / "one").mkdir(parents=True)
    square = '<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 H4 V4 H0 Z" fill="black"/></svg>'
    star = ('<svg xmlns="http://www.w3.org/2000/svg"><polygon points="2,0 2.6,1.4 4,1.5 3,2.5 3.3,4 2,3.2 '
            '0.7,4 1,2.5 0,1.5 1.4,1.4" fill="black"/></svg>')
    (folder / "one" / "source.svg").write_text(square)
    (folder / "one" / "target.svg").write_text(star)
    manifest = tmp_path / "jobs.csv"
    manifest.write_text(f"source,target,output,frames\n{folder / 'one' / 'source.svg'},"
                        f"{folder / 'one' / 'target.svg'},m.npz,5\n")
    res = isotween.batch(manifest, outdir=tmp_path / "out", workers=1)
    assert (res["done"], res["failed"]) == (1, 0)
    expected = isotween.morph(folder / "one" / "source.svg", folder / "one" / "target.svg", frames=5)
    got = io.load_sequence(tmp_path / "out" / "m.npz")
    np.testing.assert_array_equal(got.frames, expected.frames)
    assert got.shape.n_faces > 0  # filled drawings morph as solids, as `isotween interpolate` does
    result = CliRunner().invoke(main, ["batch", str(folder), "-o", str(tmp_path / "out2"), "--frames", "5"])
    assert result.exit_code == 0, result.output
    np.testing.assert_array_equal(io.load_sequence(tmp_path / "out2" / "one.npz").frames, expected.frames)



def test_a_job_sets_the_stagger_and_the_strokes_as_morph_does(tmp_path):
    pytest.importorskip("svgelements")
    head = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 24 24" fill="none" stroke="black">'
    shorts = '<path d="M16 7h2"/><path d="M6 7h2"/><path d="M6 17h2"/><path d="M16 17h2"/></svg>'
    a, b = tmp_path / "across.svg", tmp_path / "upright.svg"  # the long bar turns upright through short strokes
    a.write_text(head + '<path d="M2 12h20"/>' + shorts)
    b.write_text(head + '<path d="M12 2v20"/>' + shorts)
    manifest = tmp_path / "jobs.jsonl"
    manifest.write_text(
        json.dumps({"source": str(a), "target": str(b), "output": "off.npz", "frames": 9, "stagger": 0.3}) + "\n"
        + json.dumps({"source": str(a), "target": str(b), "output": "through.npz", "frames": 9, "strokes": "morph"})
        + "\n" + json.dumps({"source": str(a), "target": str(b), "output": "bad.npz", "strokes": "cross"}) + "\n")
    res = isotween.batch(manifest, outdir=tmp_path / "out", workers=1)
    assert (res["done"], res["failed"]) == (2, 1)
    for name, options in (("off", {"stagger": 0.3}), ("through", {"strokes": "morph"})):
        expected = isotween.morph(a, b, frames=9, **options)
        np.testing.assert_array_equal(io.load_sequence(tmp_path / "out" / f"{name}.npz").frames, expected.frames)
    failed = [r for r in records(tmp_path / "out" / "batch-report.jsonl") if r["status"] == "failed"]
    assert "strokes" in failed[0]["error"] and not (tmp_path / "out" / "bad.npz").exists()


def test_a_manifest_fits_the_target_where_it_says_so(tmp_path):
    """``fit`` (a yes/no column): the target scaled into the source's box; a value that is not yes or no fails alone."""
    small, large = tmp_path / "small.json", tmp_path / "large.json"
    io.save(curl(12, 0.5), small)
    io.save(curl(12, 0.5).scale(40.0).translate([500.0, 0.0]), large)
    manifest = tmp_path / "jobs.csv"
    manifest.write_text("source,target,output,frames,fit\n"
                        "small.json,large.json,fit.npz,3,yes\n"
                        "small.json,large.json,plain.npz,3,\n"
                        "small.json,large.json,bad.npz,3,maybe\n")
    result = CliRunner().invoke(main, ["batch", str(manifest), "-o", str(tmp_path / "out"), "-j", "1", "-q"])
    assert "jobs=3 done=2 skipped=0 failed=1" in result.stdout, result.stderr
    assert "bad value 'maybe' for option fit" in result.stderr
    box = np.ptp(curl(12, 0.5).vertices, axis=0)
    np.testing.assert_allclose(np.ptp(io.load_sequence(tmp_path / "out" / "fit.npz").frames[-1], axis=0), box)
    np.testing.assert_allclose(np.ptp(io.load_sequence(tmp_path / "out" / "plain.npz").frames[-1], axis=0), 40 * box)
