"""Turning a Sequence into same-size RGB images at one common scale."""


from ..paint import sequence_paint
from ._view import bbox_of, image_size, sequence_frames, stroke_margin
from .defaults import BACKGROUND
from .frame import FramePainter
from .texture import load_texture

__all__ = ["SequenceRenderer"]


class SequenceRenderer:
    """Draws the frames of a sequence over the bounding box of all of them.

    Parameters
    ----------
    seq : Sequence
    size : int or (2,) int
        Longest side in pixels, or ``(width, height)``.
    texture : path or array, optional
    style : str
        See `draw_frame`.
    even : bool
        Round the pixel size to even numbers (video).
    dpi : float
    background : matplotlib colour
        Colour behind the shape.
    kind : str
        What the images become (a key of `isotween.resources.OUTPUT_BYTES`):
        the memory that needs, for ``kept`` images, is checked before the
        first one is drawn.
    kept : int, optional
        Images the writer keeps in memory (default: every frame).
    """

    def __init__(self, seq, size, texture=None, style="auto", even=False, dpi=100, background=BACKGROUND,
                 kind="image", kept=None):
        from ..resources import check_output_memory

        self.seq = seq
        self.frames = sequence_frames(seq)
        self.regions, self.paints = sequence_paint(seq)
        self.bbox = bbox_of(self.frames, stroke_margin(self.paints))  # strokes drawn whole
        self.width, self.height = image_size(self.bbox, size, even=even)
        check_output_memory(kind, self.width, self.height, len(self.frames) if kept is None else kept,
                            f"a {kind}" if kind != "image" else "an image")
        self.texture = None if texture is None else load_texture(texture)
        self.style = style
        self.painter = FramePainter(self.width, self.height, self.bbox, dpi=dpi, y_down=seq.shape.y_down,
                                    background=background)

    def __len__(self):
        return len(self.frames)

    def frame(self, k):
        """Shape of frame ``k`` with its paint (interpolated, `sequence_paint`)."""
        shape = self.seq.shape.with_vertices(self.frames[k])
        if self.paints is not None:
            shape.regions, shape.paint = self.regions, self.paints[k]
        return shape

    def image(self, k, label=None):
        """(H, W, 3) uint8 image of frame ``k``."""
        shape = self.seq.shape
        return self.painter.render(
            self.frame(k),
            texture=self.texture,
            uv=shape.uv,
            style=self.style,
            source=shape.vertices,
            label=label,
        )
