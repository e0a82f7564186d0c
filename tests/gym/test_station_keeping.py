"""uvms/StationKeeping-v0: Gymnasium's checker, reproducible episodes, zero action = uvms.simulate's drift,
observations against independent rotations, termination and truncation, the vectorised version."""

from __future__ import annotations

import numpy as np
import pytest

import gymnasium  # noqa: E402  (the test extra installs it: these tests always run)

import uvms  # noqa: E402
import uvms.gym  # noqa: E402,F401  (registers the environments)
from uvms.errors import UvmsInputError  # noqa: E402
from uvms.gym.task import rotation_vector_error  # noqa: E402
from uvms.sim.integrate import pack  # noqa: E402
from uvms.sim.options import Actuation  # noqa: E402

ENV_ID = "uvms/StationKeeping-v0"
SHORT = {"duration": 1.0}


def _run(env, seed: int, steps: int, action_seed: int = 0):
    """(observations, rewards) of ``steps`` uniform random actions after ``reset(seed)``."""
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(action_seed)
    space = env.action_space
    observations, rewards = [obs], []
    for _ in range(steps):
        obs, reward, terminated, truncated, _ = env.step(rng.uniform(space.low, space.high))
        observations.append(obs)
        rewards.append(reward)
        assert not (terminated or truncated)
    return np.array(observations), np.array(rewards)


@pytest.mark.parametrize("options", [{}, {"model": "paper", "action": "wrench", "arm": "torque"},
                                     {"model": "paper", "action": "commands"}],
                         ids=["bluerov2-thrusters", "paper-wrench", "paper-commands"])
def test_gymnasium_env_checker_passes(options):
    from gymnasium.utils.env_checker import check_env

    env = gymnasium.make(ENV_ID, **SHORT, **options)
    check_env(env.unwrapped, skip_render_check=True)
    assert env.observation_space.shape == (15 + 2 * env.unwrapped.task.n_joints
                                           + env.unwrapped.task.n_thrust_states,)


def test_reset_with_a_seed_reproduces_the_episode_exactly():
    env = gymnasium.make(ENV_ID, **SHORT)
    obs_a, rewards_a = _run(env, seed=7, steps=40)
    episode_a = env.unwrapped.episode
    _run(env, seed=8, steps=5)                                   # another episode in between
    obs_b, rewards_b = _run(env, seed=7, steps=40)
    np.testing.assert_array_equal(obs_a, obs_b)
    np.testing.assert_array_equal(rewards_a, rewards_b)
    np.testing.assert_array_equal(episode_a.current, env.unwrapped.episode.current)
    obs_c, _ = _run(env, seed=9, steps=40)
    assert not np.allclose(obs_a, obs_c)                         # the seed matters


