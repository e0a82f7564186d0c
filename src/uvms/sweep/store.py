"""A sweep's output directory: ``sweep.json`` (identity), ``runs.csv`` (one row per finished run, append-only),
``summary.csv``, and the sweep and base scenario files verbatim.

``runs.csv`` is only ever appended to, one whole line per ``os.write`` followed by ``fsync``, from the client
process. A process killed mid-write can leave at most a partial last line (no newline): :meth:`RunStore.open`
cuts it off before anything else is written, so the file always parses and holds exactly one row per run_id.
A lock (``.lock``, ``flock``) keeps a second ``uvms sweep`` out of a directory in use.

A new directory is built under a temporary name and renamed into place (it never exists half made); the start-up
debris an older uvms left when killed before ``sweep.json`` is completed; a refused directory is left exactly as
it was (the checks come before the lock file is made or anything is cut). An ``OSError`` while writing names
its file.
"""

from __future__ import annotations

import csv
import errno
import glob
import io
import json
import math
import os
import re
import shutil
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from uvms.errors import UvmsInputError
from uvms.model.schema import show
from uvms.output import allowed_permissions, atomic_write_text

RUNS_CSV = "runs.csv"
SWEEP_JSON = "sweep.json"
SUMMARY_CSV = "summary.csv"
LOCK = ".lock"
BUILD_SUFFIX = ".uvms-build"
"""Suffix of the temporary name a new sweep directory is built under."""

LEADING = ("run_id", "draw", "controller")
TRAILING = ("status", "error", "wall_time_s")


def parameter_columns(sweep) -> list[tuple[str, str, int | None]]:
    """``(column, parameter, index)`` of every parameter column: a parameter whose values are all lists of the
    same number of numbers gets one column per component (``path[0]``, ``path[1]`` ...), others one column."""
    columns: list[tuple[str, str, int | None]] = []
    for key in sweep.spec.parameters:
        values = [run.parameters[key] for run in sweep.runs]
        lengths = {len(v) if isinstance(v, list) and all(_is_number(x) for x in v) else -1 for v in values}
        if len(lengths) == 1 and (n := lengths.pop()) > 0:
            columns += [(f"{key}[{i}]", key, i) for i in range(n)]
        else:
            columns.append((key, key, None))
    return columns


def columns(sweep) -> list[str]:
    """The header of ``runs.csv``."""
    return [*LEADING, *(c for c, _, _ in parameter_columns(sweep)), *sweep.metrics, *TRAILING]


def run_cells(sweep, run, outcome: dict[str, Any]) -> list[str]:
    """The cells of one ``runs.csv`` row: the run's identity and parameters, and a worker's ``outcome``
    (``metrics``, ``status``, ``error``, ``wall_time_s``)."""
    base = sweep.base.spec.controller
    controller = run.controller or (base.name if base is not None else "none")
    cells = [run.run_id, str(run.draw), controller]
    for _, key, index in parameter_columns(sweep):
        value = run.parameters[key]
        cells.append(cell(value[index] if index is not None else value))
    metrics = outcome.get("metrics") or {}
    cells += [cell(metrics.get(name, float("nan"))) for name in sweep.metrics]
    cells += [outcome["status"], one_line(outcome.get("error") or ""), f"{outcome.get('wall_time_s', 0.0):.3f}"]
    return cells


