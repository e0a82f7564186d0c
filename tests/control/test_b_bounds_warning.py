"""The sliding-mode ``b`` bounds warning: only a controller that relies on fixed bounds (``smc-ab``, ``smc-ne``,
``smc-vehicle`` with ``b_source: fixed``) warns, in one line naming every axis they miss, and the three of a
comparison warn once; ``pid``, ``lqr``, ``b_source: model`` and bounds that contain the plant do not warn."""

from __future__ import annotations

import warnings

import pytest

import uvms
from uvms.control.registry import make_controller


@pytest.fixture(scope="module")
def bluerov():
    return uvms.load_model("bluerov2_heavy_alpha5")


def _built(model, *specs) -> list[str]:
    """The warning lines shown (Python's default filter: each distinct warning once) while building ``specs``."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        for name, parameters in specs:
            controller = make_controller(name, model, period=0.01, parameters=parameters)
            if hasattr(controller, "compiled"):
                controller.compiled(4)            # what a run builds when it starts: the controller in use
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


def test_building_a_controller_does_not_warn_before_its_run(bluerov):
    """A command that refuses its input after building the controllers says only the error."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        make_controller("smc-ab", bluerov, period=0.01)
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
            make_controller("smc-ab", uvms.load_model("bluerov2_heavy_alpha5"), period=0.01).compiled(4)
        return 0

    monkeypatch.setattr(importlib.import_module("uvms.commands.validate"), "run", run)
    assert main(["validate", "paper"]) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("uvms: warning: sliding-mode controller: its b bounds miss")
