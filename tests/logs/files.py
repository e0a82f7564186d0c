"""Writing small log files for the tests: CSV streams and a description beside them."""

from __future__ import annotations

from pathlib import Path

import yaml


def write_csv(path: Path, header: list[str], rows) -> Path:
    """``rows`` (lists of numbers or strings) under ``header``, ``repr`` of floats (round-trip exact)."""
    lines = [",".join(header)] + [",".join(x if isinstance(x, str) else repr(float(x)) for x in row) for row in rows]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def write_log(folder: Path, description: dict, name: str = "log.yaml") -> Path:
    """The description as a YAML file in ``folder``."""
    path = folder / name
    path.write_text(yaml.safe_dump(description, sort_keys=False), encoding="utf-8")
    return path


POSE_XYZW = {"time": "t", "position": ["x", "y", "z"], "quaternion_xyzw": ["qx", "qy", "qz", "qw"]}
"""The pose keys of a file written with :data:`POSE_HEADER`."""

POSE_HEADER = ["t", "x", "y", "z", "qx", "qy", "qz", "qw"]


def pose_rows(times, positions, quaternions_xyzw):
    return [[t, *p, *q] for t, p, q in zip(times, positions, quaternions_xyzw)]