def cell(value: Any) -> str:
    """A CSV cell: floats at full precision (NaN empty), other scalars as text, anything else as JSON."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ("" if math.isnan(value) else repr(value))
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return one_line(value)
    return json.dumps(value, separators=(",", ":"))


def one_line(text: str, limit: int = 1000) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def format_line(cells: list[str]) -> str:
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow(cells)
    return buffer.getvalue()


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


class RunStore:
    """``runs.csv`` of one sweep directory, opened for appending (see the module docstring).

    Attributes:
        directory: the output directory.
        columns: the header.
        done: run_id -> cells of every row already in the file (first occurrence).
        created: whether :meth:`open` created the directory (and :meth:`remove` may delete it).
    """

    def __init__(self, directory: Path, columns: list[str], done: dict[str, list[str]], fd: int, lock_fd: int,
                 created: bool = False):
        self.directory = directory
        self.columns = columns
        self.done = done
        self.created = created
        self._fd = fd
        self._lock_fd = lock_fd

    @classmethod
    def open(cls, directory: str | os.PathLike[str], sweep) -> RunStore:
        """Open (or create) the sweep directory ``directory`` for ``sweep``.

        A new directory is built under a temporary name next to it (``.<name>.<random>.uvms-build``, with its
        ``sweep.json``, ``runs.csv`` header and lock) and renamed into place: it never exists half made. A
        directory that holds only what an interrupted start-up of uvms leaves (no ``sweep.json``; at most
        ``.lock``, ``sweep.yaml``, ``scenario.yaml`` and uvms's temporary files) is completed. A directory
        that is refused is left exactly as it was.

        Raises:
            UvmsInputError: ``directory`` is a file, a non-sweep directory, another sweep's directory (hash
                differs), in use by another process, or holds a ``runs.csv`` that does not parse.
            OSError: a file could not be written (its name in ``filename``).
        """
        directory = Path(directory)
        header = columns(sweep)
        if (directory.exists() or directory.is_symlink()) and not directory.is_dir():
            raise UvmsInputError("expected a directory, found a file", str(directory), "--output")
        if not directory.exists():
            store = cls._create(directory, sweep, header)
            if store is not None:
                return store
        marker = directory / SWEEP_JSON
        if not marker.exists():
            debris = _debris(directory)
            if debris is None:
                raise UvmsInputError(f"exists and is not a sweep directory (no {SWEEP_JSON}); choose another "
                                     "directory", str(directory), "--output")
        else:
            _check_identity(marker, sweep)                  # refused before anything is touched
        lock_fd, made_lock = _lock(directory)
        try:
            if not marker.exists():                         # complete an interrupted start-up
                debris = _debris(directory)
                if debris is None:
                    raise UvmsInputError(f"exists and is not a sweep directory (no {SWEEP_JSON}); choose another "
                                         "directory", str(directory), "--output")
                for path in debris:
                    if path.name.endswith(".tmp"):
                        path.unlink(missing_ok=True)
                _populate(directory, sweep, header)
            else:
                _check_identity(marker, sweep)              # again, under the lock
            fd, done = _open_runs(directory / RUNS_CSV, header)
        except BaseException:
            if made_lock:
                (directory / LOCK).unlink(missing_ok=True)
            os.close(lock_fd)
            raise
        return cls(directory, header, done, fd, lock_fd)

    @classmethod
    def _create(cls, directory: Path, sweep, header: list[str]) -> RunStore | None:
        """Build a new sweep directory under a temporary name and rename it into place; ``None`` if another
        process created ``directory`` meanwhile."""
        parent = directory.parent
        with _names(parent):
            parent.mkdir(parents=True, exist_ok=True)
        _remove_stale_builds(parent, directory.name)
        with _names(parent):
            tmp = Path(tempfile.mkdtemp(prefix=f".{directory.name}.", suffix=BUILD_SUFFIX, dir=parent))
        lock_fd = -1
        try:
            lock_fd, _ = _lock(tmp)
            _populate(tmp, sweep, header)
            os.chmod(tmp, allowed_permissions(0o777))
            try:
                os.rename(tmp, directory)
            except OSError as exc:
                if exc.errno in (errno.EEXIST, errno.ENOTEMPTY) or directory.exists():
                    shutil.rmtree(tmp, ignore_errors=True)
                    os.close(lock_fd)
                    return None
                raise OSError(exc.errno, exc.strerror, str(directory)) from None
            _fsync_directory(parent)
        except BaseException:
            if lock_fd >= 0:
                os.close(lock_fd)
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        try:
            fd, done = _open_runs(directory / RUNS_CSV, header)
        except BaseException:
            os.close(lock_fd)
            raise
        return cls(directory, header, done, fd, lock_fd, created=True)

    def append(self, cells: list[str]) -> None:
        """Append one row (one ``write`` of the whole line, then ``fsync``)."""
        data = format_line(cells).encode("utf-8")
        with _names(self.directory / RUNS_CSV):
            written = os.write(self._fd, data)
            while written < len(data):  # a short write to a regular file: only on a full disk
                written += os.write(self._fd, data[written:])
            os.fsync(self._fd)
        self.done.setdefault(cells[0], cells)

    def write_summary(self, summary) -> Path:
        """Write ``summary.csv`` atomically (it is derived from ``runs.csv``: rewritten every time)."""
        path = self.directory / SUMMARY_CSV
        _write(path, summary.to_csv(index=False))
        return path

    def close(self) -> None:
        for fd in (self._fd, self._lock_fd):
            try:
                os.close(fd)
            except OSError:
                pass
        self._fd = self._lock_fd = -1

    def remove(self) -> None:
        """Delete a directory this store created (call :meth:`close` first)."""
        if self.created:
            shutil.rmtree(self.directory, ignore_errors=True)

    def __enter__(self) -> RunStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


@contextmanager
def _names(path: Path) -> Iterator[None]:
    """An ``OSError`` without a file name (``ENOSPC`` from ``write``, ``EIO`` from ``fsync``) gets ``path``."""
    try:
        yield
    except OSError as exc:
        if exc.filename is None:
            raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
        raise


def _fsync_directory(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - not POSIX
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - some file systems refuse fsync on a directory
        pass
    finally:
        os.close(fd)


def _write(path: Path, text: str) -> None:
    """Write atomically, with the permissions the umask allows (the temporary file starts private)."""
    with _names(path):
        atomic_write_text(path, text)


def _populate(directory: Path, sweep, header: list[str]) -> None:
    """Write a new sweep directory's files: the sweep and base verbatim, ``sweep.json``, the header."""
    _write(directory / "sweep.yaml", sweep.text)
    _write(directory / "scenario.yaml", sweep.base.text)
    _write(directory / SWEEP_JSON, json.dumps(_identity(sweep, header), indent=2) + "\n")
    _write(directory / RUNS_CSV, format_line(header))


