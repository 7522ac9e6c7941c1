"""One error hierarchy for everything isotween raises on bad input.

Every message names what is wrong and where (file, line, vertex, edge), so the
command line can print it alone and exit non-zero.
"""


class IsotweenError(Exception):
    """Base class of every error isotween raises on purpose."""


class ShapeError(IsotweenError, ValueError):
    """A single shape is malformed (bad index, non-finite coordinate, ...)."""


class IncompatibleShapesError(IsotweenError, ValueError):
    """Two or more shapes do not share vertex count or connectivity."""


class ParameterError(IsotweenError, ValueError):
    """An option has a value outside its domain (frames < 2, unknown solver, ...)."""


class MethodError(IsotweenError, ValueError):
    """A method cannot take the given shape (ARAP without faces, ...)."""


class FileFormatError(IsotweenError):
    """A file cannot be read or written; the message names the file (and line)."""


class MissingDependencyError(IsotweenError, ImportError):
    """An optional extra is needed for this feature but is not installed."""


def require(module, extra):
    """Import an optional dependency or raise `MissingDependencyError`.

    Parameters
    ----------
    module : str
        Module name to import.
    extra : str
        Name of the pip extra that provides it (``pip install isotween[extra]``).
    """
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise MissingDependencyError(
            f"this feature needs '{module}': pip install 'isotween[{extra}]'"
        ) from exc


class ResourceError(IsotweenError, MemoryError):
    """A run would need more memory than is available (or allowed); the message gives the estimate and the limit."""
