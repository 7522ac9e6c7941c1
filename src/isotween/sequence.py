"""The result of an interpolation: frames plus how they were obtained."""

from dataclasses import dataclass, field

import numpy as np

from .shape import Shape

__all__ = ["Sequence"]


@dataclass
class Sequence:
    """A shape sequence with fixed connectivity.

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
        Isometric energy (SPEC.md) after every iteration.
    iterations : int
    converged : bool
    timings : dict
        Seconds spent per stage ('init', 'solve', 'total', ...).
    method : str
    info : dict
        Anything else a method reports.
    """

    frames: np.ndarray
    shape: Shape
    times: np.ndarray = None
    scheme: str = "midpoint"
    energy: list = field(default_factory=list)
    iterations: int = 0
    converged: bool = True
    timings: dict = field(default_factory=dict)
    method: str = "aiap"
    info: dict = field(default_factory=dict)

    def __post_init__(self):
        self.frames = np.asarray(self.frames, dtype=np.float64)
        if self.times is None:
            self.times = np.linspace(0.0, 1.0, len(self.frames))
        self.times = np.asarray(self.times, dtype=np.float64)

    def __len__(self):
        return len(self.frames)

    def __getitem__(self, k):
        return self.shape.with_vertices(self.frames[k])

    def __iter__(self):
        return (self[k] for k in range(len(self)))

    @property
    def z(self):
        """(F, n) complex frames."""
        return self.frames[..., 0] + 1j * self.frames[..., 1]

    def edge_vectors(self):
        """(F, E) complex edge vectors of every frame."""
        return self.shape.edge_vectors(self.z)

    def __repr__(self):
        return (
            f"Sequence({len(self)} frames, {self.shape.n_vertices} vertices, "
            f"{self.shape.n_edges} edges, method={self.method!r}, iterations={self.iterations}, "
            f"converged={self.converged})"
        )
