"""Reading one stream of a log: the columns a description names, from one CSV file, checked as data.

A log's CSV files are input files like any other (``docs/conventions.md``, "Hostile input files"): before pandas
parses anything, :func:`read_table` refuses a file over :data:`MAX_FILE_BYTES`, a header line over
:data:`MAX_HEADER_BYTES` or with more than :data:`MAX_COLUMNS` columns, and more than :data:`MAX_ROWS` rows. Then
every refusal is one :class:`~uvms.errors.UvmsInputError` line naming the file and the column or the line
(``line 1`` is the header): a column the header does not have (the header's columns listed), a cell that is
not a finite number (empty cells and ``nan`` included), time that goes backwards, one time given twice with
different values. A row repeated exactly (same time, same values in every column read) is dropped and counted
(:attr:`Table.dropped`); ``docs/logs.md`` ("Bad input") documents the rules.
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from uvms.errors import UvmsInputError, show

MAX_FILE_BYTES = 256 * 1024 * 1024
"""Largest CSV file read [bytes] (a 20-minute motion-capture log at 100 Hz is about 10 MiB)."""

MAX_HEADER_BYTES = 1024 * 1024
"""Longest header line read [bytes]."""

MAX_COLUMNS = 10_000
"""Most columns a header may have."""

MAX_ROWS = 10_000_000
"""Most data rows a file may have (about 28 hours at 100 Hz)."""


@dataclass(frozen=True)
class Table:
    """The columns read from one CSV file, rows in time order.

    Attributes:
        source: the CSV file.
        time: (K,) times on the log clock [s] (``time_scale * column + time_offset``), strictly increasing.
        values: ``{column: (K,) values}`` of the columns asked for.
        lines: (K,) the file line each row came from (the header is line 1).
        dropped: how many exact repetitions of a row were dropped.
    """

    source: str
    time: np.ndarray
    values: dict[str, np.ndarray]
    lines: np.ndarray
    dropped: int


def _header(path: Path) -> list[str]:
    """The header line's column names, within the size and count limits."""
    source = str(path)
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise UvmsInputError(f"refused: {size / 2**20:.0f} MiB is larger than the {MAX_FILE_BYTES // 2**20} "
                                 "MiB a log file may be", source)
        with path.open("rb") as fh:
            first = fh.readline(MAX_HEADER_BYTES + 1)
            if len(first) > MAX_HEADER_BYTES:
                raise UvmsInputError(f"refused: header line longer than {MAX_HEADER_BYTES // 2**20} MiB", source,
                                     "line 1")
            rows = 0
            while chunk := fh.read(1 << 24):
                rows += chunk.count(b"\n")
                if rows > MAX_ROWS:
                    raise UvmsInputError(f"refused: more than {MAX_ROWS:,} rows", source)
    except OSError as exc:
        raise UvmsInputError(f"cannot read: {exc.strerror or exc}", source) from None
    try:
        text = first.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise UvmsInputError(f"not UTF-8 text (byte {exc.start}): expected a CSV file", source, "line 1") from None
    names = next(csv.reader(io.StringIO(text)), [])
    if len(names) > MAX_COLUMNS:
        raise UvmsInputError(f"refused: {len(names):,} columns, more than {MAX_COLUMNS:,}", source, "line 1")
    if not any(name.strip() for name in names):
        raise UvmsInputError("expected a header line of column names, found an empty line", source, "line 1")
    return names


def _check_columns(names: list[str], wanted: list[str], source: str, keys: dict[str, str]) -> None:
    for column in wanted:
        count = names.count(column)
        if count == 1:
            continue
        where = f"column {show(column)} ({keys[column]})"
        if count > 1:
            raise UvmsInputError(f"the header names this column {count} times", source, where)
        listed = ", ".join(names)
        listed = listed if len(listed) <= 200 else listed[:197] + "..."
        raise UvmsInputError(f"no such column; the header has: {listed}", source, where)


