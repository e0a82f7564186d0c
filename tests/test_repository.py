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
        if any(word in ast.unparse(d) for d in node.decorator_list for word in ("jit", "kernel", "block")):
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


# -- the floors (docs/architecture.md; issue "Make the floors real") -------------------------------------------

FLOORS = (
    ("math", ("uvms.spatial", "uvms.rotations")),
    ("ground", ("uvms.jit", "uvms.state", "uvms.errors", "uvms.checks", "uvms._cache", "uvms.output", "uvms.safe_json",
                "uvms.safe_yaml", "uvms.schema_base", "uvms.bundled", "uvms._compile_watch", "uvms.frames", "uvms.input_paths", "uvms.lookup", "uvms")),
    ("physics", ("uvms.hydro", "uvms.thrusters", "uvms.kinematics", "uvms.sensors")),
    ("model", ("uvms.model",)),
    ("dynamics", ("uvms.dynamics",)),
    ("control", ("uvms.control",)),
    ("analysis", ("uvms.analysis",)),
    ("sim", ("uvms.sim", "uvms.logs", "uvms.ros")),
    ("presentation", ("uvms.plots", "uvms.view")),
    ("experiments", ("uvms.reproduce", "uvms.control.compare", "uvms.sweep", "uvms.paper_figures", "uvms.identify",
                     "uvms.replays")),
    ("face", ("uvms.commands", "uvms.cli", "uvms.__main__", "uvms.gym", "uvms.interop", "uvms.precompile")),
)
"""The floors, lowest first: a module may import its own floor and those below it, never one above. ``math``
(spatial algebra and rotations, importing nothing of uvms) is the part of Physics the ground floor's ``State``
uses; Model sits beside Physics (it builds hydrodynamic and thruster parameters), below Dynamics. A package
covers its modules, except the package ``uvms`` itself, on the ground floor for ``uvms.__version__``: it imports
only ``_cache``, and its public names (the face of the Python API) load on first use, by ``importlib``. A new
module outside every package listed here needs a floor (the test says so)."""

KNOWN_UPWARD = {
    ("uvms.sim.result", "uvms.plots"): "Result.plot(), a documented convenience of a saved run (docs/python.md); "
                                       "the figure code lives in uvms.plots, a lazy import",
    ("uvms.sim.result", "uvms.view"): "Result.animate(), a documented convenience of a saved run "
                                      "(docs/viewing.md); the replay code lives in uvms.view, a lazy import",
}
"""Imports that still go up a floor, each with its reason (out of the issue's first part)."""

KNOWN_CYCLES = {
    ("uvms.sim.result", "uvms.plots"): KNOWN_UPWARD[("uvms.sim.result", "uvms.plots")],
    ("uvms.sim.result", "uvms.view"): KNOWN_UPWARD[("uvms.sim.result", "uvms.view")],
}
"""Import edges that close a cycle, each with its reason: without them the module graph has no cycle. (A
module's import of its own package, ``uvms.view.animate`` of ``uvms.view``, is no edge: Python imports a
package before its modules anyway.)"""


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _uvms_imports() -> dict[str, set[str]]:
    """``{module: modules of uvms it imports}``, top-level and inside functions alike (``from package import
    name`` counts as the submodule ``package.name`` when that is a module)."""
    import ast

    modules = {_module_name(p): p for p in SRC.rglob("*.py")}
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets = graph.setdefault(name, set())
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                targets.update(a.name for a in node.names if a.name.split(".")[0] == "uvms")
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = package.split(".")[:len(package.split(".")) - node.level + 1]
                    base = ".".join(up + ([node.module] if node.module else []))
                if base.split(".")[0] != "uvms":
                    continue
                subs = {f"{base}.{a.name}" for a in node.names} & modules.keys()
                targets.update(subs or {base})
                if len(subs) < len(node.names):
                    targets.add(base)
        targets.discard(name)
    return graph


