"""Where numba keeps the compiled kernels: a folder keyed by a fingerprint of uvms's own sources.

numba's ``cache=True`` checks only the timestamp of the file that defines a function, yet the compiled code
also contains every kernel it calls from other modules. Keying the cache folder on the contents of every uvms
module that uses numba means an edited helper never leaves a stale caller in the cache. A user's
own ``NUMBA_CACHE_DIR`` is respected when it can be written. Whatever cannot be written, a command still runs
(:func:`configure`): a temporary folder, else no cache at all; numba never raises "cannot cache function".

Two more things make a first run fast (``docs/conventions.md``, "The first run"):

- **Kernels compiled at install.** ``pip install`` runs :mod:`uvms.precompile` (the build backend in
  ``build_backend/``), which compiles every kernel into the package's ``_kernels/numba-<fingerprint>`` folder.
  :func:`configure` copies that folder into an empty cache folder of the same fingerprint, so a first command
  loads compiled code instead of compiling it (a copy of a few MB, well under a second).
- **A cache that moves with the package.** numba names a function's cache subfolder after the absolute path of
  its source file; :class:`PackageLocator` names it after the path inside the ``uvms`` package instead, so
  kernels compiled where the package was built serve wherever it is installed (numba still checks each source
  file's contents, its own version and the CPU, and compiles again when any differs).
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import sys
from pathlib import Path

from uvms import _compile_watch
from uvms._compile_watch import FIRST_COMPILE_MINUTES


def _fingerprint(package_dir: Path) -> str:
    """Hash of the modules that hold compiled kernels (those importing numba or the kernels' decorators of
    :mod:`uvms.jit`): editing a controller or the CLI does not invalidate the compiled dynamics."""
    h = hashlib.sha256()
    for path in sorted(package_dir.rglob("*.py")):
        text = path.read_bytes()
        if b"numba" in text or b"uvms.jit" in text:
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


def _writable(folder: Path) -> str | None:
    """``None`` when files can be created in ``folder`` (creating it if needed), else the reason why not.

    A real probe, not ``os.access``: a read-only file system refuses even root."""
    import tempfile

    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".probe-")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        return exc.strerror or str(exc)
    return None


def _temporary_folder() -> Path:
    """A private folder for this process's compiled kernels, removed at exit (no cache kept between runs)."""
    import atexit
    import shutil
    import tempfile

    folder = Path(tempfile.mkdtemp(prefix="uvms-numba-"))
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    return folder


PACKAGE_DIR = Path(__file__).resolve().parent
"""The installed ``uvms`` package (the root of :class:`PackageLocator`'s relative paths)."""
PREBUILT_DIR = PACKAGE_DIR / "_kernels"
"""Where ``pip install`` leaves the kernels it compiled (:mod:`uvms.precompile`), one folder per fingerprint."""
SEEDED_MARK = ".uvms-seeded"
"""A file in a cache folder that was filled from :data:`PREBUILT_DIR` (so it is copied once)."""
SEED_LOCK = ".uvms-seed.lock"
"""The lock file of a cache folder that :func:`seed` holds while it copies (an exclusive ``flock``)."""
LOCATOR = "uvms._cache.PackageLocator"
"""numba's name of :class:`PackageLocator` (``NUMBA_CACHE_LOCATOR_CLASSES``, numba >= 0.61)."""
NUMBA_LOCATORS = ("UserProvidedCacheLocator", "InTreeCacheLocator", "UserWideCacheLocator", "IPythonCacheLocator",
                  "ZipCacheLocator")
"""numba's own locators, tried after :class:`PackageLocator` (numba's default order)."""


def fingerprint() -> str:
    """The fingerprint of the installed kernels' sources (the cache folder's suffix)."""
    return _fingerprint(PACKAGE_DIR)


