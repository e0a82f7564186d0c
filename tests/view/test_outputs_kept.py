"""No output replaces a user's file (issue "Hardening", item 2): default output names never come from file
content, a default output never replaces a file uvms did not write, a file the user names may be replaced but
is then not recorded as uvms's, and a run folder's marker records a SHA-256 per file so that a listed file that
changed is the user's. Synthetic run folders: no simulation."""

from __future__ import annotations

import json
import time
from importlib.resources import files
from pathlib import Path

import pytest

from uvms.errors import UvmsInputError
from uvms.output import (MARKER, check_destination, check_file_output, default_file_name, file_digest,
                         record_written, replace_directory, staged_directory, written_by_uvms)

from .conftest import SYNTHETIC_SCENARIO, run_cli, synthetic_result

USERS = "<html>my own page, weeks of work</html>\n"


def uvms_run_folder(tmp_path, paper, name="run", scenario=SYNTHETIC_SCENARIO, metadata=None) -> Path:
    """A run folder as ``uvms run`` writes it (staged, renamed into place, with its marker), synthetic data."""
    result = synthetic_result(paper)
    result.metadata.update(metadata or {})
    final = tmp_path / name
    with staged_directory(final, kind="run") as tmp:
        result.save(tmp)
        (tmp / "scenario.yaml").write_text(scenario)
    return final


def _one_line_exit_2(code, err, *needles):
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err


def _files(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


# -- default names never come from file content

@pytest.mark.parametrize("name, expected", [
    ("paper", "paper.html"), ("bluerov2_heavy_alpha5", "bluerov2_heavy_alpha5.html"), ("v1.2-b+c", "v1.2-b+c.html"),
    ("../../pwn", "stem.html"), ("/home/user/victim", "stem.html"), ("a\0b", "stem.html"), ("..", "stem.html"),
    (".hidden", "stem.html"), ("sub/x", "stem.html"), ("C:\\x", "stem.html"), ("", "stem.html"),
    ("x" * 101, "stem.html"), (None, "stem.html"), ("é", "stem.html"), ("a b", "stem.html"),
])
def test_a_default_name_is_a_plain_file_name_never_a_path(name, expected):
    assert default_file_name([name, "stem"], ".html") == expected
    assert default_file_name([name, "../x"], ".html", fallback="model") in (expected, "model.html")


def _model_named(tmp_path, name: str) -> Path:
    text = (files("uvms") / "model" / "models" / "paper.yaml").read_text()
    lines = text.splitlines()
    index = next(i for i, line in enumerate(lines) if line.startswith("name:"))
    lines[index] = f"name: {json.dumps(name)}"
    path = tmp_path / "models" / "hostile.yaml"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("hostile", ["../../pwn", "ABSOLUTE", "sub/dir/x", "nul\0here"])
def test_show_never_writes_where_a_model_name_points(tmp_path, monkeypatch, hostile):
    cwd = tmp_path / "a" / "b" / "work"
    cwd.mkdir(parents=True)
    victim = tmp_path / "victim.html"
    victim.write_text(USERS)
    name = str(tmp_path / "victim") if hostile == "ABSOLUTE" else hostile
    model = _model_named(tmp_path, name)
    monkeypatch.chdir(cwd)
    code, stdout, err = run_cli(["show", model])
    assert code in (0, 2) and "Traceback" not in err, err     # a loader may refuse such a name: never a traceback
    assert victim.read_text() == USERS
    outside = [p for p in tmp_path.rglob("*.html") if p != victim and cwd not in p.parents]
    assert outside == []
    if code == 0:
        assert sorted(p.name for p in cwd.iterdir()) == ["hostile.html"]   # the model file's stem


def test_show_of_a_urdf_named_with_a_path_writes_in_the_working_folder(tmp_path, monkeypatch):
    text = (files("uvms") / "model" / "models" / "paper.urdf").read_text()
    import re

    urdf = tmp_path / "robot.urdf"
    urdf.write_text(re.sub(r'<robot\s+name="[^"]*"', '<robot name="../../x"', text, count=1))
    cwd = tmp_path / "a" / "b"
    cwd.mkdir(parents=True)
    monkeypatch.chdir(cwd)
    code, _, err = run_cli(["show", urdf])
    assert code in (0, 2) and "Traceback" not in err, err
    assert not (tmp_path / "x.html").exists() and not list(tmp_path.glob("*.html"))
    if code == 0:
        assert [p.name for p in cwd.iterdir()] == ["robot.html"]


# -- a default output never replaces a file uvms did not write

def test_show_default_output_never_replaces_a_users_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "paper.html").write_text(USERS)
    start = time.perf_counter()
    code, _, err = run_cli(["show", "paper"])
    elapsed = time.perf_counter() - start
    _one_line_exit_2(code, err, "paper.html: --output: exists and uvms did not write it", "--force")
    assert elapsed < 5.0                                        # refused before drawing anything
    assert (tmp_path / "paper.html").read_text() == USERS
    assert sorted(p.name for p in tmp_path.iterdir()) == ["paper.html"]     # no temporary file either


