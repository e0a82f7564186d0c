"""Compile every kernel uvms runs, ahead of its first use: what ``pip install`` does (``uvms precompile``).

numba compiles a kernel the first time it is called with a given set of argument types and keeps the machine
code in its cache (:mod:`uvms._cache`). The types do not depend on the numbers (a model of any size, any
duration, any controller gain gives the same types), so a few milliseconds of every kind of run compile
everything a real run needs: :func:`workloads` lists them, each a short run of

- every bundled scenario, and every controller on the paper model (ideal and thruster actuation) and on the
  BlueROV2 Heavy + Alpha 5 (its thrusters);
- the Python API on both bundled models: forward and inverse dynamics, mass matrix, bias forces, hydrodynamic
  wrenches, poses, linearisation, trim, a simulation and a prescribed joint motion (``uvms.JointMotion``);
- the batch and step APIs (``uvms.rollout``, ``uvms.Simulator``), the Gymnasium environments, the thruster
  curves of ``uvms thruster-curve``;
- the compiled code called from Python outside a run ("python paths"): the dynamics of a ``State.trusted`` and
  of read-only torques, energy and momentum, a joint trajectory evaluated, the sliding-mode axis kinematics,
  and the adaptive (``solve_ivp``) integrator;
- the kernels that code may call itself ("kernels called directly": the spatial-algebra, hydrodynamic and
  thruster kernels, the thrust allocation's fast path, the dynamics on a ``ModelData``, the event schedule)
  with the argument types of a call from Python: C-ordered float64 arrays, Python floats and bools.

numba compiles one signature per combination of argument types, and a read-only array is another type than a
writeable one: the API passes the kernels one kind where it can (``Dynamics`` hands them a read-only state
vector and writeable inputs), and the workloads call each entry point with every kind a real run gives it. What
the test suite compiles besides (its own small kernels) is left to compile at first use.

``python -m uvms.precompile [--into FOLDER] [--jobs N]`` runs them in ``N`` processes (default: the number of
cores, at most 2), each one writing into the same cache. With ``--into FOLDER`` the cache is
``FOLDER/numba-<fingerprint>`` (the package's ``_kernels`` folder at install; :func:`uvms._cache.seed` copies it
into a user's empty cache); without it, the user's own cache. A workload that fails is reported and skipped: a
kernel it would have compiled then compiles at first use, as without this step.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable

SHORT = 0.03
"""Duration of each short run [s]: a few controller updates and record rows, every branch of the loop once."""

SCENARIOS = ("paper_case1_fixed", "paper_case2_released", "paper_case3_controlled", "bluerov2_heavy_alpha5_hold6",
             "bluerov2_heavy_alpha5_reach")


def _scenario(name: str, **changes) -> None:
    """A bundled scenario shortened to :data:`SHORT` seconds (and ``changes`` applied to its fields), run."""
    import uvms
    from uvms.safe_yaml import read_yaml_mapping
    from uvms.sim.scenario import run_scenario, scenario_from_data

    path = Path(uvms.__file__).parent / "scenarios" / f"{name}.yaml"
    data = read_yaml_mapping(path, "scenario fields")
    data.update(duration=SHORT, **changes)
    trajectory = (data.get("inputs") or {}).get("joint_trajectory")
    if trajectory:                       # the same knots, squeezed into the short run
        knots = len(trajectory["times"])
        trajectory["times"] = [SHORT * k / max(knots - 1, 1) for k in range(knots)]
    result = run_scenario(scenario_from_data(data, source=str(path), base_dir=path.parent, default_name=name))
    result.summary()                     # what `uvms run` prints: Euler angles, metrics, health
    result.to_dataframe()


def _controllers(scenario: str, names: tuple[str, ...], actuators: tuple[str, ...]) -> Callable[[], None]:
    def run() -> None:
        for actuator in actuators:
            for name in names:
                parameters = {"imu_noise": 0.01} if name == "smc-ne-noisy" else {}
                controller = {"name": name.replace("-noisy", ""), "period": 0.01, "parameters": parameters}
                _scenario(scenario, controller=controller, actuators=actuator)
    return run


def _api() -> None:
    """The Python API's compiled entry points on both bundled models."""
    import numpy as np

    import uvms

    for name in ("paper", "bluerov2_heavy_alpha5"):
        model = uvms.load_model(name)
        n = model.n_joints if hasattr(model, "n_joints") else len(model.joint_names)
        state = uvms.State.from_euler(model, q=np.full(n, 0.1))
        uvms.forward_dynamics(model, state, joint_torques=np.zeros(n))
        acc = uvms.forward_dynamics(model, state)
        uvms.inverse_dynamics(model, state, nu_dot=acc.nu_dot, qdd=acc.qdd)
        uvms.mass_matrix(model, state)
        uvms.bias_forces(model, state)
        uvms.hydrodynamic_wrenches(model, state)
        uvms.end_effector_position(model, state)
        uvms.frame_poses(model, state)
        uvms.linearize(model, state)
        uvms.trimmed_state(model)
        uvms.simulate(model, duration=SHORT, step=1e-3)
        motion = uvms.JointMotion.from_arrays([0.0, 2 * SHORT], np.full((2, n), 0.1))    # a prescribed replay
        uvms.simulate(model, duration=SHORT, step=1e-3, joint_motion=motion)
        flow = _every_flow()                     # the water of every kind: one compiled type, its branches
        flow.at(0.0, np.zeros((2, 3)), model.convention)
        uvms.simulate(model, duration=SHORT, step=1e-3, flow=flow)
        uvms.simulate(model, duration=SHORT, step=1e-3, flow=flow, joint_motion=motion)
        from uvms.dynamics.inspect import hydrodynamic_wrenches_in

        hydrodynamic_wrenches_in(model, state, flow, 0.0)


