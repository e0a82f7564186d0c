"""Saved runs read back through one validated reader (``uvms.sim.result``): damaged or foreign result folders
are one line and exit 2 in ``uvms plot``, never a traceback; names are drawn as written."""

from __future__ import annotations

import json
import shutil

import pytest

from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.output import MARKER
from uvms.sim.result import load_result_summary, load_result_table

from .test_cli_run import short_run, write_scenario  # noqa: F401  (the shared short run)


@pytest.fixture
def run_copy(short_run, tmp_path):  # noqa: F811
    folder = tmp_path / "run"
    shutil.copytree(short_run[0], folder)
    return folder


def _damage_csv(folder, column, value, row=3):
    lines = (folder / "result.csv").read_text().splitlines()
    header = lines[0].split(",")
    cells = lines[row].split(",")
    cells[header.index(column)] = value
    lines[row] = ",".join(cells)
    (folder / "result.csv").write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("column, value", [("x_m", "abc"), ("t_s", "1.0.0"), ("q_joint2_rad", "True"),
                                           ("ee_y_m", "[1; 2]")])
def test_text_in_a_numeric_column_is_one_line(run_copy, capsys, column, value):
    _damage_csv(run_copy, column, value)
    with pytest.raises(UvmsInputError, match=f"column '{column}': expected numbers, found .* in row 3"):
        load_result_table(run_copy)
    assert main(["plot", str(run_copy)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "result.csv" in err and "Traceback" not in err


@pytest.mark.parametrize("summary, field", [
    ("[1, 2, 3]", "expected a mapping"),
    ('{"metadata": "case 2"}', "metadata: expected dict"),
    ('{"metadata": {"scenario": ["a"]}}', "metadata.scenario: expected str"),
    ('{"complete": "yes"}', "complete: expected bool"),
    ('{"message": {"a": 1}}', "message: expected str"),
    ("{not json", "cannot read"),
])
def test_a_foreign_result_json_is_one_line(run_copy, capsys, summary, field):
    (run_copy / "result.json").write_text(summary)
    with pytest.raises(UvmsInputError, match=field):
        load_result_summary(run_copy)
    assert main(["plot", str(run_copy)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "result.json" in err


@pytest.mark.parametrize("name", ["run_$1_vs_$2", "cost $x^2$", "$", "a$b$c$"])
def test_dollar_signs_in_names_are_drawn_as_written(short_run, tmp_path, capsys, name):  # noqa: F811
    folder = tmp_path / name
    shutil.copytree(short_run[0], folder)
    summary = json.loads((folder / "result.json").read_text())
    summary["metadata"]["scenario"] = name
    summary["complete"], summary["message"] = False, f"diverged at {name}"
    (folder / "result.json").write_text(json.dumps(summary))
    assert main(["plot", str(folder)]) == 0, capsys.readouterr().err
    assert (folder / "timeseries.png").stat().st_size > 20_000


def test_a_plotted_run_stays_replaceable(tmp_path, capsys):
    path = write_scenario(tmp_path, lambda d: d.update(duration=0.01))
    out = tmp_path / "out"
    assert main(["run", str(path), "-o", str(out)]) == 0
    assert main(["plot", str(out)]) == 0
    assert "timeseries.png" in json.loads((out / MARKER).read_text())["files"]
    assert main(["run", str(path), "-o", str(out)]) == 0          # the figure was uvms's: replaced with the run
    assert not (out / "timeseries.png").exists()