@pytest.mark.parametrize("how", [["-o", "paper.html"], ["--force"]])
def test_show_replaces_a_users_file_only_when_named_or_forced(tmp_path, monkeypatch, how):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "paper.html").write_text(USERS)
    code, _, err = run_cli(["show", "paper", *how])
    assert code == 0, err
    assert "Plotly.newPlot" in (tmp_path / "paper.html").read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["paper.html"]     # no marker made in the user's folder


def test_animate_default_output_never_replaces_a_users_animation(tmp_path, paper):
    run = uvms_run_folder(tmp_path, paper)
    (run / "animation.html").write_text(USERS)
    before = _files(run)
    code, _, err = run_cli(["animate", run])
    _one_line_exit_2(code, err, f"{run / 'animation.html'}: --output: exists and uvms did not write it")
    assert _files(run) == before


def test_animate_rewrites_its_own_default_output_but_not_once_the_user_changed_it(tmp_path, paper):
    run = uvms_run_folder(tmp_path, paper)
    assert run_cli(["animate", run, "--fps", "2"])[0] == 0
    assert written_by_uvms(run / "animation.html")
    assert run_cli(["animate", run, "--fps", "3"])[0] == 0          # uvms's own page: replaced
    with (run / "animation.html").open("a") as fh:
        fh.write("<!-- the user's notes -->")
    before = _files(run)
    code, _, err = run_cli(["animate", run, "--fps", "2"])
    _one_line_exit_2(code, err, "animation.html: --output: exists and uvms did not write it (or it changed since)")
    assert _files(run) == before
    with pytest.raises(UvmsInputError, match=r"1 file changed since uvms wrote it .*animation\.html"):
        check_destination(run, "--output", kind="replaced folder")


def test_plot_default_output_never_replaces_a_users_figure(tmp_path, paper):
    run = uvms_run_folder(tmp_path, paper)
    (run / "timeseries.png").write_bytes(b"my figure")
    code, _, err = run_cli(["plot", run])
    _one_line_exit_2(code, err, "timeseries.png: --output: exists and uvms did not write it")
    assert (run / "timeseries.png").read_bytes() == b"my figure"
    code, _, err = run_cli(["plot", run, "--force"])
    assert code == 0, err
    assert (run / "timeseries.png").read_bytes().startswith(b"\x89PNG")
    assert "timeseries.png" not in json.loads((run / MARKER).read_text())["files"]   # still not uvms's


