"""Atomic file output: write to a temporary file beside the target, then rename."""

import contextlib
import os
import tempfile

from ..errors import FileFormatError, IsotweenError

__all__ = ["atomic_path"]


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path in the target's folder; move it onto ``path`` on success.

    On any exception the temporary file is removed and an existing ``path`` is left
    untouched. An ``OSError`` is turned into `FileFormatError` naming ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        Final destination. Its suffix is kept on the temporary name so that
        writers that pick a format from the extension (ffmpeg) still work.
    """
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileFormatError(f"cannot write {path}: folder {folder} does not exist")
    base = os.path.basename(path)
    suffix = os.path.splitext(base)[1]
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{base}.", suffix=f".tmp{suffix}", dir=folder)
    except OSError as exc:
        raise FileFormatError(f"cannot write {path}: {exc.strerror or exc}") from exc
    os.close(fd)
    try:
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual permissions
        yield tmp
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        if isinstance(exc, OSError) and not isinstance(exc, IsotweenError):
            raise FileFormatError(f"cannot write {path}: {exc.strerror or exc}") from exc
        raise
