"""uvms's build backend: setuptools', plus the numerical kernels compiled while the package is built.

numba compiles uvms's kernels at their first call, 2-3 minutes on a 2-core machine for a first run. This
backend runs ``python -m uvms.precompile --into src/uvms/_kernels`` (a short run of every kind of workload, see
:mod:`uvms.precompile`) before setuptools builds the wheel or the editable install, so the compiled kernels ship
with the package and a first command loads them (``uvms._cache.seed``). It needs numba and the model readers in
the build environment (``[build-system] requires`` in ``pyproject.toml``).

The compile never fails a build: if it cannot run, the install goes on without prebuilt kernels and they compile
at first use, as without this step. ``UVMS_NO_PRECOMPILE=1`` skips it (a quick development install).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

from setuptools import build_meta as _setuptools
from setuptools.build_meta import *  # noqa: F401,F403  (every other hook is setuptools' own)

SOURCES = Path(__file__).resolve().parent.parent / "src"
KERNELS = SOURCES / "uvms" / "_kernels"
TIMEOUT_S = 3600.0


def _say(text: str) -> None:
    print(f"uvms build: {text}", file=sys.stderr, flush=True)


def precompile() -> None:
    """Compile the kernels into ``src/uvms/_kernels`` (module docstring); never raises."""
    if os.environ.get("UVMS_NO_PRECOMPILE"):
        _say("UVMS_NO_PRECOMPILE is set: the kernels compile at first use instead")
        return
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, (str(SOURCES), env.get("PYTHONPATH"))))
    env.pop("NUMBA_CACHE_DIR", None)
    start = time.perf_counter()
    _say("compiling the numerical kernels for this machine (a few minutes, once: later runs load them)")
    try:
        done = subprocess.run([sys.executable, "-m", "uvms.precompile", "--into", str(KERNELS)], env=env,
                              timeout=TIMEOUT_S, check=False)
        code = done.returncode
    except (OSError, subprocess.SubprocessError) as exc:
        _say(f"could not compile the kernels ({exc}); they compile at first use instead")
        return
    if code:
        _say(f"compiling the kernels stopped (exit {code}); what is missing compiles at first use")
    else:
        _say(f"kernels compiled in {time.perf_counter() - start:.0f} s")


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    precompile()
    return _setuptools.build_wheel(wheel_directory, config_settings, metadata_directory)


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    precompile()
    return _setuptools.build_editable(wheel_directory, config_settings, metadata_directory)
