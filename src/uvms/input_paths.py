"""Where a data file named inside another input file may be (``docs/conventions.md``, "Real logs", item 9).

A log description names its CSV streams and a scenario its joint-motion table; each name is read relative to
the naming file's folder and must stay inside it once ``..`` and symbolic links are resolved: an input file
never makes uvms read a file outside its own folder (the rule ``model/xacro.py`` applies to includes).
Ground floor (``docs/architecture.md``).
"""

from __future__ import annotations

import os
from pathlib import Path

from uvms.errors import UvmsInputError


def data_file(name: str | os.PathLike[str], folder: str | os.PathLike[str], source: str | None,
              field: str) -> Path:
    """The resolved path of the file ``name`` (relative to ``folder``), or one line naming ``source`` and
    ``field`` when it is absolute, starts with ``~`` or lies outside ``folder``."""
    text = os.fspath(name)
    root = Path(folder).resolve()
    if Path(text).is_absolute() or text.startswith("~"):
        raise UvmsInputError(f"expected a file name relative to {root} (the file's own folder), got {text!r}",
                             source, field)
    path = (root / text).resolve()
    if path != root and root not in path.parents:
        raise UvmsInputError(f"{text!r} is outside {root}: a data file must lie in the folder of the file that "
                             f"names it", source, field)
    return path
