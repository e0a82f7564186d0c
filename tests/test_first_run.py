"""The first run on a fresh machine (``uvms._cache``, ``uvms._compile_watch``, ``uvms.precompile``): kernels
compiled at install are found wherever the package is, a compile at first use says so and never goes silent
for long, and the workers of one machine take turns to compile."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

import uvms
from uvms import _cache, _compile_watch

PACKAGE = Path(uvms.__file__).parent

COUNT_COMPILES = textwrap.dedent("""
    import sys
    from numba.core import event
    compiled = []
    class Count(event.Listener):
        def on_start(self, ev): compiled.append(ev.data["dispatcher"].py_func.__qualname__)
        def on_end(self, ev): pass
    event.register("numba:compile", Count())
    import numpy as np
    import uvms
    from uvms.rotations import euler_zyx
    assert uvms.__file__.startswith(sys.argv[1]), uvms.__file__
    euler_zyx(np.eye(3))
    print("compiled", len(compiled))
""")


def _python(code: str, *args: str, path: Path | None = None, cache: Path, **env: str):
    environment = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_LOCATOR_CLASSES",)}
    environment.update(NUMBA_CACHE_DIR=str(cache), **env)
    if path is not None:
        environment["PYTHONPATH"] = str(path)
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, env=environment,
                          timeout=600)


def _copy_package(to: Path) -> Path:
    shutil.copytree(PACKAGE, to / "uvms", ignore=shutil.ignore_patterns("__pycache__", "_kernels"))
    return to


def test_kernels_compiled_in_one_place_load_in_another(tmp_path):
    """numba names cache folders after the sources' absolute path; uvms's locator after the path inside the
    package, so a cache made by one copy of the package (the build's) serves another (the installed one)."""
    cache = tmp_path / "cache"
    first = _copy_package(tmp_path / "built")
    second = _copy_package(tmp_path / "installed")
    made = _python(COUNT_COMPILES, str(first), path=first, cache=cache)
    assert made.returncode == 0, made.stderr
    assert "compiled 1" in made.stdout
    assert list((cache / "uvms").glob("rotations.euler_zyx-*.nbi"))       # relative to the package
    used = _python(COUNT_COMPILES, str(second), path=second, cache=cache)
    assert used.returncode == 0, used.stderr
    assert "compiled 0" in used.stdout                                    # loaded, not compiled
    (second / "uvms" / "rotations.py").write_text((second / "uvms" / "rotations.py").read_text() + "\n# edited\n")
    edited = _python(COUNT_COMPILES, str(second), path=second, cache=cache)
    assert "compiled 1" in edited.stdout                                  # numba still checks the source


def test_a_cold_first_call_from_python_says_so_once_and_a_warm_one_says_nothing(tmp_path):
    code = "import numpy as np\nfrom uvms.rotations import euler_zyx\neuler_zyx(np.eye(3))\neuler_zyx(np.eye(3))\n"
    cold = _python(code, cache=tmp_path / "cache", UVMS_NO_PREBUILT="1")    # as if pip had compiled nothing
    assert cold.returncode == 0, cold.stderr
    lines = cold.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("uvms: compiling uvms.rotations.euler_zyx"), cold.stderr
    assert "first use only" in lines[0] and "minutes" in lines[0]
    warm = _python(code, cache=tmp_path / "cache", UVMS_NO_PREBUILT="1")
    assert warm.returncode == 0 and warm.stderr == ""


def test_a_long_compile_says_how_it_goes_every_few_seconds(monkeypatch):
    said: list[str] = []
    monkeypatch.setattr(_compile_watch, "writer", said.append)
    watch = _compile_watch.CompileWatch(heartbeat_s=0.05)
    watch.noticed = True                      # the notice is tested above; here the progress lines
    watch.begin("uvms.sim.compiled_loop.advance_loop")
    watch.begin("uvms.dynamics.aba.aba")      # nested: its callee
    time.sleep(0.2)
    watch.end()
    time.sleep(0.12)
    watch.end()
    time.sleep(0.1)                           # no line after the end
    progress = [line for line in said if line.startswith("uvms: still compiling")]
    assert len(progress) >= 3, said
    assert "now uvms.dynamics.aba.aba" in progress[0] and "1 kernels done" in progress[-1]
    assert said[-1].startswith("uvms: compiled 2 kernels in")
    count = len(said)
    time.sleep(0.15)
    assert len(said) == count
    assert not [t for t in threading.enumerate() if t.name == "uvms-compile-progress" and t.is_alive()]


def test_a_short_compile_says_only_the_notice(monkeypatch):
    said: list[str] = []
    monkeypatch.setattr(_compile_watch, "writer", said.append)
    monkeypatch.setattr(_compile_watch, "notice_said", False)
    watch = _compile_watch.CompileWatch(heartbeat_s=5.0)
    watch.begin("uvms.rotations.euler_zyx")
    watch.end()
    watch.begin("uvms.rotations.euler_zyx")
    watch.end()
    assert len(said) == 1 and said[0].startswith("uvms: compiling uvms.rotations.euler_zyx")


def test_the_prebuilt_kernels_are_copied_into_an_empty_cache_once(tmp_path, monkeypatch):
    prebuilt = tmp_path / "prebuilt"
    (prebuilt / "uvms" / "sim").mkdir(parents=True)
    (prebuilt / "uvms" / "sim" / "compiled_loop.advance_loop-1.py311.nbi").write_bytes(b"index")
    folder = tmp_path / "cache"
    monkeypatch.delenv("UVMS_NO_PREBUILT", raising=False)
    assert _cache.seed(folder, prebuilt) is True
    assert (folder / "uvms" / "sim" / "compiled_loop.advance_loop-1.py311.nbi").read_bytes() == b"index"
    (folder / "uvms" / "sim" / "compiled_loop.advance_loop-1.py311.nbi").write_bytes(b"newer")   # numba's own
    assert _cache.seed(folder, prebuilt) is False                                  # once
    assert (folder / "uvms" / "sim" / "compiled_loop.advance_loop-1.py311.nbi").read_bytes() == b"newer"
    monkeypatch.setenv("UVMS_NO_PREBUILT", "1")
    assert _cache.seed(tmp_path / "other", prebuilt) is False
    assert _cache.seed(tmp_path / "none", tmp_path / "missing") is False


def test_the_workers_of_one_machine_take_turns_to_compile(tmp_path):
    code = textwrap.dedent("""
        import sys, time
        from uvms import _cache
        with _cache.compile_lock():
            start = time.time(); time.sleep(0.4); end = time.time()
        print(start, end)
    """)
    env = {k: v for k, v in os.environ.items()}
    env["NUMBA_CACHE_DIR"] = str(tmp_path)
    processes = [subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, env=env)
                 for _ in range(3)]
    spans = sorted(tuple(map(float, p.communicate(timeout=120)[0].split())) for p in processes)
    assert len(spans) == 3
    for (_, end), (start, _) in zip(spans, spans[1:]):
        assert start >= end - 1e-3                    # one at a time


