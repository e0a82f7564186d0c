"""Result files and folders that are never seen half written: write under a temporary name, then rename.

``mkstemp``/``mkdtemp`` create private (0600/0700) entries; :func:`publish` and :func:`replace_directory` give
them the permissions the user's umask allows before they appear under their real name.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path


def _allowed(bits: int) -> int:
    mask = os.umask(0)
    os.umask(mask)
    return bits & ~mask


def publish(tmp, path) -> None:
    """Rename a finished temporary file to ``path`` with the usual permissions."""
    os.chmod(tmp, _allowed(0o666))
    os.replace(tmp, path)


def atomic_write_text(path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file in the same folder and a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        publish(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def replace_directory(tmp: Path, final: Path) -> None:
    """Put a finished temporary folder in place in one rename, swapping out an older one at ``final``."""
    os.chmod(tmp, _allowed(0o777))
    if final.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".old", dir=final.parent))
        os.replace(final, old / "previous")
        os.replace(tmp, final)
        shutil.rmtree(old, ignore_errors=True)
    else:
        os.replace(tmp, final)


def check_destination(path, option: str, *, kind: str) -> None:
    """Refuse, before any long computation, an output ``path`` that could never be written. Raises a one-line
    :class:`~uvms.errors.UvmsInputError` naming ``path`` and the command-line ``option``.

    ``kind``: ``"file"`` (written through a temporary sibling: its folder must be writable, and it must not be
    a folder), ``"replaced folder"`` (built as a temporary sibling and renamed into place: the parent must be
    writable) or ``"folder"`` (written in place, e.g. a resumable sweep: the folder itself must be writable
    if it exists).
    """
    from uvms.errors import UvmsInputError

    path = Path(path).absolute()
    if kind == "file" and path.is_dir():
        raise UvmsInputError("expected a file name, found a folder", str(path), option)
    where = path if kind == "folder" and path.exists() else path.parent
    while not where.exists() and where != where.parent:
        where = where.parent
    if not where.is_dir():
        raise UvmsInputError(f"cannot be created: {where} is a file, not a folder", str(path), option)
    if not os.access(where, os.W_OK | os.X_OK):
        raise UvmsInputError(f"cannot be written: no permission to write in {where}", str(path), option)
