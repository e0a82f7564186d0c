"""uvms.replay against logs that uvms made: a replay of its own run, written in the other frame convention with
encoder offsets and signs, follows the log to the interpolation error; the CLI writes the replay folder whole
and refuses bad input in one line."""

import json

import numpy as np
import pytest

import uvms
from tests.replays.synthetic import write_log
from uvms.cli import main


@pytest.fixture(scope="module")
def own_log(tmp_path_factory):
    model = uvms.load_model("paper")                           # written z down (ned)
    path, truth = write_log(tmp_path_factory.mktemp("own"), model, log_frame="enu")
    return model, path, truth


def test_from_the_true_start_a_replay_of_its_own_run_follows_the_log(own_log):
    """What is left is interpolation: the pose linear between 10 ms samples, the joints re-splined through
    20 ms encoder samples (of a motion with knots every 100 ms)."""
    from uvms.identify.experiment import result_signals
    from uvms.replays import plan

    model, path, truth = own_log
    e = plan(model, path)
    start = e.initial_state.replace(position=truth.position, quaternion=truth.quaternion, nu=truth.nu)
    run = uvms.simulate(model.in_frame("enu"), start, duration=e.duration, step=e.step, inputs=e.inputs,
                        record_period=e.record_period())
    sim = result_signals(run, e.times, ("roll", "pitch", "yaw", "depth"), "enu")
    held = {k: np.degrees(np.sqrt(np.mean(v ** 2))) for k, v in e.measured.items() if k != "roll"}
    assert held["pitch"] > 0.5 and held["yaw"] > 0.5                    # the arm moved the vehicle
    for name in ("roll", "pitch", "yaw"):
        assert np.degrees(np.max(np.abs(sim[name] - e.measured[name]))) < 2e-3, name
    assert np.max(np.abs(sim["depth"] - e.measured["depth"])) < 1e-5
    np.testing.assert_allclose(e.initial_state.q, truth.q, atol=1e-6)


def test_the_start_velocities_come_from_the_log_and_the_replay_has_skill(own_log):
    """From the log's own start estimate (a 0.2 s quadratic fit, ``docs/logs.md``) the run still follows the
    log within a small fraction of the no-skill score: the fitted rates are within 2 % of the true ones."""
    model, path, truth = own_log
    rp = uvms.replay(model, path)
    s = rp.scores
    assert rp.log.frame == "enu" and rp.model.convention == "enu"
    np.testing.assert_allclose(rp.experiment.initial_state.nu, truth.nu, rtol=0.02, atol=2e-4)
    for rmse, held in ((s.roll_rmse_deg, s.roll_no_skill_rmse_deg), (s.pitch_rmse_deg, s.pitch_no_skill_rmse_deg),
                       (s.yaw_change_rmse_deg, s.yaw_change_no_skill_rmse_deg)):
        assert rmse < 0.03 * held


def test_the_replay_in_the_models_own_frame_is_the_same_motion(own_log, tmp_path):
    model = own_log[0]
    path, _ = write_log(tmp_path, model, log_frame="ned")
    a, b = uvms.replay(model, own_log[1]), uvms.replay(model, path)
    for name in ("roll", "pitch", "yaw", "depth"):
        sign = -1.0 if name in ("pitch", "yaw") else 1.0        # enu -> ned: (roll, -pitch, -yaw), depth alike
        np.testing.assert_allclose(sign * a.simulated[name], b.simulated[name], atol=1e-9)


def test_the_cli_writes_the_replay_folder(own_log, tmp_path, capsys):
    path = own_log[1]
    out = tmp_path / "rp"
    assert main(["replay", "paper", str(path), "-o", str(out)]) == 0
    names = sorted(p.name for p in out.iterdir())
    assert {"result.csv", "result.json", "comparison.json", "comparison.png"} <= set(names)
    data = json.loads((out / "comparison.json").read_text())
    assert data["frame"] == "enu" and data["pitch_rmse_deg"] < 1e-2
    assert "pitch" in capsys.readouterr().out


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.replace("duration: 7.5", "duration: 80.0"), "shorter than asked"),
    (lambda t: t.replace("enc0", "enc9"), "enc9"),
    (lambda t: t.replace("frame: enu", "frame: nwu"), "frame"),
])
def test_bad_logs_exit_2_and_write_nothing(own_log, tmp_path, capsys, edit, message):
    path = own_log[1]
    bad = path.parent / "bad.yaml"
    bad.write_text(edit(path.read_text()))
    out = tmp_path / "rp"
    assert main(["replay", "paper", str(bad), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_the_default_folder_is_named_after_the_log_but_never_chosen_by_it(own_log, tmp_path, monkeypatch):
    path = own_log[1]
    monkeypatch.chdir(tmp_path)
    assert main(["replay", "paper", str(path)]) == 0
    assert (tmp_path / "replays" / "trial" / "comparison.json").is_file()
    odd = path.parent / "...yaml"                       # its stem is "..": the default would be the working folder
    odd.write_text(path.read_text())
    assert main(["replay", "paper", str(odd)]) == 0
    assert (tmp_path / "replays" / "replay" / "comparison.json").is_file()
