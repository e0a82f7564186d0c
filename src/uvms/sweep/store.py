"""A sweep's output directory: ``sweep.json`` (identity), ``runs.csv`` (one row per finished run, append-only),
``summary.csv``, and the sweep and base scenario files verbatim.

``runs.csv`` is only ever appended to, one whole line per ``os.write`` followed by ``fsync``, from the client
process. A process killed mid-write can leave at most a partial last line (no newline): :meth:`RunStore.open`
cuts it off before anything else is written, so the file always parses and holds exactly one row per run_id.
A lock (``.lock``, ``flock``) keeps a second ``uvms sweep`` out of a directory in use.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import time
from pathlib import Path
from typing import Any

from uvms.errors import UvmsInputError
from uvms.output import atomic_write_text

RUNS_CSV = "runs.csv"
SWEEP_JSON = "sweep.json"
SUMMARY_CSV = "summary.csv"
LOCK = ".lock"

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
    """

    def __init__(self, directory: Path, columns: list[str], done: dict[str, list[str]], fd: int, lock_fd: int):
        self.directory = directory
        self.columns = columns
        self.done = done
        self._fd = fd
        self._lock_fd = lock_fd

    @classmethod
    def open(cls, directory: str | os.PathLike[str], sweep) -> RunStore:
        """Open (or create) the sweep directory ``directory`` for ``sweep``.

        Raises:
            UvmsInputError: ``directory`` is a file, a non-sweep directory, another sweep's directory (hash
                differs), in use by another process, or holds a ``runs.csv`` that does not parse.
        """
        directory = Path(directory)
        header = columns(sweep)
        if directory.exists() and not directory.is_dir():
            raise UvmsInputError("expected a directory, found a file", str(directory), "--output")
        marker = directory / SWEEP_JSON
        if directory.is_dir() and not marker.exists() and any(p.name != LOCK for p in directory.iterdir()):
            raise UvmsInputError(f"exists and is not a sweep directory (no {SWEEP_JSON}); choose another directory",
                                 str(directory), "--output")
        directory.mkdir(parents=True, exist_ok=True)
        lock_fd = _lock(directory)
        try:
            if marker.exists():
                _check_identity(marker, sweep)
            else:
                _write(directory / "sweep.yaml", sweep.text)
                _write(directory / "scenario.yaml", sweep.base.text)
                _write(marker, json.dumps(_identity(sweep, header), indent=2) + "\n")
            path = directory / RUNS_CSV
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_APPEND, 0o666)
            try:
                done = _repair_and_read(fd, path, header)
            except BaseException:
                os.close(fd)
                raise
        except BaseException:
            os.close(lock_fd)
            raise
        return cls(directory, header, done, fd, lock_fd)

    def append(self, cells: list[str]) -> None:
        """Append one row (one ``write`` of the whole line, then ``fsync``)."""
        data = format_line(cells).encode("utf-8")
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

    def __enter__(self) -> RunStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _write(path: Path, text: str) -> None:
    """Write atomically, with the permissions the umask allows (the temporary file starts private)."""
    atomic_write_text(path, text)


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
        raise UvmsInputError(f"cannot read the recorded sweep identity: {exc}", str(marker)) from None
    if digest != sweep.sha256:
        raise UvmsInputError(f"this directory holds sweep {recorded.get('name')!r} with hash {str(digest)[:12]}, "
                             f"not the current sweep file (hash {sweep.sha256[:12]}): the sweep or its base scenario "
                             "changed; choose another --output directory", str(marker))


def _lock(directory: Path) -> int:
    fd = os.open(directory / LOCK, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX: no lock
        return fd
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        raise UvmsInputError("another uvms sweep is writing to this directory", str(directory), "--output") from None
    return fd


def _repair_and_read(fd: int, path: Path, header: list[str]) -> dict[str, list[str]]:
    """Cut a partial last line (a kill mid-write), write the header into an empty file, read the rows."""
    size = os.fstat(fd).st_size
    os.lseek(fd, 0, os.SEEK_SET)
    data = b""
    while len(data) < size:
        chunk = os.read(fd, size - len(data))
        if not chunk:
            break
        data += chunk
    if data and not data.endswith(b"\n"):
        data = data[: data.rfind(b"\n") + 1]
        os.ftruncate(fd, len(data))
        os.fsync(fd)
    if not data:
        line = format_line(header).encode("utf-8")
        os.write(fd, line)
        os.fsync(fd)
        return {}
    rows = list(csv.reader(io.StringIO(data.decode("utf-8", errors="replace"), newline="")))
    if rows[0] != header:
        raise UvmsInputError("its header differs from this sweep's columns (the file was changed outside uvms); "
                             "choose another --output directory", str(path))
    done: dict[str, list[str]] = {}
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise UvmsInputError(f"line {number}: expected {len(header)} fields, found {len(row)} (the file was "
                                 "changed outside uvms); remove that line to run it again", str(path))
        done.setdefault(row[0], row)
    return done
