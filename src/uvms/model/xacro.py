"""Expanding xacro as data, not as a program (``docs/models.md``, "What a xacro may do").

The ``xacro`` package (the ROS tool, installed with ``xacrodoc``) evaluates ``${...}`` with Python ``eval``
and reads any file, environment variable or package a document names. uvms runs xacro's own macro, property,
block and conditional machinery, but every way out of the document goes through this module:

* ``${...}`` and ``$(eval ...)`` are evaluated by :func:`evaluate`, an interpreter of a whitelist of Python's
  expression syntax (numbers, strings, lists, properties, arithmetic, comparisons, ``and``/``or``/``not``,
  ``a if c else b``, subscripts, ``math`` functions and constants): no attributes but the members of ``math``
  and of property / YAML namespaces, no calls but to the whitelisted functions, no lambdas or comprehensions.
  Exponents, repetitions and concatenations whose result would exceed :data:`MAX_INT_BITS` or
  :data:`MAX_STRING_CHARS` are refused before they are computed;
* ``<xacro:include>`` and ``xacro.load_yaml`` read only files inside the model's folder (the folder of the
  top-level file) or inside a package folder the user names (``package_paths``), after resolving ``..`` and
  symbolic links; ``$(find pkg)`` gives only those package folders;
* ``$(env)`` and ``$(optenv)`` are refused unless the user allows them (``allow_environment``); ``$(cwd)`` is
  refused; ``$(arg)`` and ``$(dirname)`` work as in xacro;
* limits (the ``MAX_*`` constants below, documented in ``docs/models.md``) bound the files read, the elements
  expanded, the macro depth and the text produced, so that a hostile document is refused in well under a
  second;
* every file is parsed by ``defusedxml`` (no DTD, no entities); xacro's own warnings are kept off the terminal.

xacro keeps its state in module globals: an expansion holds :data:`_LOCK`, swaps xacro's hooks for this
module's and restores them afterwards, so expansions in several threads run one after the other.
"""

from __future__ import annotations

import ast
import math
import os
import threading
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from uvms.errors import UvmsInputError, show

MAX_FILE_BYTES = 2 * 1024 * 1024
"""Largest xacro (or included, or ``load_yaml``) file read [bytes] (as for YAML files)."""
MAX_FILES = 100
"""Most files (includes and YAML files) one expansion reads."""
MAX_ELEMENTS = 20_000
"""Most XML elements one expansion produces: bounded before expanding (every macro call counted at the size of
the macro's body, both branches of a conditional counted) and counted while expanding (blocks and recursive
macros count each time they are expanded)."""
MAX_MACRO_DEPTH = 50
"""Deepest nesting of macro calls."""
MAX_WORK = 40_000
"""Most element-levels one expansion processes: each element counts ``1 +`` the depth of macro calls it is
expanded in (xacro's cost per element grows with that depth: a property is looked up through every level)."""
MAX_OUTPUT_CHARS = 32 * 1024 * 1024
"""Most characters of text the expressions and substitutions of one expansion produce, in total."""
MAX_EXPRESSION_CHARS = 10_000
"""Longest single ``${...}`` expression [characters]."""
MAX_TEXT_CHARS = 65_536
"""Longest attribute or text holding ``${...}`` or ``$(...)`` [characters]."""
MAX_STRING_CHARS = 1_000_000
"""Longest string (or list) an expression may produce [characters or items]."""
MAX_INT_BITS = 4096
"""Largest integer an expression may produce [bits] (a float ends at about 1024)."""

_LOCK = threading.RLock()


@dataclass(frozen=True)
class XacroOptions:
    """What a xacro may read beyond its own folder (all off by default; ``docs/models.md``).

    Attributes:
        package_paths: ``{package name: folder}``: what ``$(find name)`` gives and where includes and
            ``load_yaml`` may read besides the model's folder.
        allow_environment: whether ``$(env VAR)`` and ``$(optenv VAR)`` may read environment variables.
        args: values of ``<xacro:arg>`` (``$(arg name)``), as on xacro's command line ``name:=value``.
    """

    package_paths: Mapping[str, str | os.PathLike[str]] = field(default_factory=dict)
    allow_environment: bool = False
    args: Mapping[str, str] = field(default_factory=dict)


class _Refused(Exception):
    """Internal: carries a :class:`UvmsInputError` through xacro's own exception wrapping."""


# --------------------------------------------------------------------------------------------- the evaluator

class _Namespace:
    """A fixed set of whitelisted members reached as ``name.member`` (``math.pi``, ``xacro.load_yaml``)."""

    def __init__(self, members: Mapping[str, Any]) -> None:
        self.members = dict(members)