def test_a_named_users_file_is_replaced_but_never_recorded_as_uvms_s(tmp_path, paper, monkeypatch):
    """``animate -o R/scenario.html`` (the user's file) replaces it, as named, but the marker does not list it:
    a later ``uvms run -o R`` refuses to delete it."""
    run = uvms_run_folder(tmp_path, paper)
    (run / "scenario.html").write_text(USERS)
    code, _, err = run_cli(["animate", run, "-o", run / "scenario.html", "--fps", "2"])
    assert code == 0, err
    assert "Plotly.newPlot" in (run / "scenario.html").read_text()
    assert "scenario.html" not in json.loads((run / MARKER).read_text())["files"]
    with pytest.raises(UvmsInputError, match=r"holds 1 entry that uvms did not write \(scenario\.html\)"):
        check_destination(run, "--output", kind="replaced folder")
    before = _files(run)
    code, _, err = run_cli(["run", "paper_case2_released", "-o", run])   # refused before simulating
    _one_line_exit_2(code, err, "scenario.html")
    assert _files(run) == before


def test_a_new_file_named_into_a_run_folder_is_recorded(tmp_path, paper):
    run = uvms_run_folder(tmp_path, paper)
    assert run_cli(["animate", run, "-o", run / "replay.html", "--fps", "2"])[0] == 0
    assert run_cli(["plot", run, "-o", run / "figure.svg"])[0] == 0
    marker = json.loads((run / MARKER).read_text())
    assert {"replay.html", "figure.svg"} <= set(marker["files"])
    assert marker["sha256"]["replay.html"] == file_digest(run / "replay.html")
    check_destination(run, "--output", kind="replaced folder")          # all uvms's: replaceable


# -- the marker's digests

def test_a_copied_folder_whose_marker_lists_a_users_file_keeps_it(tmp_path, paper):
    """A marker that lists ``notes.txt`` (copied, hand-edited or written by another tool) does not make the
    user's notes uvms's: their content has no matching digest."""
    run = uvms_run_folder(tmp_path, paper)
    marker = json.loads((run / MARKER).read_text())
    marker["files"].append("notes.txt")
    (run / MARKER).write_text(json.dumps(marker))
    (run / "notes.txt").write_text("my notes")
    with pytest.raises(UvmsInputError, match=r"notes\.txt") as info:
        check_destination(run, "-o", kind="replaced folder")
    assert "\n" not in str(info.value) and str(info.value).startswith(f"{run}: -o: holds 1 file changed")
    code, _, err = run_cli(["run", "paper_case2_released", "-o", run])
    _one_line_exit_2(code, err, "notes.txt")
    assert (run / "notes.txt").read_text() == "my notes"
    staged = tmp_path / ".new"
    staged.mkdir()
    (staged / "result.csv").write_text("new")
    with pytest.raises(UvmsInputError, match=r"the new results are in .*run-1"):
        replace_directory(staged, run, kind="run")                     # the check at the swap, too
    assert (run / "notes.txt").read_text() == "my notes"


def test_an_edited_result_file_makes_the_folder_the_users(tmp_path, paper):
    run = uvms_run_folder(tmp_path, paper)
    check_destination(run, "-o", kind="replaced folder")
    with (run / "result.csv").open("a") as fh:
        fh.write("# my annotation\n")
    with pytest.raises(UvmsInputError, match=r"changed since uvms wrote it .*result\.csv"):
        check_destination(run, "-o", kind="replaced folder")


def test_an_old_marker_without_digests_is_the_safe_side(tmp_path):
    folder = tmp_path / "old"
    folder.mkdir()
    (folder / "result.csv").write_text("x")
    (folder / MARKER).write_text('{"written_by": "uvms 0.1.0", "kind": "run", "files": ["result.csv"]}')
    with pytest.raises(UvmsInputError, match=r"not recorded with its content \(result\.csv\)"):
        check_destination(folder, "-o", kind="replaced folder")
    assert not written_by_uvms(folder / "result.csv")