_DEBRIS_FILES = frozenset({LOCK, "sweep.yaml", "scenario.yaml"})
_DEBRIS_TMP = re.compile(r"\.(?:sweep\.yaml|scenario\.yaml|sweep\.json|runs\.csv|summary\.csv)\..+\.tmp")


def _debris(directory: Path) -> list[Path] | None:
    """The entries of a directory without ``sweep.json`` if they are all what an interrupted uvms start-up
    leaves (``.lock``, ``sweep.yaml``, ``scenario.yaml``, uvms's temporary files; regular files), else
    ``None``. An empty directory is debris-free."""
    entries = list(directory.iterdir())
    for path in entries:
        if path.is_symlink() or not path.is_file():
            return None
        if path.name not in _DEBRIS_FILES and not _DEBRIS_TMP.fullmatch(path.name):
            return None
    return entries


def _remove_stale_builds(parent: Path, name: str) -> None:
    """Delete temporary builds of ``parent/name`` left by a killed uvms (nobody holds their lock, and they
    hold only uvms's files)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        return
    try:
        candidates = [p for p in parent.glob(f".{glob.escape(name)}.*{BUILD_SUFFIX}")
                      if p.is_dir() and not p.is_symlink()]
    except OSError:
        return
    for build in candidates:
        if any(p.name not in (*_DEBRIS_FILES, SWEEP_JSON, RUNS_CSV) and not _DEBRIS_TMP.fullmatch(p.name)
               for p in build.iterdir()):
            continue
        try:
            fd = os.open(build / LOCK, os.O_RDWR)
        except OSError:
            if time.time() - build.stat().st_mtime > 60:  # an old build killed before it made its lock
                shutil.rmtree(build, ignore_errors=True)
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            continue                                    # still being built
        finally:
            os.close(fd)
        shutil.rmtree(build, ignore_errors=True)


def _identity(sweep, header: list[str]) -> dict[str, Any]:
    import uvms

    return {"format": 1, "name": sweep.name, "sweep_sha256": sweep.sha256, "sweep_source": sweep.source,
            "base_scenario": sweep.base.source, "base_sha256": sweep.base.sha256, "runs": len(sweep.runs),
            "controllers": list(sweep.spec.controllers or []), "parameters": list(sweep.spec.parameters),
            "metrics": list(sweep.metrics), "columns": header, "seed": sweep.spec.seed,
            "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "uvms_version": uvms.__version__}


def _check_identity(marker: Path, sweep) -> None:
    try:
        recorded = json.loads(marker.read_text(encoding="utf-8"))
        digest = recorded["sweep_sha256"]
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise UvmsInputError(f"cannot read the recorded sweep identity: {one_line(exc, 200)}", str(marker)) from None
    if digest != sweep.sha256:
        name = recorded.get("name") if isinstance(recorded, dict) else None
        raise UvmsInputError(f"this directory holds sweep {show(name)} with hash {str(digest)[:12]}, "
                             f"not the current sweep file (hash {sweep.sha256[:12]}): the sweep or its base scenario "
                             "changed; choose another --output directory", str(marker))


def _lock(directory: Path) -> tuple[int, bool]:
    """Take ``directory/.lock`` (``flock``); return its descriptor and whether this call created the file."""
    path = directory / LOCK
    with _names(path):
        try:
            fd, made = os.open(path, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o666), True
        except FileExistsError:
            fd, made = os.open(path, os.O_RDWR), False
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX: no lock
        return fd, made
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        raise UvmsInputError("another uvms sweep is writing to this directory", str(directory), "--output") from None
    return fd, made


def _open_runs(path: Path, header: list[str]) -> tuple[int, dict[str, list[str]]]:
    """Open ``runs.csv`` for appending and read its rows (see :func:`_repair_and_read`)."""
    with _names(path):
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_APPEND, 0o666)
    try:
        with _names(path):
            done, dropped = _repair_and_read(fd, path, header)
            if dropped:
                os.close(fd)
                fd = -1
                _drop_lines(path, dropped)
                fd = os.open(path, os.O_RDWR | os.O_APPEND)
    except BaseException:
        if fd >= 0:
            os.close(fd)
        raise
    return fd, done


INFRASTRUCTURE = "worker failure: "
"""How earlier versions of uvms recorded a run whose worker or scheduler failed (``status = failed``, this error
prefix). Such rows are not final: :meth:`RunStore.open` drops them so that the runs are run again."""


def _repair_and_read(fd: int, path: Path, header: list[str]) -> tuple[dict[str, list[str]], set[int]]:
    """Check the file, then cut a partial last line (a kill mid-write), write the header into an empty file,
    read the rows. Returns the rows by run_id and the line numbers (1-based) of rows to drop: a cluster failure
    recorded by an older uvms (:data:`INFRASTRUCTURE`). A file that does not parse is refused untouched."""
    size = os.fstat(fd).st_size
    os.lseek(fd, 0, os.SEEK_SET)
    data = b""
    while len(data) < size:
        chunk = os.read(fd, size - len(data))
        if not chunk:
            break
        data += chunk
    complete = data[: data.rfind(b"\n") + 1]
    rows = list(csv.reader(io.StringIO(complete.decode("utf-8", errors="replace"), newline="")))
    if rows and rows[0] != header:
        raise UvmsInputError("its header differs from this sweep's columns (the file was changed outside uvms); "
                             "choose another --output directory", str(path))
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise UvmsInputError(f"line {number}: expected {len(header)} fields, found {len(row)} (the file was "
                                 "changed outside uvms); remove that line to run it again", str(path))
    if len(complete) < len(data):
        os.ftruncate(fd, len(complete))
        os.fsync(fd)
    if not rows:
        line = format_line(header).encode("utf-8")
        os.write(fd, line)
        os.fsync(fd)
        return {}, set()
    status, error = header.index("status"), header.index("error")
    done: dict[str, list[str]] = {}
    dropped: set[int] = set()
    for number, row in enumerate(rows[1:], start=2):
        if row[status] == "failed" and row[error].startswith(INFRASTRUCTURE):
            dropped.add(number)
            continue
        done.setdefault(row[0], row)
    return done, dropped


def _drop_lines(path: Path, numbers: set[int]) -> None:
    """Rewrite ``path`` atomically without the lines ``numbers`` (1-based; every line is one CSV row)."""
    lines = path.read_bytes().splitlines(keepends=True)
    kept = b"".join(line for k, line in enumerate(lines, start=1) if k not in numbers)
    _write(path, kept.decode("utf-8", errors="replace"))