def _checked_round(number: Any, ndigits: Any = None) -> Any:
    """``round`` with ``|ndigits| <= 100`` (a huge negative ``ndigits`` makes Python compute ``10**-ndigits``)."""
    if ndigits is not None and (not isinstance(ndigits, int) or abs(ndigits) > 100):
        raise _user_error(f"round(): expected ndigits an integer within +/-100, found {show(ndigits)}")
    return round(number) if ndigits is None else round(number, ndigits)


_MATH_FUNCTIONS = ("sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "asinh",
                   "acosh", "atanh", "exp", "expm1", "log", "log10", "log2", "log1p", "sqrt", "pow", "fabs",
                   "floor", "ceil", "trunc", "fmod", "hypot", "copysign", "degrees", "radians", "isfinite",
                   "isinf", "isnan")
_MATH = {name: getattr(math, name) for name in _MATH_FUNCTIONS}
_MATH.update(pi=math.pi, e=math.e, tau=math.tau, inf=math.inf, nan=math.nan)
_BUILTINS = {"abs": abs, "min": min, "max": max, "round": _checked_round, "int": int, "float": float,
             "str": str, "bool": bool, "len": len}


def _user_error(message: str) -> _Refused:
    return _Refused(UvmsInputError(message))


_CALLABLE: set[int] = set()          # ids of the functions an expression may call (filled below)
_DATA = (int, float, bool, str, type(None), list, tuple, dict)


def _bounded(value: Any) -> Any:
    """``value`` if it is within :data:`MAX_INT_BITS` / :data:`MAX_STRING_CHARS`, else refused."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > MAX_INT_BITS:
        raise _user_error(f"an integer beyond {MAX_INT_BITS} bits")
    if isinstance(value, (str, list, tuple, dict)) and len(value) > MAX_STRING_CHARS:
        raise _user_error(f"a string or list longer than {MAX_STRING_CHARS:,} (limit)")
    return value


def _int_bits(value: Any) -> int:
    return abs(int(value)).bit_length() if isinstance(value, (int, bool)) else 0


def _sized(value: Any) -> bool:
    return isinstance(value, (str, list, tuple))


def _binary(op: ast.operator, a: Any, b: Any) -> Any:
    """``a op b`` for the whitelisted operators, with the result's size checked before it is computed."""
    if not isinstance(a, _DATA) or not isinstance(b, _DATA):
        raise _user_error("an operand that is not a number, string or list")
    if isinstance(op, ast.Add):
        if _sized(a) and _sized(b) and len(a) + len(b) > MAX_STRING_CHARS:
            raise _user_error(f"a string or list longer than {MAX_STRING_CHARS:,} (limit)")
        return _bounded(a + b)
    if isinstance(op, ast.Mult):
        for seq, count in ((a, b), (b, a)):
            if _sized(seq) and isinstance(count, int):
                if len(seq) * max(count, 0) > MAX_STRING_CHARS:
                    raise _user_error(f"a repetition longer than {MAX_STRING_CHARS:,} (limit)")
        if _int_bits(a) + _int_bits(b) > MAX_INT_BITS + 1:
            raise _user_error(f"an integer beyond {MAX_INT_BITS} bits")
        return _bounded(a * b)
    if isinstance(op, ast.Pow):
        if isinstance(a, int) and isinstance(b, int) and b > 0 and abs(a) > 1 and \
                (abs(a).bit_length() - 1) * b > MAX_INT_BITS:
            raise _user_error(f"a power beyond {MAX_INT_BITS} bits")
        return _bounded(a ** b)
    if isinstance(op, (ast.Sub, ast.Div, ast.FloorDiv, ast.Mod)):
        if isinstance(a, str) or isinstance(b, str) or isinstance(a, (list, tuple, dict)):
            raise _user_error("arithmetic (-, /, //, %) on a string or list")
        return _bounded({ast.Sub: lambda: a - b, ast.Div: lambda: a / b, ast.FloorDiv: lambda: a // b,
                         ast.Mod: lambda: a % b}[type(op)]())
    raise _user_error(f"the operator {type(op).__name__} is not allowed")


_COMPARE = {ast.Eq: lambda a, b: a == b, ast.NotEq: lambda a, b: a != b, ast.Lt: lambda a, b: a < b,
            ast.LtE: lambda a, b: a <= b, ast.Gt: lambda a, b: a > b, ast.GtE: lambda a, b: a >= b,
            ast.In: lambda a, b: a in b, ast.NotIn: lambda a, b: a not in b,
            ast.Is: lambda a, b: a is b, ast.IsNot: lambda a, b: a is not b}