def _every_flow():
    """A :class:`~uvms.hydro.flow.Flow` with every part (profile, field, two wave components)."""
    from types import SimpleNamespace

    import numpy as np

    from uvms.hydro.flow import Flow

    profile = SimpleNamespace(depth=np.array([0.0, 10.0]), velocity=np.array([[0.2, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    axis = np.array([-100.0, 100.0])
    field = SimpleNamespace(x=axis, y=axis, z=axis, t=np.array([0.0]), velocity=np.zeros((1, 2, 2, 2, 3)),
                            outside="hold")
    waves = SimpleNamespace(amplitude=np.array([0.1, 0.05]), omega=np.array([1.5, 2.0]),
                            wavenumber=np.array([0.25, 0.41]), direction=np.array([0.0, 0.3]),
                            phase=np.array([0.0, 1.0]), water_depth=20.0)
    return Flow.constant(profile=profile, field=field, waves=waves)


def _batch() -> None:
    """``uvms.rollout`` (threads), the step API and the batch stepper."""
    import uvms
    from uvms.control.registry import make_controller
    from uvms.sim.inputs import paper_torques

    model = uvms.load_model("paper")
    trials = [uvms.Trial(hydro_scale=s, controller=make_controller("smc-ab", model, period=0.01)) for s in (0.9, 1.1)]
    uvms.rollout(model, trials, duration=SHORT, joint_torques=paper_torques(), threads=2)
    uvms.rollout(model, [uvms.Trial(hydro_scale=1.0)], duration=SHORT, joint_torques=paper_torques(), threads=1)
    simulator = uvms.Simulator(model, controller=make_controller("smc-ab", model, period=0.01))
    simulator.step(SHORT)
    simulator.reset()
    simulator.step(SHORT, body_wrench=[0, 0, 0, 1.0, 0, 0])


def _gym() -> None:
    """The Gymnasium environment, single and vectorised (skipped without gymnasium)."""
    try:
        import gymnasium  # noqa: F401
    except ImportError:
        return
    import numpy as np

    import uvms.gym  # noqa: F401  (registers the environments)

    env = gymnasium.make("uvms/StationKeeping-v0")
    env.reset(seed=0)
    env.step(np.zeros(env.action_space.shape))
    from uvms.gym.vector import StationKeepingVectorEnv

    vector = StationKeepingVectorEnv(num_envs=2)
    vector.reset(seed=0)
    vector.step(np.zeros(vector.action_space.shape))


def _thrusters() -> None:
    """The Healey thruster curve of ``uvms thruster-curve``."""
    from uvms.thrusters.curve import default_voltages, step_responses, thrust_curve
    from uvms.thrusters.healey import HealeyParameters

    params = HealeyParameters()
    thrust_curve(params, default_voltages(params)[:2], duration=SHORT)
    step_responses(params, default_voltages(params)[:2], duration=SHORT)


def _python_paths() -> None:
    """What is compiled from Python outside the compiled loop: the dynamics of a ``State.trusted`` and of
    read-only torques, the energy and momentum of :mod:`uvms.dynamics.energy`, a joint trajectory evaluated
    (``JointTrajectory(t)``), the sliding-mode axis kinematics of :mod:`uvms.control.smc`, and the adaptive
    integrator (``solve_ivp``: the state derivative and the loop's event schedule, from Python)."""
    import numpy as np

    import uvms
    from uvms.control.arm import JointTrajectory
    from uvms.control.smc import axis_kinematics
    from uvms.dynamics.energy import kinetic_energy, potential_energy, spatial_momentum

    model = uvms.load_model("paper")
    n = model.n_joints
    state = uvms.State.from_euler(model, euler=[0.1, 0.2, 0.3], nu=np.full(6, 0.1), q=np.full(n, 0.1))
    trusted = uvms.State.trusted(*(np.array(getattr(state, k)) for k in ("position", "quaternion", "nu", "q", "qd",
                                                                          "actuator")))
    read_only = np.zeros(n)
    read_only.flags.writeable = False
    for s in (state, trusted):
        acc = uvms.forward_dynamics(model, s, joint_torques=read_only)
        uvms.inverse_dynamics(model, s, nu_dot=acc.nu_dot, qdd=acc.qdd)
    kinetic_energy(model, state)
    potential_energy(model, state)
    spatial_momentum(model, state)
    JointTrajectory([0.0, SHORT], np.full((2, n), 0.1))(0.5 * SHORT)
    kinematics = axis_kinematics(state, np.zeros(3), 0.0)
    kinematics.accelerations(np.zeros(6), "body_velocity")
    uvms.simulate(model, duration=SHORT, step=1e-3, integrator="RK45")


def _kernels_called_directly() -> None:
    """The compiled kernels that code may call itself (the spatial-algebra and hydrodynamic helpers, the
    thruster models, the thrust allocation's fast path, the dynamics on a ``ModelData``, the loops' event
    schedule), with C-ordered float64 arrays and Python floats and bools: the types a call from Python gives
    them (a kernel's callers inside the compiled code give others, compiled with them)."""
    import numpy as np

    import uvms
    from uvms.dynamics import blocks
    from uvms.dynamics.plant import fluid_table, forward_into, model_data
    from uvms.hydro.buoyancy import buoyancy_force
    from uvms.hydro.drag import link_drag_force, vehicle_drag_force
    from uvms.hydro.fossen import fossen_cross_damping_force, fossen_damping_force
    from uvms.sim.plan import events
    from uvms.thrusters.allocation import allocate_pinv
    from uvms.thrusters.first_order import FirstOrderParameters, first_order_rk4_step
    from uvms.thrusters.healey import HealeyParameters, healey_bank_derivatives
    from uvms.thrusters.table import t200_table, table_rk4_step

    v3, v6, out6, eye3, eye6, L = np.zeros(3), np.ones(6), np.zeros(6), np.eye(3), np.eye(6), np.zeros((6, 6))
    blocks.crm_mul(v6, v6, out6)
    blocks.crf_mul_add(v6, v6, 2.0, out6)
    blocks.plucker(eye3, v3, L)
    blocks.congruence_add_plucker(eye3, v3, eye6, L, np.zeros((6, 6)))
    blocks.transform_motion(eye3, v3, v6, out6)
    blocks.transform_force_add(eye3, v3, v6, out6)
    blocks.cholesky_factor(eye6, L)
    blocks.cholesky_solve(L, v6, out6)
    blocks.cholesky_solve6(eye6, v6, L, out6)
    buoyancy_force(1.0, v3, v3, v3, out6)
    link_drag_force(1.0, 1.0, v6, out6)
    vehicle_drag_force(v3, v3, v6, out6)
    fossen_damping_force(eye6, eye6, v3, v6, out6)
    fossen_cross_damping_force(np.zeros((36, 6)), np.zeros((36, 6)), v3, v6, out6)
    allocate_pinv(np.zeros((4, 6)), v6, -np.ones(4), np.ones(4), np.zeros(4))
    first_order_rk4_step(FirstOrderParameters().as_array(), 0.0, 1.0, 1e-3)
    table_rk4_step(t200_table(time_constant=0.05).as_array(), 0.0, 1500.0, 1e-3)
    bank, z2 = np.stack([HealeyParameters().as_array()] * 2), np.zeros(2)
    healey_bank_derivatives(bank, z2, z2, z2, np.empty(2), np.empty(2), np.empty(2))
    list(events(10, (3, 0), [5]))         # the loops' event schedule, stepped from Python
    model = uvms.load_model("paper")
    n = model.n_joints
    forward_into(model_data(model), np.eye(3), np.zeros(3), np.zeros(6), np.zeros(n), np.zeros(n), np.zeros(n),
                 np.zeros(6), np.zeros(6), fluid_table([0.0], [v3], [v3]), 0.0, False, np.zeros(6), np.zeros(n))


def workloads() -> dict[str, Callable[[], None]]:
    """Every kind of run, by name (module docstring); each compiles what it reaches."""
    return {
        **{f"scenario {name}": (lambda name=name: _scenario(name)) for name in SCENARIOS},
        "paper controllers": _controllers("paper_case3_controlled",
                                          ("smc-ab", "smc-ne", "smc-ne-noisy", "smc-vehicle", "pid", "lqr"),
                                          ("ideal", "paper-sway")),
        "bluerov2 controllers": _controllers("bluerov2_heavy_alpha5_hold6", ("smc-ab", "pid", "lqr"), ("model",)),
        "python api": _api,
        "batch and step": _batch,
        "gymnasium": _gym,
        "python paths": _python_paths,            # (listed so that --jobs 2 gives them to the shorter share)
        "thrusters": _thrusters,
        "kernels called directly": _kernels_called_directly,
    }


def run(names: list[str]) -> int:
    """Run the named workloads in this process; returns how many failed (each failure is one line)."""
    import warnings

    failed = 0
    every = workloads()
    for name in names:
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                every[name]()
        except Exception as exc:         # noqa: BLE001  (a workload that fails must not stop the others)
            failed += 1
            print(f"uvms precompile: {name}: skipped ({type(exc).__name__}: {' '.join(str(exc).split())[:200]})",
                  flush=True)
            continue
        print(f"uvms precompile: {name}: {time.perf_counter() - start:.0f} s", flush=True)
    return failed


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m uvms.precompile", description=__doc__.splitlines()[0])
    parser.add_argument("--into", type=Path, help="write the kernels into FOLDER/numba-<fingerprint>")
    parser.add_argument("--jobs", type=int, default=min(os.cpu_count() or 1, 2), help="processes (default: 2)")
    parser.add_argument("--only", nargs="*", help=argparse.SUPPRESS)     # one process's share (internal)
    args = parser.parse_args(argv)
    if args.only is not None:
        return 1 if run(args.only) else 0
    env = dict(os.environ)
    if args.into is not None:
        from uvms._cache import fingerprint

        folder = args.into.resolve() / f"numba-{fingerprint()}"
        folder.mkdir(parents=True, exist_ok=True)
        env["NUMBA_CACHE_DIR"] = str(folder)
        env["UVMS_NO_PREBUILT"] = "1"
    names = list(workloads())
    jobs = max(1, min(args.jobs, len(names)))
    start = time.perf_counter()
    shares = [names[i::jobs] for i in range(jobs)]
    processes = [subprocess.Popen([sys.executable, "-m", "uvms.precompile", "--only", *share], env=env)
                 for share in shares]
    codes = [p.wait() for p in processes]
    print(f"uvms precompile: done in {time.perf_counter() - start:.0f} s"
          + ("" if not any(codes) else " (some workloads were skipped: they compile at first use)"), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
