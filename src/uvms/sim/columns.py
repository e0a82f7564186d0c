"""The names of a result's joint columns (``result.csv``, :meth:`uvms.sim.result.Result.columns`, the named
metrics of :mod:`uvms.sim.metrics`, :mod:`uvms.plots`): the one place that makes and reads them.

A joint's columns carry the model's joint name and the unit of its coordinate::

    q_<joint>_rad    qd_<joint>_rad_s    tau_<joint>_Nm        revolute joint [rad, rad/s, N m]
    q_<joint>_m      qd_<joint>_m_s      tau_<joint>_N         prismatic joint [m, m/s, N]

e.g. ``q_axis_d_rad`` for the Alpha 5's joint ``axis_d``, ``q_joint1_rad`` for the paper model's first joint.
They cannot be taken for the vehicle's columns: those have no ``q_``/``qd_``/``tau_`` prefix (the pitch rate is
``q_rad_s``, which ends in ``_s`` and names no joint). A joint name is written as it is when it is made of
letters, digits and ``_ . + -`` (every URDF and bundled name so far); any other character becomes ``_``, and
names that then coincide get their joint number appended (``_2``), so every column is distinct and the CSV
header needs no quoting.

Files written before this scheme name the joints by number (``q1_rad``, ``qd1_rad_s``, ``tau1_Nm``, joint order):
:func:`table_joints` still reads them, and the metrics accept those names as aliases of the first, second, ...
joint (``docs/scenarios.md``).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from typing import NamedTuple

_PLAIN = re.compile(r"[A-Za-z0-9_.+-]+")
UNITS = {"revolute": ("rad", "rad_s", "Nm"), "prismatic": ("m", "m_s", "N")}
"""Column units of ``q``, ``qd`` and ``tau`` per joint type."""
_Q_COLUMN = re.compile(r"q_(.+)_(rad|m)")
_LEGACY = re.compile(r"(q|qd|tau)(\d+)_(rad|rad_s|Nm)")
_LEGACY_UNIT = {"q": "rad", "qd": "rad_s", "tau": "Nm"}


class JointColumns(NamedTuple):
    """The three column names of every joint, in joint order."""

    q: tuple[str, ...]
    qd: tuple[str, ...]
    tau: tuple[str, ...]

    def all(self) -> tuple[str, ...]:
        return self.q + self.qd + self.tau


def default_joint_names(n: int) -> tuple[str, ...]:
    """``joint1 ... jointN``: the names :class:`uvms.Model` gives joints that have none."""
    return tuple(f"joint{j + 1}" for j in range(n))


def joint_tokens(joint_names: Sequence[str]) -> tuple[str, ...]:
    """The joint names as they appear in column names (module docstring), distinct."""
    tokens = [name if _PLAIN.fullmatch(name) else re.sub(r"[^A-Za-z0-9_.+-]", "_", name) or "_"
              for name in map(str, joint_names)]
    repeated = {t for t in tokens if tokens.count(t) > 1}
    taken = {t for t in tokens if t not in repeated}     # names kept as they are
    out: list[str] = []
    for j, token in enumerate(tokens):
        if token in repeated:
            token = f"{token}_{j + 1}"
            while token in taken:                 # a made-up name never takes another joint's own name
                token = f"{token}_{j + 1}"
            taken.add(token)
        out.append(token)
    return tuple(out)


def joint_columns(joint_names: Sequence[str], joint_types: Sequence[str] | None = None) -> JointColumns:
    """The ``q``, ``qd`` and ``tau`` column names of joints ``joint_names`` (types default revolute)."""
    types = tuple(joint_types) if joint_types is not None else ("revolute",) * len(joint_names)
    q, qd, tau = [], [], []
    for token, kind in zip(joint_tokens(joint_names), types):
        u_q, u_qd, u_tau = UNITS["prismatic" if kind == "prismatic" else "revolute"]
        q.append(f"q_{token}_{u_q}")
        qd.append(f"qd_{token}_{u_qd}")
        tau.append(f"tau_{token}_{u_tau}")
    return JointColumns(tuple(q), tuple(qd), tuple(tau))


def legacy_joint_columns(n: int) -> JointColumns:
    """The numbered names of files written before the joint names were used (``q1_rad`` ...)."""
    return JointColumns(tuple(f"q{j + 1}_rad" for j in range(n)), tuple(f"qd{j + 1}_rad_s" for j in range(n)),
                        tuple(f"tau{j + 1}_Nm" for j in range(n)))


def table_joints(columns: Iterable[str]) -> tuple[tuple[str, ...], JointColumns]:
    """The joints of a saved table from its column names, as ``(joint tokens, their columns)`` in joint order:
    the named scheme (every ``q_<joint>_rad`` or ``q_<joint>_m`` column, in the table's order, with the
    matching ``qd_`` and ``tau_`` names), else the numbered one of older files (tokens ``joint1`` ...)."""
    columns = list(columns)
    tokens, types = [], []
    for c in columns:
        match = _Q_COLUMN.fullmatch(c)
        if match:
            tokens.append(match[1])
            types.append("prismatic" if match[2] == "m" else "revolute")
    if tokens:
        q, qd, tau = [], [], []
        for token, kind in zip(tokens, types):
            u_q, u_qd, u_tau = UNITS[kind]
            q.append(f"q_{token}_{u_q}")
            qd.append(f"qd_{token}_{u_qd}")
            tau.append(f"tau_{token}_{u_tau}")
        return tuple(tokens), JointColumns(tuple(q), tuple(qd), tuple(tau))
    n = sum(1 for c in columns if re.fullmatch(r"q\d+_rad", c))
    return default_joint_names(n), legacy_joint_columns(n)


def legacy_alias(name: str, n_joints: int) -> tuple[str, int] | None:
    """``("q" | "qd" | "tau", joint index)`` for a numbered name of an older file (``q2_rad``), else ``None``."""
    match = _LEGACY.fullmatch(name)
    if match and _LEGACY_UNIT[match[1]] == match[3] and 1 <= int(match[2]) <= n_joints:
        return match[1], int(match[2]) - 1
    return None
