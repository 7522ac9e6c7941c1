"""Defaults every animated output shares (light: importing it loads no plotting library)."""

__all__ = ["FPS", "SIZE", "BACKGROUND", "DURATION", "HOLD", "WIRE", "FILL", "FILL_EDGE"]

#: frames per second of every animated output (GIF, WebP, APNG, MP4, SVG, Lottie, the page)
FPS = 24
#: longest side in pixels of raster animations and of the Lottie composition
SIZE = 480
#: colour behind the shape in raster outputs
BACKGROUND = "#ffffff"  # white, written as matplotlib need not be loaded to read it
#: seconds the motion of a rendered animation lasts (`isotween.write_output` resamples the sequence to it)
DURATION = 1.0
#: seconds a rendered animation stays on its first and last frame
HOLD = 0.25
#: isotween's own look for a shape without paint: wire lines, and a light fill with darker edges
WIRE = "#08519c"
FILL = "#9ecae1"
FILL_EDGE = "#3182bd"
