"""The sweep folder: built under a temporary name and renamed into place, start-up debris of a killed uvms
accepted, a refused folder left exactly as it was, rows of cluster failures recorded by older versions run
again, and write errors that name their file. No Dask here except in the end-to-end resumes."""

from __future__ import annotations

import errno
import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from tests.sweep.helpers import SRC, snapshot, warm_kernels, write_sweep
from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.sweep import load_sweep
from uvms.sweep.store import BUILD_SUFFIX, LOCK, RunStore, columns, format_line


@pytest.fixture(scope="module")
def warm():
    warm_kernels()


def _row(sweep, k: int, status: str = "ok", error: str = "") -> list[str]:
    header = columns(sweep)
    cells = ["1.0"] * len(header)
    cells[0], cells[1], cells[2] = sweep.runs[k].run_id, str(sweep.runs[k].draw), "smc-ab"
    cells[header.index("status")], cells[header.index("error")] = status, error
    return cells


def _builds(parent: Path) -> list[Path]:
    return [p for p in parent.iterdir() if p.name.endswith(BUILD_SUFFIX)]


# ---------------------------------------------------------------------------------------------- creation


def test_a_new_folder_appears_complete(tmp_path):
    sweep = load_sweep(write_sweep(tmp_path))
    out = tmp_path / "deep" / "out"
    with RunStore.open(out, sweep) as store:
        assert store.created and store.done == {}
        assert {p.name for p in out.iterdir()} == {LOCK, "sweep.yaml", "scenario.yaml", "sweep.json", "runs.csv"}
        assert json.loads((out / "sweep.json").read_text())["sweep_sha256"] == sweep.sha256
        assert (out / "runs.csv").read_text() == format_line(columns(sweep))
        assert not _builds(out.parent)
        with pytest.raises(UvmsInputError, match="another uvms sweep is writing"):
            RunStore.open(out, sweep)


@pytest.mark.parametrize("when", ["sweep.yaml", "scenario.yaml", "sweep.json", "runs.csv", "rename"])
def test_killed_while_creating_the_folder_then_resumed(tmp_path, when, warm):
    """SIGKILL at each step of creating the folder: a rerun of the same command completes the sweep."""
    path = write_sweep(tmp_path)
    out = tmp_path / "out"
    code = f"""
import os, signal, sys
import uvms.sweep.store as store
when = {when!r}
if when == "rename":
    real_rename = store.os.rename
    def rename(a, b):
        os.kill(os.getpid(), signal.SIGKILL)
    store.os.rename = rename
else:
    real = store._write
    def write(path, text):
        real(path, text)
        if path.name == when:
            os.kill(os.getpid(), signal.SIGKILL)
    store._write = write
from uvms.cli import main
sys.exit(main(["sweep", {str(path)!r}, "-o", {str(out)!r}, "--workers", "1"]))
"""
    env = dict(os.environ, PYTHONPATH=SRC)
    killed = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True,
                            timeout=120)
    assert killed.returncode == -signal.SIGKILL, killed.stderr
    assert not out.exists()                        # never half made under its real name
    assert _builds(tmp_path)                        # the killed build is left under its temporary name
    assert main(["sweep", str(path), "-o", str(out), "--workers", "1"]) == 0
    df = pd.read_csv(out / "runs.csv")
    assert sorted(df["run_id"]) == sorted(r.run_id for r in load_sweep(path).runs) and (df["status"] == "ok").all()
    assert not _builds(tmp_path)                    # and cleaned up by the rerun


OLD_DEBRIS = {  # what uvms before this change left when killed between mkdir and sweep.json
    "empty": [],
    "lock only": [LOCK],
    "sweep.yaml written": [LOCK, "sweep.yaml"],
    "scenario.yaml being written": [LOCK, "sweep.yaml", ".scenario.yaml.k2j3l4.tmp"],
    "both written": [LOCK, "sweep.yaml", "scenario.yaml"],
    "sweep.json being written": [LOCK, "sweep.yaml", "scenario.yaml", ".sweep.json.ab12cd.tmp"],
}


