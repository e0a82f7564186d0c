"""Result files and folders (``uvms.output``): atomic writes, and output paths refused before any work."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from uvms.errors import UvmsInputError
from uvms.output import atomic_write_text, check_destination, replace_directory


def test_atomic_write_leaves_no_temporary_file_and_replaces_whole(tmp_path):
    target = tmp_path / "new" / "table.json"
    atomic_write_text(target, "first\n")
    atomic_write_text(target, "second\n")
    assert target.read_text() == "second\n"
    assert sorted(p.name for p in target.parent.iterdir()) == ["table.json"]


def test_replace_directory_swaps_the_old_folder_out(tmp_path):
    final = tmp_path / "run"
    final.mkdir()
    (final / "old.csv").write_text("old")
    tmp = tmp_path / ".run.tmp"
    tmp.mkdir()
    (tmp / "result.csv").write_text("new")
    replace_directory(tmp, final)
    assert sorted(p.name for p in final.iterdir()) == ["result.csv"]
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
