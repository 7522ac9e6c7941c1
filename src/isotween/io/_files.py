"""Reading text safely and writing files atomically (temp file + os.replace)."""

import os
import shutil
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path

from ..errors import FileFormatError
from ..resources import check_memory

__all__ = ["read_text", "check_readable", "check_path_text", "atomic_path", "atomic_dir", "write_text"]

# files made by mkstemp are private (0600); give results the usual permissions
_UMASK = os.umask(0)
os.umask(_UMASK)


def check_path_text(path):
    """``path`` as a `Path`; `FileFormatError` for a NUL byte or a value that is not a path.

    Raises
    ------
    FileFormatError
        The path holds a NUL byte (no file system takes one) or is not a
        str, bytes or path-like object.
    """
    try:
        text = os.fsdecode(path)
    except TypeError:
        raise FileFormatError(f"a file name must be a str or path, got {type(path).__name__}") from None
    if "\0" in text:
        raise FileFormatError(f"{text!r}: a file name cannot hold a NUL byte")
    return Path(text)


#: what `check_readable` calls each kind of file that is not a regular one
_KINDS = ((stat.S_ISDIR, "is a folder, expected a file"), (stat.S_ISFIFO, "is a pipe (FIFO), expected a file"),
          (stat.S_ISCHR, "is a device, expected a file"), (stat.S_ISBLK, "is a device, expected a file"),
          (stat.S_ISSOCK, "is a socket, expected a file"))


def check_readable(path):
    """``path`` as a `Path`; `FileFormatError` unless it is an existing regular file.

    Links are followed: a link to a regular file is fine, one to a device
    (``/dev/zero``), a FIFO (which would block) or a folder is refused
    before anything opens it.
    """
    path = check_path_text(path)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise FileFormatError(f"{path}: no such file") from None
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot read: {exc.strerror or exc}") from None
    if not stat.S_ISREG(mode):
        why = next((what for test, what in _KINDS if test(mode)), "is not a regular file")
        raise FileFormatError(f"{path}: {why}")
    return path


#: longest file name (bytes) most file systems take
NAME_MAX = 255

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
    path = check_path_text(path)
    _check_parent(path)
    if path.is_dir():
        raise FileFormatError(f"cannot write {path}: is a folder")
    # the temporary name (dot, stem, 8 random characters, suffix) stays within NAME_MAX: a long
    # legal name must not fail only because of the temporary one
    stem = path.stem[: max(0, NAME_MAX - len(path.suffix.encode("utf-8", "surrogatepass")) - 16)]
    while len(stem.encode("utf-8", "surrogatepass")) + len(path.suffix) + 16 > NAME_MAX and stem:
        stem = stem[:-1]
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{stem}.", suffix=path.suffix, dir=path.parent)
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