def _numbers(frame, column: str, source: str) -> np.ndarray:
    """The column as finite float64 values, else one line naming the first bad cell's line."""
    import pandas as pd

    raw = frame[column]
    values = pd.to_numeric(raw, errors="coerce").to_numpy(dtype=float)
    bad = ~np.isfinite(values)
    if bad.any():
        row = int(np.argmax(bad))
        cell = raw.iloc[row]
        found = "an empty cell" if not isinstance(cell, str) or not cell.strip() else show(cell)
        raise UvmsInputError(f"expected a finite number, found {found}", source,
                             f"line {row + 2}, column {show(column)}")
    return values


def read_table(path: str | os.PathLike[str], time: str, columns: dict[str, str], *, time_scale: float = 1.0,
               time_offset: float = 0.0) -> Table:
    """Read the ``time`` column and ``columns`` (``{column: the description key that names it}``, for messages)
    from the CSV file ``path``; see the module docstring for what is refused.

    Raises:
        UvmsInputError: one line naming the file and the column or line.
    """
    import pandas as pd

    path = Path(path)
    source = str(path)
    if not path.is_file():
        raise UvmsInputError("no such file" if not path.exists() else "expected a CSV file, found a directory",
                             source)
    keys = {time: "time", **{c: k for c, k in columns.items() if c != time}}
    wanted = list(keys)
    _check_columns(_header(path), wanted, source, keys)
    try:
        frame = pd.read_csv(path, usecols=wanted, dtype=str, keep_default_na=False, na_filter=False,
                            skip_blank_lines=False, encoding="utf-8-sig", engine="c")
    except (ValueError, OSError, pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise UvmsInputError(f"not a readable CSV file: {show(str(exc).splitlines()[0] if str(exc) else exc, 120)}",
                             source) from None
    values = {c: _numbers(frame, c, source) for c in wanted}
    t = values.pop(time) * time_scale + time_offset
    return checked_rows(source, t, values, np.arange(2, t.size + 2), time_name=f"column {show(time)}")


def checked_rows(source: str, t: np.ndarray, values: dict[str, np.ndarray], lines: np.ndarray, *, time_name: str,
                 line: str = "line") -> Table:
    """The :class:`Table` of rows read in file order (a CSV file's, a bag topic's): at least two, time never going
    backwards, a time given twice only as an exact repetition (dropped); ``lines`` number the rows in messages
    (``line`` says what they are), ``time_name`` names the time column."""
    if t.size < 2:
        raise UvmsInputError(f"expected at least 2 rows of data, found {t.size}", source)
    step = np.diff(t)
    back = np.flatnonzero(step < 0)
    if back.size:
        k = int(back[0]) + 1
        raise UvmsInputError(f"time goes backwards: {t[k]:.9g} s after {t[k - 1]:.9g} s on {line} {lines[k - 1]}",
                             source, f"{line} {lines[k]}, {time_name}")
    same = np.flatnonzero(step == 0) + 1
    differ = [k for k in same if any(v[k] != v[k - 1] for v in values.values())]
    if differ:
        k = differ[0]
        changed = next(c for c, v in values.items() if v[k] != v[k - 1])
        kind = "column" if line == "line" else "field"
        raise UvmsInputError(f"time {t[k]:.9g} s repeats {line} {lines[k - 1]} with another value in {kind} "
                             f"{show(changed)} (a time must not be given twice)", source,
                             f"{line} {lines[k]}, {time_name}")
    keep = np.ones(t.size, dtype=bool)
    keep[same] = False
    if not keep.all():
        t, lines = t[keep], lines[keep]
        values = {c: v[keep] for c, v in values.items()}
    if t.size < 2:
        raise UvmsInputError("expected at least 2 rows at distinct times, found 1", source)
    return Table(source=source, time=t, values=values, lines=lines, dropped=int((~keep).sum()))
