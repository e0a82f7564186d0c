"""Logs that uvms itself made: a run with a prescribed arm motion written as motion-capture and joint-encoder
CSV files and a log description, in a chosen frame convention, optionally with noise."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import uvms
from uvms import frames
from uvms.rotations import quaternion_from_euler

JOINT_TIMES = np.linspace(0.0, 8.0, 81)


def arm_motion(model, amplitude: float = 0.6, seconds: float = 8.0):
    """A smooth joint motion of every joint (a sine per joint), as a :class:`uvms.JointMotion`."""
    t = np.linspace(0.0, seconds, int(seconds * 10) + 1)
    n = model.n_joints
    angles = np.column_stack([0.4 + amplitude * np.sin(2 * np.pi * t / (3.0 + k)) * np.sin(np.pi * t / seconds)
                              for k in range(n)])
    return t, angles


def write_log(folder: Path, model, *, log_frame: str = "enu", seconds: float = 8.0, noise_deg: float = 0.0,
              noise_m: float = 0.0, seed: int = 0, start_euler=(0.05, -0.08, 0.4), name: str = "trial",
              commands=None) -> Path:
    """Simulate ``model`` (vehicle free, joints prescribed) and write the run as a log in ``log_frame``: the
    pose every 10 ms (quaternion x, y, z, w), the joints every 20 ms with an offset of -1 rad on the first joint
    and a sign of -1 on the last; the log's clock is the run's, and the replay starts 0.5 s in (so that the
    start's velocities come from a fit on both sides of it). ``commands`` (a :class:`uvms.CommandSchedule` on the
    run's clock, columns named by the model's thrusters) drive the model's thrusters and are written as a
    thrusters stream at their own times. Returns the description file and the run's state at the replay's
    start in ``log_frame``."""
    folder.mkdir(parents=True, exist_ok=True)
    t, angles = arm_motion(model, seconds=seconds + 1.0)
    motion = uvms.JointMotion.from_arrays(t, angles, joints=model.joint_names)
    state = uvms.State.zero(model).replace(quaternion=quaternion_from_euler(np.array(start_euler)),
                                           position=np.array([0.3, -0.2, 1.0]))
    actuation = uvms.Actuation.named("model", model) if commands is not None else None
    run = uvms.simulate(model, state, duration=seconds + 0.5, step=0.002, record_period=0.01, actuation=actuation,
                        inputs=uvms.Inputs(joint_motion=motion, thruster_commands=commands))
    rng = np.random.default_rng(seed)
    offset = 0.0                                     # the log's clock is the run's
    begin = 0.5                                      # the replay's start on that clock
    pos = frames.convert_vectors(run.position, model.convention, log_frame)
    quat = frames.convert_quaternions(run.quaternion, model.convention, log_frame)
    if noise_deg:
        from scipy.spatial.transform import Rotation

        tilt = Rotation.from_rotvec(rng.normal(0.0, np.radians(noise_deg), (len(run.time), 3)))
        quat_xyzw = (Rotation.from_quat(quat[:, [1, 2, 3, 0]]) * tilt).as_quat()
    else:
        quat_xyzw = quat[:, [1, 2, 3, 0]]
    pos = pos + rng.normal(0.0, noise_m, pos.shape) if noise_m else pos
    rows = ["time_secs,x_pose,y_pose,z_pose,x_ori,y_ori,z_ori,w_ori"]
    rows += [",".join(f"{v:.10g}" for v in (tk + offset, *p, *q)) for tk, p, q in zip(run.time, pos, quat_xyzw)]
    (folder / f"{name}_mocap.csv").write_text("\n".join(rows) + "\n")
    n = model.n_joints
    names = [f"enc{k}" for k in range(n)]
    sign = np.ones(n)
    sign[-1] = -1.0
    shift = np.zeros(n)
    shift[0] = -1.0                                   # q_model = sign * q_log + offset
    jt = np.arange(0.0, seconds + 0.5 + 1e-9, 0.02)
    q_model = np.column_stack([motion(tk)[0] for tk in jt]).T
    q_log = (q_model - shift) / sign
    rows = ["time_secs," + ",".join(names)]
    rows += [",".join(f"{v:.10g}" for v in (tk + offset, *q)) for tk, q in zip(jt, q_log)]
    (folder / f"{name}_joints.csv").write_text("\n".join(rows) + "\n")
    columns = ", ".join(f"{j}: {c}" for j, c in zip(model.joint_names, names))
    text = (f"start: {begin}\nduration: {seconds - begin}\nframe: {log_frame}\n"
            f"pose: {{file: {name}_mocap.csv, time: time_secs, position: [x_pose, y_pose, z_pose], "
            f"quaternion_xyzw: [x_ori, y_ori, z_ori, w_ori]}}\n"
            f"joints: {{file: {name}_joints.csv, time: time_secs, columns: {{{columns}}}, "
            f"offset: {{{model.joint_names[0]}: -1.0}}, sign: {{{model.joint_names[-1]}: -1}}}}\n")
    if commands is not None:
        rows = ["time_secs," + ",".join(f"pwm_{x}" for x in commands.names)]
        rows += [",".join(f"{v:.10g}" for v in (tk + offset, *u)) for tk, u in zip(commands.times, commands.commands)]
        (folder / f"{name}_thrusters.csv").write_text("\n".join(rows) + "\n")
        columns = ", ".join(f"{x}: pwm_{x}" for x in commands.names)
        text += f"thrusters: {{file: {name}_thrusters.csv, time: time_secs, columns: {{{columns}}}}}\n"
    path = folder / f"{name}.yaml"
    path.write_text(text)
    k = int(np.argmin(np.abs(run.time - begin)))
    return path, frames.convert_state(run.state(k), model.convention, log_frame)
