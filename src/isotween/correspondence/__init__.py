"""Correspondence: making two shapes compatible (same vertices and connectivity).

`check_compatible` checks a pair; `resample` gives two sets of outlines common
point counts; `mesh_pair` triangulates an outline pair into compatible meshes.
"""

from .compatibility import check_compatible
from .meshing import MeshPair, mesh_pair
from .resample import resample

__all__ = ["MeshPair", "check_compatible", "mesh_pair", "resample"]
