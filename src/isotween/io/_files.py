"""Reading text safely and writing files atomically (temp file + os.replace)."""

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

from ..errors import FileFormatError
from ..resources import check_memory

__all__ = ["read_text", "check_readable", "atomic_path", "atomic_dir", "write_text"]

# files made by mkstemp are private (0600); give results the usual permissions
_UMASK = os.umask(0)
os.umask(_UMASK)


def check_readable(path):
    """Raise `FileFormatError` unless ``path`` is an existing regular file."""
    path = Path(path)
    if not path.exists():
        raise FileFormatError(f"{path}: no such file")
    if path.is_dir():
        raise FileFormatError(f"{path}: is a folder, expected a file")
    return path


#: peak bytes a text parser needs per byte of file (the text, its lines and tokens,
#: the parsed numbers as Python objects)
TEXT_BYTES_PER_BYTE = 40


def read_text(path):
    """Whole file as text (UTF-8); missing or undecodable files raise `FileFormatError`."""
    path = check_readable(path)
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot read: {exc.strerror or exc}") from exc
    check_memory(TEXT_BYTES_PER_BYTE * size, f"reading {path} ({size / 1e6:.0f} MB)", advice="use a smaller file")
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise FileFormatError(f"{path}: not a UTF-8 text file (byte {exc.start})") from exc
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot read: {exc.strerror or exc}") from exc


def _unlink(path):
    try:
        os.unlink(path)
    except OSError:
        pass


def _check_parent(path):
    parent = path.parent
    if not parent.is_dir():
        what = "is not a folder" if parent.exists() else "does not exist"
        raise FileFormatError(f"cannot write {path}: {parent} {what}")


@contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; move it onto ``path`` on success.

    The temporary file keeps the suffix of ``path`` (writers that pick a format
    from the suffix still work). On any error it is removed, so no partial
    output is ever left; `OSError` becomes `FileFormatError` naming ``path``.
    """
    path = Path(path)
    _check_parent(path)
    if path.is_dir():
        raise FileFormatError(f"cannot write {path}: is a folder")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
        os.close(fd)
    except OSError as exc:
        raise FileFormatError(f"cannot write {path}: {exc.strerror or exc}") from exc
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o666 & ~_UMASK)
        os.replace(tmp, path)
    except OSError as exc:
        _unlink(tmp)
        raise FileFormatError(f"cannot write {path}: {exc.strerror or exc}") from exc
    except BaseException:
        _unlink(tmp)
        raise


def write_text(path, text):
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


@contextmanager
def atomic_dir(directory):
    """Yield a temporary folder inside ``directory`` (created if missing).

    Files written there are moved into ``directory`` only when the block
    succeeds; on error the temporary folder (and ``directory``, if this call
    created it) is removed.
    """
    directory = Path(directory)
    if directory.exists() and not directory.is_dir():
        raise FileFormatError(f"cannot write frames to {directory}: it is a file, not a folder")
    created = not directory.exists()
    if created:
        _check_parent(directory)
        try:
            directory.mkdir()
        except OSError as exc:
            raise FileFormatError(f"cannot create folder {directory}: {exc.strerror or exc}") from exc
    try:
        tmp = Path(tempfile.mkdtemp(prefix=".isotween-", dir=directory))
    except OSError as exc:
        if created:
            shutil.rmtree(directory, ignore_errors=True)
        raise FileFormatError(f"cannot write to folder {directory}: {exc.strerror or exc}") from exc
    try:
        yield tmp
        for item in sorted(tmp.iterdir()):
            os.chmod(item, 0o666 & ~_UMASK)
            os.replace(item, directory / item.name)
    except BaseException as exc:
        shutil.rmtree(tmp, ignore_errors=True)
        if created:
            shutil.rmtree(directory, ignore_errors=True)
        if isinstance(exc, OSError):
            raise FileFormatError(f"cannot write to folder {directory}: {exc.strerror or exc}") from exc
        raise
    shutil.rmtree(tmp, ignore_errors=True)