def test_force_replaces_an_earlier_run_but_never_a_folder_uvms_did_not_write(tmp_path, paper):
    run = uvms_run_folder(tmp_path, paper)
    (run / "notes.txt").write_text("added")
    check_destination(run, "-o", kind="replaced folder", force=True)
    staged = tmp_path / ".new"
    staged.mkdir()
    (staged / "result.csv").write_text("new")
    replace_directory(staged, run, kind="run", force=True)
    assert sorted(p.name for p in run.iterdir()) == [MARKER, "result.csv"]
    home = tmp_path / "home"
    home.mkdir()
    (home / "thesis.tex").write_text("years")
    with pytest.raises(UvmsInputError, match="no .uvms-output.json"):
        check_destination(home, "-o", kind="replaced folder", force=True)
    code, _, err = run_cli(["run", "paper_case2_released", "-o", home, "--force"])
    _one_line_exit_2(code, err, "thesis.tex")
    assert (home / "thesis.tex").read_text() == "years"


def test_a_damaged_or_huge_marker_is_no_marker(tmp_path):
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "result.csv").write_text("x")
    (folder / MARKER).write_text("[" * 100_000 + "]" * 100_000)
    start = time.perf_counter()
    with pytest.raises(UvmsInputError, match=f"no {MARKER}"):
        check_destination(folder, "-o", kind="replaced folder")
    assert time.perf_counter() - start < 1.0
    with open(folder / MARKER, "wb") as fh:
        fh.truncate(64 * 1024 * 1024)
    start = time.perf_counter()
    with pytest.raises(UvmsInputError, match=f"no {MARKER}"):
        check_destination(folder, "-o", kind="replaced folder")
    assert time.perf_counter() - start < 1.0


def test_check_file_output_and_record_written_follow_one_rule(tmp_path, paper):
    run = uvms_run_folder(tmp_path, paper)
    new = run / "new.png"
    assert check_file_output(new, named=False) is True                 # a new file: uvms may list it
    new.write_bytes(b"png")
    record_written(new)
    assert written_by_uvms(new) and check_file_output(new, named=False) is True
    users = run / "mine.png"
    users.write_bytes(b"mine")
    with pytest.raises(UvmsInputError, match="exists and uvms did not write it"):
        check_file_output(users, named=False)
    assert check_file_output(users, named=True) is False                # replaced if named, never listed
    assert check_file_output(users, named=False, force=True) is False
    loose = tmp_path / "loose.png"                                     # no marker in its folder: none is made
    loose.write_bytes(b"png")
    record_written(loose)
    assert not (tmp_path / MARKER).exists()


def test_a_listed_fifo_is_the_users_and_never_read(tmp_path, paper):
    """A named pipe listed in a (hand-made) marker with some digest: reading it to hash it would block for ever."""
    import os

    run = uvms_run_folder(tmp_path, paper)
    os.mkfifo(run / "pipe")
    marker = json.loads((run / MARKER).read_text())
    marker["files"].append("pipe")
    marker["sha256"]["pipe"] = "0" * 64
    (run / MARKER).write_text(json.dumps(marker))
    start = time.perf_counter()
    with pytest.raises(UvmsInputError, match=r"\(pipe\)"):
        check_destination(run, "-o", kind="replaced folder")
    assert not written_by_uvms(run / "pipe")
    assert time.perf_counter() - start < 1.0


def test_show_replaces_its_own_default_output_until_the_user_changes_it(tmp_path, monkeypatch):
    """A default output in a folder without a marker (the working folder) is remembered in the user's cache
    (``uvms.output.WRITTEN_FILES``) with its digest: the same command replaces it again, an edited one is kept."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    code, _, err = run_cli(["show", "paper"])
    assert code == 0, err
    first = (work / "paper.html").read_text()
    code, _, err = run_cli(["show", "paper"])                  # uvms's own file, unchanged: replaced
    assert code == 0, err
    assert sorted(p.name for p in work.iterdir()) == ["paper.html"]
    (work / "paper.html").write_text(first + "<!-- my notes -->")
    code, _, err = run_cli(["show", "paper"])                  # changed since: the user's now
    _one_line_exit_2(code, err, "paper.html: --output: exists and uvms did not write it")
    assert (work / "paper.html").read_text().endswith("<!-- my notes -->")
    record = json.loads((tmp_path / "cache" / "uvms" / "written-files.json").read_text())
    assert list(record) == [str(work / "paper.html")]
