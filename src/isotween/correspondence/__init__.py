"""Correspondence: making two shapes compatible (same vertices and connectivity).

`correspond` does it all for any two drawings (regions, holes and polylines
paired, rings resampled, filled regions meshed); `check_compatible` checks a
pair; `resample` gives two sets of outlines common point counts; `mesh_pair`
triangulates an outline pair into compatible meshes.
"""

import importlib
from typing import TYPE_CHECKING

# names that are also submodules are bound here: importing the submodule would otherwise
# replace a lazy name on the package (these modules need only numpy)
from .compatibility import check_compatible
from .correspond import (
    Correspondence,
    CorrespondenceReport,
    correspond,
    correspond_keys,
    mesh_outlines,
    region_key,
)
from .resample import resample

#: public name -> submodule that defines it, imported on first use (PEP 562): the meshers
#: (scipy.sparse.linalg, shapely) load only when a pair is meshed
_NAMES = {
    "MeshPair": "meshing",
    "mesh_pair": "meshing",
}

__all__ = ["Correspondence", "CorrespondenceReport", "MeshPair", "check_compatible", "correspond",
           "correspond_keys", "mesh_outlines", "mesh_pair", "region_key", "resample"]

if TYPE_CHECKING:
    from .meshing import MeshPair, mesh_pair


def __getattr__(name):
    """Load a public name, or a submodule (``meshing``, ``compatible_mesh``), on first use."""
    if name in _NAMES:
        value = getattr(importlib.import_module(f".{_NAMES[name]}", __name__), name)
    elif name in ("meshing", "compatible_mesh"):
        value = importlib.import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_NAMES))
