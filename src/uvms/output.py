"""Result files and folders that are never seen half written, and never written over a user's own files.

Files are written under a temporary name and renamed into place (``mkstemp``/``mkdtemp`` create private
0600/0700 entries; :func:`publish` and :func:`replace_directory` give them the permissions the user's umask allows
before they appear under their real name). A result folder (``uvms run -o``, ``uvms reproduce -o``) carries a
marker, :data:`MARKER`, listing the files uvms wrote into it with the SHA-256 of each; an existing folder is
replaced only when it is empty or its marker lists everything it holds with unchanged content
(:func:`check_replaceable`), so a folder that holds a user's file is never touched. A single output file
(a figure, a page) follows one rule, :func:`check_file_output`: an existing file uvms did not write is replaced
only when the user named it or passed ``--force``, and a default output name never comes from file content
(:func:`default_file_name`). An ``OSError`` while writing names the user's path, never a hidden temporary one.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

MARKER = ".uvms-output.json"
"""File in every result folder uvms writes: ``{"written_by": "uvms <version>", "kind": ..., "files": [...],
"sha256": {file: hex digest}}``."""


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


MARKER_MAX_BYTES = 4 * 1024 * 1024
"""Largest :data:`MARKER` read [bytes] (one line per file uvms wrote; a bigger one is not uvms's)."""


def file_digest(path) -> str:
    """SHA-256 of a file's content (hex), read in 1 MiB blocks."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _marker(folder: Path) -> dict | None:
    """The :data:`MARKER` of ``folder`` as ``{"files": [...], "sha256": {...}, ...}``, or ``None`` when there is
    no readable one (absent, damaged, oversized, or a file list that is not a list of names)."""
    from uvms.errors import UvmsInputError
    from uvms.safe_json import read_json

    path = folder / MARKER
    if not path.is_file() or path.is_symlink():
        return None
    try:
        data = read_json(path, max_bytes=MARKER_MAX_BYTES)
    except UvmsInputError:
        return None
    files = data.get("files") if isinstance(data, dict) else None
    if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
        return None
    digests = data.get("sha256")
    if not isinstance(digests, dict):
        data["sha256"] = {}        # an older marker, without digests: its files are not known to be uvms's
    return data


def _listed(folder: Path) -> set[str] | None:
    """The files the marker of ``folder`` says uvms wrote, or ``None`` when there is no readable marker."""
    data = _marker(folder)
    return None if data is None else set(data["files"])


def _changed(folder: Path, name: str, digests: dict) -> bool:
    """Whether the listed file ``name`` is not provably as uvms wrote it: no digest recorded, a link or anything
    but a regular file, or a content whose SHA-256 differs from the recorded one (the user edited it, or copied their own file in)."""
    path = folder / name
    recorded = digests.get(name)
    if not isinstance(recorded, str) or path.is_symlink() or not path.is_file():   # a FIFO would block a read
        return True
    try:
        return file_digest(path) != recorded
    except OSError:
        return True


WRITTEN_FILES = "written-files.json"
"""The user's record of single files uvms wrote outside its own folders (``uvms show`` into the working
folder): ``{absolute path: SHA-256}`` in ``<cache home>/uvms/`` (``XDG_CACHE_HOME`` or ``~/.cache``)."""
MAX_WRITTEN_FILES = 1000
"""Most files :data:`WRITTEN_FILES` remembers (the oldest are forgotten: such a file then counts as the user's)."""


def _written_files_path() -> Path:
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "uvms" / WRITTEN_FILES


def _written_files() -> dict[str, str]:
    """:data:`WRITTEN_FILES` as read (empty when missing, unreadable or not as uvms writes it)."""
    from uvms.errors import UvmsInputError
    from uvms.safe_json import read_json

    try:
        data = read_json(_written_files_path(), max_bytes=MARKER_MAX_BYTES, max_depth=2)
    except (UvmsInputError, OSError):
        return {}
    if not isinstance(data, dict):
        return {}
    return {k: v for k, v in data.items() if isinstance(k, str) and isinstance(v, str)}


def _remember_written(path: Path) -> None:
    """Add ``path`` (a file uvms just wrote where no marker is) to :data:`WRITTEN_FILES`; a cache home that
    cannot be written only means the next default output there needs ``--force``."""
    record = _written_files()
    record.pop(str(path), None)
    record[str(path)] = file_digest(path)
    record = dict(list(record.items())[-MAX_WRITTEN_FILES:])
    target = _written_files_path()
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(target, json.dumps(record, indent=0, sort_keys=False) + "\n")
    except OSError:
        pass


def written_by_uvms(path) -> bool:
    """Whether the existing file ``path`` is one uvms wrote and nobody changed since: the :data:`MARKER` of its
    folder lists it with the SHA-256 of its present content, or (a file outside uvms's folders) the user's
    :data:`WRITTEN_FILES` does."""
    path = Path(path).absolute()
    data = _marker(path.parent)
    if data is not None:
        return path.name in data["files"] and not _changed(path.parent, path.name, data["sha256"])
    recorded = _written_files().get(str(path))
    if recorded is None or path.is_symlink() or not path.is_file():
        return False
    try:
        return file_digest(path) == recorded
    except OSError:
        return False


def check_replaceable(folder, option: str = "--output", *, force: bool = False) -> None:
    """Refuse to replace ``folder`` unless it is absent, empty, or holds only what uvms wrote there: every file
    listed by its :data:`MARKER` with the SHA-256 it had when uvms wrote it (a listed file that changed since,
    or one listed without a digest by an older marker, is the user's). Raises a one-line
    :class:`~uvms.errors.UvmsInputError` naming ``folder``, the ``option`` and a few of the foreign entries;
    nothing is touched. ``force`` (``--force``) accepts a folder uvms wrote (one with a readable marker) even
    when files were added or changed since (they are replaced with it); a folder without a marker is refused
    even then: it was never uvms's (a home, a thesis folder), and a typo in ``-o`` must not delete it."""
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
    data = _marker(folder)
    if data is None:
        names = ", ".join(sorted(files + folders)[:3]) + (", ..." if len(files) + len(folders) > 3 else "")
        raise UvmsInputError(f"holds files that uvms did not write ({names}; no {MARKER}); nothing was "
                             "changed: choose a new or empty folder", str(folder), option)
    if force:
        return
    listed = set(data["files"])
    parents = {parent.as_posix() for f in listed for parent in Path(f).parents if parent != Path(".")}
    foreign = sorted([f for f in files if f not in listed and f != MARKER] +
                     [d for d in folders if d not in parents])
    if foreign:
        names = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise UvmsInputError(f"holds {len(foreign)} entr{'y' if len(foreign) == 1 else 'ies'} that uvms did not "
                             f"write ({names}); nothing was changed: move them or choose another folder (or pass "
                             "--force)", str(folder), option)
    changed = sorted(f for f in files if f != MARKER and _changed(folder, f, data["sha256"]))
    if changed:
        names = ", ".join(changed[:3]) + (", ..." if len(changed) > 3 else "")
        raise UvmsInputError(f"holds {len(changed)} file{'' if len(changed) == 1 else 's'} changed since uvms wrote "
                             f"{'it' if len(changed) == 1 else 'them'} or not recorded with its content ({names});"
                             " nothing was changed: move them or choose another folder (or pass --force)",
                             str(folder), option)


def _marker_text(data: dict) -> str:
    return json.dumps(data, indent=1, sort_keys=False) + "\n"


def _write_marker(folder: Path, kind: str) -> None:
    import uvms

    files, _ = _entries(folder)
    files = sorted(f for f in files if f != MARKER)
    digests = {f: file_digest(folder / f) for f in files if (folder / f).is_file() and not (folder / f).is_symlink()}
    atomic_write_text(folder / MARKER, _marker_text(
        {"written_by": f"uvms {uvms.__version__}", "kind": kind, "files": files, "sha256": digests}))


def check_file_output(path, option: str = "--output", *, named: bool, force: bool = False) -> bool:
    """Check an output file before any work (:func:`check_destination`) and apply the one rule of every output
    file uvms writes: an existing file uvms did not write (:func:`written_by_uvms`) is replaced only when the
    user named it (``named``: ``-o`` that file) or passed ``--force`` (``force``); a default output is otherwise
    refused with one line naming the file, and nothing is written.

    Returns whether uvms may list the file, once written, in its folder's :data:`MARKER`
    (:func:`record_written`): only a new file, or one uvms wrote before (a user's file that the user named
    stays the user's: the folder holding it is then no longer replaceable as a whole)."""
    from uvms.errors import UvmsInputError

    check_destination(path, option, kind="file")
    path = Path(path)
    if not path.exists() and not path.is_symlink():
        return True
    if written_by_uvms(path):
        return True
    if named or force:
        return False
    raise UvmsInputError("exists and uvms did not write it (or it changed since); nothing was written: name it "
                         f"with {option} to replace it, pass --force, or choose another file", str(path), option)


def record_written(path) -> None:
    """Add ``path``, a file uvms just wrote, with its SHA-256 to the :data:`MARKER` of the uvms folder it lies
    in (a figure that ``uvms plot`` draws into a run folder), so that the folder may still be replaced by a
    rerun. Call it only when :func:`check_file_output` said so; a folder without a marker gets none: the file
    is remembered in the user's :data:`WRITTEN_FILES` instead, so that the same command may replace it again
    while nobody changed it."""
    path = Path(path).absolute()
    folder = path.parent
    data = _marker(folder)
    if data is None:
        _remember_written(path)
        return
    data["files"] = sorted(set(data["files"]) | {path.name})
    data["sha256"] = {**data["sha256"], path.name: file_digest(path)}
    atomic_write_text(folder / MARKER, _marker_text(data))


_SAFE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]{0,99}")


