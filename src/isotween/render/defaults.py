"""Defaults every animated output shares (light: importing it loads no plotting library)."""

__all__ = ["FPS", "SIZE", "BACKGROUND"]

#: frames per second of every animated output (GIF, WebP, APNG, MP4, SVG, Lottie, the page)
FPS = 24
#: longest side in pixels of raster animations and of the Lottie composition
SIZE = 480
#: colour behind the shape in raster outputs
BACKGROUND = "white"
