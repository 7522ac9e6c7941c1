"""Correspondence: making two shapes compatible (same vertices and connectivity).

`correspond` does it all for any two drawings (regions, holes and polylines
paired, rings resampled, filled regions meshed); `check_compatible` checks a
pair; `resample` gives two sets of outlines common point counts; `mesh_pair`
triangulates an outline pair into compatible meshes.
"""

from .compatibility import check_compatible
from .correspond import Correspondence, CorrespondenceReport, correspond, correspond_keys
from .meshing import MeshPair, mesh_pair
from .resample import resample

__all__ = ["Correspondence", "CorrespondenceReport", "MeshPair", "check_compatible", "correspond",
           "correspond_keys", "mesh_pair", "resample"]
