"""Reading user YAML files (models, scenarios, sweeps) safely: hostile input is refused quickly, never expanded.

YAML lets a small file describe a huge value (aliases of aliases, "billion laughs"), nest deeper than Python's
recursion limit, or hold integers with hundreds of digits. Before anything is built, :func:`read_yaml` walks
the parser's event stream once (a flat loop, no recursion) and refuses, with one line naming the file and the
line:

- a file larger than :data:`MAX_BYTES`;
- nesting deeper than :data:`MAX_DEPTH` levels;
- a document whose aliases would expand it to more than :data:`MAX_VALUES` values;
- an integer that does not fit in 64 bits.

What passes is then constructed by PyYAML's safe loader with two changes: a key repeated in one mapping is an
error (PyYAML silently keeps the last), and YAML 1.2 floats without a dot (``1e2``) are numbers. Merge keys
(``<<: *defaults``) work as YAML defines them. The limits are documented in ``docs/conventions.md``.
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

import yaml

from uvms.errors import UvmsInputError

MAX_BYTES = 2 * 1024 * 1024
"""Largest YAML file read [bytes]; uvms's own files are a few kB (the cap keeps a refusal well under 1 s)."""

MAX_DEPTH = 64
"""Deepest nesting of mappings and lists accepted."""

MAX_VALUES = 1_000_000
"""Most values (scalars, mappings, lists) a document may hold once its aliases are expanded."""

MAX_INT_CHARACTERS = 80
"""Integers must fit in 64 bits; one written with more characters is refused before it is even converted."""

_MERGE = "tag:yaml.org,2002:merge"


class _Loader(yaml.SafeLoader):
    """Safe loader: repeated keys refused, integers bounded, YAML 1.2 exponent floats read as numbers."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
        own = [key for key, _ in node.value if key.tag != _MERGE]   # merged keys may be overridden, by design
        seen: list[Any] = []
        for key_node in own:
            key = self.construct_object(key_node, deep=deep)
            if key in seen:
                raise yaml.constructor.ConstructorError(None, None, f"duplicate key {_short(key)}",
                                                        key_node.start_mark)
            seen.append(key)
        return super().construct_mapping(node, deep=deep)

    def construct_yaml_int(self, node: yaml.ScalarNode) -> int:
        value = super().construct_yaml_int(node) if len(str(node.value)) <= MAX_INT_CHARACTERS else None
        if value is None or not -(2**63) <= value < 2**63:
            raise yaml.constructor.ConstructorError(None, None, "integer refused: it does not fit in 64 bits",
                                                    node.start_mark)
        return value


_Loader.add_constructor("tag:yaml.org,2002:int", _Loader.construct_yaml_int)
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float", re.compile(r"^[-+]?[0-9][0-9_]*[eE][-+]?[0-9]+$"), list("-+0123456789"))


def _short(value: Any, limit: int = 60, *, quote: bool = True) -> str:
    text = " ".join((repr(value) if quote else str(value))[: limit + 1].split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _where(mark: Any) -> str | None:
    return f"line {mark.line + 1}, column {mark.column + 1}" if mark is not None else None


def check_events(text: str, source: str) -> None:
    """Refuse nesting deeper than :data:`MAX_DEPTH` and alias expansion beyond :data:`MAX_VALUES` values.

    One pass over the parser's events: each scalar and each collection counts one value, an alias counts the
    values of the node it names (recorded when that node ended), so the expanded size is known without
    expanding anything.
    """
    sizes: dict[str, int] = {}
    open_at: list[tuple[str | None, int]] = []   # (anchor, values counted when the collection opened)
    values = 0
    for event in yaml.parse(text, Loader=_Loader):
        if isinstance(event, yaml.ScalarEvent):
            values += 1
            if event.anchor is not None:
                sizes[event.anchor] = 1
        elif isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent)):
            values += 1
            open_at.append((event.anchor, values))
            if len(open_at) > MAX_DEPTH:
                raise UvmsInputError(f"refused: nested more than {MAX_DEPTH} levels deep", source,
                                     _where(event.start_mark))
        elif isinstance(event, (yaml.SequenceEndEvent, yaml.MappingEndEvent)):
            anchor, start = open_at.pop()
            if anchor is not None:
                sizes[anchor] = values - start + 1
        elif isinstance(event, yaml.AliasEvent):
            values += sizes.get(event.anchor, 1)
        if values > MAX_VALUES:
            raise UvmsInputError(f"refused: aliases expand this document beyond {MAX_VALUES:,} values",
                                 source, _where(event.start_mark))


def parse_yaml(text: str, source: str) -> Any:
    """Parse YAML ``text`` under the limits above; every problem is a one-line :class:`UvmsInputError`."""
    try:
        check_events(text, source)
        return yaml.load(text, Loader=_Loader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        what = exc.problem or exc.context
        raise UvmsInputError(f"invalid YAML: {_short(what, 200, quote=False)}", source, _where(mark)) from None
    except (yaml.YAMLError, RecursionError) as exc:
        raise UvmsInputError(f"invalid YAML: {_short(exc, 200, quote=False)}", source) from None


def read_yaml(path: str | os.PathLike[str]) -> Any:
    """Read and parse a YAML file (see the module docstring for what is refused)."""
    path = Path(path)
    if not path.exists():
        raise UvmsInputError("no such file", str(path))
    if not path.is_file():
        found = "a directory" if path.is_dir() else "something that is not a regular file"
        raise UvmsInputError(f"expected a YAML file, found {found}", str(path))
    try:
        with path.open("rb") as fh:
            raw = fh.read(MAX_BYTES + 1)
    except OSError as exc:
        raise UvmsInputError(f"cannot read: {exc.strerror or exc}", str(path)) from None
    if len(raw) > MAX_BYTES:
        raise UvmsInputError(f"refused: larger than {MAX_BYTES // (1024 * 1024)} MiB, not a uvms YAML file",
                             str(path))
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise UvmsInputError(f"not UTF-8 text (byte {exc.start}): expected a YAML file", str(path)) from None
    return parse_yaml(text, str(path))


def _kind(value: Any) -> str:
    """What a value is, in words, without rendering it (a file read by mistake may hold anything)."""
    if value is None:
        return "an empty file"
    kinds = {str: "a line of text", list: "a list", bool: "true or false", int: "a number", float: "a number"}
    return next((name for kind, name in kinds.items() if isinstance(value, kind)), type(value).__name__)


def read_yaml_mapping(path: str | os.PathLike[str], what: str) -> dict[Any, Any]:
    """Read a YAML file that must hold a mapping of ``what`` (``"model fields"``...) at the top level; otherwise
    one line that says what was found, never the file's content (the path may name any file)."""
    data = read_yaml(path)
    if not isinstance(data, dict):
        raise UvmsInputError(f"expected a mapping of {what} at the top level, found {_kind(data)}: "
                             "is this a uvms file?", str(path))
    return data
