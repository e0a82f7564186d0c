"""Result files and folders (``uvms.output``): atomic writes, and output paths refused before any work."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from uvms.errors import UvmsInputError
from uvms.output import MARKER, atomic_write_text, check_destination, replace_directory


def test_atomic_write_leaves_no_temporary_file_and_replaces_whole(tmp_path):
    target = tmp_path / "new" / "table.json"
    atomic_write_text(target, "first\n")
    atomic_write_text(target, "second\n")
    assert target.read_text() == "second\n"
    assert sorted(p.name for p in target.parent.iterdir()) == ["table.json"]


def test_replace_directory_swaps_the_old_folder_out(tmp_path):
    final = tmp_path / "run"
    first = tmp_path / ".run.first"
    first.mkdir()
    (first / "old.csv").write_text("old")
    replace_directory(first, final, kind="run")                    # uvms's own folder, with its marker
    tmp = tmp_path / ".run.tmp"
    tmp.mkdir()
    (tmp / "result.csv").write_text("new")
    replace_directory(tmp, final, kind="run")
    assert sorted(p.name for p in final.iterdir()) == [MARKER, "result.csv"]
    assert json.loads((final / MARKER).read_text())["files"] == ["result.csv"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]


@pytest.fixture
def read_only(tmp_path, monkeypatch):
    """A folder the user may not write to (simulated: the tests may run as root, for whom every folder is)."""
    folder = tmp_path / "mounted"
    folder.mkdir()
    real = os.access
    monkeypatch.setattr("uvms.output.os.access",
                        lambda p, mode: False if Path(p) == folder else real(p, mode))
    return folder


def test_file_and_replaced_folder_need_a_writable_parent(read_only):
    for kind in ("file", "replaced folder"):
        with pytest.raises(UvmsInputError, match=f"no permission to write in {read_only}"):
            check_destination(read_only / "out", "--output", kind=kind)
        with pytest.raises(UvmsInputError, match=f"no permission to write in {read_only}"):
            check_destination(read_only / "deeper" / "out", "--output", kind=kind)
        check_destination(read_only.parent / "elsewhere" / "out", "--output", kind=kind)


def test_a_folder_written_in_place_needs_only_itself_writable(read_only, tmp_path):
    existing = read_only / "sweep"
    existing.mkdir()
    check_destination(existing, "--output", kind="folder")          # resuming inside a read-only mount: fine
    with pytest.raises(UvmsInputError, match="no permission"):
        check_destination(read_only / "new-sweep", "--output", kind="folder")
    with pytest.raises(UvmsInputError, match="no permission"):
        check_destination(read_only, "--output", kind="folder")       # the folder itself is read-only


def test_under_a_file_and_a_folder_for_a_file(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    for kind in ("file", "replaced folder", "folder"):
        with pytest.raises(UvmsInputError, match=f"{blocker} is a file, not a folder"):
            check_destination(blocker / "out", "--output", kind=kind)
    with pytest.raises(UvmsInputError, match="expected a file name, found a folder") as info:
        check_destination(tmp_path, "--json", kind="file")
    assert str(info.value) == f"{tmp_path}: --json: expected a file name, found a folder"


def _uvms_folder(tmp_path, name="run", files=("result.csv",)):
    """A folder as uvms writes it (through replace_directory, so with its marker)."""
    staged = tmp_path / f".{name}.staged"
    staged.mkdir()
    for file in files:
        (staged / file).parent.mkdir(parents=True, exist_ok=True)
        (staged / file).write_text("uvms")
    replace_directory(staged, tmp_path / name, kind="run")
    return tmp_path / name


@pytest.mark.parametrize("intruder", ["notes.txt", ".hidden", "figures/", "sub/extra.csv", "link"])
def test_a_folder_holding_anything_uvms_did_not_write_is_never_replaced(tmp_path, intruder):
    final = _uvms_folder(tmp_path, files=("result.csv", "sub/a.csv"))
    if intruder == "link":
        (final / "link").symlink_to(tmp_path)
    elif intruder.endswith("/"):
        (final / intruder).mkdir()
    else:
        (final / intruder).write_text("the user's")
    snapshot = sorted(str(p.relative_to(final)) for p in final.rglob("*"))
    with pytest.raises(UvmsInputError, match="that uvms did not write") as info:
        check_destination(final, "--output", kind="replaced folder")
    assert str(info.value).startswith(f"{final}: --output: holds 1 entry") and "\n" not in str(info.value)
    staged = tmp_path / ".run.new"
    staged.mkdir()
    (staged / "result.csv").write_text("new")
    with pytest.raises(UvmsInputError, match=r"the new results are in .*run-1"):
        replace_directory(staged, final, kind="run")               # a file that appeared during the run
    assert sorted(str(p.relative_to(final)) for p in final.rglob("*")) == snapshot
    assert (tmp_path / "run-1" / "result.csv").read_text() == "new"   # nothing computed is lost


@pytest.mark.parametrize("marker", ["not json", '["result.csv"]', '{"files": "result.csv"}', '{"files": [1]}'])
def test_a_folder_without_a_readable_marker_is_not_uvms_s(tmp_path, marker):
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "result.csv").write_text("x")
    (folder / MARKER).write_text(marker)
    with pytest.raises(UvmsInputError, match=f"no {MARKER}"):
        check_destination(folder, "-o", kind="replaced folder")
    assert sorted(p.name for p in folder.iterdir()) == [MARKER, "result.csv"]


def test_new_empty_and_own_folders_are_accepted(tmp_path):
    check_destination(tmp_path / "new", "-o", kind="replaced folder")
    (tmp_path / "empty").mkdir()
    check_destination(tmp_path / "empty", "-o", kind="replaced folder")
    own = _uvms_folder(tmp_path, files=("result.csv", "figures/a.png"))
    check_destination(own, "-o", kind="replaced folder")
    (own / "result.csv").unlink()                                  # fewer files than listed: still uvms's
    check_destination(own, "-o", kind="replaced folder")


def test_write_errors_name_the_users_path_not_a_temporary_one(tmp_path, monkeypatch):
    import errno

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp_path / ".table.json.x1y2.tmp"))

    monkeypatch.setattr("uvms.output.os.fsync", full)
    with pytest.raises(OSError) as info:
        atomic_write_text(tmp_path / "table.json", "x")
    assert info.value.filename == str(tmp_path / "table.json") and info.value.errno == errno.ENOSPC
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not Path("/proc/self").exists(), reason="needs Linux's /proc")
@pytest.mark.parametrize("kind", ["file", "replaced folder"])
def test_a_file_system_that_refuses_new_files_is_caught_before_any_work(kind):
    with pytest.raises(UvmsInputError, match="/proc refuses new files"):
        check_destination("/proc/uvms-out", "--output", kind=kind)   # os.access says yes to root here
