"""The Dask cluster a sweep runs on: a private local one, or an external scheduler reached with TLS.

A local cluster is started per sweep and is closed to everyone else (``docs/sweeps.md``, "Security"):

- every connection (client, scheduler, nannies, workers; all on 127.0.0.1) is TLS with mutual authentication,
  using a key and self-signed certificate made for this cluster alone and kept in memory
  (``distributed.security.Security.temporary``): a process without them cannot connect, so another account on
  the machine cannot submit code to the workers, which run it as the sweep's user;
- no HTTP server listens (no dashboard, no Prometheus or health routes): :mod:`uvms.sweep._private`'s scheduler and
  worker do not start one;
- a Ctrl-C at the terminal reaches the whole foreground process group: the event-loop thread of the client
  blocks SIGINT before it spawns anything, so the worker processes start with SIGINT blocked (a signal mask is
  inherited across fork and exec) and only the client's main thread reacts, even during start-up;
- distributed's loggers are silenced while the cluster starts and stops (a worker torn down mid-start is not
  an error worth 50 lines), in the worker processes from their first line (:func:`quiet_children`).

An external scheduler (``--scheduler``) is reached with the credentials given (``--tls-*`` files) or those of
the Dask configuration (``distributed.comm.tls.*``); plain TCP to a host other than this machine's loopback
interface is refused unless asked for (:func:`check_scheduler`).
"""

from __future__ import annotations

import ipaddress
import logging
import multiprocessing
import os
import re
import signal
import subprocess
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from uvms.errors import UvmsInputError


SECURE_PROTOCOLS = ("tls", "wss")
PROTOCOLS = ("tcp", "tls", "ws", "wss", "ucx")
ADDRESS = re.compile(r"(?:(?P<protocol>[a-z]+)://)?(?P<host>\[[0-9a-fA-F:.]+\]|[^\s/:\[\]]+):(?P<port>\d{1,5})")
"""A Dask scheduler address: ``[protocol://]host:port``, an IPv6 host in brackets."""

_LOGGERS = ("distributed", "tornado", "asyncio")


CHILD_LOGGING = "DASK_LOGGING__DISTRIBUTED"
"""The environment variable by which a worker process, when it imports distributed, takes its loggers' level
(dask's configuration from the environment): set while the local cluster starts its processes."""


@contextmanager
def quiet_children() -> Iterator[None]:
    """Worker processes started meanwhile log only critical messages from their first line on. A nanny's
    ``silence_logs`` reaches its worker process only once that process runs, and a Ctrl-C in between made a
    starting worker print distributed's INFO line about its closed connection under the one-line message."""
    old = os.environ.get(CHILD_LOGGING)
    os.environ[CHILD_LOGGING] = "critical"
    try:
        yield
    finally:
        if old is None:
            os.environ.pop(CHILD_LOGGING, None)
        else:
            os.environ[CHILD_LOGGING] = old


@contextmanager
def quiet_logs() -> Iterator[None]:
    """Silence distributed's, tornado's and asyncio's loggers (start-up and shutdown noise)."""
    loggers = [logging.getLogger(name) for name in _LOGGERS]
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for logger, level in zip(loggers, levels):
            logger.setLevel(level)


def close_quietly(close: Callable[..., Any], **kwargs: Any) -> None:
    """Shut something down, ignoring errors and the logging noise of a cluster going away."""
    with quiet_logs():
        try:
            close(**kwargs)
        except BaseException:  # noqa: BLE001 - a second Ctrl-C or a dead worker must not hide the first cause
            pass


def _loop_without_sigint():
    """A running Dask event-loop thread that blocks SIGINT, as does every thread and process it starts."""
    from distributed.utils import LoopRunner

    if hasattr(signal, "pthread_sigmask"):
        # multiprocessing's resource tracker, started on first use, unblocks SIGINT in the thread that starts it
        from multiprocessing import resource_tracker

        resource_tracker.ensure_running()
    runner = LoopRunner(asynchronous=False)
    main = threading.current_thread() is threading.main_thread() and hasattr(signal, "pthread_sigmask")
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT}) if main else None
    try:
        runner.start()
    finally:
        if old is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)  # a Ctrl-C that came meanwhile is raised here
    return runner


