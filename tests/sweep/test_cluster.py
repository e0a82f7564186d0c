"""The sweep's Dask cluster: private (TLS with its own in-memory credentials, refused to anyone without them,
no HTTP port), its workers deaf to the terminal's Ctrl-C from birth, a Ctrl-C during start-up one line, and the
checks on an external scheduler's address and credentials."""

from __future__ import annotations

import os
import signal
import sys
import time
from pathlib import Path

import psutil
import pytest

from tests.sweep.helpers import BIN, alive_in_group, scheduler_address, start, stop_group, wait_for, write_sweep
from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.sweep.cluster import check_scheduler, local_cluster, security_from_files


def _mark(path: str) -> str:
    """What a hostile client would run: leave a file behind."""
    Path(path).write_text("ran")
    return "ran"


@pytest.fixture(scope="module")
def cluster():
    with local_cluster(2) as client:
        yield client


def _listening(pids: list[int]) -> set[tuple[int, int]]:
    found = set()
    for pid in pids:
        for conn in psutil.Process(pid).net_connections(kind="inet"):
            if conn.status == psutil.CONN_LISTEN:
                found.add((pid, conn.laddr.port))
    return found


def _cluster_pids() -> list[int]:
    me = psutil.Process()
    return [me.pid, *(child.pid for child in me.children(recursive=True))]


def _comm_ports(client) -> set[int]:
    info = client.scheduler_info(n_workers=-1)
    addresses = [client.scheduler.address, *info["workers"],
                 *(w["nanny"] for w in info["workers"].values() if w.get("nanny"))]
    return {int(a.rsplit(":", 1)[1]) for a in addresses}


def test_every_address_is_tls_on_loopback(cluster):
    info = cluster.scheduler_info(n_workers=-1)
    addresses = [cluster.scheduler.address, *info["workers"], *(w["nanny"] for w in info["workers"].values())]
    assert len(info["workers"]) == 2
    assert all(a.startswith("tls://127.0.0.1:") for a in addresses), addresses


@pytest.mark.parametrize("how", ["tcp", "tls without credentials", "tls with another cluster's credentials"])
@pytest.mark.parametrize("target", ["scheduler", "worker", "nanny"])
def test_a_client_without_the_credentials_cannot_connect_or_run_anything(cluster, tmp_path, how, target):
    from distributed import Client
    from distributed.security import Security

    info = cluster.scheduler_info(n_workers=-1)
    worker, details = next(iter(info["workers"].items()))
    address = {"scheduler": cluster.scheduler.address, "worker": worker, "nanny": details["nanny"]}[target]
    kwargs = {}
    if how == "tcp":
        address = address.replace("tls://", "tcp://")
    elif how == "tls with another cluster's credentials":
        kwargs["security"] = Security.temporary()
    marker = tmp_path / "hostile"
    if target == "scheduler":
        with pytest.raises(Exception) as caught:  # noqa: PT011 - OSError, TypeError or a comm error: any refusal
            intruder = Client(address, timeout=3, set_as_default=False, **kwargs)
            try:
                intruder.submit(_mark, str(marker)).result(timeout=5)
            finally:
                intruder.close()
        assert not isinstance(caught.value, AssertionError)
    else:  # a worker's or nanny's own port: its "run" handler executes the function it is sent
        from distributed.core import rpc
        from distributed.protocol import pickle

        async def attempt(where: str, connection_args: dict) -> None:
            async with rpc(where, connection_args=connection_args, timeout=3) as remote:
                await remote.run(function=pickle.dumps(_mark), args=pickle.dumps((str(marker),)))

        bad = kwargs["security"].get_connection_args("client") if "security" in kwargs else {}
        with pytest.raises(Exception):  # noqa: B017, PT011 - any refusal
            cluster.sync(attempt, address, bad)
        assert not marker.exists()
        control = {"scheduler": cluster.scheduler.address, "worker": worker, "nanny": details["nanny"]}[target]
        cluster.sync(attempt, control, cluster.cluster.security.get_connection_args("client"))
        assert marker.exists()  # the same call with the cluster's credentials does run: the refusal was theirs
        marker.unlink()
    assert not marker.exists()
    assert cluster.submit(len, [1, 2]).result(timeout=30) == 2  # the cluster itself still works