def _floor(module: str) -> int:
    best, rank = -1, None
    for i, (_, prefixes) in enumerate(FLOORS):
        for prefix in prefixes:
            covers = module == prefix or prefix != "uvms" and module.startswith(prefix + ".")
            if covers and len(prefix) > best:
                best, rank = len(prefix), i
    assert rank is not None, f"{module} is on no floor: add it to FLOORS (and to docs/architecture.md)"
    return rank


def test_no_module_imports_a_floor_above_its_own():
    """Physics never imports Dynamics, Sim or Control; Control never imports Sim; Model never imports Sim,
    Control, Dynamics or Analysis; Dynamics never imports Control; the ground floor imports only the math."""
    offending = []
    for module, targets in sorted(_uvms_imports().items()):
        for target in sorted(targets):
            if _floor(target) > _floor(module) and (module, target) not in KNOWN_UPWARD:
                offending.append(f"{module} ({FLOORS[_floor(module)][0]}) imports {target} "
                                 f"({FLOORS[_floor(target)][0]})")
    assert not offending, "\n".join(offending)


def test_the_floors_rules_catch_an_upward_import():
    """The rules the floor map encodes (a wrong map would make the test above pass vacuously)."""
    below = {a: b for a, b in [("uvms.hydro.drag", "uvms.dynamics.aba"), ("uvms.kinematics", "uvms.dynamics.plant"),
                               ("uvms.thrusters.command", "uvms.control.kernels"), ("uvms.hydro.shapes", "uvms.sim.run"),
                               ("uvms.control.imu", "uvms.sim.plan"), ("uvms.model.build", "uvms.dynamics.api"),
                               ("uvms.model.urdf", "uvms.control.smc"), ("uvms.model.load", "uvms.sim.run"),
                               ("uvms.model.report", "uvms.analysis.trim"), ("uvms.dynamics.api", "uvms.control.smc"),
                               ("uvms.checks", "uvms.model.model"), ("uvms.jit", "uvms.dynamics.aba"),
                               ("uvms.state", "uvms.sim.integrate"), ("uvms.analysis.trim", "uvms.sim.run")]}
    for low, high in below.items():
        assert _floor(low) < _floor(high), (low, high)
    for low, high in [("uvms.analysis.trim", "uvms.control.smc"), ("uvms.sim.run", "uvms.analysis.trim"),
                      ("uvms.dynamics.api", "uvms.model.model"), ("uvms.state", "uvms.rotations"),
                      ("uvms.reproduce", "uvms.sim.run"), ("uvms.commands.run", "uvms.reproduce")]:
        assert _floor(low) >= _floor(high), (low, high)
    with pytest.raises(AssertionError, match="on no floor"):
        _floor("uvms.a_new_module")


def test_the_import_graph_has_no_cycle_but_the_known_ones():
    """Top-level and lazy imports together: a cycle means two modules cannot be understood (or moved) apart."""
    graph = {m: {t for t in ts if (m, t) not in KNOWN_CYCLES and not m.startswith(t + ".")}
             for m, ts in _uvms_imports().items()}
    state: dict[str, int] = {}
    cycles = []

    def visit(module: str, path: list[str]) -> None:
        state[module] = 1
        path.append(module)
        for target in sorted(graph.get(module, ())):
            if state.get(target) == 1:
                cycles.append(" -> ".join(path[path.index(target):] + [target]))
            elif target not in state:
                visit(target, path)
        path.pop()
        state[module] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module, [])
    assert not cycles, "\n".join(cycles)


def test_the_known_exceptions_are_still_imports():
    """An exception whose import is gone is deleted from the lists (they only shrink). (An exception naming a
    module that does not exist, one of a move under way, is not checked.)"""
    graph = _uvms_imports()
    stale = [pair for pair in list(KNOWN_UPWARD) + list(KNOWN_CYCLES)
             if pair[0] in graph and pair[1] in graph and pair[1] not in graph[pair[0]]]
    assert not stale, stale


