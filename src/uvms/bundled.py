"""Files shipped with uvms (models, scenarios, sweeps), found by name or by path."""

from __future__ import annotations

import os
from pathlib import Path

from uvms.errors import UvmsInputError


def bundled_names(folder) -> list[str]:
    """Names (file stems) of the YAML files in a package folder (an ``importlib.resources`` traversable)."""
    if not folder.is_dir():
        return []
    return sorted(e.name[: -len(".yaml")] for e in folder.iterdir() if e.name.endswith(".yaml"))


def resolve_path(name_or_path: str | os.PathLike[str], folder, kind: str) -> Path:
    """An existing file path as given, else the bundled ``kind`` (model, scenario, sweep) of that name.

    Raises:
        UvmsInputError: neither (one line listing the bundled names), or not a string or path at all.
    """
    if not isinstance(name_or_path, (str, os.PathLike)) or isinstance(os.fspath(name_or_path), bytes):
        from uvms.checks import show

        raise UvmsInputError(f"expected a file path or a bundled {kind} name, got {show(name_or_path)}",
                             path="name_or_path")
    path = Path(name_or_path)
    if path.exists():
        return path
    names = bundled_names(folder)
    if str(name_or_path) in names:
        return Path(str(folder / f"{name_or_path}.yaml"))
    raise UvmsInputError(f"no such file or bundled {kind} (bundled: {', '.join(names) or 'none'})",
                         str(name_or_path))