def test_a_client_with_the_credentials_can(cluster, tmp_path):
    """The control of the refusals above: a new client holding the cluster's credentials connects and runs."""
    from distributed import Client

    marker = tmp_path / "owner"
    # the new client shares the running IO loop (no second loop thread to start in this busy process)
    with Client(cluster.scheduler.address, security=cluster.cluster.security, timeout=30, loop=cluster.loop,
                set_as_default=False) as owner:
        assert owner.submit(_mark, str(marker), pure=False).result(timeout=60) == "ran"
    assert marker.exists()


def test_no_http_or_dashboard_port_is_open(cluster):
    scheduler = cluster.cluster.scheduler  # in this process
    assert scheduler.http_server is None and "dashboard" not in scheduler.services
    http = cluster.run(lambda dask_worker: getattr(dask_worker, "http_server", "missing"))
    assert set(http.values()) == {None}
    listening = _listening(_cluster_pids())
    assert listening, "expected the TLS comm ports at least"
    assert {port for _, port in listening} <= _comm_ports(cluster), listening  # nothing but the comm ports


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_workers_start_with_sigint_blocked(cluster):
    def sigint_blocked_at_start() -> bool:
        status = Path("/proc/self/status").read_text()
        blocked = int(next(line for line in status.splitlines() if line.startswith("SigBlk:")).split()[1], 16)
        return bool(blocked & (1 << (signal.SIGINT - 1)))

    assert set(cluster.run(sigint_blocked_at_start).values()) == {True}
    assert not sigint_blocked_at_start()  # this process's main thread still takes Ctrl-C


def test_worker_processes_are_quiet_from_their_start_and_the_environment_is_restored(cluster):
    """A starting worker takes its loggers' level from the environment when it imports distributed (before
    its nanny's ``silence_logs``): critical only; this process's environment is as it was."""
    import os

    import dask

    from uvms.sweep.cluster import CHILD_LOGGING

    assert set(cluster.run(lambda: dask.config.get("logging.distributed")).values()) == {"critical"}
    assert CHILD_LOGGING not in os.environ


# ---------------------------------------------------------------------------------------------- Ctrl-C


@pytest.mark.slow
@pytest.mark.parametrize("delay", [0.0, 0.4, 1.0, 2.0])
def test_ctrl_c_while_the_cluster_starts_is_one_line(tmp_path, delay):
    path = write_sweep(tmp_path, duration=1.0)
    out = tmp_path / "out"
    proc = start([str(BIN / "uvms"), "sweep", str(path), "-o", str(out), "--workers", "2"], tmp_path)
    try:
        wait_for(lambda: out.exists() or proc.poll() is not None, 60, "the output folder")
        time.sleep(delay)
        os.killpg(proc.pid, signal.SIGINT)  # a terminal's Ctrl-C: the whole foreground group
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == 130, err
        assert err.count("\n") == 1 and "Traceback" not in err and "interrupted:" in err, err
        deadline = time.monotonic() + 20
        while alive_in_group(proc.pid) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert not alive_in_group(proc.pid)
    finally:
        stop_group(proc)


@pytest.mark.parametrize("when", ["workers starting", "workers started"])
def test_ctrl_c_inside_cluster_creation_leaves_no_process(monkeypatch, when):
    """A Ctrl-C (SIGINT to this process) while the workers are being created: KeyboardInterrupt in the main
    thread, and the parts already started are shut down."""
    from distributed.deploy.spec import SpecCluster

    real = SpecCluster._correct_state_internal

    async def interrupted(self):
        if when == "workers starting":
            os.kill(os.getpid(), signal.SIGINT)
        await real(self)
        if when == "workers started":
            os.kill(os.getpid(), signal.SIGINT)

    def children() -> set[int]:  # multiprocessing's resource tracker stays for the life of this process
        return {c.pid for c in psutil.Process().children(recursive=True) if c.status() != psutil.STATUS_ZOMBIE
                and "resource_tracker" not in " ".join(c.cmdline())}

    before, clusters = children(), set(SpecCluster._instances)
    monkeypatch.setattr(SpecCluster, "_correct_state_internal", interrupted)
    with pytest.raises(KeyboardInterrupt), local_cluster(1):
        time.sleep(30)  # the signal arrives before or here
    wait_for(lambda: not (children() - before), 20, "no worker process left")
    assert not set(SpecCluster._instances) - clusters  # nothing left for distributed's exit handler to wait for


