"""``docs/logs.md`` documents every key of the log description, and its example description is valid."""

from __future__ import annotations

import re
from pathlib import Path

from uvms.logs.schema import ImuSpec, JointsSpec, LogSpec, PoseSpec, ThrustersSpec
from uvms.safe_yaml import parse_yaml

DOC = Path(__file__).resolve().parents[2] / "docs" / "logs.md"


def test_every_key_is_documented():
    text = DOC.read_text(encoding="utf-8")
    keys = {key for spec in (LogSpec, PoseSpec, ImuSpec, JointsSpec, ThrustersSpec) for key in spec.model_fields}
    missing = sorted(key for key in keys if f"`{key}`" not in text)
    assert not missing, missing


def test_the_example_description_is_valid():
    block = re.search(r"```yaml\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S).group(1)
    spec = LogSpec.model_validate(parse_yaml(block, "docs/logs.md"))
    assert (spec.start, spec.duration, spec.frame) == (3.75, 19.0, "enu")
    assert spec.pose.quaternion_columns() == ("w_ori", "x_ori", "y_ori", "z_ori")
    assert spec.joints.offset == {"base": -3.07, "wrist": -2.879}


def test_the_worked_example_runs_on_the_bundled_trial(tmp_path, monkeypatch, capsys):
    """"A worked example": the description above beside the two CSV files of the bundled ``traj003-0``, its
    Python run as written (a model with the example's joints in place of ``my_vehicle.yaml``), printing what
    its comments say; and the 20 s replay it mentions is refused as "log shorter than asked"."""
    import shutil

    import pytest

    import uvms
    from uvms.errors import UvmsInputError
    from uvms.logs.bundled import resolve_logs

    text = DOC.read_text(encoding="utf-8")
    description = re.search(r"```yaml\n(.*?)```", text, re.S).group(1)
    section = text[text.index("## A worked example"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    trial = resolve_logs("hinsdale_2023/traj003-0")[0].parent
    for name in ("traj003-0_mocap.csv", "traj003-0_joint_states.csv"):
        shutil.copy(trial / name, tmp_path / name)
    (tmp_path / "traj003-0.yaml").write_text(description)
    monkeypatch.chdir(tmp_path)
    assert 'uvms.load_model("my_vehicle.yaml")' in code
    namespace: dict = {}
    exec(compile(code.replace('"my_vehicle.yaml"', '"hinsdale_bluerov2_alpha5"'), "docs/logs.md", "exec"), namespace)
    printed = capsys.readouterr().out.splitlines()
    assert printed[0] == "enu 3.75 19.0"
    held = namespace["held"].to_dict()
    for quantity in ("roll", "pitch"):
        assert held[f"{quantity}_rmse_deg"] == held[f"{quantity}_no_skill_rmse_deg"] > 0
    assert namespace["state"].q.shape == (4,)
    (tmp_path / "long.yaml").write_text(description.replace("duration: 19.0", "duration: 20.0"))
    with pytest.raises(UvmsInputError, match="log shorter than asked") as info:
        uvms.Log.load(tmp_path / "long.yaml")
    assert "ends at 23.0" in str(info.value)
