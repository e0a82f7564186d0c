"""The compiled-kernel cache folder (``uvms._cache``): every command works when it cannot be written."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from uvms import _cache


def test_an_unwritable_cache_falls_back_to_a_temporary_folder_with_one_warning(tmp_path, monkeypatch, capsys):
    from numba.core import config

    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker / "cache"))       # a read-only home behaves the same
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setattr(config, "CACHE_DIR", config.CACHE_DIR)
    _cache.configure()
    folder = Path(os.environ["NUMBA_CACHE_DIR"])
    assert folder.is_dir() and folder.name.startswith("uvms-numba-") and config.CACHE_DIR == str(folder)
    assert _cache._writable(folder) is None
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("uvms: warning: cannot write the compiled-kernel cache")


def test_a_writable_cache_home_is_used_silently(tmp_path, monkeypatch, capsys):
    from numba.core import config

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setattr(config, "CACHE_DIR", config.CACHE_DIR)
    _cache.configure()
    assert Path(os.environ["NUMBA_CACHE_DIR"]).parent == tmp_path / "uvms"
    assert capsys.readouterr().err == ""


def test_a_command_runs_with_an_unwritable_cache(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(blocker / "cache")
    proc = subprocess.run([sys.executable, "-m", "uvms", "validate", "paper"], capture_output=True, text=True,
                          env=env, timeout=120)
    assert proc.returncode == 0 and "net buoyancy" in proc.stdout
    assert proc.stderr.count("uvms: warning:") == 1 and "Traceback" not in proc.stderr


def test_the_first_compile_notice_is_said_once_and_only_on_a_cold_cache(tmp_path, monkeypatch):
    """With no compiled loop in numba's cache the notice is said once (through the CLI's writer); once the
    loop's index file exists, or without a writer (library use), nothing is said."""
    from uvms import _cache

    said = []
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    _cache.set_compile_notice(None)                                 # (a CLI test of this process may have set one)
    assert _cache.announce_compile() is False                      # no writer set: library use
    _cache.set_compile_notice(said.append)
    assert _cache.announce_compile() is True and _cache.announce_compile() is False
    assert len(said) == 1 and "first run only" in said[0] and "\n" not in said[0]
    index = tmp_path / "uvms_sim_somewhere" / "compiled_loop.advance_loop-123.py311.nbi"
    index.parent.mkdir()
    index.write_bytes(b"")
    _cache.set_compile_notice(said.append)
    assert _cache.announce_compile() is False and len(said) == 1
    _cache.set_compile_notice(None)


def test_the_cli_says_it_before_a_run_but_not_for_bad_input(tmp_path, monkeypatch, capsys):
    from uvms import cli

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert cli.main(["run", "no-such-scenario"]) == 2
    assert "first run only" not in capsys.readouterr().err
    assert cli.main(["run", "paper_case2_released", "-o", str(tmp_path / "out")]) == 0   # numba keeps its cache
    assert capsys.readouterr().err.startswith("uvms: compiling the numerical kernels")


def test_a_local_sweep_says_it_before_starting_its_workers(tmp_path, monkeypatch, capsys):
    """The local workers compile into this machine's cache, so ``uvms sweep`` says the notice (a cold cache is
    simulated: the workers' real cache is warm); with an external scheduler the workers' caches are elsewhere
    and nothing is said."""
    from tests.sweep.helpers import write_sweep
    from uvms import cli
    from uvms.sweep import execute

    monkeypatch.setattr(_cache, "compiled_before", lambda kernel="": False)
    path = write_sweep(tmp_path)
    assert cli.main(["sweep", str(path), "-o", str(tmp_path / "out"), "--workers", "1"]) == 0
    err = capsys.readouterr().err
    assert err.startswith("uvms: compiling the numerical kernels") and err.count("first run only") == 1, err
    monkeypatch.setattr(execute, "CONNECT_TIMEOUT", 1.0)
    assert cli.main(["sweep", str(path), "-o", str(tmp_path / "other"), "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err
    assert "first run only" not in err and "cannot connect to the Dask scheduler" in err, err


def test_an_unwritable_numba_cache_dir_of_the_user_falls_back_too(tmp_path, monkeypatch, capsys):
    """A user's own ``NUMBA_CACHE_DIR`` that cannot be written is not handed to numba (which would then try the
    folder next to the installed sources, and raise ``cannot cache function``)."""
    from numba.core import config

    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(blocker / "numba"))
    monkeypatch.setattr(config, "CACHE_DIR", config.CACHE_DIR)
    _cache.configure()
    folder = Path(os.environ["NUMBA_CACHE_DIR"])
    assert folder.name.startswith("uvms-numba-") and _cache._writable(folder) is None
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"NUMBA_CACHE_DIR={blocker / 'numba'}" in err


def test_no_writable_folder_at_all_compiles_without_a_cache(tmp_path, monkeypatch, capsys):
    """Neither the cache home nor a temporary folder can be written (and, simulated, no folder numba could
    cache in): ``cache=True`` kernels still compile and run, with one warning line."""
    import numba
    from numba.core import caching, config, dispatcher

    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker / "cache"))
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setattr(config, "CACHE_DIR", config.CACHE_DIR)
    monkeypatch.setattr(dispatcher.Dispatcher, "enable_caching", dispatcher.Dispatcher.enable_caching)

    def no_temporary_folder():
        raise FileNotFoundError(2, "No usable temporary directory found")

    monkeypatch.setattr(_cache, "_temporary_folder", no_temporary_folder)
    monkeypatch.setattr(caching.CacheImpl, "_locator_classes", [])      # numba finds nowhere to cache
    _cache.configure()
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "compiling without a cache" in err and "nor a temporary folder" in err
    module = tmp_path / "kernel_mod.py"
    module.write_text("def twice(x):\n    return 2 * x\n")
    import importlib.util

    spec = importlib.util.spec_from_file_location("kernel_mod", module)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert numba.njit(cache=True)(mod.twice)(21) == 42                # without the fix: RuntimeError