class _Evaluator:
    """Walks a parsed expression; names are looked up in ``symbols`` (xacro's property table)."""

    def __init__(self, symbols: Any) -> None:
        self.symbols = symbols

    def __call__(self, node: ast.AST) -> Any:
        method = getattr(self, "_" + type(node).__name__, None)
        if method is None:
            raise _user_error(f"{_describe(node)} is not allowed in a xacro expression (arithmetic, comparisons, "
                              "properties and math functions only)")
        return method(node)

    def _Expression(self, node: ast.Expression) -> Any:
        return self(node.body)

    def _Constant(self, node: ast.Constant) -> Any:
        if not isinstance(node.value, (int, float, str, bool, type(None))):
            raise _user_error(f"a constant of type {type(node.value).__name__} is not allowed")
        return _bounded(node.value)

    def _Name(self, node: ast.Name) -> Any:
        return self._lookup(node.id)

    def _lookup(self, name: str) -> Any:
        if name.startswith("_"):
            raise _user_error(f"the name {name!r} is not allowed (names starting with '_')")
        try:
            value = self.symbols[name]
        except KeyError:
            raise _user_error(f"name {name!r} is not defined") from None
        return _exposed(value, name)

    def _Attribute(self, node: ast.Attribute) -> Any:
        base = self(node.value)
        name = node.attr
        if name.startswith("_"):
            raise _user_error(f"the attribute {name!r} is not allowed (names starting with '_')")
        if isinstance(base, _Namespace):
            if name not in base.members:
                raise _user_error(f"{name!r} is not one of the allowed functions and constants")
            return base.members[name]
        if isinstance(base, dict):          # a property namespace (include ns=) or a YAML mapping
            try:
                return _exposed(base[name], name)
            except (KeyError, AttributeError, NameError):
                raise _user_error(f"no key {name!r}") from None
        raise _user_error(f"attribute access (.{name}) is allowed only on math, xacro, namespaces and YAML "
                          "mappings")

    def _Subscript(self, node: ast.Subscript) -> Any:
        base = self(node.value)
        if not isinstance(base, (str, list, tuple, dict)):
            raise _user_error("a subscript of something that is not a string, list or mapping")
        if isinstance(node.slice, ast.Slice):
            parts = [None if p is None else self(p) for p in (node.slice.lower, node.slice.upper, node.slice.step)]
            if not all(p is None or isinstance(p, int) for p in parts) or isinstance(base, dict):
                raise _user_error("a slice must have integer bounds and apply to a string or list")
            return base[slice(*parts)]
        key = self(node.slice)
        if not isinstance(key, (int, float, str, bool, tuple)):
            raise _user_error("a subscript must be a number or a string")
        try:
            return _exposed(base[key], show(key))
        except (KeyError, IndexError, TypeError, AttributeError):
            raise _user_error(f"no item {show(key)}") from None

    def _BinOp(self, node: ast.BinOp) -> Any:
        return _binary(node.op, self(node.left), self(node.right))

    def _UnaryOp(self, node: ast.UnaryOp) -> Any:
        value = self(node.operand)
        if isinstance(node.op, ast.Not):
            return not value
        if isinstance(value, (int, float)):
            return {ast.USub: lambda: -value, ast.UAdd: lambda: +value, ast.Invert: lambda: ~int(value)}[
                type(node.op)]()
        raise _user_error("a sign on something that is not a number")

    def _BoolOp(self, node: ast.BoolOp) -> Any:
        value = None
        for item in node.values:
            value = self(item)
            if isinstance(node.op, ast.And) and not value or isinstance(node.op, ast.Or) and value:
                return value
        return value

    def _Compare(self, node: ast.Compare) -> Any:
        left = self(node.left)
        for op, item in zip(node.ops, node.comparators):
            right = self(item)
            if not isinstance(left, _DATA) or not isinstance(right, _DATA):
                raise _user_error("a comparison of something that is not a number, string or list")
            if not _COMPARE[type(op)](left, right):
                return False
            left = right
        return True

    def _IfExp(self, node: ast.IfExp) -> Any:
        return self(node.body) if self(node.test) else self(node.orelse)

    def _List(self, node: ast.List) -> Any:
        return _bounded([self(item) for item in node.elts])

    def _Tuple(self, node: ast.Tuple) -> Any:
        return _bounded(tuple(self(item) for item in node.elts))

    def _Dict(self, node: ast.Dict) -> Any:
        if any(key is None for key in node.keys):
            raise _user_error("'**' in a mapping is not allowed")
        return _bounded({self(k): self(v) for k, v in zip(node.keys, node.values)})

    def _Call(self, node: ast.Call) -> Any:
        function = self(node.func)
        if id(function) not in _CALLABLE:
            raise _user_error("a call of something that is not an allowed function (math functions, abs, min, "
                              "max, round, int, float, str, bool, len, xacro.load_yaml, xacro.arg)")
        if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
            raise _user_error("keyword and '*' arguments are not allowed")
        args = [self(a) for a in node.args]
        if not all(isinstance(a, _DATA) for a in args):
            raise _user_error("a function argument that is not a number, string or list")
        try:
            return _bounded(function(*args))
        except _Refused:
            raise
        except (ValueError, TypeError, OverflowError, ArithmeticError) as exc:
            raise _user_error(f"{getattr(function, '__name__', 'call')}(): {exc}") from None