def process_threads(workers: int, threads: int = 1) -> list[int]:
    """Threads of each local worker process for ``workers`` threads in all, at most ``threads`` per process:
    ``ceil(workers / threads)`` processes, as even as can be (5 threads by 2: ``[2, 2, 1]``)."""
    processes = -(-workers // max(1, threads))
    return [workers // processes + (k < workers % processes) for k in range(processes)]


@contextmanager
def local_cluster(workers: int, *, threads: int = 1, preload: list[str] | None = None) -> Iterator[Any]:
    """A client on a new private local cluster (see the module docstring) of ``workers`` worker threads in
    processes of at most ``threads`` threads each (:func:`process_threads`), closed on the way out. A Ctrl-C
    while it starts raises ``KeyboardInterrupt`` after the parts already started are shut down. distributed's
    loggers are silent meanwhile: the sweep reports what matters (runs lost with a worker, no worker left)
    itself, in one line."""
    with quiet_logs(), _local_cluster(process_threads(workers, threads), preload) as client:
        yield client


@contextmanager
def _local_cluster(layout: list[int], preload: list[str] | None) -> Iterator[Any]:
    from distributed import Client, Nanny
    from distributed.deploy.spec import SpecCluster
    from distributed.system import MEMORY_LIMIT

    security = temporary_security()
    from uvms.sweep._private import PrivateScheduler, PrivateWorker

    scheduler = {"cls": PrivateScheduler, "options": {
        "host": "127.0.0.1", "port": 0, "protocol": "tls://", "security": security, "dashboard": False,
        "dashboard_address": None, "validate": False}}
    def worker_spec(nthreads: int) -> dict[str, Any]:
        return {"cls": Nanny, "options": {
            "host": "127.0.0.1", "protocol": "tls://", "security": security, "nthreads": nthreads,
            "worker_class": PrivateWorker, "dashboard": False, "dashboard_address": None,
            "silence_logs": logging.CRITICAL,
            "preload": list(preload or []), "memory_limit": max(1, MEMORY_LIMIT // len(layout))}}

    worker = worker_spec(layout[0])
    started: list[Any] = []

    class _Cluster(SpecCluster):
        async def _start(self):
            started.append(self)
            await super()._start()

    runner = None
    client = None
    before = {child.pid for child in multiprocessing.active_children()}
    try:
        with quiet_logs(), quiet_children():
            runner = _loop_without_sigint()
            cluster = _Cluster(scheduler=scheduler, workers={k: worker_spec(t) for k, t in enumerate(layout)},
                               worker=worker,
                               loop=runner.loop, security=security, silence_logs=logging.CRITICAL,
                               name="uvms-sweep")
            # made in two steps so that a Ctrl-C inside its __init__ still leaves it here to close (a half-started
            # client collected at exit waited 60 s for the stopped loop)
            client = Client.__new__(Client)
            client.__init__(cluster, security=security, set_as_default=False)
        yield client
    finally:
        with _sigint_blocked():  # a second Ctrl-C must not cut the shutdown short (it is raised afterwards)
            if runner is not None:  # the tasks of a start cut short report their errors when collected: drop them
                runner.loop.asyncio_loop.set_exception_handler(lambda loop, context: None)
            if client is not None:
                close_quietly(client.close, timeout=10)
            for each in started:
                close_quietly(each.close, timeout=20)
                # a start cut short leaves the cluster "closing" for ever: forget it, or distributed's exit
                # handler waits 10 s for it
                SpecCluster._instances.discard(each)
            clean = client is not None and all(str(each.status) == "Status.closed" for each in started)
            if runner is not None:
                close_quietly(runner.stop)
            if client is not None:
                # set once its loop has stopped (a start still running there could set it back to "connecting",
                # seen in CI): when collected it must not wait for the stopped loop again
                client.status = "closed"
            _kill_new_children(before, settle=0.0 if clean else 1.0)


def _kill_new_children(before: set[int], settle: float = 1.0, limit: float = 10.0) -> None:
    """Kill the worker processes of an interrupted start that outlived the shutdown: child processes not in
    ``before``, including one a nanny was still spawning (watched until none appears for ``settle`` s)."""
    end = time.monotonic() + limit
    quiet_since = time.monotonic()
    while True:
        new = [child for child in multiprocessing.active_children() if child.pid not in before]
        for child in new:
            close_quietly(child.kill)
            close_quietly(child.join, timeout=5)
        if new:
            quiet_since = time.monotonic()
        if time.monotonic() >= end or time.monotonic() - quiet_since >= settle:
            return
        time.sleep(0.05)


@contextmanager
def _sigint_blocked() -> Iterator[None]:
    """Hold a Ctrl-C back while the cluster shuts down; raise it (``KeyboardInterrupt``) afterwards."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda number, frame: caught.append(number))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught:
        raise KeyboardInterrupt


def temporary_security():
    """TLS credentials for one private cluster, in memory only: a new 2048-bit RSA key and a self-signed
    certificate that is its own authority, used by every role (client, scheduler, workers).

    Made by ``distributed.security.Security.temporary`` (the Python package ``cryptography``), else by the
    ``openssl`` command through a pipe (the key never touches the disk).

    Raises:
        UvmsInputError: neither is available (one line).
    """
    from distributed.security import Security

    try:
        return Security.temporary()
    except ImportError:
        pass
    try:
        made = subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "30", "-subj",
                               "/CN=dask-internal", "-addext", "subjectAltName=DNS:dask-internal", "-addext",
                               "basicConstraints=critical,CA:TRUE", "-keyout", "-", "-out", "-"],
                              capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL)
        pem = made.stdout
        key = pem[pem.index("-----BEGIN PRIVATE KEY-----"):pem.index("-----END PRIVATE KEY-----") + 25] + "\n"
        cert = pem[pem.index("-----BEGIN CERTIFICATE-----"):pem.index("-----END CERTIFICATE-----") + 25] + "\n"
    except (OSError, ValueError, subprocess.SubprocessError):
        raise UvmsInputError("the private local cluster needs the Python package 'cryptography' or the 'openssl' "
                             "command to make its TLS credentials: install one (pip install cryptography), or use "
                             "--scheduler", path="--workers") from None
    return Security(require_encryption=True, tls_ca_file=cert, tls_client_key=key, tls_client_cert=cert,
                    tls_scheduler_key=key, tls_scheduler_cert=cert, tls_worker_key=key, tls_worker_cert=cert)


def security_from_files(ca_file: str | None, cert: str | None, key: str | None):
    """``distributed.security.Security`` for a client from PEM files (``--tls-ca-file``, ``--tls-cert``,
    ``--tls-key``), or ``None`` when none is given (then the Dask configuration's ``distributed.comm.tls.*``
    apply). The certificate and key go together; each file must exist."""
    given = {"--tls-ca-file": ca_file, "--tls-cert": cert, "--tls-key": key}
    if all(v is None for v in given.values()):
        return None
    for option, value in given.items():
        if value is not None and not Path(value).is_file():
            raise UvmsInputError("no such file", show_path(value), option)
    if (cert is None) != (key is None):
        raise UvmsInputError("expected --tls-cert and --tls-key together (the client's certificate and its key)",
                             path="--tls-key" if key is None else "--tls-cert")
    from distributed.security import Security

    return Security(tls_ca_file=ca_file, tls_client_cert=cert, tls_client_key=key, require_encryption=True)


def show_path(path: Any, limit: int = 200) -> str:
    """A path for a message, cut to ``limit`` characters."""
    text = " ".join(str(path).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def is_loopback(host: str) -> bool:
    """Whether ``host`` (a name or an address, IPv6 in brackets) is this machine's loopback interface."""
    host = host.strip("[]")
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def check_scheduler(address: str, *, secured: bool, insecure: bool = False) -> str | None:
    """Check an external scheduler address; return a warning (one line) or ``None``. Plain TCP to the loopback
    interface passes (a scheduler the user started on this machine); to another machine it needs ``insecure``.

    Args:
        address: ``[protocol://]host:port``.
        secured: whether TLS credentials were given (``--tls-*`` files).
        insecure: accept plain TCP to another machine (``--insecure``).

    Raises:
        UvmsInputError: a malformed address or unknown protocol; credentials with a plain protocol; plain TCP
            to a host other than the loopback interface without ``insecure``.
    """
    match = ADDRESS.fullmatch(address)
    if match is None:
        raise UvmsInputError("expected a Dask scheduler address such as tls://10.0.0.5:8786", show_path(address),
                             "--scheduler")
    protocol = match["protocol"] or "tcp"
    if protocol not in PROTOCOLS:
        raise UvmsInputError(f"unknown protocol {protocol!r}; expected one of: {', '.join(PROTOCOLS)}",
                             show_path(address), "--scheduler")
    if protocol in SECURE_PROTOCOLS:
        return None
    if secured:
        raise UvmsInputError(f"TLS credentials were given but the address is {protocol}://; use tls://",
                             show_path(address), "--scheduler")
    if is_loopback(match["host"]):
        return None  # the user's own scheduler on this machine: docs/sweeps.md says why tls:// is still better
    if not insecure:
        raise UvmsInputError(f"plain {protocol}:// to another machine has no authentication and no encryption: "
                             "anyone who reaches the scheduler runs code on its workers; use tls:// with "
                             "--tls-ca-file/--tls-cert/--tls-key (or pass --insecure on a trusted network)",
                             show_path(address), "--scheduler")
    return (f"--scheduler {address}: plain {protocol.upper()} without authentication or encryption (--insecure)")


@contextmanager
def external_client(address: str, security=None, *, connect_timeout: float = 20.0,
                    worker_wait: float = 120.0) -> Iterator[Any]:
    """A client on the scheduler at ``address`` (waiting up to ``connect_timeout`` seconds for it) with at
    least one worker (waiting up to ``worker_wait`` seconds), closed on the way out; distributed's loggers
    are silent meanwhile."""
    with quiet_logs(), _external_client(address, security, connect_timeout, worker_wait) as client:
        yield client


@contextmanager
def _external_client(address: str, security, connect_timeout: float, worker_wait: float) -> Iterator[Any]:
    from distributed import Client

    try:
        with quiet_logs():
            client = Client(address, timeout=connect_timeout, set_as_default=False,
                            **({"security": security} if security is not None else {}))
    except (OSError, TimeoutError, ValueError, TypeError) as exc:
        raise UvmsInputError(f"cannot connect to the Dask scheduler: {show_path(' '.join(str(exc).split()))}",
                             show_path(address), "--scheduler") from None
    try:
        try:
            client.wait_for_workers(1, timeout=worker_wait)
        except (TimeoutError, OSError):
            raise UvmsInputError(f"the Dask scheduler has no workers (waited {worker_wait:g} s)", address,
                                 "--scheduler") from None
        yield client
    finally:
        close_quietly(client.close, timeout=10)
