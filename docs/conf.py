"""Sphinx configuration of the isotween documentation."""

import os
import sys

sys.path.insert(0, os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "src")))

import isotween  # noqa: E402

project = "isotween"
author = "The isotween contributors"
copyright = "2026, The isotween contributors"
version = release = isotween.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "**/__pycache__"]
myst_enable_extensions = ["deflist"]
myst_heading_anchors = 3

autodoc_typehints = "none"  # the numpydoc sections give types and shapes
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
numpydoc_validation_checks = set()

html_theme = "alabaster"
html_title = f"isotween {release}"
nitpicky = False
# docs/formats.md shows JSON with placeholders (x, y, ...), which the highlighter cannot lex
suppress_warnings = ["misc.highlighting_failure"]
