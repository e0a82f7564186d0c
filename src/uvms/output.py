"""Result files and folders that are never seen half written, and never written over a user's own files.

Files are written under a temporary name and renamed into place (``mkstemp``/``mkdtemp`` create private
0600/0700 entries; :func:`publish` and :func:`replace_directory` give them the permissions the user's umask allows
before they appear under their real name). A result folder (``uvms run -o``, ``uvms reproduce -o``) carries a
marker, :data:`MARKER`, listing the files uvms wrote into it; an existing folder is replaced only when it is
empty or its marker lists everything it holds (:func:`check_replaceable`), so a folder that holds a user's file
is never touched. An ``OSError`` while writing names the user's path, never a hidden temporary one.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

MARKER = ".uvms-output.json"
"""File in every result folder uvms writes: ``{"written_by": "uvms <version>", "kind": ..., "files": [...]}``."""


def allowed_permissions(bits: int) -> int:
    """``bits`` less what the user's umask takes away (the permissions a new file would get)."""
    mask = os.umask(0)
    os.umask(mask)
    return bits & ~mask


@contextlib.contextmanager
def naming(path) -> Iterator[None]:
    """Re-raise an ``OSError`` (disk full, permission, a read-only file system) with ``path`` as its file name:
    the user sees the output they asked for, not a temporary sibling."""
    try:
        yield
    except OSError as exc:
        if exc.filename == str(path):
            raise
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from exc


def publish(tmp, path) -> None:
    """Rename a finished temporary file to ``path`` with the usual permissions."""
    os.chmod(tmp, allowed_permissions(0o666))
    os.replace(tmp, path)


