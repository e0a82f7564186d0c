"""The repository is self-contained: no doc, comment or data file points to files outside it."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
OUTSIDE = re.compile(r"(?<![\w.])(shared/[\w./-]+|seed/[\w./-]+\.txt|design-review\.md|style\.md)")


def _tracked() -> list[Path]:
    try:
        out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")
    return [ROOT / line for line in out.splitlines()
            if line.endswith((".py", ".md", ".yaml", ".toml", ".txt", ".urdf", ".xacro", ".csv"))]


def test_nothing_points_outside_the_repository():
    offending = []
    for path in _tracked():
        if path == Path(__file__).resolve() or not path.is_file():
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
            if OUTSIDE.search(line):
                offending.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:80]}")
    assert not offending, "\n".join(offending)


# -- the shape of the middle floor (issue "One compiled plant": acceptance) ------------------------------------

SRC = ROOT / "src" / "uvms"


def _functions():
    import ast

    for path in sorted(SRC.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield path, node


def test_no_function_outside_the_compiled_kernels_takes_more_than_eight_parameters():
    """Options travel in groups (inputs, recording, integrator objects), not as long parameter lists; only
    ``@njit`` kernels (which numba cannot give objects) may take more."""
    import ast

    offending = []
    for path, node in _functions():
        if any("jit" in ast.unparse(d) for d in node.decorator_list):
            continue
        a = node.args
        names = [x.arg for x in a.posonlyargs + a.args]
        count = len(names) + len(a.kwonlyargs) + (a.vararg is not None) + (a.kwarg is not None)
        count -= bool(names) and names[0] in ("self", "cls")
        if count > 8:
            offending.append(f"{path.relative_to(ROOT)}:{node.lineno} {node.name} ({count})")
    assert not offending, offending


def test_simulate_is_a_short_loop():
    for path, node in _functions():
        if path.name == "run.py" and node.name == "simulate":
            assert node.end_lineno - node.lineno + 1 < 60
            return
    raise AssertionError("simulate not found")


def test_kernels_are_called_and_workspaces_built_only_by_the_plant_owner_and_the_simulation_core():
    """Outside ``dynamics/`` (the owner: :mod:`uvms.dynamics.plant`) and the simulation core (``sim/``), no module
    builds a workspace, imports a dynamics kernel or numba's dispatch internals."""
    pattern = re.compile(r"make_workspace|specialised|fastcall|from uvms\.dynamics\.(aba|rnea|crba|passes) import")
    offending = []
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC)
        if rel.parts[0] in ("dynamics", "sim"):
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if pattern.search(line):
                offending.append(f"{rel}:{number}: {line.strip()}")
    assert not offending, offending
