"""``uvms compare``'s table (no simulation: a made-up comparison table): every cell whole however narrow the
output (rich cut them to fit 80 columns when stdout is not a terminal), and a note, in the table and in the
JSON settings, that each column's controller replaces the scenario file's own."""

from __future__ import annotations

import argparse

import pandas as pd
import pytest

from uvms.commands.compare import print_table, replaced_controller
from uvms.control.compare import AXIS_COMMAND, SIX_AXIS_CASES
from uvms.sim.scenario import load_scenario

HOLD6 = "bluerov2_heavy_alpha5_hold6"


def _table(labels) -> pd.DataFrame:
    rows = []
    for k, label in enumerate(labels):
        row = {"case": label, "controller": label, "peak_world_xy_error_mm": 123456.7 + k,
               "peak_depth_error_mm": 0.000123456, "peak_roll_error_deg": 98765.4, "peak_pitch_error_deg": -1.5e-7,
               "peak_yaw_error_deg": 42.0, "complete": True, "healthy": k != 1}
        for name, unit in AXIS_COMMAND.values():
            row[f"rms_command_{name}_{unit}"] = 1234.5
            row[f"chatter_{name}"] = 1000 + k
        rows.append(row)
    return pd.DataFrame(rows)


def _args(**extra):
    return argparse.Namespace(duration=8.0, step=0.001, period=0.01, hydro_scale=0.4, actuators="scenario", **extra)


def test_cells_are_never_cut(capsys):
    scenario = load_scenario(HOLD6)
    labels = [c.label for c in SIX_AXIS_CASES] + ["a rather long case label"]
    print_table(_table(labels), _args(), scenario=scenario, model=scenario.model)
    out = capsys.readouterr().out
    assert "\u2026" not in out and "..." not in out                    # rich's ellipsis: nothing was cut
    lines = out.splitlines()
    assert max(len(line) for line in lines) > 80                       # wider than the default console
    for text in (*labels[:1], "a rather long case label", "(unhealthy)", "1.23e+05", "0.000123", "9.88e+04",
                 "-1.5e-07", "1000/1000/1000/1000/1000/1000", "1005/1005/1005/1005/1005/1005",
                 "world xy error [mm]", "RMS N [N m]"):
        assert any(text in line for line in lines), text


def test_the_note_says_the_files_controller_is_replaced(capsys):
    scenario = load_scenario(HOLD6)
    print_table(_table(["smc-ab", "pid"]), _args(), scenario=scenario, model=scenario.model)
    out = " ".join(capsys.readouterr().out.split())
    assert ("Each column's controller replaces the scenario's own (smc-ab, axes: all): only its axes and period are "
            "kept (period 0.01 s); every other setting is the column controller's default.") in out
    assert replaced_controller(scenario) == {"name": "smc-ab", "period_s": 0.01, "parameters": {"axes": "all"}}


def test_a_scenario_without_a_controller_says_so(capsys):
    scenario = load_scenario("paper_case2_released")
    assert replaced_controller(scenario) is None
    table = _table(["smc-ab"]).assign(peak_xy_error_mm=1.0, max_abs_s_surge=0.1, max_abs_s_sway=0.1,
                                      max_abs_s_yaw=0.1)
    print_table(table, _args(), scenario=scenario, model=scenario.model)
    assert "has no controller of its own" in capsys.readouterr().out


@pytest.mark.slow
def test_cli_json_records_the_replaced_controller(tmp_path, capsys):
    import json

    from uvms.cli import main

    path = tmp_path / "c.json"
    assert main(["compare", "--scenario", HOLD6, "--duration", "0.02", "--json", str(path)]) == 0
    assert json.loads(path.read_text())["settings"]["scenario_controller_replaced"]["name"] == "smc-ab"
    assert "replaces the scenario's own (smc-ab" in " ".join(capsys.readouterr().out.split())
