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
