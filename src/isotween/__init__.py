"""isotween: as-isometric-as-possible planar shape interpolation.

Pipeline: correspondence (compatibility, resampling, meshing) -> initialisation
(edge-vector or linear) -> optimisation (local or global solver, time scheme) ->
outputs (metrics, files, rendering).
"""

from . import metrics
from .correspondence import check_compatible
from .errors import IsotweenError
from .interpolate import interpolate
from .sequence import Sequence
from .shape import Shape

__version__ = "0.1.0"

__all__ = ["IsotweenError", "Sequence", "Shape", "check_compatible", "interpolate", "metrics"]