def default_file_name(names, suffix: str, fallback: str = "uvms") -> str:
    """A default output file name ``<name><suffix>`` in the working folder from the first of ``names`` that is
    a plain file name: a letter or digit, then letters, digits, ``_ . + -`` (at most 100 characters). A model's
    name comes from its file and may be anything (``../../x``, ``/home/u/victim``, a NUL): it never chooses
    where an output goes; ``fallback`` when none qualifies."""
    for name in names:
        if isinstance(name, str) and _SAFE_NAME.fullmatch(name) and name not in (".", ".."):
            return name + suffix
    return fallback + suffix


def replace_directory(tmp: Path, final: Path, *, kind: str, option: str = "--output", force: bool = False) -> None:
    """Put a finished temporary folder in place in one rename, swapping out an older uvms folder at ``final``.

    The folder is marked as uvms's (:data:`MARKER`, with ``kind`` such as ``"run"``). ``final`` is checked
    again just before the swap: if a foreign file appeared there meanwhile, the new results are kept in a free
    sibling folder and the error says where. ``force`` (``--force``): any folder at ``final`` is replaced.
    """
    from uvms.errors import UvmsInputError

    tmp, final = Path(tmp), Path(final)
    with naming(final):
        _write_marker(tmp, kind)
        os.chmod(tmp, allowed_permissions(0o777))
        try:
            check_replaceable(final, option, force=force)
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
def staged_directory(final, *, kind: str, option: str = "--output", force: bool = False) -> Iterator[Path]:
    """A temporary sibling of ``final`` to write a result folder into; on success it replaces ``final`` as a
    whole (:func:`replace_directory`), on any error or Ctrl-C it is removed and ``final`` is untouched."""
    final = Path(final)
    with naming(final):
        final.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".tmp", dir=final.parent))
    try:
        with naming(final):
            yield tmp
        replace_directory(tmp, final, kind=kind, option=option, force=force)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def check_output_folder(path, option: str = "--output", *, kind: str, force: bool = False) -> None:
    """:func:`check_destination` for a command's output folder (``kind`` ``"replaced folder"`` or ``"folder"``),
    and first the rule every such folder keeps: it may not be, or contain, the working folder (even with
    ``force``), so that no command replaces the folder it was started in."""
    from uvms.errors import UvmsInputError

    if Path(path).resolve() in (Path.cwd().resolve(), *Path.cwd().resolve().parents):
        raise UvmsInputError("expected a directory that does not contain the working directory", str(path), option)
    check_destination(path, option, kind=kind, force=force)


def check_destination(path, option: str, *, kind: str, force: bool = False) -> None:
    """Refuse, before any long computation, an output ``path`` that could never be written. Raises a one-line
    :class:`~uvms.errors.UvmsInputError` naming ``path`` and the command-line ``option``.

    ``kind``: ``"file"`` (written through a temporary sibling: its folder must be writable, and it must not be
    a folder), ``"replaced folder"`` (built as a temporary sibling and renamed into place: the parent must be
    writable, and an existing folder must pass :func:`check_replaceable`, with ``force`` passed on) or
    ``"folder"`` (written in place, e.g. a resumable sweep: the folder itself must be writable
    if it exists).
    """
    from uvms.errors import UvmsInputError

    path = Path(path).absolute()
    if kind == "replaced folder":
        check_replaceable(path, option, force=force)
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
