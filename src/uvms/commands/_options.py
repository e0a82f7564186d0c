"""Options shared by several subcommands, parsed in one place.

``--q`` (``uvms show``, ``uvms validate``, ``uvms trim``): the arm's joint values [rad or m], given either as
numbers in the model's joint order (``--q 0 -1.57 0``) or as ``NAME=VALUE`` with the model's joint names
(``--q axis_d=0.4 axis_c=0.4``, the joints not named at zero). One form per command line: mixing them is one
:class:`~uvms.errors.UvmsInputError` line, as are a malformed item, a joint named twice, an unknown joint name
(the message lists the model's joints), a count of numbers other than the model's joint count, and a value that
is not finite.
"""

from __future__ import annotations

import argparse

Q_OPTION = "--q"
"""The option's name, used as the ``where`` of every error it raises."""


def add_q_argument(parser: argparse.ArgumentParser, default_help: str = "all zero") -> None:
    """Register ``--q`` on ``parser``: strings, repeated options adding up (``--q a=1 --q b=2``)."""
    parser.add_argument(Q_OPTION, metavar="Q", nargs="+", action="extend", default=None,
                        help="joint values [rad or m]: numbers in the model's joint order (--q 0 -1.57 0), or "
                             f"NAME=VALUE by joint name, the others zero (--q axis_d=0.4); default: {default_help}. "
                             "Give it after the model")


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def split_q_items(items: list[str] | None) -> list[float] | dict[str, float] | None:
    """The ``--q`` strings as numbers in joint order (a list) or ``{joint name: value}`` (a dict), ``None``
    when not given; no model needed (the names and the count are checked by :func:`q_option`)."""
    from uvms.errors import UvmsInputError, show

    if items is None:
        return None
    numbers: list[float] = []
    named: dict[str, float] = {}
    first: dict[str, str] = {}          # the first item of each form, for the message when they are mixed
    for item in items:
        number = _number(item)
        if number is not None:
            numbers.append(number)
            first.setdefault("number", item)
            continue
        name, sep, text = item.partition("=")
        value = _number(text) if sep and name else None
        if value is None:
            raise UvmsInputError("expected NAME=VALUE (a joint name and a number) or numbers in joint order, "
                                 f"found {show(item)}", None, Q_OPTION)
        if name in named:
            raise UvmsInputError(f"joint {show(name)} is given twice", None, Q_OPTION)
        named[name] = value
        first.setdefault("named", item)
    if numbers and named:
        raise UvmsInputError("give every joint value as a number (in joint order) or every one as NAME=VALUE, not "
                             f"both; found {show(first['number'])} and {show(first['named'])}", None, Q_OPTION)
    return named if named else numbers


def q_option(model, items: list[str] | None):
    """``--q`` for ``model`` as (n,) finite floats in ``model.joint_names`` order, or ``None`` when not given.

    Raises:
        UvmsInputError: one line naming ``--q`` (module docstring).
    """
    from uvms.analysis.trim import joint_values
    from uvms.errors import UvmsInputError

    values = split_q_items(items)
    if values is None:
        return None
    try:
        return joint_values(model, values)
    except UvmsInputError as exc:
        raise UvmsInputError(exc.message, None, Q_OPTION) from None
