"""The result of an interpolation: frames plus how they were obtained."""

from __future__ import annotations

import html
import numbers
import os
import weakref
from collections.abc import Iterator
from dataclasses import dataclass, field, replace
from typing import Any, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._validate import check_int, is_int
from .errors import ParameterError
from .shape import Shape

__all__ = ["Sequence"]

#: Sequence -> (options, PathData) of its last path_data() call
_PATH_DATA: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


@dataclass(eq=False, repr=False)
class Sequence:
    """A shape sequence with fixed connectivity.

    A Sequence behaves like a read-mostly container of shapes: ``seq[k]`` is
    the :class:`Shape` of frame ``k`` (negative indices count from the end),
    ``seq[a:b]`` (or an index array) is the Sequence of the kept frames with
    their times and metadata, ``len(seq)`` counts frames, iteration yields
    shapes, and ``np.asarray(seq)`` is the ``(F, n, 2)`` frame array.

    ``==`` is identity (a Sequence holds a writeable frame array, so it is
    hashed by identity too); compare values with :meth:`equals`.

    Attributes
    ----------
    frames : (F, n, 2) float64 array
        Vertex positions of every frame, both inputs included.
    shape : Shape
        Connectivity (and source geometry) shared by every frame.
    times : (F,) float array
        Time parameter t_k of every frame in [0, 1].
    scheme : str
        Time discretisation the energy was measured with ('midpoint' or 'paper').
    energy : list of float
        Isometric energy (docs/how-it-works.md) after every iteration.
    iterations : int
    converged : bool
    timings : dict
        Seconds spent per stage ('init', 'solve', 'total', ...).
    method : str
    info : dict
        Anything else a method reports.

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    >>> seq = isotween.interpolate(bar, bar.rotate(np.pi / 2), frames=5)
    >>> len(seq), np.asarray(seq).shape, len(seq[1:4]), seq[-1].equals(seq[4])
    (5, (5, 3, 2), 3, True)
    """

    frames: np.ndarray
    shape: Shape
    times: np.ndarray = None  # type: ignore[assignment]
    scheme: str = "midpoint"
    energy: list = field(default_factory=list)
    iterations: int = 0
    converged: bool = True
    timings: dict = field(default_factory=dict)
    method: str = "aiap"
    info: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.frames = np.asarray(self.frames, dtype=np.float64)
        if self.times is None:
            self.times = np.linspace(0.0, 1.0, len(self.frames))
        self.times = np.asarray(self.times, dtype=np.float64)

    # ------------------------------------------------------------------ container
    def __len__(self) -> int:
        return len(self.frames)

    @overload
    def __getitem__(self, k: int) -> Shape: ...
    @overload
    def __getitem__(self, k: slice | ArrayLike) -> Sequence: ...
    def __getitem__(self, k: int | slice | ArrayLike) -> Shape | Sequence:
        """Frame ``k`` as a Shape, or the Sequence of the frames a slice or index array keeps."""
        if is_int(k):
            n = len(self)
            if not -n <= k < n:
                raise IndexError(f"frame {k} out of range for a sequence of {n} frames")
            return self.shape.with_vertices(self.frames[k])
        if not isinstance(k, slice):
            k = np.asarray(k)
            if k.dtype == bool and k.shape != (len(self),):
                raise IndexError(f"a boolean index must have one value per frame ({len(self)}), got {k.shape}")
            if k.dtype != bool and not np.issubdtype(k.dtype, np.integer) or k.ndim != 1:
                raise IndexError("index a Sequence with an integer, a slice, or a 1-D integer or boolean array")
        return replace(self, frames=self.frames[k].copy(), times=self.times[k].copy(),
                       energy=list(self.energy), timings=dict(self.timings), info=dict(self.info))

    def __iter__(self) -> Iterator[Shape]:
        return (self.shape.with_vertices(f) for f in self.frames)

    #: numpy defers to Sequence in binary operations, so ``array == seq`` is False, not elementwise
    __array_ufunc__ = None

    def __array__(self, dtype: Any = None, copy: bool | None = None) -> NDArray:
        """The (F, n, 2) frames, so that ``np.asarray(seq)`` gives the positions."""
        if copy is False and dtype is not None and np.dtype(dtype) != self.frames.dtype:
            raise ValueError("a copy is needed to change the dtype of the frames")
        f = self.frames if dtype is None else self.frames.astype(dtype, copy=False)
        return f.copy() if copy else f

    @property
    def y_down(self) -> bool:
        """Whether the frames are drawn with y growing downwards (from :attr:`shape`)."""
        return self.shape.y_down

    def equals(self, other: object, atol: float = 0.0) -> bool:
        """Whether ``other`` is a Sequence with the same frames and times, up to ``atol``.

        The shapes' connectivity (edges, faces, paths, paint, ``y_down``) must
        match exactly, frames and times within ``atol`` in every coordinate. Metadata (energy, timings, ...) is not
        compared. Never raises: anything that is not a Sequence is unequal.

        Parameters
        ----------
        other : object
        atol : float
            Largest coordinate difference still called equal.

        Returns
        -------
        bool

        Examples
        --------
        >>> import copy
        >>> import isotween
        >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
        >>> seq = isotween.interpolate(bar, bar.rotate(1.0), frames=4)
        >>> seq.equals(copy.deepcopy(seq)), seq.equals(seq[:3]), seq.equals("a string")
        (True, False, False)
        """
        if other is self:
            return True
        if not isinstance(other, Sequence):
            return False
        if (self.frames.shape != other.frames.shape or self.times.shape != other.times.shape
                or self.shape.vertices.shape != other.shape.vertices.shape):
            return False
        if not self.shape.with_vertices(other.shape.vertices).equals(other.shape):
            return False  # connectivity, paths, paint differ
        tol = float(atol)
        return bool(np.all(np.abs(self.frames - other.frames) <= tol)
                    and np.all(np.abs(self.times - other.times) <= tol))

    # ------------------------------------------------------------------ complex views
    @property
    def z(self) -> NDArray[np.complex128]:
        """(F, n) complex frames."""
        return self.frames[..., 0] + 1j * self.frames[..., 1]

    def edge_vectors(self) -> NDArray[np.complex128]:
        """(F, E) complex edge vectors of every frame.

        Examples
        --------
        >>> import isotween
        >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
        >>> isotween.interpolate(bar, bar.translate([0, 1]), frames=3).edge_vectors().tolist()
        [[(1+0j)], [(1+0j)], [(1+0j)]]
        """
        return self.shape.edge_vectors(self.z)

    # ------------------------------------------------------------------ in-between times
    def at(self, t: float) -> Shape:
        """The shape at any time ``t`` between the first and the last frame.

        Exact at the frames and smooth between them: in the interval
        [t_k, t_{k+1}] every edge turns at its fitted angular speed (the
        corrected Eq. 8 at the interval's midpoint, the relative velocity
        field of Sec. 3) while its length moves linearly from ``|e(t_k)|`` to
        ``|e(t_{k+1})|``; the vertices are then assembled from those edge
        vectors by Eq. (10), each connected component's centroid moving
        linearly between the frames. A rigid motion that turns at constant
        speed about the centroid is reproduced exactly at every t.

        Parameters
        ----------
        t : float
            In ``[times[0], times[-1]]`` ([0, 1] for a whole sequence).

        Returns
        -------
        Shape

        Raises
        ------
        ParameterError
            ``t`` outside the sequence's time range, or times that do not
            increase.

        Examples
        --------
        >>> import numpy as np
        >>> import isotween
        >>> bar = isotween.Shape.from_polyline([[-1, 0], [0, 0], [1, 0]])
        >>> seq = isotween.interpolate(bar, bar.rotate(np.pi / 2), frames=3)
        >>> mid = seq.at(0.25)  # an eighth of a turn
        >>> bool(np.allclose(mid.vertices, bar.rotate(np.pi / 8).vertices))
        True
        """
        if not isinstance(t, numbers.Real):
            raise ParameterError(f"t must be a number, got {t!r}")
        try:
            value = float(t)
        except OverflowError:  # an integer beyond every float
            raise ParameterError(f"t (an integer of {len(str(abs(int(t))))} digits) is outside the sequence's "
                                 f"times [{self.times[0]}, {self.times[-1]}]") from None
        return self.shape.with_vertices(self._positions(np.array([value]))[0])

    def resample(self, frames: int | None = None, times: ArrayLike | None = None) -> Sequence:
        """The sequence at new frame times, by :meth:`at`.

        Parameters
        ----------
        frames : int, optional
            Number of evenly spaced frames over the sequence's time range.
        times : (k,) array_like of float, optional
            The new frame times instead (within the time range, increasing).

        Returns
        -------
        Sequence
            Same shape and metadata; ``info['resampled_from']`` holds the
            original frame times.

        Examples
        --------
        >>> import numpy as np
        >>> import isotween
        >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
        >>> seq = isotween.interpolate(bar, bar.rotate(np.pi / 2), frames=5)
        >>> fine = seq.resample(frames=9)
        >>> len(fine), bool(np.allclose(fine.frames[::2], seq.frames))
        (9, True)
        """
        if (frames is None) == (times is None):
            raise ParameterError("give either frames or times")
        if times is None:
            frames = check_int("frames", frames, 2)
            from .resources import check_memory

            # the edge arrays of every new frame (a dozen complex values per edge and vertex)
            check_memory(200.0 * float(frames) * (self.shape.n_vertices + self.shape.n_edges + 1),
                         f"resampling to {frames} frames of {self.shape.n_vertices} vertices",
                         advice="use fewer frames")
            t = np.linspace(self.times[0], self.times[-1], int(frames))
        else:
            t = np.asarray(times, dtype=np.float64)
            if t.ndim != 1 or not len(t) or np.any(np.diff(t) <= 0):
                raise ParameterError("times must be a non-empty 1-D array of increasing times")
            from .resources import check_memory

            check_memory(200.0 * len(t) * (self.shape.n_vertices + self.shape.n_edges + 1),
                         f"resampling to {len(t)} frames of {self.shape.n_vertices} vertices", advice="use fewer times")
        info = dict(self.info, resampled_from=self.times.copy())
        return replace(self, frames=self._positions(t), times=t, energy=list(self.energy),
                       timings=dict(self.timings), info=info)

    def _positions(self, t: NDArray[np.float64]) -> NDArray[np.float64]:
        """(T, n, 2) vertex positions at the times ``t`` (see :meth:`at`)."""
        from .optimisation import backend
        from .optimisation.assembly import assembler_for
        from .optimisation.problem import pack
        from .optimisation.schemes import step_angle

        times = self.times
        if len(times) < 2 or np.any(np.diff(times) <= 0):
            raise ParameterError("at(t) needs at least two frames with increasing times")
        bad = np.flatnonzero(~np.isfinite(t) | (t < times[0]) | (t > times[-1]))
        if bad.size:
            raise ParameterError(f"t = {t[bad[0]]!r} is outside the sequence's times [{times[0]}, {times[-1]}]")
        k = np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2)  # interval of each t
        s = (t - times[k]) / (times[k + 1] - times[k])  # (T,) in [0, 1]
        z = self.z  # (F, n)
        top = self.shape.topology
        e = self.shape.edge_vectors(z).T  # (E, F)
        e0, e1 = e[:, k], e[:, k + 1]  # (E, T)
        # corrected Eq. (8) at the midpoint: the step angle omega = h c, whose Cayley
        # angle 2 atan(omega / 2) is exact for an edge that keeps its length
        omega = step_angle(e0 + e1, 2.0 * (e1 - e0))
        turn = 2.0 * np.arctan(0.5 * omega)
        len0, len1 = np.abs(e0), np.abs(e1)
        ok = (len0 > 0) & (len1 > 0)
        ratio = np.where(ok, e1 / np.where(ok, e0, 1.0), 1.0)
        # land exactly on e(t_{k+1}): the fitted turn picks the branch, the remainder is < pi
        turn = turn + np.angle(ratio * np.exp(-1j * turn))
        unit = np.where(ok, e0 / np.where(ok, len0, 1.0), 0.0)
        length = (1.0 - s) * len0 + s * len1
        edges = np.where(ok, length * np.exp(1j * s * turn) * unit, (1.0 - s) * e0 + s * e1)
        c = top.centroids(z.T)  # (C, F)
        centroids = (1.0 - s) * c[:, k] + s * c[:, k + 1]
        first, last = np.abs(e[:, 0]), np.abs(e[:, -1])
        weights = 2.0 / np.maximum(first + last, np.finfo(float).tiny)
        with backend.sized(e.shape[0] * len(t)):  # a short command's resample does not load numba
            out = assembler_for(self, self.shape, weights).positions(edges, centroids)  # Eq. (10), (n, T)
        for at_frame, frame in ((s == 0.0, k), (s == 1.0, k + 1)):  # the frames themselves, bit for bit
            out[:, at_frame] = z[frame[at_frame]].T
        return pack(out)

    # ------------------------------------------------------------------ path strings
    def path_data(self, t: float, *, curves: bool = True, precision: int | None = None,
                  tolerance: float | None = None) -> list[str]:
        """The SVG ``d`` string of every drawn group at time ``t``.

        A group is a region with its holes (filled by the even-odd rule) or
        one open path (see :func:`isotween.render.paths.outline_groups`).
        With ``curves`` the outlines are cubic Bezier curves within
        ``tolerance`` of the polylines, with the same commands at every t
        (the structure is chosen once for all frames), so the strings of two
        times interpolate command by command, as flubber's or GSAP's
        morphs expect. Coordinates are SVG user units, y down (a y-up
        shape is mirrored), those of :meth:`to_svg`.

        Parameters
        ----------
        t : float
            In ``[times[0], times[-1]]``; between frames, :meth:`at`.
        curves : bool
            Bezier curves (``C`` and ``L`` commands) or polylines (``L``).
        precision : int, optional
            Decimal places (default: about 1e-4 of the drawing's size).
        tolerance : float, optional
            Largest distance between curves and polylines, in shape units
            (default: 0.1 % of the diagonal of all frames).

        Returns
        -------
        list of str

        Examples
        --------
        >>> import isotween
        >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
        >>> seq = isotween.interpolate(bar, bar.translate([0, 1]), frames=3)
        >>> seq.path_data(0.5, precision=1), seq.path_data(0.5, precision=1, curves=False)
        (['M0,-.5C.7,-.5 1.3,-.5 2,-.5'], ['M0,-.5L1,-.5L2,-.5'])
        """
        from .render.paths import PathData

        key = (bool(curves), precision, tolerance)
        cached = _PATH_DATA.get(self)
        if cached is None or cached[0] != key or cached[1].seq.frames is not self.frames:
            cached = _PATH_DATA[self] = (key, PathData(self, curves=curves, precision=precision,
                                                       tolerance=tolerance))
        return cached[1](t)

    def to_svg(self, t: float, *, curves: bool = True, precision: int | None = None, size: int = 480,
               background: Any = None) -> str:
        """A standalone SVG document of the drawing at time ``t``, in its paint.

        Parameters
        ----------
        t : float
        curves, precision
            As in :meth:`path_data`.
        size : int or (2,) int
            Longest side in px, or ``(width, height)``.
        background : matplotlib colour, optional
            A rectangle behind the drawing; transparent when None.

        Returns
        -------
        str
            The view box is that of all frames, so documents of two times
            line up.

        Examples
        --------
        >>> import isotween
        >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
        >>> seq = isotween.interpolate(bar, bar.translate([0, 1]), frames=3)
        >>> seq.to_svg(1.0).count("<path")
        1
        """
        from .render.paths import svg_document

        self.path_data(t, curves=curves, precision=precision)  # builds (or reuses) the interpolator
        return svg_document(self, t, size=size, background=background, data=_PATH_DATA[self][1])

    # ------------------------------------------------------------------ output
    def save(self, path: str | os.PathLike, **options: Any) -> list:
        """Write the sequence as the output kind the path names.

        ``.npz`` / ``.json`` sequence files, ``.gif`` / ``.mp4`` / ``.svg`` /
        ``.html`` animations, a ``.png`` strip, or a folder of frame files; see
        :func:`isotween.write_output`.

        Parameters
        ----------
        path : str or os.PathLike
        **options
            ``format``, ``texture``, ``quiet`` as in :func:`isotween.write_output`.

        Returns
        -------
        list of pathlib.Path
            The files written.

        Examples
        --------
        >>> import os, tempfile
        >>> import isotween
        >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
        >>> seq = isotween.interpolate(bar, bar.rotate(1.0), frames=3)
        >>> with tempfile.TemporaryDirectory() as d:
        ...     back = isotween.load_sequence(seq.save(os.path.join(d, "bar.npz"))[0])
        >>> back.equals(seq)
        True
        """
        from .outputs import write_output

        return write_output(self, path, **options)

    def plot(self, ax: Any = None, frames: ArrayLike | int | None = None, *, indices: ArrayLike | None = None,
             **style: Any) -> Any:
        """Draw frames over each other on matplotlib axes, darker with time.

        As everywhere in isotween, ``frames`` is a count (the sequence's
        ``frames`` attribute is its array) and ``indices`` picks frames.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Default: a new figure's axes.
        frames : int, optional
            How many frames to pick evenly; default all of them up to 9, else
            9 evenly picked. (Frame indices here are deprecated: give
            ``indices``.)
        indices : (k,) array_like of int, optional
            The frames to draw (not with ``frames``).
        **style
            ``style`` and ``linewidth`` as in :func:`isotween.render.draw_frame`.

        Returns
        -------
        matplotlib.axes.Axes

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import isotween
        >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
        >>> ax = isotween.interpolate(bar, bar.rotate(1.0), frames=5).plot(frames=3)
        >>> len(ax.lines)
        3
        """
        from .render import draw_frame

        n = len(self)
        if indices is not None:
            if frames is not None:
                raise ParameterError("give frames (a count) or indices, not both")
            frames = indices
        elif frames is not None and not isinstance(frames, numbers.Integral):
            import warnings

            warnings.warn("Sequence.plot(frames=<indices>) is deprecated; give indices=", DeprecationWarning,
                          stacklevel=2)
        if frames is None or isinstance(frames, numbers.Integral):
            count = min(n, 9) if frames is None else int(frames)
            if not 1 <= count:
                raise ParameterError(f"frames must be at least 1, got {frames!r}")
            pick = np.unique(np.round(np.linspace(0, n - 1, min(count, n))).astype(int))
        else:
            pick = np.asarray(frames)
            if pick.ndim != 1 or not np.issubdtype(pick.dtype, np.integer) or np.any((pick < -n) | (pick >= n)):
                raise ParameterError(f"frames must be frame indices in [-{n}, {n}), got {frames!r}")
        if ax is None:
            import matplotlib.pyplot as plt

            ax = plt.figure().add_subplot()
        from matplotlib import colormaps

        cmap = colormaps["viridis"]
        options = {"style": "wire", **style}
        for j, k in enumerate(pick):
            draw_frame(ax, self[int(k)], color=cmap(j / max(len(pick) - 1, 1)), **options)
        return ax

    # ------------------------------------------------------------------ display
    def _repr_html_(self) -> str:
        """The interactive viewer (render/html.py) in an iframe, for Jupyter."""
        from .render.html import page_html

        page = page_html(self)
        return (f'<iframe srcdoc="{html.escape(page, quote=True)}" style="width:100%;height:560px;border:0" '
                f'title="{html.escape(repr(self))}"></iframe>')

    def __repr__(self) -> str:
        return (
            f"Sequence({len(self)} frames, t={self.times[0]:.3g}..{self.times[-1]:.3g}, "
            f"{self.shape.n_vertices} vertices, {self.shape.n_edges} edges, method={self.method!r}, "
            f"iterations={self.iterations}, converged={self.converged})"
        ) if len(self) else f"Sequence(0 frames, {self.shape.n_vertices} vertices, method={self.method!r})"
