"""The way from any two inputs to an animation: load, correspondence, solve, fold check, output.

`prepare_pair` loads two inputs (files or shapes) and makes them compatible
as the correspondence policy says; `morph` then interpolates them, falls
back to the fold-free morph where meshes built here fold, and writes the
output. The command line, the batch runner and the studio call these.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypeGuard

from .errors import IncompatibleShapesError, ParameterError, ShapeError

__all__ = ["Prepared", "PreparedKeys", "prepare_pair", "prepare_steps", "mesh_prepared", "prepare_keys", "morph",
           "fitted", "size_hint", "collapse_vanishing", "finish", "unmatched_spans", "stagger_shares", "check_stagger",
           "needs_correspondence", "onto_connectivity", "CORRESPONDENCE", "DRAWING_SUFFIXES", "FIT_HINT", "STAGGER",
           "QUICK_STAGGERS", "STROKES"]

#: two inputs whose bounding boxes differ in size (diagonal) by this factor or more get a hint to fit them
FIT_HINT = 8.0
#: correspondence policies: 'auto' (drawings always, other compatible inputs kept), 'always', 'never'
CORRESPONDENCE = ("auto", "always", "never")
#: file kinds whose point order means nothing: correspondence always runs on them under 'auto'
DRAWING_SUFFIXES = (".svg",)

#: a piece with no partner leaves within this first share of a morph, one that appears comes in the last
STAGGER = 0.5
#: the shorter shares tried, in turn, where the pieces cannot be kept apart with the first
QUICK_STAGGERS = (0.2, 0.1)
#: what strokes that would pass through other paths do: drawn off and on ('untangle'), or morph all the same
STROKES = ("untangle", "morph")
#: options of `isotween.correspond` that `prepare_pair` passes on
CORRESPOND_OPTIONS = ("points", "segment", "rotation", "outline", "mesh_size", "unmatched", "pairs", "landmarks",
                      "meshes")
#: options of `isotween.correspondence.correspond_keys` that `prepare_keys` passes on
KEYS_OPTIONS = ("points", "segment", "rotation", "unmatched")


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
    notes : list of str
        Warnings for the user, one line each (e.g. flipped triangles of the
        older `prepare_steps` mesh).
    """

    source: object
    target: object
    report: object = None
    built_meshes: bool = False
    notes: list = field(default_factory=list)

    def summary(self):
        """One line on the correspondence, or '' when none ran."""
        return "" if self.report is None else self.report.summary()


def _is_drawing(item):
    """An SVG file, or a shape read from one (`Shape.drawing`)."""
    if _is_path(item):
        return Path(item).suffix.lower() in DRAWING_SUFFIXES
    return bool(getattr(item, "drawing", False))


def _is_path(item: object) -> TypeGuard[str | os.PathLike]:
    """A file to load: a path object, or a string with a file ending (or naming a file)."""
    if isinstance(item, os.PathLike):
        return True
    return isinstance(item, str) and (bool(Path(item).suffix) or os.path.isfile(item))


def _check_policy(correspondence):
    if correspondence not in CORRESPONDENCE:
        raise ParameterError(f"correspondence must be one of {', '.join(CORRESPONDENCE)}, got {correspondence!r}")


def _check_request(correspondence, options, allowed, which):
    """The policy and the option names of a request, else `ParameterError` naming what is unknown."""
    _check_policy(correspondence)
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        raise ParameterError(f"unknown correspondence option(s){which}: {', '.join(unknown)}")


