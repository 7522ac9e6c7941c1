"""`compare`: every interpolation method on one pair of shapes, measured alike.

Runs AIAP and the baselines of :mod:`isotween.baselines`, measures each
sequence with :mod:`isotween.metrics`, and optionally writes a report folder:
``methods.png`` (one row per method, one column per selected frame, all at one
scale), ``metrics.png`` (distortion per frame, one line per method),
``table.md`` and ``table.csv``.
"""

from __future__ import annotations

import csv
import io
import math
from typing import TYPE_CHECKING

from . import metrics
from ._callable import make_callable
from .baselines import METHODS as BASELINES
from .errors import MethodError, ParameterError, require
from .interpolate import interpolate
from .io import atomic_dir

if TYPE_CHECKING:
    from collections.abc import Iterable
    from os import PathLike
    from typing import Any

    from .shape import ShapeLike

__all__ = ["compare", "METHODS", "COLUMNS"]

METHODS = ("aiap",) + BASELINES
#: columns of the comparison table, in order
COLUMNS = ("method", "status", "edge_length_deviation", "area_deviation", "flipped_faces",
           "isometric_energy", "iterations", "seconds", "note")


def compare(source: ShapeLike, target: ShapeLike, methods: Iterable[str] = METHODS, frames: int = 9,
            report_dir: str | PathLike | None = None, columns: int = 12, correspondence: str = "auto",
            **options: Any) -> list[dict]:
    """Interpolate with several methods and measure each with the same metrics.

    Parameters
    ----------
    source, target : Shape, (n, 2) array_like, or path
        Any two inputs: made compatible first as `isotween.prepare_pair` does.
    methods : sequence of str
        Any of :data:`METHODS`.
    frames : int
        Frames per sequence, both inputs included.
    report_dir : path-like, optional
        Folder to write ``methods.png``, ``metrics.png``, ``table.md`` and
        ``table.csv`` into (created if missing; all files or none).
    columns : int
        Most frames shown per method in ``methods.png``: every frame when
        they fit, else evenly spaced ones (`isotween.render.compared_frames`).
    correspondence : {'auto', 'always', 'never'}
        See `isotween.prepare_pair`.
    **options
        Passed to :func:`isotween.interpolate` (``tol``, ``max_iter``, ...).

    Returns
    -------
    list of dict
        One row per method with the keys of :data:`COLUMNS`: ``status`` is
        'ok', or 'skipped' when the method cannot take these shapes (``note``
        then says why and the numbers are NaN). ``edge_length_deviation`` and
        ``area_deviation`` are maxima (docs/how-it-works.md), ``flipped_faces`` is summed
        over the intermediate frames, ``seconds`` is the method's own time.

    Raises
    ------
    ParameterError
        An unknown or repeated method name.

    Examples
    --------
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    >>> rows = isotween.compare(bar, bar.rotate(2.0), methods=["aiap", "linear"], frames=5)
    >>> [(row["method"], row["status"]) for row in rows]
    [('aiap', 'ok'), ('linear', 'ok')]
    >>> rows[0]["edge_length_deviation"] < rows[1]["edge_length_deviation"]
    True
    """
    methods = list(methods)
    unknown = [m for m in methods if m not in METHODS]
    if unknown or not methods or len(set(methods)) < len(methods):
        raise ParameterError(
            f"methods must be distinct names among {', '.join(METHODS)}; got {', '.join(methods) or 'none'}")
    from .pipeline import prepare_pair

    prepared = prepare_pair(source, target, correspondence=correspondence)
    source, target = prepared.source, prepared.target
    rows, sequences = [], {}
    for method in methods:
        try:
            seq = interpolate(source, target, frames=frames, method=method, **options)
        except MethodError as exc:
            rows.append(dict.fromkeys(COLUMNS, math.nan) | {"method": method, "status": "skipped", "note": str(exc)})
            continue
        sequences[method] = seq
        rows.append({
            "method": method, "status": "ok",
            "edge_length_deviation": metrics.edge_length_deviation(seq),
            "area_deviation": metrics.area_deviation(seq),
            "flipped_faces": metrics.flipped_faces(seq),
            "isometric_energy": metrics.isometric_energy(seq, "midpoint"),
            "iterations": seq.iterations, "seconds": float(seq.timings["total"]),
            "note": "" if seq.converged else "not converged",
        })
    if report_dir is not None:
        write_report(report_dir, rows, sequences, columns)
    return rows


def table_markdown(rows):
    """The comparison table as Markdown text."""
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(_cell(r[c]) for c in COLUMNS) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def table_csv(rows):
    """The comparison table as CSV text (numbers at full precision)."""
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return out.getvalue()


def _cell(value):
    if isinstance(value, float):
        return "" if math.isnan(value) else f"{value:.4g}"
    return str(value).replace("|", "/")


def write_report(report_dir, rows, sequences, columns=12):
    """Write the report files of :func:`compare` into ``report_dir`` atomically."""
    render = require("isotween.render", "cli")
    with atomic_dir(report_dir) as tmp:
        (tmp / "table.md").write_text(table_markdown(rows), encoding="utf-8")
        (tmp / "table.csv").write_text(table_csv(rows), encoding="utf-8")
        if sequences:
            render.write_methods_figure(sequences, tmp / "methods.png", columns)
            render.write_metrics_figure(sequences, tmp / "metrics.png")


# `isotween.compare(...)` calls `compare`; `import isotween.compare` still gives this module
make_callable(__name__)
