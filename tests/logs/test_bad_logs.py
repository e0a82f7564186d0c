"""Bad log input: every case is one line naming the file and the key, column or line (``docs/logs.md``, "Bad
input")."""

from __future__ import annotations

import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.logs import Log, read

from .files import POSE_HEADER, POSE_XYZW, pose_rows, write_csv, write_log

GOOD_ROWS = pose_rows([0, 1, 2], [[0, 0, 0]] * 3, [[0, 0, 0, 1]] * 3)


def _refused(tmp_path, description=None, rows=GOOD_ROWS, header=POSE_HEADER) -> str:
    """The one-line message of loading ``description`` (default: the pose stream alone) over ``rows``."""
    write_csv(tmp_path / "pose.csv", header, rows)
    path = write_log(tmp_path, description or {"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW}})
    with pytest.raises(UvmsInputError) as error:
        Log.load(path)
    message = str(error.value)
    assert "\n" not in message and "Traceback" not in message
    return message.replace(str(tmp_path) + "/", "")


def test_a_missing_column_names_the_file_the_column_and_the_key(tmp_path):
    header = ["t", "x", "y", "Z", "qx", "qy", "qz", "qw"]
    assert _refused(tmp_path, header=header) == (
        "pose.csv: column 'z' (pose.position): no such column; the header has: t, x, y, Z, qx, qy, qz, qw")


def test_a_column_the_header_names_twice_is_refused_as_ambiguous_not_as_missing(tmp_path):
    header = ["t", "x", "y", "z", "z", "qx", "qy", "qz", "qw"]
    rows = [[*row[:4], row[3], *row[4:]] for row in GOOD_ROWS]
    assert _refused(tmp_path, header=header, rows=rows) == (
        "pose.csv: column 'z' (pose.position): the header names this column 2 times")


def test_time_that_goes_backwards_names_the_line(tmp_path):
    rows = pose_rows([0, 1, 0.5], [[0, 0, 0]] * 3, [[0, 0, 0, 1]] * 3)
    assert _refused(tmp_path, rows=rows) == (
        "pose.csv: line 4, column 't': time goes backwards: 0.5 s after 1 s on line 3")


def test_one_time_twice_with_different_values(tmp_path):
    rows = pose_rows([0, 1, 1], [[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 0, 0, 1]] * 3)
    assert _refused(tmp_path, rows=rows) == ("pose.csv: line 4, column 't': time 1 s repeats line 3 with another "
                                             "value in column 'x' (a time must not be given twice)")


@pytest.mark.parametrize("cell, found", [("nan", "'nan'"), ("", "an empty cell"), ("fast", "'fast'"),
                                         ("inf", "'inf'")])
def test_a_nan_or_empty_or_text_cell_names_line_and_column(tmp_path, cell, found):
    rows = [list(r) for r in GOOD_ROWS]
    rows[1][2] = cell
    assert _refused(tmp_path, rows=rows) == f"pose.csv: line 3, column 'y': expected a finite number, found {found}"


def test_a_log_shorter_than_asked_names_the_stream_and_its_end(tmp_path):
    write_csv(tmp_path / "joints.csv", ["t", "a"], [[0, 0], [1.5, 0]])
    description = {"frame": "ned", "duration": 1.8, "pose": {"file": "pose.csv", **POSE_XYZW},
                   "joints": {"file": "joints.csv", "time": "t", "columns": {"joint1": "a"}}}
    assert _refused(tmp_path, description) == (
        "log.yaml: duration: log shorter than asked: stream joints (joints.csv) ends at 1.5 s of log "
        "time, before start + duration = 1.8 s")


def test_a_start_before_a_stream_begins(tmp_path):
    description = {"frame": "ned", "start": -0.5, "pose": {"file": "pose.csv", **POSE_XYZW}}
    assert _refused(tmp_path, description) == (
        "log.yaml: start: stream pose (pose.csv) starts at 0 s of log time, after the replay's start "
        "-0.5 s")


def test_a_non_unit_quaternion_names_its_line_and_columns(tmp_path):
    rows = pose_rows([0, 1, 2], [[0, 0, 0]] * 3, [[0, 0, 0, 1], [0, 0, 0, 1], [0, 0, 0.5, 0.5]])
    assert _refused(tmp_path, rows=rows) == ("pose.csv: line 4, columns qw, qx, qy, qz: expected a unit quaternion "
                                             "(norm within 0.001 of 1), found norm 0.707107")


def test_joint_names_that_are_not_the_models(tmp_path):
    write_csv(tmp_path / "pose.csv", POSE_HEADER, GOOD_ROWS)
    write_csv(tmp_path / "joints.csv", ["t", "a"], [[0, 0], [2, 0]])
    log = Log.load(write_log(tmp_path, {"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW},
                                        "joints": {"file": "joints.csv", "time": "t", "columns": {"base": "a"}}}))
    with pytest.raises(UvmsInputError) as error:
        log.initial_state(uvms.load_model("paper"))
    assert str(error.value) == (f"{tmp_path}/log.yaml: joints.columns: model 'paper' has no joint 'base'; its "
                                "joints: joint1, joint2, joint3")


@pytest.mark.parametrize("change, expected", [
    ({"durations": 3.0}, "log.yaml: durations: unknown key; expected one of: duration, frame, imu, joints, name, "
                         "pose, start, thrusters"),
    ({"pose": {"file": "pose.csv", **POSE_XYZW, "quaternion": [1, 2, 3, 4]}},
     "log.yaml: pose.quaternion: unknown key; expected one of: file, position, quaternion_wxyz, quaternion_xyzw, "
     "scale, time, time_offset, time_scale, topic"),
    ({"frame": "nwu"}, "log.yaml: frame: expected 'ned' or 'enu', found 'nwu'"),
    ({"duration": "20"}, "log.yaml: duration: expected a finite number, found '20'"),
    ({"pose": {"file": "pose.csv", "time": "t", "position": ["x", "y", "z"]}},
     "log.yaml: pose: expected quaternion_xyzw or quaternion_wxyz (the body-to-world attitude's 4 columns)"),
    ({"pose": {"file": "pose.csv", **POSE_XYZW, "quaternion_wxyz": ["qw", "qx", "qy", "qz"]}},
     "log.yaml: pose: give quaternion_xyzw or quaternion_wxyz, not both"),
    ({"joints": {"file": "pose.csv", "time": "t", "columns": {"a": "x"}, "offset": {"b": 1.0}}},
     "log.yaml: joints.offset: joint 'b' has no angle column; joints in columns: a"),
    ({"joints": {"file": "pose.csv", "time": "t", "columns": {"a": "x"}, "sign": {"a": 2}}},
     "log.yaml: joints.sign.a: expected 1 or -1, found 2"),
    ({"imu": {"file": "pose.csv", "time": "t"}},
     "log.yaml: imu: expected at least one of quaternion_xyzw, quaternion_wxyz, angular_velocity, "
     "linear_acceleration"),
    ({"pose": {"file": "nowhere.csv", **POSE_XYZW}}, "nowhere.csv: no such file"),
    ({"pose": {"file": "pose.csv", "position": ["x", "y", "z"], "quaternion_xyzw": ["qx", "qy", "qz", "qw"]}},
     "log.yaml: pose.time: expected the time column's name (time: ...); a bag stream gives topic: instead"),
    ({"pose": {"file": "pose.csv", "time": "t", "quaternion_xyzw": ["qx", "qy", "qz", "qw"]}},
     "log.yaml: pose.position: expected position: the 3 position columns (x, y, z)"),
])
def test_the_description_is_checked_key_by_key(tmp_path, change, expected):
    assert _refused(tmp_path, {"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW}} | change) == expected


def test_a_missing_frame_is_required_not_guessed(tmp_path):
    assert _refused(tmp_path, {"pose": {"file": "pose.csv", **POSE_XYZW}}) == (
        "log.yaml: frame: expected a value (required field), found none")


def test_limits_come_before_parsing(tmp_path, monkeypatch):
    monkeypatch.setattr(read, "MAX_FILE_BYTES", 100)
    assert _refused(tmp_path) == "pose.csv: refused: 0 MiB is larger than the 0 MiB a log file may be"
    monkeypatch.setattr(read, "MAX_FILE_BYTES", 1 << 20)
    monkeypatch.setattr(read, "MAX_COLUMNS", 4)
    assert _refused(tmp_path) == "pose.csv: line 1: refused: 8 columns, more than 4"
    monkeypatch.setattr(read, "MAX_COLUMNS", 100)
    monkeypatch.setattr(read, "MAX_ROWS", 2)
    assert _refused(tmp_path) == "pose.csv: refused: more than 2 rows"


def test_a_description_that_is_not_a_mapping(tmp_path):
    path = tmp_path / "log.yaml"
    path.write_text("- a list\n", encoding="utf-8")
    with pytest.raises(UvmsInputError, match=r"log.yaml: expected a mapping of log description fields at the top "
                                             r"level, found a list"):
        Log.load(path)


@pytest.mark.parametrize("name, expected", [
    ("../pose.csv", "is outside"), ("~/pose.csv", "relative to"), ("/etc/passwd", "relative to")])
def test_a_stream_file_outside_the_descriptions_folder_is_refused_unread(tmp_path, name, expected):
    inner = tmp_path / "inner"
    inner.mkdir()
    write_csv(tmp_path / "pose.csv", POSE_HEADER, GOOD_ROWS)               # exists, but outside the folder
    path = write_log(inner, {"frame": "ned", "pose": {"file": name, **POSE_XYZW}})
    with pytest.raises(UvmsInputError, match=expected) as error:
        Log.load(path)
    assert "pose.file" in str(error.value) and "\n" not in str(error.value)
