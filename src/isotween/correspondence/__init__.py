"""Correspondence: making two shapes compatible (same vertices and connectivity)."""

from .compatibility import check_compatible

__all__ = ["check_compatible"]
