"""isotween: as-isometric-as-possible planar shape interpolation.

Pipeline: correspondence (compatibility, resampling, meshing) -> initialisation
(edge-vector or linear) -> optimisation (local or global solver, time scheme) ->
outputs (metrics, files, rendering); docs/architecture.md maps it onto the modules.
"""

from . import easing, io, metrics, studio, times
from .batch import batch
from .compare import compare
from .correspondence import check_compatible, correspond, mesh_pair, resample
from .editing import edit
from .errors import IsotweenError
from .interpolate import interpolate
from .io import load, load_sequence, save, save_sequence
from .keyframes import interpolate_keyframes
from .outputs import write_output
from .pipeline import morph, prepare_pair
from .sequence import Sequence
from .shape import Shape, ShapeLike
from .transfer import transfer
from .velocity import RelativeVelocityField, relative_velocity_field

__version__ = "0.1.0"

__all__ = [
    "IsotweenError", "RelativeVelocityField", "Sequence", "Shape", "ShapeLike", "batch", "check_compatible", "compare",
    "correspond", "easing", "edit", "interpolate", "interpolate_keyframes", "io", "load", "load_sequence", "mesh_pair",
    "metrics", "morph", "prepare_pair", "relative_velocity_field", "resample", "save", "save_sequence", "studio",
    "times", "transfer", "write_output",
]