@pytest.mark.parametrize("action", ["wrench", "thrusters"])
def test_zero_action_drifts_as_simulate_predicts(action):
    """No thrust: the vehicle drifts under the current and the arm's motion exactly as uvms.simulate of the same
    episode (initial state, current, arm tracker) predicts, with ideal zero-wrench actuation. In the thrusters
    mode a zero thrust set point holds each T200 in its dead band: its lag state stays 0."""
    env = gymnasium.make(ENV_ID, **SHORT, action=action, current=0.3).unwrapped
    _, info = env.reset(seed=3)
    episode, steps = info["episode"], 50
    for _ in range(steps):
        obs, *_ = env.step(np.zeros(env.action_space.shape))
    task = env.task
    result = uvms.simulate(task.model, episode.initial_state, duration=steps * task.dt, step=task.h,
                           inputs=episode.inputs, actuation=Actuation())
    final = pack(env.simulator.state)
    expected = result.states[-1]
    np.testing.assert_allclose(final[:expected.size], expected, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(final[expected.size:], 0.0)
    assert np.linalg.norm(expected[:3] - episode.initial_state.position) > 1e-3     # it did drift
    assert np.linalg.norm(expected[13:17] - episode.initial_state.q) > 1e-2         # the arm moved
    # the observation of that state, from uvms's own rotation and scipy's rotation vector
    from scipy.spatial.transform import Rotation

    state = env.simulator.state
    R = state.rotation
    error = state.position - task.target_position
    np.testing.assert_allclose(obs[0:3], error, atol=1e-12)
    np.testing.assert_allclose(obs[3:6], R.T @ error, atol=1e-12)
    np.testing.assert_allclose(obs[6:9], Rotation.from_matrix(R).as_rotvec(), atol=1e-9)   # target: level, yaw 0
    np.testing.assert_allclose(obs[9:15], state.nu, atol=0)
    np.testing.assert_allclose(obs[15:15 + 2 * task.n_joints], np.concatenate([state.q, state.qd]), atol=0)


def test_attitude_error_is_scipys_relative_rotation_vector():
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(1)
    target = Rotation.from_euler("z", 0.7)
    rotations = Rotation.random(20, random_state=rng)
    tq = np.roll(target.as_quat(), 1)                            # scipy: [x y z w]; uvms: [w x y z]
    q = np.roll(rotations.as_quat(), 1, axis=1) * rng.choice([-1.0, 1.0], (20, 1))   # either sign
    expected = (target.inv() * rotations).as_rotvec()
    np.testing.assert_allclose(rotation_vector_error(tq, q), expected, atol=1e-12)


@pytest.mark.parametrize("arm", ["trajectory", "torque", "hold", "none"])
def test_every_arm_mode_moves_the_arm_as_documented(arm):
    """Trajectory and torque modes move the arm; hold keeps it near its pose; none lets it fall (gravity)."""
    env = gymnasium.make_vec(ENV_ID, num_envs=2, arm=arm, threads=1, arm_period=0.2,
                             arm_torque=(0.5, 0.5, 0.5, 0.005))    # the wrist roll is light
    obs, _ = env.reset(seed=1)
    pose = env.unwrapped.task.arm_pose
    for _ in range(50):
        obs, _, terminated, _, _ = env.step(np.zeros((2,) + env.single_action_space.shape))
        assert not terminated.any()
    moved = np.abs(obs[:, 15:19] - pose).max()
    if arm == "hold":
        assert moved < 0.05
    else:
        assert moved > 0.05
    env.close()


def test_truncation_at_the_episode_duration():
    env = gymnasium.make(ENV_ID, duration=0.1, dt=0.02, step=0.002).unwrapped
    env.reset(seed=0)
    ends = [env.step(np.zeros(env.action_space.shape))[3] for _ in range(5)]
    assert ends == [False, False, False, False, True]


def test_tumbling_terminates_with_the_penalty():
    """A full roll moment tips the vehicle past max_tilt: terminated, and the reward loses the penalty per
    step left."""
    env = gymnasium.make(ENV_ID, action="wrench", max_tilt=0.3, initial_attitude=0.0, current=0.0).unwrapped
    env.reset(seed=0)
    action = np.zeros(6)
    action[0] = env.action_space.high[0]
    for k in range(1, 500):
        obs, reward, terminated, truncated, _ = env.step(action)
        if terminated:
            break
    assert terminated and not truncated
    tilt = np.arccos(env.simulator.state.rotation[2, 2])
    assert tilt > 0.3
    left = env.task.max_steps - k
    assert reward < -env.task.termination_penalty * left
    assert env.task.termination_penalty == pytest.approx(1.0 * 5.0 ** 2 + 1.0 * 0.3 ** 2)   # w_p d^2 + w_a tilt^2


def test_vector_env_rows_are_the_single_envs():
    """Environment k of make_vec(seed) behaves as the single environment reset with seed + k, to the bit; an
    ended episode is reset at the next step (reward 0)."""
    n, steps = 3, 12
    venv = gymnasium.make_vec(ENV_ID, num_envs=n, duration=0.1, threads=2)
    assert venv.metadata["autoreset_mode"] == gymnasium.vector.AutoresetMode.NEXT_STEP
    obs, _ = venv.reset(seed=10)
    rng = np.random.default_rng(5)
    space = venv.single_action_space
    actions = rng.uniform(space.low, space.high, (steps, n, space.shape[0]))
    rows = [obs]
    rewards, truncations = [], []
    for a in actions:
        obs, reward, terminated, truncated, _ = venv.step(a)
        rows.append(obs)
        rewards.append(reward)
        truncations.append(truncated)
        assert not terminated.any()
    rows, rewards, truncations = np.array(rows), np.array(rewards), np.array(truncations)
    assert truncations[9].all() and not truncations[:9].any()       # 0.1 s of 10 ms steps
    np.testing.assert_array_equal(rewards[10], 0.0)                   # the autoreset step
    again, _ = venv.reset(seed=[10, 11, 12])
    np.testing.assert_array_equal(again, rows[0])
    single = gymnasium.make(ENV_ID, duration=0.1).unwrapped
    for k in range(n):
        o, _ = single.reset(seed=10 + k)
        np.testing.assert_array_equal(rows[0, k], o)
        for s in range(10):
            o, r, *_ = single.step(actions[s, k])
            np.testing.assert_array_equal(rows[s + 1, k], o)
            assert rewards[s, k] == r
    venv.close()


def test_bad_options_are_one_clear_error():
    no_thrusters = uvms.load_model("paper").replace(thrusters=())
    with pytest.raises(UvmsInputError, match="action"):
        gymnasium.make(ENV_ID, model=no_thrusters, action="thrusters")
    assert gymnasium.make(ENV_ID, model=no_thrusters).unwrapped.task.action == "wrench"
    with pytest.raises(UvmsInputError, match="action"):
        gymnasium.make(ENV_ID, action="torque")
    with pytest.raises(UvmsInputError, match="dt"):
        gymnasium.make(ENV_ID, dt=0.015, step=0.01)
    with pytest.raises(UvmsInputError, match="arm"):
        gymnasium.make(ENV_ID, arm="wave")
    with pytest.raises(UvmsInputError, match="weights.effort"):
        gymnasium.make(ENV_ID, weights=uvms.gym.Weights(effort=-1.0))
    with pytest.raises(UvmsInputError, match="arm_torque"):
        gymnasium.make(ENV_ID, arm_torque=[1.0, 2.0])
    with pytest.raises(UvmsInputError, match="max_tilt"):
        gymnasium.make(ENV_ID, max_tilt=0.0)
    with pytest.raises(TypeError, match="colour"):
        gymnasium.make(ENV_ID, colour="red")


@pytest.mark.slow
def test_default_step_agrees_with_a_five_times_finer_one():
    """The default 5 ms RK4 step against 1 ms on the default model under random thrusts (docs/gym.md's step
    study): RK4's fourth-order error stays far below what a station keeper resolves."""
    finals = []
    for step in (0.005, 0.001):
        env = gymnasium.make(ENV_ID, step=step, current=0.2).unwrapped
        env.reset(seed=3)
        rng = np.random.default_rng(0)
        for _ in range(100):
            obs, _, terminated, _, _ = env.step(0.5 * rng.uniform(env.action_space.low, env.action_space.high))
            assert not terminated
        finals.append(obs)
    coarse, fine = finals
    assert np.linalg.norm(fine[0:3]) > 0.01                      # the vehicle did move
    np.testing.assert_allclose(coarse[0:3], fine[0:3], atol=1e-5)            # position [m]
    np.testing.assert_allclose(coarse[6:9], fine[6:9], atol=1e-5)            # attitude [rad]
    np.testing.assert_allclose(coarse[23:], fine[23:], atol=1e-2)            # thrusts [N]


def test_commands_mode_spans_the_thrust_limits():
    """The T200's commands: the action box is the PWM range giving the datasheet's thrust limits (1100-1900 us
    at 16 V) and the command of zero thrust (1500 us, the dead band's centre) drifts as zero thrust does."""
    env = gymnasium.make(ENV_ID, action="commands", **SHORT).unwrapped
    np.testing.assert_allclose(env.action_space.low, 1100.0)
    np.testing.assert_allclose(env.action_space.high, 1900.0)
    np.testing.assert_allclose(env.task.offset, 1500.0, atol=5.0)
    thrust = gymnasium.make(ENV_ID, action="thrusters", **SHORT).unwrapped
    env.reset(seed=2)
    thrust.reset(seed=2)
    for _ in range(10):
        a, ra, *_ = env.step(env.task.offset)
        b, rb, *_ = thrust.step(np.zeros(8))
    np.testing.assert_array_equal(a, b)
    assert ra == rb


@pytest.mark.parametrize("action, words", [
    (np.zeros(7), "expected 8 finite values (the action space's thrusters bounds: shape (8,)), got shape (7,)"),
    (np.zeros((1, 8)), "got shape (1, 8)"),
    (None, "got None"),
    ("forward", "'forward'"),
    ([True] * 8, "got values of type bool"),
    (np.full(8, np.nan), "got nan at index 0"),
    (np.r_[np.zeros(7), np.inf], "got inf at index 7"),
])
def test_bad_actions_are_one_line_naming_the_action(action, words):
    """Gymnasium leaves invalid actions to the environment: an action of the wrong shape or type, or not finite,
    is one UvmsInputError line (a ValueError) naming ``action``; the episode does not advance. Finite actions
    outside the box are clipped."""
    env = gymnasium.make(ENV_ID, **SHORT).unwrapped
    env.reset(seed=0)
    before = pack(env.simulator.state)
    with pytest.raises(UvmsInputError) as info:
        env.step(action)
    assert isinstance(info.value, ValueError) and str(info.value) == f"action: {info.value.message}"
    assert words in str(info.value) and "\n" not in str(info.value)
    assert env.simulator.steps_done == 0 and np.array_equal(pack(env.simulator.state), before)
    env.step(np.full(8, 1e9))                                      # clipped to the box: fine


def test_bad_vector_actions_change_nothing():
    venv = gymnasium.make_vec(ENV_ID, num_envs=2, duration=0.1, threads=1)
    venv.reset(seed=0)
    x = venv.unwrapped.batch.x.copy() if hasattr(venv, "unwrapped") else venv.batch.x.copy()
    batch = venv.unwrapped.batch if hasattr(venv, "unwrapped") else venv.batch
    for bad, words in ((np.zeros((3, 8)), "got shape (3, 8)"), (np.full((2, 8), np.nan), "got nan at row 0"),
                       (None, "got None")):
        with pytest.raises(UvmsInputError, match=r"^actions: expected 2 rows of 8 finite values") as info:
            venv.step(bad)
        assert words in str(info.value)
    np.testing.assert_array_equal(batch.x, x)
    assert (batch.done == 0).all()
    venv.close()


@pytest.mark.parametrize("options, argument", [
    ({"duration": 1e12}, "duration"),
    ({"duration": 3601.0}, "duration"),
    ({"arm_period": 1e-9}, "arm_period"),
    ({"step": 1e-9, "dt": 1e-9}, "step"),
    ({"dt": 1e6, "step": 0.005}, "dt"),
])
def test_sizes_beyond_the_limits_are_refused_at_once(options, argument):
    """``duration=1e12`` used to run out of memory drawing the episode: the episode is at most the step API's
    horizon (3600 s), the arm motion at most MAX_ARM_KNOTS knots, the step at least horizon / MAX_STEPS; each
    refused in well under a second, naming the option."""
    import time

    tic = time.perf_counter()
    with pytest.raises(UvmsInputError, match=rf"^{argument}: expected"):
        gymnasium.make(ENV_ID, **options)
    assert time.perf_counter() - tic < 1.0


def test_a_million_vector_environments_are_refused_at_once():
    import time

    from uvms.sim.batch_stepper import MAX_MEMBERS

    tic = time.perf_counter()
    with pytest.raises(UvmsInputError, match=rf"^num_envs: expected at most {MAX_MEMBERS} environments"):
        gymnasium.make_vec(ENV_ID, num_envs=10**6)
    assert time.perf_counter() - tic < 1.0
