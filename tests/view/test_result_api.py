"""Python and notebook use: Result.load / state / plot / animate, uvms.show, and short Model/Result summaries
instead of kilobytes of arrays."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.sim.result import Result


def test_load_reads_back_what_was_saved(synthetic_run):
    folder, saved = synthetic_run
    loaded = Result.load(folder)
    assert loaded.n_joints == saved.n_joints == 3
    assert loaded.time == pytest.approx(saved.time)
    assert loaded.position == pytest.approx(saved.position, abs=1e-9)
    assert loaded.q == pytest.approx(saved.q, abs=1e-9)
    assert loaded.end_effector == pytest.approx(saved.end_effector, abs=1e-9)
    assert loaded.rotations() == pytest.approx(saved.rotations(), abs=1e-9)   # rebuilt from the Euler angles
    assert set(loaded.signals) == set(saved.signals)
    assert loaded.signals["thrust_cmd_surge_port"] == pytest.approx(saved.signals["thrust_cmd_surge_port"])
    assert loaded.metadata["scenario"] == "synthetic" and loaded.complete


def test_load_of_a_real_run_matches_its_kinematics(short_run, paper):
    """The loaded end-effector column equals forward kinematics of the loaded states (the quaternion rebuilt
    from the saved Euler angles)."""
    r = Result.load(short_run)
    for k in (0, len(r.time) // 2, -1):
        assert uvms.end_effector_position(paper, r.state(k)) == pytest.approx(r.end_effector[k], abs=1e-8)
    assert r.q[-1, 0] > 0.1                     # joint 1 was driven


def test_load_errors_are_one_line(tmp_path):
    with pytest.raises(UvmsInputError, match="no such run directory"):
        Result.load(tmp_path / "nothing")
    (tmp_path / "empty").mkdir()
    with pytest.raises(UvmsInputError, match="no result.csv here"):
        Result.load(tmp_path / "empty")


def test_state_of_a_sample(synthetic_run):
    _, saved = synthetic_run
    s = saved.state(-1)
    assert isinstance(s, uvms.State)
    assert s.q == pytest.approx([np.pi, 0, 0]) and s.position == pytest.approx([0.4, 0, 0])
    assert s.euler[2] == pytest.approx(np.pi / 2)
    with pytest.raises(IndexError, match="out of range: the run has 41 samples"):
        saved.state(41)


def test_reprs_are_short_summaries(synthetic_run, paper):
    _, saved = synthetic_run
    text = repr(saved)
    assert text.startswith("Result('synthetic', 41 samples, t = 0..2 s, 3 joints") and "array" not in text
    assert len(text) < 200
    html = saved._repr_html_()
    assert "uvms Result" in html and "synthetic" in html and len(html) < 3000
    text = repr(paper)
    assert text.startswith("Model('paper', 3 joints, 35 kg, 4 thrusters") and "array" not in text
    assert len(text) < 300
    html = paper._repr_html_()
    assert "uvms Model" in html and "surge_port" in html and len(html) < 3000


def test_plot_and_animate_return_figures(synthetic_run, paper):
    folder, saved = synthetic_run
    from matplotlib.figure import Figure

    assert isinstance(saved.plot(), Figure)
    fig = Result.load(folder).animate(fps=5)            # the model comes from the folder's scenario.yaml
    assert len(fig.frames) == 11 and fig.layout.sliders[0].steps[-1].label == "2.00"
    moving = fig.frames[0].traces                       # each frame updates the robot's traces, in place
    assert list(moving) == list(range(len(fig.data) - len(moving), len(fig.data)))
    names = next(t for t in fig.data if t.name == "thruster names")
    assert list(names.text) == ["surge_port", "surge_starboard", "heave", "sway"]   # the run's 'paper-sway'
    with pytest.raises(UvmsInputError, match="pass the model"):
        saved.animate()                                 # not read from a folder: no scenario to take it from
    assert len(saved.animate(paper, fps=5).frames) == 11


def test_show_is_exported_and_draws_every_part(paper):
    fig = uvms.show(paper, q=[0.3, -0.5, 0.2])
    names = {t.name for t in fig.data}
    assert {"vehicle", "links", "body x axes", "joint axes", "centre of mass", "centre of buoyancy",
            "thrusters"} <= names
    assert "q = [0.3, -0.5, 0.2] rad" in fig.layout.title.text
    with pytest.raises(UvmsInputError, match="--q: expected 3 joint angles"):
        uvms.show(paper, q=[0.1])