def _exposed(value: Any, name: str) -> Any:
    """A looked-up value as an expression may see it: data, a property namespace, a whitelisted function or
    namespace; anything else (a function or module of xacro's) is refused."""
    if isinstance(value, (_Namespace, *_DATA)) or id(value) in _CALLABLE:
        return value
    raise _user_error(f"{name!r} is not a number, string, list or allowed function")


def _describe(node: ast.AST) -> str:
    names = {"Lambda": "a lambda", "ListComp": "a comprehension", "SetComp": "a comprehension",
             "DictComp": "a comprehension", "GeneratorExp": "a generator", "NamedExpr": "':='",
             "JoinedStr": "an f-string", "Starred": "'*'", "Await": "await", "Yield": "yield"}
    return names.get(type(node).__name__, f"the construct {type(node).__name__}")


def evaluate(expression: str, symbols: Any) -> Any:
    """The value of one xacro expression (the text inside ``${...}``), by the whitelist interpreter.

    Raises:
        UvmsInputError: a construct outside the whitelist, an undefined name, or a result beyond the limits.
    """
    try:
        return _evaluate(expression, symbols)
    except _Refused as exc:
        raise exc.args[0] from None


def _evaluate(expression: str, symbols: Any) -> Any:
    text = expression.strip()
    if len(text) > MAX_EXPRESSION_CHARS:
        raise _user_error(f"an expression longer than {MAX_EXPRESSION_CHARS:,} characters (limit)")
    try:
        tree = ast.parse(text, mode="eval")
    except (SyntaxError, ValueError, MemoryError, RecursionError) as exc:
        raise _user_error(f"invalid expression {show(text)}: {getattr(exc, 'msg', exc)}") from None
    try:
        value = _Evaluator(symbols)(tree)
    except RecursionError:
        raise _user_error(f"expression nested too deeply: {show(text)}") from None
    except ZeroDivisionError:
        raise _user_error(f"division by zero in {show(text)}") from None
    except (OverflowError, ArithmeticError) as exc:
        raise _user_error(f"{exc} in {show(text)}") from None
    except TypeError as exc:
        raise _user_error(f"{exc} in {show(text)}") from None
    if not isinstance(value, _DATA):
        raise _user_error(f"{show(text)} is not a number, string or list")
    return value


# ------------------------------------------------------------------------------------------- the expansion

@dataclass
class _Context:
    """The state of one expansion: the file allowed roots, options and the budgets used so far."""

    top: Path
    roots: tuple[Path, ...]
    options: XacroOptions
    files: int = 0
    elements: int = 0
    work: int = 0
    output_chars: int = 0
    macro_depth: int = 0
    warnings: list[str] = field(default_factory=list)
    refusal: UvmsInputError | None = None
    macro_sizes: dict[str, int] = field(default_factory=dict)


_current: _Context | None = None


def _refuse(message: str) -> _Refused:
    """Record the first refusal (xacro may wrap or swallow the exception) and return the exception."""
    error = UvmsInputError(message)
    if _current is not None and _current.refusal is None:
        _current.refusal = error
    return _Refused(error)


def _inside(path: Path, roots: tuple[Path, ...]) -> bool:
    return any(path == root or root in path.parents for root in roots)