# ---------------------------------------------------------------------------------------------- external


@pytest.mark.parametrize("address, secured, insecure, message", [
    ("tcp://10.0.0.5:8786", False, False, "plain tcp:// to another machine has no authentication"),
    ("10.0.0.5:8786", False, False, "plain tcp:// to another machine"),
    ("ws://cluster.example.org:8786", False, False, "plain ws:// to another machine"),
    ("tcp://10.0.0.5:8786", True, False, "TLS credentials were given but the address is tcp://"),
    ("ftp://10.0.0.5:8786", False, False, "unknown protocol 'ftp'"),
    ("notanaddress", False, False, "expected a Dask scheduler address such as tls://"),
    ("tcp://" + "a" * 100_000 + ":1", False, False, "plain tcp:// to another machine"),
])
def test_scheduler_addresses_refused(address, secured, insecure, message):
    with pytest.raises(UvmsInputError, match=message) as caught:
        check_scheduler(address, secured=secured, insecure=insecure)
    assert len(str(caught.value)) < 600  # an echoed address is cut short


@pytest.mark.parametrize("address, insecure, warns", [
    ("tls://10.0.0.5:8786", False, False), ("wss://host.example.org:443", False, False),
    ("tcp://127.0.0.1:8786", False, False), ("tcp://localhost:8786", False, False),
    ("tcp://[::1]:8786", False, False), ("tcp://10.0.0.5:8786", True, True),
])
def test_scheduler_addresses_accepted(address, insecure, warns):
    warning = check_scheduler(address, secured=False, insecure=insecure)
    assert (warning is not None) == warns
    if warns:
        assert "without authentication" in warning and "\n" not in warning


def test_tls_files_checked(tmp_path):
    assert security_from_files(None, None, None) is None
    with pytest.raises(UvmsInputError, match="--tls-ca-file: no such file"):
        security_from_files(str(tmp_path / "ca.pem"), None, None)
    (tmp_path / "cert.pem").write_text("x")
    with pytest.raises(UvmsInputError, match="--tls-key: expected --tls-cert and --tls-key together"):
        security_from_files(None, str(tmp_path / "cert.pem"), None)


