"""Imports every command module so that each registers itself on the group."""
from . import batch, compare, demo, info, interpolate, motion, prepare, render  # noqa: F401
