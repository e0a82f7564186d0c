"""Where numba keeps the compiled kernels: a folder keyed by a fingerprint of uvms's own sources.

numba's ``cache=True`` checks only the timestamp of the file that defines a function, yet the compiled code
also contains every kernel it calls from other modules. Keying the cache folder on all of uvms's sources
(paths, sizes, modification times) means an edited helper never leaves a stale caller in the cache. A user's
own ``NUMBA_CACHE_DIR`` is respected.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path


def _fingerprint(package_dir: Path) -> str:
    h = hashlib.sha256()
    for path in sorted(package_dir.rglob("*.py")):
        st = path.stat()
        h.update(f"{path.relative_to(package_dir)}:{st.st_size}:{st.st_mtime_ns}\n".encode())
    return h.hexdigest()[:16]


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
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    if "numba" in sys.modules:
        from numba.core import config

        config.CACHE_DIR = str(folder)


configure()