@pytest.mark.parametrize("extra, message", [
    (["--tls-ca-file", "ca.pem"], "--tls-ca-file: only applies with --scheduler"),
    (["--insecure"], "--insecure: only applies with --scheduler"),
    (["--scheduler", "tcp://10.0.0.5:8786"], "--scheduler: plain tcp:// to another machine"),
    (["--scheduler", "tls://10.0.0.5:8786", "--tls-cert", "nowhere.pem", "--tls-key", "nowhere.pem"],
     "--tls-cert: no such file"),
])
def test_cli_refuses_insecure_or_misplaced_options_in_one_line(tmp_path, capsys, extra, message):
    path = write_sweep(tmp_path)
    assert main(["sweep", str(path), "-o", str(tmp_path / "out"), *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_external_tls_scheduler_with_credential_files(tmp_path, capsys):
    """The docs' cluster recipe on loopback: a TLS scheduler and worker; the sweep reaches them with --tls-*
    files, and is refused (one line, nothing left) without them."""
    from distributed.security import Security

    from tests.sweep.helpers import warm_kernels

    warm_kernels()
    made = Security.temporary()
    ca, cert, key = tmp_path / "ca.pem", tmp_path / "cert.pem", tmp_path / "key.pem"
    ca.write_text(made.tls_ca_file)
    cert.write_text(made.tls_scheduler_cert)
    key.write_text(made.tls_scheduler_key)
    key.chmod(0o600)
    tls = ["--tls-ca-file", str(ca), "--tls-cert", str(cert), "--tls-key", str(key)]
    scheduler_file = tmp_path / "scheduler.json"
    scheduler = start([str(BIN / "dask"), "scheduler", "--protocol", "tls", "--host", "127.0.0.1", "--port", "0",
                       "--no-dashboard", "--dashboard-address", "127.0.0.1:0", "--scheduler-file",
                       str(scheduler_file), *tls], tmp_path)
    worker = None
    try:
        address = scheduler_address(scheduler_file, scheduler)
        assert address.startswith("tls://127.0.0.1:")
        worker = start([str(BIN / "dask"), "worker", address, "--nthreads", "1", "--nworkers", "1", "--host",
                        "127.0.0.1", "--no-dashboard", "--death-timeout", "60", *tls], tmp_path)
        path = write_sweep(tmp_path)
        out = tmp_path / "out"
        assert main(["sweep", str(path), "-o", str(out), "--scheduler", address, *tls]) == 0
        assert "3 new" in capsys.readouterr().out
        other = tmp_path / "other"
        assert main(["sweep", str(path), "-o", str(other), "--scheduler", address]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--scheduler: cannot connect to the Dask scheduler" in err, err
        assert not other.exists()
    finally:
        for proc in (worker, scheduler):
            if proc is not None:
                stop_group(proc)


def test_without_cryptography_the_credentials_come_from_openssl(monkeypatch, tmp_path):
    """The fallback for an installation without the ``cryptography`` package: a private cluster all the same."""
    import shutil

    from distributed import Client
    from distributed.security import Security

    if shutil.which("openssl") is None:
        pytest.skip("no openssl command")

    def unavailable(cls, **kwargs):
        raise ImportError("no cryptography")

    monkeypatch.setattr(Security, "temporary", classmethod(unavailable))
    with local_cluster(1) as client:
        marker = tmp_path / "ran"
        assert client.submit(_mark, str(marker), pure=False).result(timeout=60) == "ran"
        with pytest.raises(Exception):  # noqa: B017, PT011 - refused without the credentials
            Client(client.scheduler.address.replace("tls://", "tcp://"), timeout=3, set_as_default=False)
        with pytest.raises(Exception):  # noqa: B017, PT011
            Client(client.scheduler.address, timeout=3, set_as_default=False)
    monkeypatch.setattr("uvms.sweep.cluster.subprocess.run", lambda *a, **k: (_ for _ in ()).throw(OSError("none")))
    with pytest.raises(UvmsInputError, match="needs the Python package 'cryptography' or the 'openssl' command"):
        with local_cluster(1):
            pass  # pragma: no cover


@pytest.mark.parametrize("uncancelled", [False, True], ids=["cancelled", "going-on-connecting"])
def test_ctrl_c_while_the_client_connects_leaves_nothing_to_wait_for_at_exit(monkeypatch, uncancelled):
    """A Ctrl-C (SIGINT to this process) while the client connects, inside its ``__init__``: the half-made
    client is closed with the cluster, so collecting it at exit does not wait for the stopped event loop (it
    waited 60 s; found by the clean-clone CI as a hang after the one-line message).

    ``going-on-connecting``: the interrupt lands where distributed's ``sync`` does not cancel the start, which
    goes on connecting while the cluster closes (CI once found the client left "connecting" that way)."""
    import asyncio

    from distributed import Client

    real, made = Client._start, []

    async def interrupted(self, *args, **kwargs):
        made.append(self)
        os.kill(os.getpid(), signal.SIGINT)
        try:
            await asyncio.sleep(0.1)  # still connecting when the main thread takes the KeyboardInterrupt
        except asyncio.CancelledError:
            if not uncancelled:
                raise
        return await real(self, *args, **kwargs)

    monkeypatch.setattr(Client, "_start", interrupted)
    with pytest.raises(KeyboardInterrupt), local_cluster(1):
        time.sleep(30)  # the signal arrives before or here
    assert len(made) == 1 and made[0].status == "closed"  # its __del__ (Client.close) returns at once