def test_a_sweep_worker_warms_up_under_the_lock(monkeypatch):
    from uvms.sweep import execute

    held = []

    class Lock:
        def __enter__(self):
            held.append("in")

        def __exit__(self, *exc):
            held.append("out")

    monkeypatch.setattr(_cache, "compile_lock", Lock)
    monkeypatch.setattr(execute, "run_batch", lambda tasks: held.append(len(tasks)) or tasks)
    assert execute.warm_up([{"data": {"controller": {"period": 0.01}, "step": 0.001}}]) == 1
    assert held == ["in", 1, "out"]


@pytest.mark.slow
def test_precompiled_kernels_serve_a_fresh_cache_without_compiling(tmp_path):
    """What ``pip install`` does, end to end on one workload: ``uvms.precompile --into`` compiles the Healey
    thruster curve into a package-style ``_kernels`` folder; a fresh process with an empty cache, seeded from
    it, draws the same curve without compiling anything."""
    kernels = tmp_path / "_kernels"
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    made = subprocess.run([sys.executable, "-m", "uvms.precompile", "--into", str(kernels), "--only", "thrusters"],
                          capture_output=True, text=True, env={**env, "NUMBA_CACHE_DIR":
                                                               str(kernels / f"numba-{_cache.fingerprint()}"),
                                                               "UVMS_NO_PREBUILT": "1"}, timeout=900)
    assert made.returncode == 0 and "thrusters:" in made.stdout, made.stdout + made.stderr
    prebuilt = kernels / f"numba-{_cache.fingerprint()}"
    assert list(prebuilt.rglob("*.nbi"))
    code = textwrap.dedent(f"""
        import os
        from pathlib import Path
        from uvms import _cache
        os.environ.pop("UVMS_NO_PREBUILT")
        assert _cache.seed(Path({str(tmp_path / 'fresh')!r}), Path({str(prebuilt)!r}))
        from numba.core import event
        compiled = []
        class Count(event.Listener):
            def on_start(self, ev): compiled.append(ev.data["dispatcher"].py_func.__qualname__)
            def on_end(self, ev): pass
        event.register("numba:compile", Count())
        from uvms.precompile import run
        assert run(["thrusters"]) == 0
        print("compiled", compiled)
    """)
    fresh = _python(code, cache=tmp_path / "fresh", UVMS_NO_PREBUILT="1")
    assert fresh.returncode == 0, fresh.stderr
    assert "compiled []" in fresh.stdout, fresh.stdout
