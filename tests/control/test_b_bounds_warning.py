"""The sliding-mode ``b`` bounds warning: only a controller that relies on fixed bounds (``smc-ab``, ``smc-ne``,
``smc-vehicle`` with ``b_source: fixed``) warns, when a command is about to use it, in one line naming every
axis they miss, and the three of a comparison warn once; ``pid``, ``lqr``, ``b_source: model`` and bounds that
contain the plant do not warn; a sweep's workers never do."""

from __future__ import annotations

import warnings

import pytest

import uvms
from uvms.control.registry import make_controller
from uvms.control.smc import warn_controller_b_bounds


@pytest.fixture(scope="module")
def bluerov():
    return uvms.load_model("bluerov2_heavy_alpha5")


def _built(model, *specs) -> list[str]:
    """The warning lines shown (Python's default filter: each distinct warning once) while building ``specs``."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        for name, parameters in specs:
            warn_controller_b_bounds(make_controller(name, model, period=0.01, parameters=parameters))
    return [str(w.message) for w in caught if "b bounds" in str(w.message)]


def test_sliding_mode_controllers_warn_once_naming_every_axis(bluerov):
    shown = _built(bluerov, *[(name, {}) for name in ("smc-ab", "smc-ne", "smc-vehicle", "smc-ab")])
    assert len(shown) == 1
    line = shown[0]
    assert line.startswith("sliding-mode controller: its b bounds miss model 'bluerov2_heavy_alpha5' (arm at q = 0)")
    for part in ("surge effective mass 21.19 kg outside [36, 44.44] kg",
                 "sway effective mass 21.43 kg outside [36, 44.44] kg",
                 "yaw effective inertia 0.6374 kg m^2 outside [1.287, 1.5889] kg m^2",
                 "b_source: model"):
        assert part in line
    assert "\n" not in line


@pytest.mark.parametrize("name, parameters", [
    ("pid", {}), ("lqr", {}),
    ("smc-ab", {"b_source": "model"}),
    ("smc-ab", {"b_surge": [15, 30], "b_sway": [15, 30], "b_yaw": [0.5, 0.8]}),
    ("smc-vehicle", {"axes": ["heave", "roll", "pitch"]}),         # axes without bounds: b from the model
])
def test_controllers_that_do_not_rely_on_bounds_that_miss_do_not_warn(bluerov, name, parameters):
    assert _built(bluerov, (name, parameters)) == []


def test_building_or_running_a_controller_does_not_warn(bluerov):
    """Building it (a command that then refuses its input says only the error) or compiling it for a run (a
    sweep's worker) is silent: the warning is the command's, before it runs."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        make_controller("smc-ab", bluerov, period=0.01).compiled(4)
    assert caught == []


def test_only_the_axes_in_use_are_named(bluerov):
    (line,) = _built(bluerov, ("smc-ab", {"axes": ["surge", "heave"]}))
    assert "surge effective mass" in line and "sway" not in line and "yaw" not in line


def test_the_cli_shows_a_warning_as_one_line_once(monkeypatch, capsys):
    """Python warnings during a command are ``uvms: warning: ...`` on stderr, each distinct one once."""
    import importlib

    from uvms.cli import main

    def run(args):
        for _ in range(3):
            warn_controller_b_bounds(make_controller("smc-ab", uvms.load_model("bluerov2_heavy_alpha5"), period=0.01))
        return 0

    monkeypatch.setattr(importlib.import_module("uvms.commands.validate"), "run", run)
    assert main(["validate", "paper"]) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("uvms: warning: sliding-mode controller: its b bounds miss")


def test_uvms_run_and_compare_warn_before_running(monkeypatch, capsys, tmp_path):
    """``uvms run`` with an smc-ab scenario says it once before simulating, ``pid`` says nothing; every case of
    a comparison is checked (no simulation here: the runs are replaced)."""
    import uvms.sim.scenario as scenario_module
    from uvms.cli import main
    from uvms.control import compare

    ran = []

    def no_run(scenario, progress=None):
        ran.append(scenario.name)
        raise KeyboardInterrupt                   # stop before anything is simulated or written

    monkeypatch.setattr(scenario_module, "run_scenario", no_run)
    assert main(["run", "bluerov2_heavy_alpha5_hold6", "-o", str(tmp_path / "a")]) == 130
    err = capsys.readouterr().err.splitlines()
    assert ran == ["bluerov2_heavy_alpha5_hold6"] and len(err) == 2
    assert err[0].startswith("uvms: warning: sliding-mode controller: its b bounds miss model 'bluerov2_heavy_alpha5'")
    assert main(["run", "bluerov2_heavy_alpha5_reach", "-o", str(tmp_path / "b")]) == 130     # pid
    assert capsys.readouterr().err == "uvms: interrupted\n"

    monkeypatch.setattr("uvms.sim.run.simulate", lambda **options: options["controller"])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        labels = [c.label for c in compare.SIX_AXIS_CASES]
        built = [compare.run_case(None, case, scenario="bluerov2_heavy_alpha5_hold6")
                 for case in compare.SIX_AXIS_CASES]
    assert len(built) == len(labels)
    assert [str(w.message)[:40] for w in caught if "b bounds" in str(w.message)] == [
        "sliding-mode controller: its b bounds mi"]