def needs_correspondence(*items, correspondence="auto", names=None, options=False, drawings=True):
    """Whether inputs go through the pipeline's correspondence rather than straight to a solve.

    The rule shared by `isotween.interpolate`, `interpolate_keyframes`,
    `transfer` and `edit`: files (they need loading; drawings are always
    corresponded under ``'auto'``), ``correspondence='always'`` and explicit
    correspondence ``options`` go through it; under ``'auto'`` so do shapes
    that are not compatible but have paths (drawings that correspondence can
    pair). Compatible shapes, ``'never'``, and shapes without paths (bare
    meshes, point sets) do not: the caller's own checks then raise as before.

    Parameters
    ----------
    *items : Shape, (n, 2) array_like, or path
    correspondence : {'auto', 'always', 'never'}
    names : list of str, optional
        How to call the inputs in `as_shape`'s messages.
    options : bool
        Correspondence options were given.
    drawings : bool
        Under ``'auto'``, shapes read from drawings (`Shape.drawing`) go
        through it even when compatible. ``False`` for an edited frame that
        keeps the sequence's connectivity (a rendered frame read back).

    Returns
    -------
    bool
    """
    from .correspondence.compatibility import as_shape, check_compatible

    _check_policy(correspondence)
    if any(_is_path(x) for x in items):
        return True
    if drawings and correspondence == "auto" and any(_is_drawing(x) for x in items):
        return True
    if correspondence == "never":
        return False
    if correspondence == "always" or options:
        return True
    names = names or ["source", "target"] + [f"shape {i}" for i in range(2, len(items))]
    shapes = [as_shape(x, n) for x, n in zip(items, names, strict=False)]
    try:
        check_compatible(*shapes)
    except IncompatibleShapesError:
        return all(s.paths for s in shapes)
    except ShapeError:  # compatible connectivity, a degenerate edge: the solve reports it
        return False
    return False


def _load(item, name):
    """A Shape of a path, a Shape or a polygon array."""
    from .correspondence.compatibility import as_shape
    from .io import load

    return load(item) if _is_path(item) else as_shape(item, name)


def fitted(shape, into):
    """``shape`` scaled (strokes too) and moved so that its bounding box sits centred in ``into``'s, as large as fits.

    Parameters
    ----------
    shape, into : Shape

    Returns
    -------
    Shape
        ``shape`` under ``p -> s (p - c) + c'``, ``c`` and ``c'`` the two
        bounding-box centres and ``s`` the largest uniform scale that keeps
        the box inside ``into``'s (their diagonals' ratio where a box is flat
        along the axis that limits it, 1 for a single point); stroke widths
        times ``s``.

    Examples
    --------
    >>> from isotween import Shape
    >>> big = Shape.from_polygon([[0, 0], [32, 0], [32, 32], [0, 32]])
    >>> fitted(big, Shape.from_polygon([[0, 0], [1, 0], [1, 1], [0, 1]])).vertices.tolist()
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    """
    import dataclasses

    import numpy as np

    lo, hi = shape.vertices.min(axis=0), shape.vertices.max(axis=0)
    lo_to, hi_to = into.vertices.min(axis=0), into.vertices.max(axis=0)
    size, room = hi - lo, hi_to - lo_to
    both = (size > 0) & (room > 0)
    flat = np.hypot(*size) > 0 and np.hypot(*room) > 0
    scale = float(np.min(room[both] / size[both])) if both.any() else \
        float(np.hypot(*room) / np.hypot(*size)) if flat else 1.0  # a single point: moved only
    shift = 0.5 * (lo_to + hi_to) - scale * 0.5 * (lo + hi)
    out = shape.transform([[scale, 0.0, shift[0]], [0.0, scale, shift[1]], [0.0, 0.0, 1.0]])
    if shape.paint is not None:
        out.paint = [dataclasses.replace(p, stroke_width=p.stroke_width * scale) for p in shape.paint]
    return out


def size_hint(a, b, switch="fit=True (--fit)"):
    """A line for the user where shapes ``a`` and ``b`` differ in size by `FIT_HINT` or more, else None.

    ``switch``: how the user asks for `fitted` where the line is read.
    """
    da, db = a.bbox_diagonal(), b.bbox_diagonal()
    if not (da > 0 and db > 0) or max(db / da, da / db) < FIT_HINT:  # a single point is refused later
        return None
    return (f"hint: the target is {db / da:.3g} times the size of the source (bounding-box diagonals; each drawing "
            f"keeps its own units); {switch} scales it into the source's box")


