"""The way from any two inputs to an animation: load, correspondence, solve, fold check, output.

`prepare_pair` loads two inputs (files or shapes) and makes them compatible
as the correspondence policy says; `morph` then interpolates them, falls
back to the fold-free morph where meshes built here fold, and writes the
output. The command line, the batch runner and the studio call these.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from .errors import IncompatibleShapesError, ParameterError, ShapeError

__all__ = ["Prepared", "prepare_pair", "morph", "collapse_vanishing", "CORRESPONDENCE", "DRAWING_SUFFIXES"]

#: correspondence policies: 'auto' (drawings always, other compatible inputs kept), 'always', 'never'
CORRESPONDENCE = ("auto", "always", "never")
#: file kinds whose point order means nothing: correspondence always runs on them under 'auto'
DRAWING_SUFFIXES = (".svg",)

#: options of `isotween.correspond` that `prepare_pair` passes on
CORRESPOND_OPTIONS = ("points", "segment", "rotation", "outline", "mesh_size", "unmatched", "pairs", "landmarks")


@dataclass
class Prepared:
    """Two compatible shapes and how they were made.

    Attributes
    ----------
    source, target : Shape
    report : CorrespondenceReport or None
        None when the inputs were used as they were.
    built_meshes : bool
        Correspondence built triangle meshes that the inputs did not have
        (their in-betweens are fold-checked by `morph`).
    """

    source: object
    target: object
    report: object = None
    built_meshes: bool = False

    def summary(self):
        """One line on the correspondence, or '' when none ran."""
        return "" if self.report is None else self.report.summary()


def _is_drawing(item):
    return isinstance(item, (str, os.PathLike)) and Path(item).suffix.lower() in DRAWING_SUFFIXES


def _load(item, name):
    """A Shape of a path, a Shape or a polygon array."""
    from .correspondence.compatibility import as_shape
    from .io import load

    return load(item) if isinstance(item, (str, os.PathLike)) else as_shape(item, name)


def prepare_pair(source, target, *, correspondence="auto", names=None, _drawing=False, **options):
    """Two inputs made compatible.

    Parameters
    ----------
    source, target : Shape, (n, 2) array_like, or path
        Shapes, polygons, or files (.svg .obj .off .json .npz).
    correspondence : {'auto', 'always', 'never'}
        ``'auto'``: drawings (SVG files) always go through `isotween.correspond`
        (their point order means nothing); other inputs are used as they are
        when compatible and corresponded otherwise. ``'always'``: correspond
        even compatible inputs. ``'never'``: use the inputs as they are
        (`IncompatibleShapesError` if they are not compatible).
    names : (str, str), optional
        How to call the inputs in messages (default: their paths, or
        'source' and 'target').
    **options
        Options of `isotween.correspond` (``points``, ``segment``,
        ``rotation``, ``outline``, ``mesh_size``, ``unmatched``, ``pairs``,
        ``landmarks``).

    Returns
    -------
    Prepared

    Raises
    ------
    ParameterError
        An unknown policy or option.
    IncompatibleShapesError
        ``correspondence='never'`` on inputs that are not compatible.
    """
    from .correspondence import check_compatible, correspond

    if correspondence not in CORRESPONDENCE:
        raise ParameterError(f"correspondence must be one of {', '.join(CORRESPONDENCE)}, got {correspondence!r}")
    unknown = sorted(set(options) - set(CORRESPOND_OPTIONS))
    if unknown:
        raise ParameterError(f"unknown correspondence option(s): {', '.join(unknown)}")
    drawing = _drawing or _is_drawing(source) or _is_drawing(target)
    if names is None:
        names = [str(x) if isinstance(x, (str, os.PathLike)) else role
                 for x, role in ((source, "source"), (target, "target"))]
    a, b = _load(source, "source"), _load(target, "target")
    if correspondence == "never" or (correspondence == "auto" and not drawing and not options):
        try:
            check_compatible(a, b)
        except IncompatibleShapesError as exc:
            if correspondence == "never":
                raise IncompatibleShapesError(
                    f"{names[0]} and {names[1]} are not compatible ({exc}); let correspondence run "
                    "(correspondence='auto')") from None
        else:
            return Prepared(a, b)
    try:
        src, tgt, report = correspond(a, b, always=True, **options)
    except (ShapeError, IncompatibleShapesError) as exc:
        raise type(exc)(f"{names[0]} (source) and {names[1]} (target): {exc}") from None
    return Prepared(src, tgt, report, built_meshes=not a.n_faces and src.n_faces > 0)


def collapse_vanishing(seq, report):
    """Collapse, in the first (last) frame, every ring that is only a small copy in the source (target).

    An item or hole that one drawing lacks grows from (shrinks to) a small
    copy; at its end it becomes one point (its centroid), so that the end
    frame is the drawing exactly, with no speck.

    Parameters
    ----------
    seq : Sequence
        Changed in place.
    report : CorrespondenceReport or None
    """
    if report is None or not getattr(report, "vanishing", None):
        return
    for key, frame in zip(report.vanishing, (0, -1), strict=False):
        for idx in key:
            seq.frames[frame, idx] = seq.frames[frame, idx].mean(axis=0)


def morph(source, target, output=None, *, frames=9, correspondence="auto", fold=None, correspond_options=None,
          render_options=None, **options):
    """Any two inputs to an in-between sequence (and an output file).

    Parameters
    ----------
    source, target : Shape, (n, 2) array_like, or path
    output : path, optional
        Written with `isotween.write_output` (its kind follows the suffix).
    frames : int
        Frames, both inputs included.
    correspondence : {'auto', 'always', 'never'}
        See `prepare_pair`.
    fold : {'allow', 'fallback'}, optional
        Default: ``'fallback'`` when correspondence built the meshes (an
        in-between that folds is replaced by the fold-free morph, and
        ``info['fallback']`` says so), else ``'allow'``.
    correspond_options : dict, optional
        Options of `isotween.correspond`.
    render_options : dict, optional
        Options of `isotween.write_output`.
    **options
        Options of `isotween.interpolate` (``method``, ``solver``, ...).

    Returns
    -------
    Sequence
        ``info['correspondence']``: the correspondence's one-line summary
        ('' when none ran).

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> theta = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    >>> a = np.c_[np.cos(theta), 0.5 * np.sin(theta)]
    >>> seq = isotween.morph(a, a @ [[0, 1], [-1, 0]] + [3, 0], frames=5)
    >>> seq.frames.shape
    (5, 24, 2)
    """
    from .interpolate import interpolate

    prepared = prepare_pair(source, target, correspondence=correspondence, **(correspond_options or {}))
    if fold is None:
        fold = "fallback" if prepared.built_meshes else "allow"
    seq = interpolate(prepared.source, prepared.target, frames=frames, fold=fold, **options)
    seq.info["correspondence"] = prepared.summary()
    collapse_vanishing(seq, prepared.report)
    if output is not None:
        from .outputs import write_output

        write_output(seq, output, **(render_options or {}))
    return seq