def atomic_write_text(path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file in the same folder and a rename."""
    path = Path(path)
    with naming(path):
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


def _entries(folder: Path) -> tuple[list[str], list[str]]:
    """Every file (symbolic links included, never followed) and every folder below ``folder``, relative."""
    files: list[str] = []
    folders: list[str] = []
    for root, dirs, names in os.walk(folder, followlinks=False):
        rel = Path(root).relative_to(folder)
        files += [(rel / name).as_posix() for name in names]
        folders += [(rel / name).as_posix() for name in dirs if not (Path(root) / name).is_symlink()]
        files += [(rel / name).as_posix() for name in dirs if (Path(root) / name).is_symlink()]
    return files, folders


def _listed(folder: Path) -> set[str] | None:
    """The files the marker of ``folder`` says uvms wrote, or ``None`` when there is no readable marker."""
    try:
        data = json.loads((folder / MARKER).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    files = data.get("files") if isinstance(data, dict) else None
    if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
        return None
    return set(files)


def check_replaceable(folder, option: str = "--output") -> None:
    """Refuse to replace ``folder`` unless it is absent, empty, or holds only what uvms wrote there (as listed
    by its :data:`MARKER`). Raises a one-line :class:`~uvms.errors.UvmsInputError` naming ``folder``, the
    ``option`` and a few of the foreign entries; nothing is touched."""
    from uvms.errors import UvmsInputError

    folder = Path(folder)
    if not folder.exists() and not folder.is_symlink():
        return
    if folder.is_symlink() or not folder.is_dir():
        raise UvmsInputError("expected a folder, found a file or a link; choose another folder", str(folder),
                             option)
    files, folders = _entries(folder)
    if not files and not folders:
        return
    listed = _listed(folder)
    if listed is None:
        names = ", ".join(sorted(files + folders)[:3]) + (", ..." if len(files) + len(folders) > 3 else "")
        raise UvmsInputError(f"holds files that uvms did not write ({names}; no {MARKER}); nothing was "
                             "changed: choose a new or empty folder", str(folder), option)
    parents = {parent.as_posix() for f in listed for parent in Path(f).parents if parent != Path(".")}
    foreign = sorted([f for f in files if f not in listed and f != MARKER] +
                     [d for d in folders if d not in parents])
    if foreign:
        names = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise UvmsInputError(f"holds {len(foreign)} entr{'y' if len(foreign) == 1 else 'ies'} that uvms did not "
                             f"write ({names}); nothing was changed: move them or choose another folder",
                             str(folder), option)


def _write_marker(folder: Path, kind: str) -> None:
    import uvms

    files, _ = _entries(folder)
    atomic_write_text(folder / MARKER, json.dumps(
        {"written_by": f"uvms {uvms.__version__}", "kind": kind, "files": sorted(f for f in files if f != MARKER)},
        indent=1) + "\n")


def record_written(path) -> None:
    """Add ``path``, a file uvms just wrote, to the :data:`MARKER` of the uvms folder it lies in (a figure that
    ``uvms plot`` draws into a run folder), so that the folder may still be replaced by a rerun."""
    path = Path(path).absolute()
    folder = path.parent
    listed = _listed(folder)
    if listed is None or path.name in listed:
        return
    data = json.loads((folder / MARKER).read_text(encoding="utf-8"))
    data["files"] = sorted(listed | {path.name})
    atomic_write_text(folder / MARKER, json.dumps(data, indent=1) + "\n")


def replace_directory(tmp: Path, final: Path, *, kind: str, option: str = "--output") -> None:
    """Put a finished temporary folder in place in one rename, swapping out an older uvms folder at ``final``.

    The folder is marked as uvms's (:data:`MARKER`, with ``kind`` such as ``"run"``). ``final`` is checked
    again just before the swap: if a foreign file appeared there meanwhile, the new results are kept in a free
    sibling folder and the error says where.
    """
    from uvms.errors import UvmsInputError

    tmp, final = Path(tmp), Path(final)
    with naming(final):
        _write_marker(tmp, kind)
        os.chmod(tmp, allowed_permissions(0o777))
        try:
            check_replaceable(final, option)
        except UvmsInputError as exc:
            kept = _free_sibling(final)
            os.replace(tmp, kept)
            raise UvmsInputError(f"{exc.message}; the new results are in {kept}", exc.source, exc.path) from None
        if final.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".old", dir=final.parent))
            os.replace(final, old / "previous")
            os.replace(tmp, final)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, final)


def _free_sibling(path: Path) -> Path:
    for i in range(1, 10_000):
        candidate = path.with_name(f"{path.name}-{i}")
        if not candidate.exists():
            return candidate
    raise OSError(17, "no free folder name", str(path))


@contextlib.contextmanager
def staged_directory(final, *, kind: str, option: str = "--output") -> Iterator[Path]:
    """A temporary sibling of ``final`` to write a result folder into; on success it replaces ``final`` as a
    whole (:func:`replace_directory`), on any error or Ctrl-C it is removed and ``final`` is untouched."""
    final = Path(final)
    with naming(final):
        final.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".tmp", dir=final.parent))
    try:
        with naming(final):
            yield tmp
        replace_directory(tmp, final, kind=kind, option=option)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def check_destination(path, option: str, *, kind: str) -> None:
    """Refuse, before any long computation, an output ``path`` that could never be written. Raises a one-line
    :class:`~uvms.errors.UvmsInputError` naming ``path`` and the command-line ``option``.

    ``kind``: ``"file"`` (written through a temporary sibling: its folder must be writable, and it must not be
    a folder), ``"replaced folder"`` (built as a temporary sibling and renamed into place: the parent must be
    writable, and an existing folder must pass :func:`check_replaceable`) or ``"folder"`` (written in place, e.g. a resumable sweep: the folder itself must be writable
    if it exists).
    """
    from uvms.errors import UvmsInputError

    path = Path(path).absolute()
    if kind == "replaced folder":
        check_replaceable(path, option)
    if kind == "file" and path.is_dir():
        raise UvmsInputError("expected a file name, found a folder", str(path), option)
    where = path if kind == "folder" and path.exists() else path.parent
    while not where.exists() and where != where.parent:
        where = where.parent
    if not where.is_dir():
        raise UvmsInputError(f"cannot be created: {where} is a file, not a folder", str(path), option)
    if not os.access(where, os.W_OK | os.X_OK):
        raise UvmsInputError(f"cannot be written: no permission to write in {where}", str(path), option)
    try:   # a real probe: a read-only or virtual file system (/proc, /sys) refuses even root, whom os.access lets by
        fd, probe = tempfile.mkstemp(prefix=".uvms-probe-", dir=where)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise UvmsInputError(f"cannot be written: {where} refuses new files ({exc.strerror or exc})", str(path),
                             option) from None