def _allowed_file(name: str, what: str, count: bool = True) -> Path:
    """The resolved path of a file an include or ``load_yaml`` names, relative to the file being processed;
    refused outside the model's folder and the named package folders, or beyond the limits."""
    import xacro

    ctx = _current
    if any(ch in name for ch in "*?["):
        raise _refuse(f"{what} {show(name)}: wildcard file names are not supported")
    base = Path(xacro.filestack[-1]).parent if xacro.filestack and xacro.filestack[-1] else ctx.top.parent
    path = Path(name)
    path = (path if path.is_absolute() else base / path).resolve()
    if not _inside(path, ctx.roots):
        raise _refuse(f"{what} {show(name)} is outside the model's folder {ctx.top.parent} (and the package "
                      "folders given in package_paths): a xacro may read only those")
    ctx.files += count
    if ctx.files > MAX_FILES:
        raise _refuse(f"more than {MAX_FILES} files included or loaded (limit)")
    if not path.exists():
        if what == "include":                  # xacro's own error, which an optional="true" include skips
            raise FileNotFoundError(name)
        raise _refuse(f"{what} {show(name)}: no such file")
    if not path.is_file():
        raise _refuse(f"{what} {show(name)}: not a regular file")
    size = path.stat().st_size
    if size > MAX_FILE_BYTES:
        raise _refuse(f"{what} {show(name)}: file of {size:,} bytes, over the limit of {MAX_FILE_BYTES:,}")
    return path


def _read(path: Path, what: str) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise _refuse(f"{what} {path}: cannot read: {exc}") from None


def parse_xml_dom(text: str) -> Any:
    """A ``xml.dom.minidom`` document of ``text`` parsed by ``defusedxml``: a DTD (and so any entity) is
    refused (:class:`defusedxml.DefusedXmlException`)."""
    from defusedxml import minidom

    return minidom.parseString(text, forbid_dtd=True, forbid_entities=True, forbid_external=True)


def _parse_hook(inp: Any, filename: str | None = None) -> Any:
    """xacro's ``parse``: an included file, read only inside the allowed folders and parsed safely."""
    import xacro

    if inp is None:
        try:
            path = _allowed_file(filename, "include")
        except FileNotFoundError:
            raise _missing_include(filename) from None
        xacro.filestack[-1] = str(path)
        inp = _read(path, "include")
    if isinstance(inp, str):
        doc = _dom_or_refuse(inp, filename)
        _check_static_size(doc, filename)
        return doc
    raise _refuse("unexpected input to the xacro parser")


def _check_static_size(doc: Any, filename: str | None) -> None:
    """Refuse at once a document whose macros would expand to more than :data:`MAX_ELEMENTS` elements: each
    macro's size is its body's element count with every macro call in it counted at the callee's size (macros
    of files read before included; both branches of conditionals counted; a recursive call counted once, the
    running count catches the rest). Sizes saturate just above the limit, so ``2**40`` costs nothing."""
    sizes = _current.macro_sizes
    cap = MAX_ELEMENTS + 1
    bodies: dict[str, Any] = {}
    for node in doc.getElementsByTagName("xacro:macro"):
        name = node.getAttribute("name")
        bodies[name[6:] if name.startswith("xacro:") else name] = node
    busy: set[str] = set()

    def macro_size(name: str) -> int:
        if name in busy or (name not in bodies and name not in sizes):
            return 1                                   # recursive, or defined later: the running count
        if name not in sizes or name in bodies:
            busy.add(name)
            sizes[name] = min(cap, count(bodies[name]))
            busy.discard(name)
            bodies.pop(name)
        return sizes[name]

    def count(node: Any) -> int:
        total = 0
        for child in node.childNodes:
            if child.nodeType != child.ELEMENT_NODE or child.tagName == "xacro:macro":
                continue
            tag = child.tagName
            own = macro_size(tag[6:].rsplit(".", 1)[-1]) if tag.startswith("xacro:") and tag[6:] not in (
                "if", "unless", "include", "property", "arg", "insert_block", "element", "attribute") else 1
            total = min(cap, total + own + count(child))
        return total

    for name in list(bodies):
        if name in bodies:
            macro_size(name)
    if count(doc.documentElement) > MAX_ELEMENTS:
        where = f"include {filename}: " if filename else ""
        raise _refuse(f"{where}its macros expand to more than {MAX_ELEMENTS:,} XML elements (limit)")


def _dom_or_refuse(text: str, filename: str | None) -> Any:
    from xml.parsers.expat import ExpatError

    from defusedxml import DefusedXmlException

    prefix = f"include {filename}: " if filename else ""
    try:
        return parse_xml_dom(text)
    except DefusedXmlException:
        raise _refuse(f"{prefix}a DTD or entity declaration (<!DOCTYPE ...>, <!ENTITY ...>) is not allowed in a "
                      "robot description") from None
    except ExpatError as exc:
        raise _refuse(f"{prefix}invalid XML: {exc}") from None


