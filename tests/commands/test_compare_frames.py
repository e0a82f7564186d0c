"""``uvms compare`` honours the frame option (issue 25, "Frame conventions ... honoured everywhere": the
controllers' set points and ``compare``): the bundled BlueROV2 Heavy + Alpha 5 (z down) and the same robot
written z up by hand (``tests/sim/test_frame_equivalence.write_bluerov_enu``) give the same comparison table,
every controller's peak errors, sliding surfaces and RMS commands (magnitudes: frame-invariant) to rounding."""

import json

import pytest

from tests.sim.test_frame_equivalence import write_bluerov_enu
from uvms.cli import main

pytestmark = pytest.mark.filterwarnings("ignore:.*crossed its position limit")


def test_compare_of_the_z_up_robot_is_the_z_down_table(tmp_path, capsys):
    enu_model = write_bluerov_enu(tmp_path)
    tables = []
    for model in ("bluerov2_heavy_alpha5", str(enu_model)):
        out = tmp_path / f"{len(tables)}.json"
        assert main(["compare", "--scenario", "bluerov2_heavy_alpha5_reach", "--model", model, "--duration", "2",
                     "--json", str(out)]) == 0
        tables.append(json.loads(out.read_text())["rows"])
    capsys.readouterr()
    ned, enu = tables
    assert [r["case"] for r in ned] == [r["case"] for r in enu] and len(ned) >= 4
    for a, b in zip(ned, enu):
        assert a["complete"] and b["complete"] and a["healthy"] == b["healthy"]
        numbers = [k for k, v in a.items() if isinstance(v, float) and k != "wall_time_s"]
        assert "peak_xy_error_mm" in numbers and "rms_command_X_N" in numbers
        for key in numbers:         # chatter counts (sign changes of increments) may flip on rounding: not compared
            assert b[key] == pytest.approx(a[key], rel=1e-9, abs=1e-12), (a["case"], key)
