"""`isotween compare` and `isotween.compare`: every method's row, report files, skipped methods."""

import csv
import math

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

import isotween
from isotween import Shape, metrics
from isotween.cli import main
from isotween.compare import COLUMNS, METHODS
from isotween.errors import ParameterError
from shapes import bend, ellipse, rotation


def strip(k=10, length=6.0, width=0.6):
    """A two-row triangulated bar whose boundary ring visits every vertex.

    Every method (mesh and outline ones) can take it.
    """
    x = np.linspace(0.0, length, k)
    v = np.r_[np.c_[x, 0 * x], np.c_[x, 0 * x + width]]
    b, t = np.arange(k), np.arange(k, 2 * k)
    faces = np.r_[np.c_[b[:-1], b[1:], t[1:]], np.c_[b[:-1], t[1:], t[:-1]]]
    return Shape(v, faces=faces, paths=[(np.r_[b, t[::-1]], True)])


@pytest.fixture
def files(tmp_path):
    src = strip()
    isotween.save(src, tmp_path / "a.json")
    isotween.save(src.with_vertices(bend(src.vertices, np.pi)), tmp_path / "b.json")
    return tmp_path / "a.json", tmp_path / "b.json"


def test_compare_command_writes_figure_plots_and_tables(tmp_path, files):
    report = tmp_path / "report"
    result = CliRunner().invoke(main, ["compare", *map(str, files), "--frames", "7", "-o", str(report)])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in report.iterdir()) == ["methods.png", "metrics.png", "table.csv", "table.md"]
    with open(report / "table.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["method"] for r in rows] == list(METHODS)
    for row in rows:
        assert row["status"] == "ok", row
        assert all(math.isfinite(float(row[k])) for k in COLUMNS[2:-1]), row
    md = (report / "table.md").read_text().splitlines()
    assert md[0] == "| " + " | ".join(COLUMNS) + " |" and len(md) == 2 + len(METHODS)
    for name in ("methods.png", "metrics.png"):
        with Image.open(report / name) as img:
            assert img.format == "PNG" and min(img.size) > 100


def test_compare_command_on_the_built_in_bar(tmp_path):
    """The built-in 'bar' (a strip curled by 270 degrees) is taken by every method.

    Plain ARAP folds it where AIAP and Baxter's variant do not.
    """
    report = tmp_path / "bar"
    result = CliRunner().invoke(main, ["compare", "--example", "bar", "--frames", "9", "-o", str(report)])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in report.iterdir()) == ["methods.png", "metrics.png", "table.csv", "table.md"]
    with open(report / "table.csv", newline="") as fh:
        rows = {r["method"]: r for r in csv.DictReader(fh)}
    assert list(rows) == list(METHODS)
    for _method, row in rows.items():
        assert row["status"] == "ok", row
        assert all(math.isfinite(float(row[k])) for k in COLUMNS[2:-1]), row
    flips = {m: int(r["flipped_faces"]) for m, r in rows.items()}
    assert flips["aiap"] == flips["arap-baxter"] == 0 < flips["arap"]
    assert float(rows["aiap"]["edge_length_deviation"]) < 0.01 < float(rows["linear"]["edge_length_deviation"])
    for args in (["--example", "bar", "a.obj"], []):
        bad = CliRunner().invoke(main, ["compare", *args, "-o", str(tmp_path / "no")])
        assert bad.exit_code != 0 and bad.stderr.startswith("error: ") and not (tmp_path / "no").exists()


def test_compare_rows_are_the_metrics_of_each_method():
    src = strip()
    tgt = src.with_vertices(bend(src.vertices, np.pi))
    rows = isotween.compare(src, tgt, methods=["linear", "arap-baxter"], frames=5)
    for row in rows:
        seq = isotween.interpolate(src, tgt, frames=5, method=row["method"])
        assert row["edge_length_deviation"] == metrics.edge_length_deviation(seq)
        assert row["area_deviation"] == metrics.area_deviation(seq)
        assert row["flipped_faces"] == metrics.flipped_faces(seq)
    assert rows[0]["edge_length_deviation"] > 10 * rows[1]["edge_length_deviation"]


def test_methods_that_cannot_take_the_shape_are_skipped_with_the_reason(tmp_path):
    src = ellipse()
    tgt = src.with_vertices(src.vertices @ rotation(90).T)
    rows = isotween.compare(src, tgt, frames=5, report_dir=tmp_path / "r")
    status = {r["method"]: r for r in rows}
    for method in ("arap", "arap-baxter"):
        assert status[method]["status"] == "skipped"
        assert "needs a triangle mesh" in status[method]["note"]
        assert math.isnan(status[method]["edge_length_deviation"])
    assert all(status[m]["status"] == "ok" for m in ("aiap", "linear", "intrinsic", "shapespace"))
    assert "skipped" in (tmp_path / "r" / "table.md").read_text()


def test_unknown_method_fails_before_writing_anything(tmp_path, files):
    report = tmp_path / "report"
    result = CliRunner().invoke(main, ["compare", *map(str, files), "--methods", "aiap,morph", "-o", str(report)])
    assert result.exit_code != 0 and "Traceback" not in result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "morph" in lines[0]
    assert not report.exists()
    with pytest.raises(ParameterError):
        isotween.compare(strip(), strip(), methods=["linear", "linear"])