def _include_files_hook(filename_spec: str, symbols: Any):
    """xacro's ``get_include_files``: the one file an include names (checked when it is parsed)."""
    import xacro

    name = str(xacro.eval_text(filename_spec, symbols))
    try:
        _allowed_file(name, "include", count=False)     # refuse before xacro does anything with it
    except FileNotFoundError:
        pass                                            # xacro's error when it is parsed (or skipped if optional)
    yield name if os.path.isabs(name) else os.path.join(os.path.dirname(xacro.filestack[-1] or "."), name)


def _missing_include(filename: str) -> Any:
    """xacro's error for an include that does not exist (an ``optional="true"`` include is skipped)."""
    import xacro

    xacro.filestack.pop()
    return xacro.XacroException(f"no such file: {filename}", exc=FileNotFoundError(filename))


def _load_yaml(filename: Any) -> Any:
    """``xacro.load_yaml``: a YAML file inside the allowed folders, read by uvms's safe YAML reader."""
    import xacro

    from uvms.safe_yaml import read_yaml

    if not isinstance(filename, str):
        raise _refuse("load_yaml(): expected a file name")
    path = _allowed_file(filename, "load_yaml")
    try:
        data = read_yaml(path)
    except UvmsInputError as exc:
        raise _refuse(f"load_yaml: {exc}") from None
    return xacro.YamlListWrapper.wrap(data)


def _arg(name: Any) -> Any:
    """``xacro.arg(name)``: the value of a ``<xacro:arg>``."""
    import xacro

    values = xacro.substitution_args_context.get("arg", {})
    if name not in values:
        raise _refuse(f"undefined xacro argument {show(name)}")
    return values[name]


def _fatal(*parts: Any) -> Any:
    raise _refuse("xacro.fatal: " + " ".join(map(str, parts)))


_XACRO_NAMESPACE = _Namespace({"load_yaml": _load_yaml, "arg": _arg, "fatal": _fatal})
_ROOT: dict[str, Any] = {**_MATH, **_BUILTINS, "True": True, "False": False, "load_yaml": _load_yaml,
                         "math": _Namespace(_MATH), "xacro": _XACRO_NAMESPACE, "python": _Namespace(_BUILTINS)}
_CALLABLE.update(id(f) for f in (*_MATH.values(), *_BUILTINS.values(), _load_yaml, _arg, _fatal) if callable(f))


def _safe_eval_hook(expr: str, globals: Any, locals: Any = None) -> Any:
    """xacro's ``safe_eval``: the whitelist interpreter instead of ``eval``."""
    try:
        return _evaluate(expr, globals)
    except _Refused as exc:
        if _current is not None and _current.refusal is None:
            _current.refusal = exc.args[0]
        raise


ROS_PACKAGE_SEARCH_DEPTH = 3
"""How many folder levels below each ``ROS_PACKAGE_PATH`` entry a package is looked for (as ``rospack`` crawls
a workspace's ``src``; bounded so that a broad entry such as ``/`` cannot make a look-up crawl a disk)."""
MAX_PACKAGE_SEARCH_FOLDERS = 10_000
"""Folders one ``$(find pkg)`` look-up visits at the most under ``ROS_PACKAGE_PATH``."""


def _package_name(folder: Path) -> str | None:
    """The ``<name>`` of the ROS ``package.xml`` in ``folder`` (``None`` without one, or when unreadable)."""
    manifest = folder / "package.xml"
    try:
        if not manifest.is_file() or manifest.stat().st_size > MAX_FILE_BYTES:
            return None
        from defusedxml import ElementTree

        element = ElementTree.fromstring(manifest.read_bytes()).find("name")
    except Exception:       # an unreadable or invalid manifest names no package
        return None
    return element.text.strip() if element is not None and element.text else None


def ros_package(name: str) -> Path | None:
    """The folder of ROS package ``name`` under the user's ``ROS_PACKAGE_PATH`` (``:``-separated folders,
    each a package or a folder holding packages up to :data:`ROS_PACKAGE_SEARCH_DEPTH` levels down; a package
    is a folder with a ``package.xml`` whose ``<name>`` is ``name``), or ``None``.

    The environment variable is the user's own setting, not the model file's: a package found through it is a
    folder the user named (``docs/models.md``, "What a xacro may do")."""
    visited = 0
    for entry in filter(None, os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep)):
        level = [Path(entry)]
        for _ in range(ROS_PACKAGE_SEARCH_DEPTH + 1):
            below = []
            for folder in level:
                visited += 1
                if visited > MAX_PACKAGE_SEARCH_FOLDERS:
                    return None
                if _package_name(folder) == name:
                    return folder.resolve()
                try:
                    below.extend(sorted(p for p in folder.iterdir() if p.is_dir() and not p.name.startswith(".")))
                except OSError:
                    continue
            level = below
    return None


