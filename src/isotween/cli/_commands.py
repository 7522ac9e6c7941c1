"""Imports every command module so that each registers itself on the group."""
from . import batch, compare, demo, edit, info, interpolate, keyframes, prepare, render, studio, transfer  # noqa: F401
