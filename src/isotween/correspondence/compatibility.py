"""Checks that two shapes can be interpolated: same vertices, same connectivity."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import IncompatibleShapesError, ShapeError
from ..shape import Shape

if TYPE_CHECKING:
    from collections.abc import Sequence
    from typing import Any

    from ..shape import ShapeLike

__all__ = ["check_compatible", "as_shape"]


def as_shape(obj: ShapeLike, name: str = "shape") -> Shape:
    """Accept a `Shape`, or an (n, 2) array_like polygon (`Shape.from_polygon`).

    Examples
    --------
    >>> from isotween.correspondence.compatibility import as_shape
    >>> as_shape([[0, 0], [1, 0], [0, 1]]).n_edges
    3
    """
    if isinstance(obj, Shape):
        return obj
    return Shape.coerce(obj, name)


def check_compatible(*shapes: Shape, names: Sequence[str] | None = None,
                     edge_vectors: Sequence[Any] | None = None, diagonal: float | None = None) -> None:
    """Raise `IncompatibleShapesError` unless all shapes share connectivity.

    Checks the vertex count, the edge list (same pairs, same order), the faces,
    and that no edge has zero length in any shape.

    Parameters
    ----------
    *shapes : Shape
        Two or more shapes; the first is the reference.
    names : list of str, optional
        How to call each shape in messages (default 'source', 'target', 'shape 2', ...).
    edge_vectors : list of (E,) complex, optional
        Every shape's edge vectors (in any orientation), when the caller has
        them already; they are only used once the connectivity checks passed.
    diagonal : float, optional
        An upper bound of every shape's bounding-box diagonal (e.g. that of
        all shapes together): the diagonals are then computed only when an
        edge is short enough to need them.

    Examples
    --------
    >>> import isotween
    >>> tri = isotween.Shape.from_polygon([[0, 0], [1, 0], [0, 1]])
    >>> isotween.check_compatible(tri, tri.rotate(1.0))  # passes silently
    >>> isotween.check_compatible(tri, isotween.Shape.from_polygon([[0, 0], [1, 0], [1, 1], [0, 1]]))
    Traceback (most recent call last):
        ...
    isotween.errors.IncompatibleShapesError: source has 3 vertices but target has 4; ...
    """
    if names is None:
        names = ["source", "target"] + [f"shape {i}" for i in range(2, len(shapes))]
    ref = shapes[0]
    for s, name in zip(shapes[1:], names[1:], strict=False):
        if s.n_vertices != ref.n_vertices:
            raise IncompatibleShapesError(
                f"{names[0]} has {ref.n_vertices} vertices but {name} has {s.n_vertices}; "
                "put them in correspondence first (isotween.morph(source, target) or isotween.correspond)"
            )
        if s.n_edges != ref.n_edges:
            raise IncompatibleShapesError(
                f"{names[0]} has {ref.n_edges} edges but {name} has {s.n_edges}; "
                "both shapes need the same connectivity"
            )
        same = s.edges is ref.edges or (  # shapes made by with_vertices share the arrays
            np.all(ref.edges == s.edges, axis=1) | np.all(ref.edges == s.edges[:, ::-1], axis=1))
        if same is not True and not np.all(same):
            k = int(np.flatnonzero(~same)[0])
            raise IncompatibleShapesError(
                f"edge {k} joins vertices {ref.edges[k].tolist()} in {names[0]} "
                f"but {s.edges[k].tolist()} in {name}; list the edges in the same order"
            )
        if (ref.faces is None) != (s.faces is None) or (
            ref.faces is not None and ref.faces.shape != s.faces.shape
        ):
            raise IncompatibleShapesError(
                f"{names[0]} has {ref.n_faces} faces but {name} has {s.n_faces}"
            )
        if ref.faces is not None and len(ref.faces) and s.faces is not ref.faces:
            diff = np.flatnonzero(np.any(ref.faces != s.faces, axis=1))
            if diff.size:
                k = int(diff[0])
                raise IncompatibleShapesError(
                    f"face {k} is {ref.faces[k].tolist()} in {names[0]} but "
                    f"{s.faces[k].tolist()} in {name}"
                )
    if edge_vectors is None:
        edge_vectors = [s.edge_vectors() for s in shapes]
    for s, e, name in zip(shapes, edge_vectors, names, strict=False):
        _check_edge_lengths(s, e, name, diagonal)


def _check_edge_lengths(shape, e, name, diagonal=None):
    squared = e.real**2 + e.imag**2
    if not squared.size:
        return
    small = squared.min()
    if small > 0.0 and small > (1e-12 * (shape.bbox_diagonal() if diagonal is None else diagonal)) ** 2:
        return
    zero = np.flatnonzero(squared <= (1e-12 * max(shape.bbox_diagonal(), 1e-300)) ** 2)
    if zero.size:
        k = int(zero[0])
        raise ShapeError(
            f"edge {k} {shape.edges[k].tolist()} has zero length in {name} "
            f"(vertices {shape.edges[k, 0]} and {shape.edges[k, 1]} coincide)"
        )
