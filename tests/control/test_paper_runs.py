"""The paper's runs are defined once, in the bundled scenario files: ``uvms compare`` and ``uvms reproduce``
run exactly what ``uvms run`` runs, and the paper's constants are the sliding-mode defaults."""

from __future__ import annotations

import ast
import copy
from importlib.resources import files
from pathlib import Path

import numpy as np
import yaml

import uvms

CASE3 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case3_controlled.yaml").read_text())


def _same_run(a, b) -> None:
    assert a.complete and b.complete
    assert np.array_equal(a.time, b.time)
    np.testing.assert_allclose(a.states, b.states, rtol=0, atol=1e-12)
    assert set(a.signals) == set(b.signals)
    for name in a.signals:
        np.testing.assert_allclose(a.signals[name], b.signals[name], rtol=0, atol=1e-12, equal_nan=True)


def test_compare_runs_the_scenario_file_with_ideal_actuation():
    """``run_case`` = ``uvms run paper_case3_controlled`` with ``actuators: ideal`` (shortened to 2 s)."""
    from uvms.control.compare import Case, run_case
    from uvms.sim.scenario import run_scenario, scenario_from_data

    data = copy.deepcopy(CASE3)
    data.update(duration=2.5, actuators="ideal")
    scenario = scenario_from_data(data)
    _same_run(run_case(scenario.model, Case("smc-ab", "smc-ab"), duration=2.5), run_scenario(scenario))


def test_reproduce_runs_the_scenario_files():
    """The report's controlled case with Healey thrusters (``--actuators healey``: the paper layout with a sway
    thruster) is ``uvms run paper_case3_controlled``; the fixed case is ``paper_case1_fixed``."""
    from uvms.reproduce import cases as reproduce
    from uvms.sim.scenario import load_scenario, run_scenario

    model = uvms.load_model("paper")
    for case, actuators in (("controlled", "healey"), ("fixed", "ideal")):
        mine = reproduce._simulate_case(model, case, actuators)
        _same_run(mine, run_scenario(load_scenario(reproduce.CASE_SCENARIOS[case])))
    assert reproduce.CONTROL_PERIOD == CASE3["controller"]["period"] and reproduce.DURATION == CASE3["duration"]


def test_the_paper_constants_are_the_sliding_mode_defaults():
    from uvms import reproduce
    from uvms.control.smc import SlidingModeParameters

    paper = SlidingModeParameters()
    assert paper.bandwidth == (reproduce.PAPER_LAMBDA,) * len(paper.axes)        # one value on every paper axis
    assert paper.boundary_layer == (reproduce.PAPER_PHI,) * len(paper.axes)
    assert reproduce.PAPER_MODEL_ERROR == paper.hydro_scale
    assert reproduce.PAPER_B == {"surge": paper.b_surge, "sway": paper.b_sway, "yaw": paper.b_yaw}


def test_no_paper_constant_is_typed_twice_in_the_package():
    """lambda = 3.14, Phi = 0.02 and the b bounds appear as numbers only in ``control/smc.py``."""
    root = Path(uvms.__file__).parent
    paper = {3.14, 0.02, 36.0, 44.44, 1.287, 1.5889}
    found = []
    for path in root.rglob("*.py"):
        if path.name == "smc.py" and path.parent.name == "control":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and type(node.value) is float and node.value in paper:
                found.append(f"{path.relative_to(root)}:{node.lineno} {node.value}")
    allowed = {"plots.py", "view/plotly_html.py"}            # 0.02 there is a layout fraction, not Phi
    assert [f for f in found if f.split(":")[0] not in allowed] == []