def test_every_module_compiling_with_the_ground_floors_decorators_keys_the_kernel_cache(tmp_path):
    """numba's cache checks only the timestamp of a function's own file: an edit of any module that compiles
    with :mod:`uvms.jit` must change the cache folder's fingerprint (:func:`uvms._cache._fingerprint`)."""
    compiled = sorted(m for m, targets in _uvms_imports().items() if "uvms.jit" in targets)
    assert len(compiled) > 20 and "uvms.hydro.buoyancy" in compiled
    files = {_module_name(p): p for p in SRC.rglob("*.py")}
    assert not _edits_that_keep_the_fingerprint(tmp_path, {m: files[m] for m in compiled})


def _edits_that_keep_the_fingerprint(tmp_path, modules: dict) -> list[str]:
    """The modules (name -> source path) whose edit, in a copy of the package, leaves the kernel cache's
    fingerprint (:func:`uvms._cache._fingerprint`) as it was."""
    import shutil

    from uvms._cache import _fingerprint

    package = tmp_path / "uvms"
    shutil.copytree(SRC, package, ignore=shutil.ignore_patterns("__pycache__"))
    before = _fingerprint(package)
    unchanged = []
    for module in sorted(modules):
        path = package / modules[module].relative_to(SRC)
        text = path.read_text()
        path.write_text(text + "\n# edited\n")
        if _fingerprint(package) == before:
            unchanged.append(module)
        path.write_text(text)
    return unchanged


STATE_OFFSETS = re.compile(r"\[\s*:?,?\s*(?:3:7|7:13|13:|0:3\]\s*,\s*\w+\[3:7)|\b13 \+ (?:2 \* )?n\b|- 13 - 2 \*")


def test_the_state_vectors_offsets_are_named_only_in_uvms_state():
    """The state vector's layout has one owner (:mod:`uvms.state`: ``POSITION, QUATERNION, NU, JOINTS`` and
    :class:`~uvms.state.StateLayout`); no other module slices it by literal offsets."""
    offending = []
    for path in sorted(SRC.rglob("*.py")):
        if path == SRC / "state.py":
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if STATE_OFFSETS.search(line):
                offending.append(f"{path.relative_to(SRC)}:{number}: {line.strip()}")
    assert not offending, "\n".join(offending)
    assert STATE_OFFSETS.search("    nu = x[7:13]") and STATE_OFFSETS.search("q = x[13:13 + n]")
    assert STATE_OFFSETS.search("y[3:7] /= norm") and STATE_OFFSETS.search("n_act = K - 13 - 2 * n")


def test_every_module_whose_constants_a_kernel_reads_keys_the_kernel_cache(tmp_path):
    """numba freezes a global constant into the compiled code: a module whose upper-case constants are read
    inside a compiled function (``@kernel``, ``@block``, ``@njit``) of another module must change the cache
    folder's fingerprint when edited (the state offsets of :mod:`uvms.state`, the columns of
    :mod:`uvms.dynamics.kernel_model` ...)."""
    import ast

    files = {_module_name(p): p for p in SRC.rglob("*.py")}
    read = set()
    for path in files.values():
        tree = ast.parse(path.read_text())
        constants = {a.asname or a.name: node.module for node in tree.body if isinstance(node, ast.ImportFrom)
                     and node.module in files for a in node.names if a.name.isupper()}
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and any(word in ast.unparse(d) for d in node.decorator_list
                                                         for word in ("jit", "kernel", "block", "allocating")):
                read.update(constants[n.id] for n in ast.walk(node) if isinstance(n, ast.Name) and n.id in constants)
    assert {"uvms.state", "uvms.dynamics.kernel_model", "uvms.kinematics"} <= read
    assert not _edits_that_keep_the_fingerprint(tmp_path, {m: files[m] for m in read})