def prepare_pair(source, target, *, correspondence="auto", names=None, fit=False, _drawing=False, **options):
    """Two inputs made compatible.

    Parameters
    ----------
    source, target : Shape, (n, 2) array_like, or path
        Shapes, polygons, or files (.svg .obj .off .json .npz).
    correspondence : {'auto', 'always', 'never'}
        ``'auto'``: drawings (SVG files, and shapes read from them:
        `Shape.drawing`) always go through `isotween.correspond` (their
        point order means nothing); other inputs are used as they are
        when compatible and corresponded otherwise. ``'always'``: correspond
        even compatible inputs. ``'never'``: use the inputs as they are
        (`IncompatibleShapesError` if they are not compatible).
    names : (str, str), optional
        How to call the inputs in messages (default: their paths, or
        'source' and 'target').
    fit : bool
        Scale and move the target into the source's bounding box first
        (`fitted`): drawings from sets drawn in different units (a 16-unit
        icon and a 512-unit one) then morph at one size. Without it, inputs
        that differ in size by `FIT_HINT` or more get a hint in ``notes``.
    **options
        Options of `isotween.correspond` (``points``, ``segment``,
        ``rotation``, ``outline``, ``mesh_size``, ``unmatched``, ``pairs``,
        ``landmarks``, ``meshes``).

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

    _check_request(correspondence, options, CORRESPOND_OPTIONS, "")
    drawing = _drawing or _is_drawing(source) or _is_drawing(target)
    if names is None:
        names = [str(x) if _is_path(x) else role for x, role in ((source, "source"), (target, "target"))]
    a, b = _load(source, "source"), _load(target, "target")
    notes = [] if fit or (hint := size_hint(a, b)) is None else [hint]
    if fit:
        b = fitted(b, a)
    hints = {k for k in options if k != "meshes"}  # a mesh cache asks for nothing
    if correspondence == "never" or (correspondence == "auto" and not drawing and not hints):
        try:
            check_compatible(a, b)
        except IncompatibleShapesError as exc:
            if correspondence == "never":
                raise IncompatibleShapesError(
                    f"{names[0]} and {names[1]} are not compatible ({exc}); let correspondence run "
                    "(correspondence='auto')") from None
        else:
            return Prepared(a, b, notes=notes)
    try:
        src, tgt, report = correspond(a, b, always=True, **options)
    except (ShapeError, IncompatibleShapesError) as exc:
        raise type(exc)(f"{names[0]} (source) and {names[1]} (target): {exc}") from None
    return Prepared(src, tgt, report, built_meshes=not a.n_faces and src.n_faces > 0, notes=notes)


def prepare_steps(source, target, *, resample=None, mesh=None, rotation=False):
    """Two inputs made compatible by the older explicit steps, instead of correspondence.

    Parameters
    ----------
    source, target : Shape, (n, 2) array_like, or path
    resample : int, optional
        Resample the outlines to this many vertices in all, rings paired in
        order (`isotween.resample`; ``rotation`` as there).
    mesh : float or 'auto', optional
        Triangulate the source outline with Triangle (largest triangle area,
        or ``'auto'``) and map it onto the target outline
        (`isotween.correspondence.mesh_pair`); the target mesh may have
        flipped triangles, which ``notes`` then names.
    rotation : bool

    Returns
    -------
    Prepared

    Raises
    ------
    ParameterError
        Neither step asked, or ``mesh`` is not a number or 'auto'.
    IncompatibleShapesError
        ``mesh`` on outlines that are not compatible (give ``resample`` too).
    """
    from .correspondence import check_compatible, mesh_pair
    from .correspondence import resample as resample_pair

    if resample is None and mesh is None:
        raise ParameterError("give resample=N and/or mesh=MAX_AREA (or 'auto')")
    a, b = _load(source, "source"), _load(target, "target")
    if resample is not None:
        a, b = resample_pair(a, b, points=resample, rotation=rotation)
    notes = []
    if mesh is not None:
        if mesh == "auto":
            max_area = None
        else:
            try:
                max_area = float(mesh)
            except (TypeError, ValueError):
                raise ParameterError(f"mesh takes a largest triangle area (a number) or 'auto', got {mesh!r}") \
                    from None
        check_compatible(a, b)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            a, b, flipped = mesh_pair(a, b, max_area=max_area)
        if flipped.size:
            notes.append(f"warning: the target mesh has {flipped.size} flipped triangle(s) of {a.n_faces} "
                         f"(first: triangle {flipped[0]})")
    return Prepared(a, b, built_meshes=mesh is not None, notes=notes)


def mesh_prepared(outline, *, mesh_size=None, meshes=None):
    """The meshes of an outline correspondence, as `prepare_pair` without ``outline`` makes them.

    Parameters
    ----------
    outline : Prepared
        From ``prepare_pair(..., outline=True)`` with a correspondence report; not changed.
    mesh_size, meshes
        As in `isotween.correspond`.

    Returns
    -------
    Prepared
    """
    from .correspondence import mesh_outlines

    src, tgt, report = mesh_outlines(outline.source, outline.target, outline.report, mesh_size=mesh_size,
                                     meshes=meshes)
    return Prepared(src, tgt, report, built_meshes=not outline.source.n_faces and src.n_faces > 0)


@dataclass
class PreparedKeys:
    """Several compatible shapes (keyframes, transfer inputs) and how they were made.

    Attributes
    ----------
    shapes : list of Shape
    report : CorrespondenceReport or None
        None when the inputs were used as they were.
    """

    shapes: list
    report: object = None

    def summary(self):
        """One line on the correspondence, or '' when none ran (or it changed nothing)."""
        return "" if self.report is None or self.report.unchanged else self.report.summary()


def prepare_keys(items, *, correspondence="auto", names=None, role="keyframe", fit=False, **options):
    """Several inputs (keyframes, transfer inputs) made compatible together, as outlines.

    Parameters
    ----------
    items : list of Shape, (n, 2) array_like, or path
    correspondence : {'auto', 'always', 'never'}
        As in `prepare_pair`: drawings (SVG files, shapes read from them)
        and inputs that are not compatible go through
        `isotween.correspondence.correspond_keys` (each paired with the first,
        one point count per ring), and under ``'always'`` any inputs; other
        compatible sets come back as they are.
    names : list of str, optional
        How to call the inputs in messages (default: their paths, or
        ``'<role> k'``).
    role : str
        What the inputs are, for messages ('keyframe', 'input').
    fit : bool
        Every input after the first scaled (strokes too) and moved into the
        first's bounding box first (`fitted`).
    **options
        Options of `correspond_keys` (``points``, ``segment``, ``rotation``,
        ``unmatched``).

    Returns
    -------
    PreparedKeys

    Raises
    ------
    ParameterError
        An unknown policy or option, or fewer than two inputs.
    IncompatibleShapesError
        ``correspondence='never'`` on inputs that are not compatible.
    """
    from .correspondence import check_compatible, correspond_keys

    _check_request(correspondence, options, KEYS_OPTIONS, " for several inputs")
    items = list(items)
    if names is None:
        names = [str(x) if _is_path(x) else f"{role} {k}" for k, x in enumerate(items)]
    shapes = [_load(x, f"{role} {k}") for k, x in enumerate(items)]
    if fit:
        shapes = [shapes[0], *(fitted(s, shapes[0]) for s in shapes[1:])]
    if correspondence == "never":
        try:
            check_compatible(*shapes, names=list(names))
        except IncompatibleShapesError as exc:
            raise IncompatibleShapesError(f"{', '.join(map(str, names))} are not compatible: {exc}; "
                                          "let correspondence run (correspondence='auto')") from None
        return PreparedKeys(shapes)
    try:  # drawings always (their point order means nothing), as a pair of drawings
        drawing = any(_is_drawing(x) or _is_drawing(s) for x, s in zip(items, shapes, strict=True))
        shapes, report = correspond_keys(shapes, always=correspondence == "always" or drawing, **options)
    except (ShapeError, IncompatibleShapesError) as exc:
        named = ", ".join(f"{n} ({role} {k})" if str(n) != f"{role} {k}" else str(n) for k, n in enumerate(names))
        raise type(exc)(f"{named}: {exc}") from None
    check_compatible(*shapes, names=list(names))
    return PreparedKeys(list(shapes), None if report.unchanged else report)


def onto_connectivity(frame, drawing, *, name="drawing", **options):
    """A drawing brought onto a frame's connectivity: the frame moved so that its outline is the drawing's.

    The frame and the drawing are corresponded as outlines
    (`isotween.correspond` with ``outline=True``, which keeps every vertex of
    both inputs), every path vertex of the frame goes where its partner on
    the drawing is, and the vertices on no path (a mesh's interior) follow by
    the mean-value map of the frame's mesh (`geometry.convex_map`). A region
    that only the drawing has is left out (the frame has nothing to carry
    it); one that only the frame has shrinks to a small copy.

    Parameters
    ----------
    frame : Shape
        With paths (the connectivity kept).
    drawing : Shape or path
        With paths.
    name : str
        How to call the drawing in messages.
    **options
        Options of `isotween.correspond` (``points``, ``segment``,
        ``unmatched``, ``landmarks``, ...; not ``outline``).

    Returns
    -------
    Shape
        ``frame.with_vertices(...)``: compatible with ``frame``.

    Raises
    ------
    IncompatibleShapesError
        The frame or the drawing has no paths, or a vertex of the frame is
        not found in the correspondence.
    """
    import numpy as np
    from scipy.spatial import cKDTree

    from .correspondence import correspond
    from .geometry import bbox_diagonal, convex_map

    drawing = _load(drawing, name)
    for shape, who in ((frame, "the sequence's frame"), (drawing, name)):
        if not shape.paths:
            raise IncompatibleShapesError(
                f"{who} has no paths (outlines), so {name} cannot be brought onto the sequence's connectivity; "
                "give a shape with the sequence's vertices and edges (e.g. an edited copy of the frame)")
    options.pop("outline", None)
    a, b, _ = correspond(frame, drawing, outline=True, always=True, **options)
    on_path = np.unique(np.concatenate([idx for idx, _ in frame.paths]))
    dist, where = cKDTree(a.vertices).query(frame.vertices[on_path])
    tol = 1e-9 * max(bbox_diagonal(frame.vertices), 1e-300)
    if np.any(dist > tol):
        k = int(on_path[np.argmax(dist)])
        raise IncompatibleShapesError(
            f"vertex {k} of the sequence's frame is not kept by the correspondence with {name}; "
            "give a shape with the sequence's vertices and edges")
    z = frame.z.copy()
    z[on_path] = b.z[where]
    if frame.n_faces and len(on_path) < frame.n_vertices:
        z = convex_map(frame.vertices, frame.faces, on_path, z[on_path])
    return frame.with_vertices(np.c_[z.real, z.imag])


def collapse_vanishing(seq, report):
    """Collapse, in the first (last) frame, every ring that is only a small copy in the source (target).

    An item or hole that one drawing lacks grows from (shrinks to) a small
    copy; at its end it becomes one point, so that the end frame is the
    drawing exactly, with no speck: a whole piece (every ring of a mesh
    component, its inner vertices too) at the mean of its ring vertices,
    so every one of its triangles is flat; a hole at the mean of its
    vertices, or where that would turn a triangle around it over, at the
    first of its own vertices that turns none, else inside the kernel of
    the triangles around it (`_kernel_point`). A slit that opened a hole
    into a notch is closed at its end (`correspondence.notches.close_slits`).

    Parameters
    ----------
    seq : Sequence
        Changed in place.
    report : CorrespondenceReport or None
    """
    if report is None:
        return
    import numpy as np

    from .correspondence.notches import close_slits
    from .geometry import triangle_areas

    shape = seq.shape
    faces = np.zeros((0, 3), dtype=np.int64) if shape.faces is None else shape.faces
    comp = shape.components
    on_paths = np.concatenate([p for p, _ in shape.paths]) if shape.paths else np.zeros(0, dtype=np.int64)
    for key, frame in zip(getattr(report, "vanishing", None) or [], (0, -1), strict=False):
        if not key:
            continue
        z = seq.frames[frame, :, 0] + 1j * seq.frames[frame, :, 1]
        gone = np.zeros(len(z), dtype=bool)
        gone[np.concatenate(key)] = True
        whole = np.ones(shape.n_components, dtype=bool)  # components whose every path vertex vanishes
        whole[comp[on_paths[~gone[on_paths]]]] = False
        for idx in key:
            if whole[comp[idx[0]]]:  # the whole piece, inner vertices too, to the mean of its ring vertices
                piece = comp == comp[idx[0]]
                z[piece] = z[piece & gone].mean()
                continue
            around = faces[np.isin(faces, idx).any(axis=1) & ~np.isin(faces, idx).all(axis=1)]
            points = np.r_[z[idx].mean(), z[idx]]  # the mean, else the first vertex that turns none over
            moved = np.repeat(z[None], len(points), axis=0)
            moved[:, idx] = points[:, None]
            turns = (triangle_areas(moved, around) * np.sign(triangle_areas(z, around)) < 0).any(axis=1)
            z[idx] = points[np.argmin(turns)] if not turns.all() else _kernel_point(z, around, idx)
        seq.frames[frame] = np.c_[z.real, z.imag]
    for slits, frame in zip(getattr(report, "slits", None) or [], (0, -1), strict=False):
        if slits:
            z = close_slits(seq.frames[frame, :, 0] + 1j * seq.frames[frame, :, 1], slits)
            seq.frames[frame] = np.c_[z.real, z.imag]


def _kernel_point(z, around, idx):
    """Where the vertices ``idx`` can meet so that no triangle of ``around`` (A, 3) turns over, at ``z`` (N,) complex.

    A triangle with one vertex of ``idx`` keeps its orientation while the
    meeting point stays on its side of the opposite edge: the kernel of the
    star is the intersection of those half-planes (within the star's
    bounding box), and the point is the centre of the largest circle inside
    it (shapely's maximum inscribed circle; scipy.optimize's linear
    programme for the same Chebyshev centre costs a command 0.15-0.2 s to
    import); triangles with two or three vertices of ``idx`` become flat.
    Where the kernel is empty, the mean of ``z[idx]``.

    Returns
    -------
    complex
    """
    import numpy as np

    from .errors import require
    from .geometry import triangle_areas

    shapely = require("shapely", "cli")
    mine = np.isin(around, idx)
    single = mine.sum(axis=1) == 1
    one, mean = around[single], complex(z[idx].mean())
    if not len(one):
        return mean
    sign = np.sign(triangle_areas(z, one))  # each triangle's orientation at z, to keep
    first = np.argmax(mine[single], axis=1)  # rolled so the moving vertex comes first: (p, v, w)
    r = np.arange(len(one))
    v, w = z[one[r, (first + 1) % 3]], z[one[r, (first + 2) % 3]]
    d = w - v
    keep = (np.abs(d) > 0) & (sign != 0)
    v, d, sign = v[keep], d[keep] / np.abs(d[keep]), sign[keep]
    star = z[np.unique(one)]
    lo, hi = complex(star.real.min(), star.imag.min()), complex(star.real.max(), star.imag.max())
    reach = 4 * abs(hi - lo) + 1e-300
    # the side of the line v -> w where (p, v, w) keeps its sign: twice its area grows along i d
    side = np.stack([v - reach * d, v + reach * d, v + reach * (d + 1j * sign * d), v + reach * (1j * sign * d - d)],
                    axis=1)
    halves = shapely.polygons(np.stack([side.real, side.imag], axis=-1))
    kernel = shapely.intersection_all(np.r_[halves, shapely.box(lo.real, lo.imag, hi.real, hi.imag)])
    if kernel.is_empty or kernel.area <= 0:
        return mean
    x0, y0, x1, y1 = kernel.bounds
    circle = shapely.maximum_inscribed_circle(kernel, 1e-6 * max(x1 - x0, y1 - y0))
    if circle.length <= 0:
        return mean
    x, y = shapely.get_coordinates(circle)[0]
    return complex(x, y)


def finish(seq, report, stagger=STAGGER, strokes="untangle"):
    """The steps after `isotween.interpolate` of a corresponded pair, in place (`morph`, the command line, the studio).

    An item one drawing lacks becomes one point in its end frame
    (`collapse_vanishing`); with ``strokes='untangle'``, a stroke that would
    pass through another path is drawn off and on instead
    (`isotween.strokes.untangle`, within ``stagger``, at most half). The
    parts of a region cut where the other drawing parts it go into
    ``info['joined']`` (lists of region indices), which the web outputs draw
    as one path (`isotween.render.paths.PathData`).
    """
    if getattr(report, "joined", None):
        seq.info["joined"] = [list(r) for r in report.joined]
    collapse_vanishing(seq, report)
    if strokes == "untangle":
        from .strokes import untangle

        untangle(seq, report, stagger)


def check_stagger(stagger):
    """``stagger`` as a float in (0, 1], or `ParameterError` naming it."""
    from ._validate import check_number

    value = check_number("stagger", stagger, bound="a number in (0, 1]")
    if value > 1.0:
        raise ParameterError(f"stagger must be a number in (0, 1], got {stagger!r}")
    return value


def stagger_shares(stagger):
    """The shares `unmatched_spans` gives, in the order `isotween.interpolate` tries them (1.0: the whole morph)."""
    shares = [stagger, *[q for q in QUICK_STAGGERS if q < stagger]]
    return shares if len(shares) > 1 else [stagger, 1.0]  # short already: the whole morph is the alternative


def unmatched_spans(shape, report, stagger=STAGGER, target=None):
    """Spans of time (`isotween.interpolate`'s ``spans``) that stagger the pieces with no partner.

    A filled piece (a connected part of ``shape`` with a region) that is
    only a small copy in the target shrinks to it, and fades out, within the
    first ``stagger`` of the morph; one that is only a small copy in the
    source grows and fades in within the last ``stagger``. So what leaves is
    gone before what comes arrives, as an animator staggers them, and the
    two rarely meet. A hole copy inside a piece that stays keeps the
    piece's span, and so does a stroke (it grows out of another stroke,
    drawn as it is, over the whole morph). The spans of shorter shares
    follow as alternatives, which `isotween.interpolate` tries in turn
    where the fold check cannot keep the pieces apart with the first:
    `QUICK_STAGGERS` below ``stagger`` (a piece that comes in later finds
    the others gone from its place), or where ``stagger`` is that short
    already, the whole morph. With ``target``, the first alternative gives
    each piece its own span: one that grows into a place that the pieces
    which stay still pass over (their outlines blended linearly from the
    source to the target) starts once they have passed, one that shrinks
    from such a place ends before they come (each within the last or
    first `FREE_UNTIL` of the morph; where that is not enough, the
    shared span).

    Parameters
    ----------
    shape : Shape
        The corresponded source.
    report : CorrespondenceReport or None
        Its ``vanishing`` rings: per drawing, the rings that are small copies there.
    stagger : float
        In (0, 1]; 1 leaves every piece on the whole morph.
    target : Shape, optional
        The corresponded target: the pieces' own spans (above).

    Returns
    -------
    (m, n, 2) float array, or None
        The alternatives; None where no piece is staggered.
    """
    import numpy as np

    stagger = check_stagger(stagger)
    vanishing = getattr(report, "vanishing", None) or []
    if stagger == 1.0 or not any(vanishing) or not shape.regions:
        return None
    component = shape.topology.components
    on_path = np.zeros(shape.n_vertices, dtype=bool)
    for idx, _ in shape.paths:
        on_path[idx] = True
    filled = np.unique(component[np.concatenate([shape.paths[r[0]][0] for r in shape.regions])])
    shares = stagger_shares(stagger)
    spans = np.tile([0.0, 1.0], (len(shares), shape.n_vertices, 1))
    wholes = []
    for rings in vanishing[:2]:
        small = np.zeros(shape.n_vertices, dtype=bool)
        for idx in rings:
            small[idx] = True
        # filled pieces whose every outline vertex is a small copy at this end
        wholes.append(np.isin(component, np.setdiff1d(np.intersect1d(component[small], filled),
                                                      component[on_path & ~small])))
    passing = None if target is None or shares[0] == 1.0 else _passing(shape, target, ~np.any(wholes, axis=0))
    for end, whole in enumerate(wholes):
        for spans_m, share in zip(spans, shares, strict=True):
            if share < 1.0:
                spans_m[whole] = (1.0 - share, 1.0) if end == 0 else (0.0, share)
        for c in [] if passing is None else np.unique(component[whole]):
            free = _free_time(shape, target, component == c, passing, end, shares[0])
            if free is not None:
                spans[0][component == c] = (free, 1.0) if end == 0 else (0.0, free)
    return None if np.all(spans[0] == (0.0, 1.0)) else spans


FREE_UNTIL = 0.1  # a staggered piece's own span lasts at least this share of the morph
FREE_STEPS = 20  # steps of the linear blend at which a staggered piece's place is tried


def _passing(shape, target, stay):
    """The pieces that stay, blended linearly from ``shape`` to ``target``; None where there are none.

    Returns
    -------
    (FREE_STEPS + 1, R) array of shapely Polygon, or None
        The filled regions whose outline lies in ``stay`` (N,) bool, at
        times 0 .. 1 (rows).
    """
    import numpy as np
    import shapely

    rings = [shape.paths[r[0]][0] for r in shape.regions if stay[shape.paths[r[0]][0]].all()]
    if not rings:
        return None
    t = np.linspace(0.0, 1.0, FREE_STEPS + 1)[:, None, None]
    return np.stack([shapely.polygons((1 - t) * shape.vertices[r] + t * target.vertices[r]) for r in rings], axis=1)


def _free_time(shape, target, piece, passing, end, share):
    """When a staggered piece's place is free of the pieces that stay, or None where it always is, or never.

    The place: the outer ring of ``piece`` ((N,) bool, its vertices) where
    it is whole (the target for one that grows, ``end`` 0; the source for one
    that shrinks); the pieces that stay: ``passing`` (`_passing`). Returns
    the start (growing) after the last step that meets the place, or the end
    (shrinking) before the first, where that is later (earlier) than the
    shared span's and leaves at least `FREE_UNTIL` of the morph.
    """
    import numpy as np
    import shapely

    mine = [shape.paths[r[0]][0] for r in shape.regions if piece[shape.paths[r[0]][0]].all()]
    if len(mine) != 1:
        return None
    place = shapely.Polygon((target if end == 0 else shape).vertices[mine[0]])
    meets = shapely.intersects(place, passing).any(axis=1)
    if not place.is_valid or not meets.any():
        return None
    t = np.linspace(0.0, 1.0, FREE_STEPS + 1)
    if end == 0:
        start = t[min(np.flatnonzero(meets)[-1] + 1, FREE_STEPS)]
        return float(start) if 1.0 - share < start <= 1.0 - FREE_UNTIL else None
    stop = t[max(np.flatnonzero(meets)[0] - 1, 0)]
    return float(stop) if FREE_UNTIL <= stop < share else None


def morph(source, target, output=None, *, frames=9, correspondence="auto", fit=False, fold=None,
          correspond_options=None, render_options=None, stagger=STAGGER, strokes="untangle", **options):
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
    fit : bool
        Scale and move the target into the source's bounding box first
        (`prepare_pair`).
    fold : {'allow', 'fallback'}, optional
        Default: ``'fallback'`` when correspondence built the meshes (an
        in-between that folds is replaced by the fold-free morph, and
        ``info['fallback']`` says so), else ``'allow'``.
    correspond_options : dict, optional
        Options of `isotween.correspond`.
    render_options : dict, optional
        Options of `isotween.write_output`.
    stagger : float
        A piece with no partner in the other drawing leaves (shrinks and
        fades) within this first share of the morph, and one that appears
        comes in within the last (`unmatched_spans`); 1: both over the whole
        morph.
    strokes : {'untangle', 'morph'}
        'untangle': a stroke that would pass through another path is drawn
        off within the first ``stagger`` (at most half) and on within the
        last (`isotween.strokes.untangle`; ``info['strokes']`` says how
        many); 'morph': every stroke morphs, through others or not.
    **options
        Options of `isotween.interpolate` (``method``, ``solver``, ...).

    Returns
    -------
    Sequence
        ``info['correspondence']``: the correspondence's one-line summary
        ('' when none ran); ``info['notes']``: `prepare_pair`'s notes for
        the user (e.g. the size hint), where there are any.

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
    from ._validate import check_choice
    from .interpolate import interpolate

    stagger = check_stagger(stagger)  # before any work
    check_choice("strokes", strokes, STROKES)
    prepared = prepare_pair(source, target, correspondence=correspondence, fit=fit, **(correspond_options or {}))
    if fold is None:
        fold = "fallback" if prepared.built_meshes else "allow"
    spans = unmatched_spans(prepared.source, prepared.report, stagger, prepared.target)
    seq = interpolate(prepared.source, prepared.target, frames=frames, fold=fold, correspondence="never",
                      spans=spans, **options)
    seq.info["correspondence"] = prepared.summary()
    if prepared.notes:
        seq.info["notes"] = list(prepared.notes)
    finish(seq, prepared.report, stagger, strokes)
    if output is not None:
        from .outputs import write_output

        write_output(seq, output, **(render_options or {}))
    return seq
