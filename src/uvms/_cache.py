"""Where numba keeps the compiled kernels: a folder keyed by a fingerprint of uvms's own sources.

numba's ``cache=True`` checks only the timestamp of the file that defines a function, yet the compiled code
also contains every kernel it calls from other modules. Keying the cache folder on the contents of every uvms
module that uses numba means an edited helper never leaves a stale caller in the cache. A user's
own ``NUMBA_CACHE_DIR`` is respected.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path


def _fingerprint(package_dir: Path) -> str:
    """Hash of the modules that hold compiled kernels (those importing numba): editing a controller or the
    CLI does not invalidate the compiled dynamics."""
    h = hashlib.sha256()
    for path in sorted(package_dir.rglob("*.py")):
        text = path.read_bytes()
        if b"numba" in text:
            h.update(str(path.relative_to(package_dir)).encode() + b"\0" + text)
    return h.hexdigest()[:16]


def _prune(base: Path, keep: Path, max_age_s: float = 7 * 86400.0) -> None:
    """Remove cache folders of other source versions unused for a week."""
    import shutil
    import time

    now = time.time()
    for other in base.glob("numba-*"):
        try:
            if other != keep and now - other.stat().st_mtime > max_age_s:
                shutil.rmtree(other, ignore_errors=True)
        except OSError:
            pass


def configure() -> None:
    """Point numba's cache at ``<cache home>/uvms/numba-<fingerprint>`` unless the user chose a folder."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "uvms"
    folder = base / f"numba-{_fingerprint(Path(__file__).parent)}"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return
    _prune(base, keep=folder)
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    if "numba" in sys.modules:
        from numba.core import config

        config.CACHE_DIR = str(folder)


configure()