def _package_locator():
    """:class:`PackageLocator`, built on first use so that ``import uvms`` does not import numba."""
    from numba.core import config
    from numba.core.caching import UserProvidedCacheLocator

    class PackageLocator(UserProvidedCacheLocator):
        """numba's user-folder locator with the cache subfolder named by the source file's folder *inside*
        the ``uvms`` package (``<cache>/uvms/dynamics/...``) rather than by its absolute path; functions
        outside the package are left to numba's own locators."""

        def __init__(self, py_func, py_file):
            super().__init__(py_func, py_file)
            inside = Path(py_file).resolve().parent.relative_to(PACKAGE_DIR)
            self._cache_path = os.path.join(config.CACHE_DIR, "uvms", *inside.parts)

        @classmethod
        def from_function(cls, py_func, py_file):
            try:
                Path(py_file).resolve().relative_to(PACKAGE_DIR)
            except (ValueError, OSError):
                return None
            watch_compiles()
            return super().from_function(py_func, py_file)

    return PackageLocator


def __getattr__(name: str):
    if name == "PackageLocator":          # numba imports it by name (NUMBA_CACHE_LOCATOR_CLASSES)
        global PackageLocator
        PackageLocator = _package_locator()
        return PackageLocator
    raise AttributeError(name)


def _use_package_locator() -> None:
    """Put :class:`PackageLocator` first in numba's locators, unless the user chose locators of their own."""
    if os.environ.get("NUMBA_CACHE_LOCATOR_CLASSES"):
        return
    os.environ["NUMBA_CACHE_LOCATOR_CLASSES"] = ",".join((LOCATOR, *NUMBA_LOCATORS))
    if "numba" in sys.modules:
        from numba.core import config

        config.CACHE_LOCATOR_CLASSES = os.environ["NUMBA_CACHE_LOCATOR_CLASSES"]
        watch_compiles()


def seed(folder: Path, prebuilt: Path | None = None) -> bool:
    """Fill an empty cache ``folder`` with the kernels compiled at install (``_kernels/numba-<fingerprint>``)
    once; returns whether it copied anything. A folder that already holds compiled kernels is left as it is
    (numba replaces what is stale), and nothing is copied when ``UVMS_NO_PREBUILT`` is set (to measure a
    compile from nothing).

    Processes that start at once on an empty cache (a sweep's workers, the test suite's parallel workers) take
    turns through the folder's :data:`SEED_LOCK`: one copies, the others wait for its :data:`SEEDED_MARK` and
    copy nothing, so none of them reads a kernel file that another is still writing."""
    import shutil

    prebuilt = prebuilt or PREBUILT_DIR / f"numba-{fingerprint()}"
    if os.environ.get("UVMS_NO_PREBUILT") or not prebuilt.is_dir() or (folder / SEEDED_MARK).exists():
        return False
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with _locked(folder / SEED_LOCK):
            if (folder / SEEDED_MARK).exists():
                return False          # another process seeded it while this one waited
            shutil.copytree(prebuilt, folder, dirs_exist_ok=True)
            (folder / SEEDED_MARK).write_text(str(prebuilt) + "\n")
    except OSError:
        return False          # a partly copied folder is a partial cache: numba compiles what is missing
    return True


FIRST_COMPILE_NOTICE = ("uvms: compiling the numerical kernels for this machine (first run only, about {minutes}; "
                        "later runs start in about a second)")
"""What the CLI says once when the compiled kernels are not cached yet (instead of a progress bar at 0)."""



def compiled_before(kernel: str = "compiled_loop.advance_loop") -> bool:
    """Whether numba's cache holds ``kernel`` (``module.function``) already: its index file exists in the cache
    folder. ``True`` when the folder is unknown (nothing sensible to say)."""
    folder = os.environ.get("NUMBA_CACHE_DIR")
    if not folder:
        return True
    try:
        return any(Path(folder).rglob(f"{kernel}-*.nbi"))
    except OSError:
        return True


_announce = None
"""Where :func:`announce_compile` says it (set by the CLI: stderr); ``None``: say nothing (library use)."""


def set_compile_notice(write) -> None:
    """Let :func:`announce_compile` call ``write(text)`` (once per process), and the compile watch say its
    progress lines through ``write`` (``None``: through the ``uvms.compile`` logger)."""
    global _announce
    _announce = _compile_watch.writer = write


def watch_compiles() -> None:
    """Say what compiles while it compiles (:mod:`uvms._compile_watch`; numba is imported by then)."""
    _compile_watch.install()


