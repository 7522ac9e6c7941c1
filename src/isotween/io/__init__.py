"""Files: shapes (.obj .off .svg .json .npz), sequences (.npz .json, frame folders).

Formats are described in docs/formats.md. Every reader raises
`isotween.errors.FileFormatError` naming the file and the line or element at
fault; every writer writes atomically (temporary file, then rename: `atomic_path`,
`atomic_dir`). Rendered outputs (animations, pictures) are written by `isotween.outputs`.
"""

from ._files import atomic_dir, atomic_path, write_text
from .frames import FRAME_FORMATS, write_frames
from .sequence_file import is_sequence_file, load_sequence, save_sequence
from .shapes import SHAPE_FORMATS, load, save

__all__ = [
    "load",
    "save",
    "load_sequence",
    "save_sequence",
    "is_sequence_file",
    "write_frames",
    "atomic_path",
    "atomic_dir",
    "write_text",
    "SHAPE_FORMATS",
    "FRAME_FORMATS",
]
