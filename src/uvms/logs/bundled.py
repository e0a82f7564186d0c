"""Logs shipped with uvms, found by name: ``<dataset>/<trial>`` (e.g. ``hinsdale_2023/traj_alt_001-0``), or a
shell-style pattern of such names (``hinsdale_2023/traj_alt_*``) matched against the bundled trials.

A bundled data set is a folder of ``uvms/data/`` holding one folder per trial with a log description
``<trial>/<trial>.yaml`` (``docs/logs.md``, "Bundled logs").
"""

from __future__ import annotations

import fnmatch
import os
from importlib.resources import files
from pathlib import Path

from uvms.errors import UvmsInputError

MAX_MATCHES = 1000
"""Most logs one pattern may name."""


def _data():
    return files("uvms") / "data"


def bundled_logs() -> list[str]:
    """Every bundled log's name, ``<dataset>/<trial>``, sorted."""
    data = _data()
    if not data.is_dir():
        return []
    out = []
    for dataset in data.iterdir():
        if not dataset.is_dir():
            continue
        for trial in dataset.iterdir():
            if trial.is_dir() and (trial / f"{trial.name}.yaml").is_file():
                out.append(f"{dataset.name}/{trial.name}")
    return sorted(out)


def resolve_logs(name_or_path: str | os.PathLike[str]) -> list[Path]:
    """The log description files ``name_or_path`` names: an existing file itself, else the bundled logs whose
    names match it (a name or a pattern), else one line listing the bundled data sets."""
    path = Path(name_or_path)
    if path.is_file():
        return [path]
    text = str(name_or_path)
    names = bundled_logs()
    matched = [n for n in names if fnmatch.fnmatchcase(n, text)]
    if not matched:
        sets = sorted({n.split("/")[0] for n in names})
        raise UvmsInputError(f"no such log file or bundled log (bundled: {', '.join(f'{s}/<trial>' for s in sets)}"
                             f" or a pattern such as {sets[0] + '/traj_alt_*' if sets else 'none'})", text)
    if len(matched) > MAX_MATCHES:
        raise UvmsInputError(f"names {len(matched)} logs; expected at most {MAX_MATCHES}", text)
    return [Path(str(_data() / n / f"{n.split('/')[1]}.yaml")) for n in matched]


def log_name(path) -> str:
    """A log's name for records: ``<dataset>/<trial>`` for a bundled log, else the path as given."""
    path = Path(path)
    try:
        data = Path(str(_data())).resolve()
        relative = path.resolve().relative_to(data)
    except (ValueError, OSError):
        return str(path)
    return f"{relative.parts[0]}/{relative.parts[1]}" if len(relative.parts) == 3 else str(path)