@pytest.mark.parametrize("case", sorted(OLD_DEBRIS))
def test_start_up_debris_is_completed(tmp_path, case):
    sweep = load_sweep(write_sweep(tmp_path))
    out = tmp_path / "out"
    out.mkdir()
    for name in OLD_DEBRIS[case]:
        (out / name).write_text("partial" if name != LOCK else "")
    with RunStore.open(out, sweep) as store:
        assert not store.created and store.done == {}
    assert {p.name for p in out.iterdir()} == {LOCK, "sweep.yaml", "scenario.yaml", "sweep.json", "runs.csv"}
    assert (out / "sweep.yaml").read_text() == sweep.text
    assert json.loads((out / "sweep.json").read_text())["sweep_sha256"] == sweep.sha256


def test_start_up_debris_resumes_end_to_end(tmp_path, capsys, warm):
    path = write_sweep(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    for name in OLD_DEBRIS["scenario.yaml being written"]:
        (out / name).write_text("partial")
    assert main(["sweep", str(path), "-o", str(out), "--workers", "1"]) == 0
    assert "3 new" in capsys.readouterr().out
    assert len(pd.read_csv(out / "runs.csv")) == 3


# ---------------------------------------------------------------------------------------------- refusals


def _refused_untouched(out: Path, sweep, match: str) -> None:
    before = snapshot(out)
    with pytest.raises(UvmsInputError, match=match):
        RunStore.open(out, sweep)
    assert snapshot(out) == before


@pytest.mark.parametrize("entries", [
    ["notes.txt"], [LOCK, "sweep.yaml", "results.csv"], [LOCK, "runs.csv"], ["sweep.yaml", ".hidden"],
    [".sweep.json.x.tmp", "data"],
])
def test_a_folder_with_other_content_is_refused_untouched(tmp_path, entries):
    sweep = load_sweep(write_sweep(tmp_path))
    out = tmp_path / "out"
    out.mkdir()
    for name in entries:
        (out / name).write_text("mine")
    _refused_untouched(out, sweep, "exists and is not a sweep directory")


def test_debris_lookalikes_that_are_not_regular_files_are_refused(tmp_path):
    sweep = load_sweep(write_sweep(tmp_path))
    out = tmp_path / "out"
    out.mkdir()
    (tmp_path / "elsewhere.yaml").write_text("precious")
    (out / "sweep.yaml").symlink_to(tmp_path / "elsewhere.yaml")
    _refused_untouched(out, sweep, "not a sweep directory")
    (out / "sweep.yaml").unlink()
    (out / "scenario.yaml").mkdir()
    _refused_untouched(out, sweep, "not a sweep directory")
    assert (tmp_path / "elsewhere.yaml").read_text() == "precious"


def _sweep_folder(tmp_path: Path, *, rows: int = 1, lock: bool = False):
    path = write_sweep(tmp_path)
    sweep = load_sweep(path)
    out = tmp_path / "out"
    with RunStore.open(out, sweep) as store:
        for k in range(rows):
            store.append(_row(sweep, k))
    if not lock:
        (out / LOCK).unlink()  # as copied from another machine, or made before the lock existed
    return path, sweep, out


def test_another_sweeps_folder_is_refused_without_a_lock_left(tmp_path):
    _, _, out = _sweep_folder(tmp_path)
    other = load_sweep(write_sweep(tmp_path, parameters={"controller.parameters.hydro_scale": [0.7]}))
    _refused_untouched(out, other, "not the current sweep file")
    assert not (out / LOCK).exists()


def test_a_runs_csv_changed_outside_uvms_is_refused_untouched(tmp_path):
    _, sweep, out = _sweep_folder(tmp_path)
    with open(out / "runs.csv", "ab") as fh:
        fh.write(b"only,three,fields\n0001-partial-line")  # a bad row and a partial last line
    _refused_untouched(out, sweep, "line 3: expected")
    text = (out / "runs.csv").read_text().splitlines()
    (out / "runs.csv").write_text("\n".join(["run_id,other,header", *text[1:2]]) + "\n0002-partial")
    _refused_untouched(out, sweep, "its header differs")


def test_a_folder_in_use_is_refused_untouched(tmp_path):
    _, sweep, out = _sweep_folder(tmp_path, lock=True)
    with RunStore.open(out, sweep):
        _refused_untouched(out, sweep, "another uvms sweep is writing")


def test_an_unreadable_identity_is_refused_untouched_and_not_echoed(tmp_path):
    _, sweep, out = _sweep_folder(tmp_path)
    (out / "sweep.json").write_text(json.dumps({"sweep_sha256": "0" * 64, "name": "n" * 100_000}))
    before = snapshot(out)
    with pytest.raises(UvmsInputError, match="this directory holds sweep 'nnn") as caught:
        RunStore.open(out, sweep)
    assert len(str(caught.value)) < 1000 and snapshot(out) == before


def test_cli_refusal_leaves_the_folder_untouched(tmp_path, capsys):
    _, _, out = _sweep_folder(tmp_path)
    other = write_sweep(tmp_path, parameters={"controller.parameters.hydro_scale": [0.7]})
    before = snapshot(out)
    assert main(["sweep", str(other), "-o", str(out), "--workers", "1"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert snapshot(out) == before


# ---------------------------------------------------------------------------------------------- cluster failures


def test_rows_of_cluster_failures_from_older_versions_run_again(tmp_path, capsys, warm):
    path, sweep, out = _sweep_folder(tmp_path, rows=0)
    with RunStore.open(out, sweep) as store:
        store.append(_row(sweep, 0))
        store.append(_row(sweep, 1, "failed", "worker failure: KilledWorker: Attempted to run task uvms-sweep-1"))
        store.append(_row(sweep, 2, "failed", "worker failure: CancelledError: scheduler-connection-lost"))
    with RunStore.open(out, sweep) as store:
        assert list(store.done) == [sweep.runs[0].run_id]
    assert (out / "runs.csv").read_text().count("\n") == 2  # the two rows are gone from the file
    assert main(["sweep", str(path), "-o", str(out), "--workers", "1"]) == 0
    assert "2 new" in capsys.readouterr().out
    df = pd.read_csv(out / "runs.csv", keep_default_na=False)
    assert df["run_id"].is_unique and len(df) == 3 and not df["error"].str.startswith("worker failure").any()


def test_a_runs_own_failure_stays_final(tmp_path):
    _, sweep, out = _sweep_folder(tmp_path, rows=0)
    with RunStore.open(out, sweep) as store:
        store.append(_row(sweep, 0, "failed", "controller.parameters.hydro_scale: expected a number >= 0"))
        store.append(_row(sweep, 1, "failed", "simulation diverged at t = 0.1 s: joint velocity"))
    with RunStore.open(out, sweep) as store:
        assert set(store.done) == {sweep.runs[0].run_id, sweep.runs[1].run_id}


# ---------------------------------------------------------------------------------------------- write errors


class _FullDisk:
    """``os`` with a ``write`` that fails like a full disk (no file name in the error)."""

    def __init__(self) -> None:
        self._os = os

    def __getattr__(self, name):
        return getattr(self._os, name)

    @staticmethod
    def write(fd, data):
        raise OSError(errno.ENOSPC, "No space left on device")


def test_a_full_disk_while_appending_names_runs_csv(tmp_path, monkeypatch):
    sweep = load_sweep(write_sweep(tmp_path))
    with RunStore.open(tmp_path / "out", sweep) as store:
        monkeypatch.setattr("uvms.sweep.store.os", _FullDisk())
        with pytest.raises(OSError) as caught:
            store.append(_row(sweep, 0))
    assert caught.value.errno == errno.ENOSPC and caught.value.filename == str(tmp_path / "out" / "runs.csv")


@pytest.mark.parametrize("name", ["sweep.yaml", "sweep.json", "runs.csv"])
def test_a_full_disk_while_creating_the_folder_is_one_line_naming_the_file(tmp_path, capsys, monkeypatch, name):
    import uvms.sweep.store as store

    real = store.atomic_write_text

    def full(path, text):
        if Path(path).name == name:
            with open(os.devnull, "w"):
                raise OSError(errno.ENOSPC, "No space left on device")
        real(path, text)

    monkeypatch.setattr(store, "atomic_write_text", full)
    path = write_sweep(tmp_path)
    assert main(["sweep", str(path), "-o", str(tmp_path / "out"), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{name}: No space left on device" in err, err
    assert not (tmp_path / "out").exists() and not _builds(tmp_path)


def test_a_full_disk_while_writing_the_summary_names_it(tmp_path, monkeypatch):
    sweep = load_sweep(write_sweep(tmp_path))
    with RunStore.open(tmp_path / "out", sweep) as store:
        monkeypatch.setattr("uvms.sweep.store.atomic_write_text", lambda path, text: (_ for _ in ()).throw(
            OSError(errno.ENOSPC, "No space left on device")))
        with pytest.raises(OSError) as caught:
            store.write_summary(pd.DataFrame({"a": [1]}))
    assert caught.value.filename == str(tmp_path / "out" / "summary.csv")