def announce_compile() -> bool:
    """Just before the first compiled run of the process (its inputs checked): if the kernels are not cached
    yet, say :data:`FIRST_COMPILE_NOTICE` through the function given to :func:`set_compile_notice`, once.
    Returns whether it was said."""
    global _announce
    write, _announce = _announce, None
    if write is None or compiled_before():
        return False
    write(FIRST_COMPILE_NOTICE.format(minutes=FIRST_COMPILE_MINUTES))
    _compile_watch.notice_said = True
    return True


@contextlib.contextmanager
def _locked(lock_file: Path):
    """Hold an exclusive ``flock`` of ``lock_file`` (created if needed) for the duration; hold nothing when it
    cannot be opened or on a system without ``fcntl``."""
    try:
        import fcntl
    except ImportError:                  # pragma: no cover - not POSIX
        fcntl = None
    handle = None
    if fcntl is not None:
        try:
            handle = open(lock_file, "a")
        except OSError:
            handle = None
    if handle is None:
        yield
        return
    with handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


@contextlib.contextmanager
def compile_lock():
    """Hold the cache folder's lock file (``.uvms-compile.lock``, an exclusive ``flock``) for the duration: the
    processes of one machine that may compile the same kernels (a sweep's workers warming up) take turns, so
    the first compiles and the others load what it cached. Without a cache folder, or on a system without
    ``fcntl``, it holds nothing."""
    folder = os.environ.get("NUMBA_CACHE_DIR")
    if not folder:
        yield
        return
    with _locked(Path(folder) / ".uvms-compile.lock"):
        yield


def compile_without_cache() -> None:
    """Let every ``cache=True`` kernel compile without a cache when numba finds no folder to cache it in.

    numba raises ``RuntimeError: cannot cache function ...`` when neither ``NUMBA_CACHE_DIR``, nor the folder
    next to the sources (an installed package's folder is often read-only), nor its user-wide folder can be
    written; uvms then compiles in memory instead, for this process only (numba's ``NullCache``)."""
    from numba.core import dispatcher
    from numba.core.caching import NullCache

    original = dispatcher.Dispatcher.enable_caching
    if getattr(original, "uvms_guarded", False):
        return

    def enable_caching(self) -> None:
        try:
            original(self)
        except RuntimeError:          # "cannot cache function ...: no locator available"
            self._cache = NullCache()

    enable_caching.uvms_guarded = True    # type: ignore[attr-defined]
    dispatcher.Dispatcher.enable_caching = enable_caching


def _use(folder: Path) -> None:
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    if "numba" in sys.modules:
        from numba.core import config

        config.CACHE_DIR = str(folder)


def configure() -> None:
    """Point numba's cache at ``<cache home>/uvms/numba-<fingerprint>`` unless the user chose a folder
    (``NUMBA_CACHE_DIR``).

    When that folder (the user's one included) cannot be written (a read-only home, a service account), the
    kernels are compiled into a temporary folder for this process only, with one warning line on stderr: every
    command still works, it just compiles again next time. When no temporary folder can be made either, the
    kernels are compiled without any cache (:func:`compile_without_cache`), again with one warning line: numba's
    own default, next to the installed sources, is never relied on.
    """
    _use_package_locator()
    user = os.environ.get("NUMBA_CACHE_DIR")
    if user:
        reason = _writable(Path(user))
        if reason is None:
            seed(Path(user))
            return
        where = f"NUMBA_CACHE_DIR={user}"
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "uvms"
        folder = base / f"numba-{fingerprint()}"
        reason = _writable(folder)
        if reason is None:
            _prune(base, keep=folder)
            seed(folder)
            _use(folder)
            return
        where = str(base)
    try:
        folder = _temporary_folder()
    except OSError as exc:
        compile_without_cache()
        sys.stderr.write(f"uvms: warning: cannot write the compiled-kernel cache {where} ({reason}) nor a "
                         f"temporary folder ({exc.strerror or exc}); compiling without a cache (set "
                         "NUMBA_CACHE_DIR to a writable folder to keep the compiled kernels)\n")
        return
    sys.stderr.write(f"uvms: warning: cannot write the compiled-kernel cache {where}"
                     f" ({reason}); compiling for this run only (set NUMBA_CACHE_DIR to a writable folder "
                     "to keep the compiled kernels)\n")
    seed(folder)
    _use(folder)


configure()
