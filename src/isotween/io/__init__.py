"""Files: shapes (.obj .off .svg .json .npz), sequences (.npz .json, frame folders), outputs.

Formats are described in docs/formats.md. Every reader raises
`isotween.errors.FileFormatError` naming the file and the line or element at
fault; every writer writes atomically (temporary file, then rename).
"""

from .frames import FRAME_FORMATS, write_frames
from .output import OUTPUT_KINDS, output_kind, write_output
from .sequence_file import is_sequence_file, load_sequence, save_sequence
from .shapes import SHAPE_FORMATS, load, save

__all__ = [
    "load",
    "save",
    "load_sequence",
    "save_sequence",
    "is_sequence_file",
    "write_frames",
    "write_output",
    "output_kind",
    "SHAPE_FORMATS",
    "FRAME_FORMATS",
    "OUTPUT_KINDS",
]
