"""uvms.replay against logs that uvms made: a replay of its own run, written in the other frame convention with
encoder offsets and signs, follows the log to the interpolation error; the CLI writes the replay folder whole
and refuses bad input in one line."""

import dataclasses
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


@pytest.mark.parametrize("options, message", [
    (["--step", "0"], "--step: expected a positive, finite number [s], got 0.0"),
    (["--step", "nan"], "--step: expected a positive, finite number [s], got nan"),
    (["--grid", "0"], "--grid: expected a positive, finite number [s], got 0.0"),
    (["--grid", "100"], "--grid: expected at most the log's duration, 7.5 s, got 100.0"),
])
def test_bad_step_or_grid_exit_2_and_write_nothing(own_log, tmp_path, capsys, options, message):
    out = tmp_path / "rp"
    assert main(["replay", "paper", str(own_log[1]), "-o", str(out), *options]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
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


@pytest.fixture(scope="module")
def thruster_log(tmp_path_factory):
    """The BlueROV2 Heavy + Alpha 5 (eight T200 table thrusters, ESC pulse widths [us]) driven by a new command
    every 0.25 s while the arm moves, written as a log with a thrusters stream (replay from 0.5 s on)."""
    model = uvms.load_model("bluerov2_heavy_alpha5")
    rng = np.random.default_rng(3)
    times = np.arange(0.0, 8.5, 0.25)
    pwm = 1500.0 + rng.uniform(-80.0, 80.0, (times.size, len(model.thrusters)))
    table = uvms.CommandSchedule(times, pwm, names=tuple(t.name for t in model.thrusters))
    path, truth = write_log(tmp_path_factory.mktemp("thr"), model, log_frame="enu", commands=table)
    return model, path, truth, table


def test_a_replay_drives_the_models_thrusters_with_the_logged_commands(thruster_log):
    """From the true start (pose, velocities and thrust states), the replay with the logged commands follows
    the log to the interpolation error; the same replay with the thrusters off does not (the commands moved
    the vehicle by tens of centimetres and degrees); the result records the commands held at the log's times."""
    from uvms.identify.experiment import result_signals
    from uvms.replays import plan

    model, path, truth, table = thruster_log
    e = plan(model, path)
    assert e.actuation is not None and e.inputs.thruster_commands is not None
    start = e.initial_state.replace(position=truth.position, quaternion=truth.quaternion, nu=truth.nu,
                                    actuator=truth.actuator)
    enu = model.in_frame("enu")
    run = uvms.simulate(enu, start, duration=e.duration, step=e.step, inputs=e.inputs, actuation=e.actuation,
                        record_period=e.record_period())
    off = uvms.simulate(enu, start, duration=e.duration, step=e.step, record_period=e.record_period(),
                        inputs=uvms.Inputs(joint_motion=e.inputs.joint_motion))
    names = ("roll", "pitch", "yaw", "depth", "x", "y")
    sim, free = (result_signals(r, e.times, names, "enu") for r in (run, off))
    for name in ("roll", "pitch", "yaw"):
        assert np.degrees(np.max(np.abs(sim[name] - e.measured[name]))) < 5e-3, name
        assert np.degrees(np.max(np.abs(free[name] - e.measured[name]))) > 1.0, name
    for name in ("depth", "x", "y"):
        assert np.max(np.abs(sim[name] - e.measured[name])) < 1e-4, name
    assert max(np.max(np.abs(free[n] - e.measured[n])) for n in ("depth", "x", "y")) > 0.1
    k = np.searchsorted(table.times, run.time + 0.5 + 1e-9, side="right") - 1      # the log's clock
    # the CSV holds 10 digits
    np.testing.assert_allclose(run.signals["thruster_command_t3"], table.commands[k, 2], rtol=1e-9)


def test_logged_commands_must_name_the_models_thrusters(thruster_log, tmp_path, capsys):
    model, path, _, _ = thruster_log
    bad = path.parent / "bad_thrusters.yaml"
    bad.write_text(path.read_text().replace("t8: pwm_t8", "t9: pwm_t8"))
    assert main(["replay", "bluerov2_heavy_alpha5", str(bad), "-o", str(tmp_path / "rp")]) == 2
    err = capsys.readouterr().err
    assert "not a thruster of the model: t9; missing t8" in err and len(err.strip().splitlines()) == 1
    assert main(["replay", "hinsdale_bluerov2_alpha5", str(path), "-o", str(tmp_path / "rp")]) == 2
    assert "has no thrusters" in capsys.readouterr().err


def test_animate_draws_the_simulation_and_the_log_in_one_page(own_log, tmp_path):
    """One page, one slider: every frame moves the simulated robot to the run's pose and the faint one to the
    log's pose at the same time (their vehicle trails end there); no second page."""
    from uvms.replays import log_result
    from uvms.view.animate import replay as frames
    from uvms.view.plotly_html import animation_figure

    model, path, _ = own_log
    out = tmp_path / "rp"
    assert main(["replay", "paper", str(path), "-o", str(out), "--animate"]) == 0
    assert (out / "animation.html").is_file() and not (out / "log_animation.html").exists()
    assert "log: vehicle trail" in (out / "animation.html").read_text()

    rp = uvms.replay(model, path)
    shifted = dataclasses.replace(rp.result, states=rp.result.states.copy())
    shifted.states[:, 0] += 0.5                                         # tell the two robots apart
    logged = log_result(rp.log, rp.model, times=rp.result.time)
    sim, log = frames(shifted, rp.model), frames(logged, rp.model)
    fig = animation_figure(sim, ghost=log)
    names = [t.name for t in fig.data]
    main_trail, ghost_trail = names.index("vehicle trail"), names.index("log: vehicle trail")
    for frame in (fig.frames[0], fig.frames[len(fig.frames) // 2], fig.frames[-1]):
        k = int(frame.name)
        by_trace = dict(zip(frame.traces, frame.data))
        end = lambda i: np.array([by_trace[i].x[-1], by_trace[i].y[-1], by_trace[i].z[-1]])   # noqa: E731
        np.testing.assert_allclose(end(main_trail), sim.vehicle_path[k], atol=1e-5)
        np.testing.assert_allclose(end(ghost_trail), log.vehicle_path[k], atol=1e-5)
        assert abs(end(main_trail)[0] - end(ghost_trail)[0] - 0.5) < 0.05