def _nearby_package(name: str, top: Path) -> Path | None:
    """A folder named ``name`` (or holding the ``package.xml`` of ``name``) among the top-level file's parent
    folders (up to 4 levels up) and their sub-folders two levels down, looked at only to word the refusal
    (nothing is read from it); at most :data:`MAX_PACKAGE_SEARCH_FOLDERS` folders."""
    visited = 0
    for ancestor in [top.parent, *top.parent.parents][:5]:
        level = [ancestor]
        for _ in range(3):
            below = []
            for folder in level:
                visited += 1
                if visited > MAX_PACKAGE_SEARCH_FOLDERS:
                    return None
                if folder.name == name or _package_name(folder) == name:
                    return folder.resolve()
                try:
                    below.extend(sorted(p for p in folder.iterdir() if p.is_dir() and not p.name.startswith(".")))
                except OSError:
                    continue
            level = below
    return None


def _extension_hook(text: str) -> Any:
    """xacro's ``eval_extension``: ``$(arg)``, ``$(find)`` of a named package, ``$(dirname)``, ``$(eval)``,
    and ``$(env)`` / ``$(optenv)`` only when allowed."""
    import xacro

    ctx = _current
    body = text[2:-1].strip()
    command, _, rest = body.partition(" ")
    words = rest.split()
    if command == "arg" and len(words) == 1:
        return _arg(words[0])
    if command == "find" and len(words) == 1:
        folder = ctx.options.package_paths.get(words[0])
        if folder is None:
            folder = ros_package(words[0])
            if folder is None:
                hint = _nearby_package(words[0], ctx.top)
                seen = (f"; a folder {hint} is near the file: ROS_PACKAGE_PATH={hint.parent} or package_paths="
                        f"{{{words[0]!r}: {str(hint)!r}}}" if hint is not None else "")
                raise _refuse(f"$(find {words[0]}): package {words[0]!r} is not named; give its folder in "
                              "package_paths, or add the folder holding it to ROS_PACKAGE_PATH (a xacro may "
                              f"read only its own folder and the packages you name){seen}")
            ctx.roots = (*ctx.roots, folder)
        return str(Path(folder).resolve())
    if command in ("env", "optenv") and words:
        if not ctx.options.allow_environment:
            raise _refuse(f"$({command} {words[0]}) reads the environment variable {words[0]!r}; a xacro may "
                          "not unless you allow it (allow_environment: true)")
        if command == "env" and words[0] not in os.environ:
            raise _refuse(f"$(env {words[0]}): environment variable {words[0]!r} is not set")
        return os.environ.get(words[0], " ".join(words[1:]))
    if command == "dirname" and not words:
        return os.path.dirname(os.path.abspath(xacro.filestack[-1] or str(ctx.top)))
    if command == "eval":
        names = {k: xacro.Table._eval_literal(v) for k, v in xacro.substitution_args_context.get("arg", {}).items()}
        return str(_safe_eval_hook(rest, {**_ROOT, **names}))
    raise _refuse(f"the substitution {show(text)} is not allowed (arg, find of a named package, dirname, eval; "
                  "env and optenv with allow_environment)")


def _budget_hooks(xacro: Any) -> dict[str, Any]:
    """Wrappers of xacro's ``eval_all``, ``handle_macro_call`` and ``eval_text`` counting the elements, the
    macro depth and the text produced against the limits."""
    eval_all, handle_macro_call, eval_text = xacro.eval_all, xacro.handle_macro_call, xacro.eval_text

    def counted_eval_all(node, macros, symbols):
        ctx = _current
        ctx.elements += 1
        ctx.work += 1 + ctx.macro_depth
        if ctx.elements > MAX_ELEMENTS:
            raise _refuse(f"expands to more than {MAX_ELEMENTS:,} XML elements (limit)")
        if ctx.work > MAX_WORK:
            raise _refuse(f"expands to more than {MAX_WORK:,} element-levels (elements times the depth of the "
                          "macro calls they are expanded in; limit)")
        return eval_all(node, macros, symbols)

    def counted_macro_call(node, macros, symbols):
        ctx = _current
        ctx.macro_depth += 1
        try:
            if ctx.macro_depth > MAX_MACRO_DEPTH:
                raise _refuse(f"macro calls nested deeper than {MAX_MACRO_DEPTH} (limit)")
            return handle_macro_call(node, macros, symbols)
        finally:
            ctx.macro_depth -= 1

    def counted_eval_text(text, symbols):
        ctx = _current
        if isinstance(text, str) and len(text) > MAX_TEXT_CHARS and "$" in text:
            raise _refuse(f"a text with ${{...}} or $(...) longer than {MAX_TEXT_CHARS:,} characters (limit)")
        value = eval_text(text, symbols)
        if isinstance(value, str):
            if len(value) > MAX_STRING_CHARS:
                raise _refuse(f"a text longer than {MAX_STRING_CHARS:,} characters (limit)")
            ctx.output_chars += len(value)
            if ctx.output_chars > MAX_OUTPUT_CHARS:
                raise _refuse(f"expands to more than {MAX_OUTPUT_CHARS:,} characters of text (limit)")
        return value

    return {"eval_all": counted_eval_all, "handle_macro_call": counted_macro_call, "eval_text": counted_eval_text}


