"""isotween: as-isometric-as-possible planar shape interpolation.

Pipeline: correspondence (compatibility, resampling, meshing) -> initialisation
(edge-vector or linear) -> optimisation (local or global solver, time scheme) ->
outputs (metrics, files, rendering); docs/architecture.md maps it onto the modules.

``import isotween`` loads the model (`Shape`, `Sequence`) and the errors only;
every other public name and submodule loads on first use (PEP 562), so a
program pays for the solver, the readers or the renderers only when it calls
them.
"""

import importlib
from typing import TYPE_CHECKING

from .errors import IsotweenError
from .sequence import Sequence
from .shape import Shape, ShapeLike

__version__ = "0.1.0"

#: public name -> module that defines it (relative to the package), loaded on first use
_NAMES = {
    # modules named as their function are callable as it (see isotween._callable)
    "batch": ".batch",
    "compare": ".compare",
    "interpolate": ".interpolate",
    "transfer": ".transfer",
    "check_compatible": ".correspondence",
    "correspond": ".correspondence",
    "mesh_pair": ".correspondence",
    "resample": ".correspondence",
    "edit": ".editing",
    "interpolate_keyframes": ".keyframes",
    "load": ".io",
    "load_sequence": ".io",
    "save": ".io",
    "save_sequence": ".io",
    "write_output": ".outputs",
    "morph": ".pipeline",
    "prepare_pair": ".pipeline",
    "prepare_keys": ".pipeline",
    "RelativeVelocityField": ".velocity",
    "relative_velocity_field": ".velocity",
}

#: submodules that are public names of the package, loaded on first use
_SUBMODULES = ("easing", "io", "metrics", "studio", "times")

__all__ = [
    "IsotweenError", "RelativeVelocityField", "Sequence", "Shape", "ShapeLike", "batch", "check_compatible", "compare",
    "correspond", "easing", "edit", "interpolate", "interpolate_keyframes", "io", "load", "load_sequence", "mesh_pair",
    "metrics", "morph", "prepare_keys", "prepare_pair", "relative_velocity_field", "resample", "save", "save_sequence",
    "studio", "times", "transfer", "write_output",
]

if TYPE_CHECKING:  # what the lazy names are, for type checkers and editors
    from . import easing, io, metrics, studio, times
    from .batch import batch
    from .compare import compare
    from .correspondence import check_compatible, correspond, mesh_pair, resample
    from .editing import edit
    from .interpolate import interpolate
    from .io import load, load_sequence, save, save_sequence
    from .keyframes import interpolate_keyframes
    from .outputs import write_output
    from .pipeline import morph, prepare_keys, prepare_pair
    from .transfer import transfer
    from .velocity import RelativeVelocityField, relative_velocity_field


def __getattr__(name):
    """Load a public name or a submodule on first use (PEP 562) and keep it in the package's namespace."""
    if name in _NAMES:
        module = importlib.import_module(_NAMES[name], __name__)
        value = module if module.__name__ == f"{__name__}.{name}" else getattr(module, name)
    elif name.startswith("__"):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    else:  # a submodule: the public ones in _SUBMODULES, and the others as `import isotween.NAME` gives them
        try:
            value = importlib.import_module(f".{name}", __name__)
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":
                raise
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