def _quiet_warning(*args: Any, **kwargs: Any) -> None:
    if _current is not None:
        _current.warnings.append(" ".join(" ".join(map(str, args)).split()))


def expand(path: str | os.PathLike[str], options: XacroOptions | None = None) -> str:
    """The URDF text of a xacro file, expanded under the rules of this module (see the module docstring).

    Raises:
        UvmsInputError: a refused construct, file, substitution or limit; an XML or xacro error (one line,
            naming ``path``).
    """
    global _current
    import xacro

    options = options or XacroOptions()
    top = Path(path).resolve()
    source = str(path)
    size = top.stat().st_size
    if size > MAX_FILE_BYTES:
        raise UvmsInputError(f"xacro file of {size:,} bytes, over the limit of {MAX_FILE_BYTES:,}", source)
    roots = (top.parent, *(Path(p).resolve() for p in options.package_paths.values()))
    hooks = {"safe_eval": _safe_eval_hook, "eval_extension": _extension_hook, "parse": _parse_hook,
             "get_include_files": _include_files_hook, "load_yaml": _load_yaml, "warning": _quiet_warning,
             "message": _quiet_warning, "print_location": lambda *a, **k: None, "_global_symbols": _ROOT,
             "verbosity": 0, "all_includes": []}
    with _LOCK:
        hooks.update(_budget_hooks(xacro))
        saved = {name: getattr(xacro, name) for name in hooks}
        saved_stacks = (xacro.filestack, xacro.macrostack, dict(xacro.substitution_args_context))
        _current = _Context(top=top, roots=roots, options=options)
        try:
            for name, value in hooks.items():
                setattr(xacro, name, value)
            xacro.init_stacks(str(top))
            text = _read(top, "xacro")
            doc = _dom_or_refuse(text, None)
            _check_static_size(doc, None)
            xacro.process_doc(doc, mappings={str(k): str(v) for k, v in options.args.items()})
            result = doc.toxml()
            if len(result) > MAX_OUTPUT_CHARS:
                raise _refuse(f"expands to more than {MAX_OUTPUT_CHARS:,} characters (limit)")
            ctx = _current
        except _Refused as exc:
            raise _as_input_error(_current.refusal or exc.args[0], source) from None
        except RecursionError:
            raise UvmsInputError("xacro nested too deeply (elements or macros)", source) from None
        except Exception as exc:   # xacro's own errors (XacroException, KeyError...) are problems of the file
            if _current.refusal is not None:
                raise _as_input_error(_current.refusal, source) from None
            raise UvmsInputError(f"cannot expand xacro: {_first_line(exc)}", source) from None
        finally:
            for name, value in saved.items():
                setattr(xacro, name, value)
            xacro.filestack, xacro.macrostack = saved_stacks[0], saved_stacks[1]
            xacro.substitution_args_context.clear()
            xacro.substitution_args_context.update(saved_stacks[2])
            _current = None
    if ctx.refusal is not None:       # refused somewhere xacro swallowed the exception
        raise _as_input_error(ctx.refusal, source)
    _warn_once(ctx.warnings, source)
    return result


def _as_input_error(error: UvmsInputError, source: str) -> UvmsInputError:
    return UvmsInputError(error.message, source, error.path)


def _first_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 300 else text[:297] + "..."


_NOISE = ("redefining global symbol", "is deprecated")


def _warn_once(messages: list[str], source: str) -> None:
    """At most one warning line for xacro's own warnings that matter (unknown attributes, ignored children)."""
    import warnings

    kept = [m for m in messages if m and not any(n in m for n in _NOISE)]
    if kept:
        more = f" (and {len(kept) - 1} more)" if len(kept) > 1 else ""
        warnings.warn(f"{source}: xacro: {kept[0]}{more}", stacklevel=3)
