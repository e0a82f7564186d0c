"""Speed of the uvms dynamics against Pinocchio and MuJoCo, and ABA against CRBA + solve as chains grow.

Run ``python benchmarks/bench_dynamics.py [--json FILE] [--repeats 20] [--calls 2000] [--statistic median|min]
[--only NAME ...]``.
Every figure is the median (``--statistic min``: the best) over ``repeats`` batches of ``calls`` calls, in
microseconds per call.

Sections (each a function returning a :class:`Section`; add new ones to ``BENCHMARKS``):

* ``python``: ``uvms.forward_dynamics`` called from Python (rigid and hydrodynamic paper model).
* ``compiled``: the ``aba`` kernel called in a loop inside an ``@njit`` function (per evaluation).
* ``pinocchio``: ``pinocchio.aba`` from Python on the same rigid model (skipped without ``pin``).
* ``mujoco``: an MJCF of the same bodies with MuJoCo's ellipsoid fluid model: ``mj_step`` (RK4) and
  ``mj_forward`` (skipped without ``mujoco``).
* ``flow``: the RK4 step in a uniform current, a depth profile and 50-component irregular waves.
* ``scaling``: ``aba`` against ``crba`` + ``rnea`` (bias at zero acceleration) + a dense solve, compiled, on
  random hydrodynamic chains of 3 to 48 links.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

import numpy as np
from numba import njit

import uvms
from uvms.dynamics.plant import fluid_table, forward_into, inverse_into, mass_matrix_into, model_data
from uvms.hydro.flow import fluid_at
from uvms.model.model import Model
from uvms.rotations import quaternion_from_rotation, rotation_from_euler
from uvms.spatial import modified_dh_pose, rotz

SCALING_LINKS = (3, 6, 12, 24, 48)
MIN_INERTIA = 1e-9      # added to every rotational inertia in the MJCF (the paper's links have Ixx = 0) [kg m^2]


@dataclass
class Settings:
    repeats: int = 20
    calls: int = 2000
    statistic: str = "median"       # or "min": the best batch, steadier on a busy machine


@dataclass
class Section:
    """One printed table: ``rows`` of values under ``columns``; ``figures`` are the named numbers for JSON."""

    key: str
    title: str
    columns: list[str]
    rows: list[list] = field(default_factory=list)
    figures: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


# -- timing ---------------------------------------------------------------------------------------------------

def time_side_by_side(batches: dict[str, Callable[[int], object]], settings: Settings,
                      calls: int | None = None) -> dict[str, float]:
    """Per name, the median (or minimum, ``settings.statistic``) over ``settings.repeats`` of the time of
    ``batch(calls)`` divided by ``calls`` [us per call].

    The batches take turns within every repeat (in a rotating order), so a busy spell of the machine slows
    all of them alike and their ratios stay meaningful."""
    calls = settings.calls if calls is None else calls
    names = list(batches)
    for name in names:
        batches[name](min(calls, 10))                       # warm-up (compilation, caches)
    times: dict[str, list[float]] = {name: [] for name in names}
    for repeat in range(settings.repeats):
        for k in range(len(names)):
            name = names[(repeat + k) % len(names)]
            t0 = time.perf_counter()
            batches[name](calls)
            times[name].append(time.perf_counter() - t0)
    pick = min if settings.statistic == "min" else statistics.median
    return {name: pick(t) / calls * 1e6 for name, t in times.items()}


def time_per_call_us(batch: Callable[[int], object], settings: Settings, calls: int | None = None) -> float:
    """:func:`time_side_by_side` of one batch."""
    return time_side_by_side({"batch": batch}, settings, calls)["batch"]


def python_loop(fn: Callable, *args, **kwargs) -> Callable[[int], None]:
    """A batch of ``calls`` calls of ``fn(*args, **kwargs)`` from a plain Python loop."""
    def batch(calls: int) -> None:
        for _ in range(calls):
            fn(*args, **kwargs)
    return batch


@njit(cache=True)
def aba_loop(md, R0, p0, nu, q, qd, tau, f_body, f_ee, flow, fixed_base, nu_dot, qdd, calls):
    """``calls`` evaluations of the articulated-body algorithm (what a compiled integrator does)."""
    for _ in range(calls):
        forward_into(md, R0, p0, nu, q, qd, tau, f_body, f_ee, flow, 0.0, fixed_base, nu_dot, qdd)


@njit(cache=True)
def cholesky_solve(A, b, L, x):
    """``x = A^-1 b`` for a symmetric positive-definite ``A`` by a dense Cholesky factor ``L`` (no allocation)."""
    n = A.shape[0]
    for j in range(n):
        s = A[j, j]
        for k in range(j):
            s -= L[j, k] * L[j, k]
        d = np.sqrt(s)
        L[j, j] = d
        for i in range(j + 1, n):
            s = A[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            L[i, j] = s / d
    for i in range(n):                      # L y = b
        s = b[i]
        for k in range(i):
            s -= L[i, k] * x[k]
        x[i] = s / L[i, i]
    for i in range(n - 1, -1, -1):          # L^T x = y
        s = x[i]
        for k in range(i + 1, n):
            s -= L[k, i] * x[k]
        x[i] = s / L[i, i]


@njit(cache=True)
def crba_solve_once(md, R0, p0, nu, q, qd, tau, f_body, f_ee, flow, M, L, rhs, x, zero6, zero_n,
                    h0, h_tau, use_lapack):
    """``M(q) [nu_dot; qdd] = [f_body; tau] - h`` with ``M`` from CRBA and ``h`` from RNEA at zero acceleration."""
    n = q.shape[0]
    mass_matrix_into(md, q, M)
    inverse_into(md, R0, p0, nu, q, qd, zero6, zero_n, f_ee, flow, 0.0, h0, h_tau)
    for k in range(6):
        rhs[k] = f_body[k] - h0[k]
    for k in range(n):
        rhs[6 + k] = tau[k] - h_tau[k]
    if use_lapack:
        y = np.linalg.solve(M, rhs)
        for k in range(6 + n):
            x[k] = y[k]
    else:
        cholesky_solve(M, rhs, L, x)


@njit(cache=True)
def crba_solve_loop(md, R0, p0, nu, q, qd, tau, f_body, f_ee, flow, M, L, rhs, x, zero6, zero_n,
                    h0, h_tau, use_lapack, calls):
    for _ in range(calls):
        crba_solve_once(md, R0, p0, nu, q, qd, tau, f_body, f_ee, flow, M, L, rhs, x, zero6, zero_n,
                        h0, h_tau, use_lapack)


class KernelInputs:
    """Contiguous float64 arrays for the kernels at one representative state of ``model``."""

    def __init__(self, model: Model, seed: int = 7):
        rng = np.random.default_rng(seed)
        n = model.n_joints
        self.model = model
        self.md = model_data(model)
        self.state = uvms.State.from_euler(model, position=[1.0, -2.0, 5.0], euler=[0.2, -0.3, 1.0],
                                           nu=rng.normal(scale=0.3, size=6), q=rng.uniform(-1.5, 1.5, n),
                                           qd=rng.normal(scale=0.5, size=n))
        self.R0 = np.ascontiguousarray(self.state.rotation)
        self.p0 = np.array(self.state.position)
        self.nu = np.array(self.state.nu)
        self.q = np.array(self.state.q)
        self.qd = np.array(self.state.qd)
        self.tau = rng.normal(scale=0.5, size=n)
        self.f_body = rng.normal(scale=5.0, size=6)
        self.f_ee = np.zeros(6)
        self.flow = fluid_table([0.0], [model.current], [model.fluid_acceleration])
        self.nu_dot = np.zeros(6)
        self.qdd = np.zeros(n)

    def aba_batch(self, calls: int) -> None:
        aba_loop(self.md, self.R0, self.p0, self.nu, self.q, self.qd, self.tau, self.f_body, self.f_ee,
                 self.flow, False, self.nu_dot, self.qdd, calls)

    def crba_batch(self, use_lapack: bool) -> Callable[[int], None]:
        nd = self.model.n_dof
        M, L = np.zeros((nd, nd)), np.zeros((nd, nd))
        self.rhs, self.x = np.zeros(nd), np.zeros(nd)
        zero6, zero_n, h0, h_tau = np.zeros(6), np.zeros(nd - 6), np.zeros(6), np.zeros(nd - 6)

        def batch(calls: int) -> None:
            crba_solve_loop(self.md, self.R0, self.p0, self.nu, self.q, self.qd, self.tau, self.f_body,
                            self.f_ee, self.flow, M, L, self.rhs, self.x, zero6, zero_n, h0, h_tau, use_lapack,
                            calls)
        return batch


# -- models ---------------------------------------------------------------------------------------------------

def paper_models() -> tuple[Model, Model]:
    """The paper model with every effect (hydrodynamic) and its rigid part (gravity kept)."""
    hydro = uvms.load_model("paper")
    return hydro, hydro.with_effects(added_mass=False, drag=False, buoyancy=False)


def random_chain(rng: np.random.Generator, n: int, *, hydro: bool = True) -> Model:
    """A vehicle with an n-link chain of random modified-DH rows, masses and full inertias (benchmark only)."""
    nb = n + 1

    def inertia(mass: float, size: float) -> np.ndarray:
        d = rng.uniform(0.2, 1.0, 3) * size
        R = rotation_from_euler(rng.uniform(-np.pi, np.pi, 3))
        return R @ np.diag(mass / 12 * np.array([d[1]**2 + d[2]**2, d[0]**2 + d[2]**2, d[0]**2 + d[1]**2])) @ R.T

    def spd6(ang: float, lin: float) -> np.ndarray:
        A = rng.normal(size=(6, 6))
        D = np.diag([ang] * 3 + [lin] * 3) ** 0.5
        return D @ (A @ A.T / 6 + 0.1 * np.eye(6)) @ D

    mass = np.concatenate([[32.0], rng.uniform(0.3, 3.0, n)])
    com = np.vstack([np.zeros(3), rng.normal(scale=0.1, size=(n, 3))])
    rows = [modified_dh_pose(rng.uniform(-np.pi, np.pi), rng.uniform(-0.3, 0.3), rng.uniform(-0.2, 0.2), 0.0)
            for _ in range(n)]
    h = 1.0 if hydro else 0.0
    return Model(
        name=f"chain{n}", source=None, body_names=tuple(f"b{i}" for i in range(nb)),
        mass=mass, com=com, inertia_com=np.stack([inertia(mass[0], 0.6)] + [inertia(m, 0.3) for m in mass[1:]]),
        added_mass=np.stack([spd6(2.0, 20.0)] + [spd6(0.002, 0.1) for _ in range(n)]) * h,
        buoyancy_mass=mass * h, cob=com + rng.normal(scale=0.02, size=(nb, 3)),
        vehicle_drag_area=np.full(3, 0.061), vehicle_drag_coefficient=np.full(3, 1.07) * h,
        vehicle_rotational_drag_side=0.596, vehicle_rotational_drag_coefficient=1.07 * h,
        vehicle_box=np.full(3, 0.596), link_radius=np.full(n, 0.0125), link_length=rng.uniform(0.1, 0.3, n),
        link_drag_coefficient=np.full(n, 1.0) * h,
        joint_rotation=np.stack([R for R, _ in rows]), joint_position=np.stack([p for _, p in rows]),
        theta_offset=rng.uniform(-1, 1, n), ee_rotation=np.eye(3), ee_position=np.array([0.2, 0.0, 0.0]),
        density=1000.0, gravity=np.array([0.0, 0.0, 9.81]), current=np.zeros(3), fluid_acceleration=np.zeros(3),
    )


# -- sections -------------------------------------------------------------------------------------------------

def bench_python(settings: Settings) -> Section:
    """(a) ``uvms.forward_dynamics`` from Python (argument checks, workspace allocation and the kernel)."""
    sec = Section("python", "uvms.forward_dynamics from Python, paper model", ["model", "us/call", "ratio"])
    hydro, rigid = paper_models()
    batches = {}
    for name, model in (("rigid", rigid), ("hydrodynamic", hydro)):
        inp = KernelInputs(model)
        batches[f"forward_dynamics_{name}_us"] = python_loop(uvms.forward_dynamics, model, inp.state,
                                                             joint_torques=inp.tau, body_wrench=inp.f_body)
    sec.figures.update(time_side_by_side(batches, settings))
    r, h = sec.figures["forward_dynamics_rigid_us"], sec.figures["forward_dynamics_hydrodynamic_us"]
    sec.rows = [["rigid", r, 1.0], ["hydrodynamic", h, h / r]]
    return sec


def bench_compiled(settings: Settings) -> Section:
    """(b) the compiled ``aba`` kernel in an ``@njit`` loop, rigid and hydrodynamic."""
    sec = Section("compiled", "aba kernel in an @njit loop, paper model (per evaluation)",
                  ["model", "us/call", "ratio"])
    hydro, rigid = paper_models()
    sec.figures.update(time_side_by_side({f"aba_{name}_us": KernelInputs(model).aba_batch
                                          for name, model in (("rigid", rigid), ("hydrodynamic", hydro))}, settings))
    r, h = sec.figures["aba_rigid_us"], sec.figures["aba_hydrodynamic_us"]
    sec.figures["hydro_over_rigid"] = h / r
    sec.rows = [["rigid", r, 1.0], ["hydrodynamic", h, h / r]]
    return sec


def bench_pinocchio(settings: Settings) -> Section:
    """(c) ``pinocchio.aba`` from Python on the rigid paper model (free flyer)."""
    sec = Section("pinocchio", "pinocchio.aba from Python, paper model, rigid",
                  ["call", "us/call", "ratio to pinocchio"])
    try:
        import pinocchio as pin
    except ImportError:
        sec.notes.append("skipped: pinocchio (pip package 'pin') is not installed")
        return sec
    from uvms.interop.pinocchio_model import (
        body_wrench_force,
        generalized_from_pinocchio,
        pinocchio_configuration,
        pinocchio_model_from,
        pinocchio_velocity,
    )

    _, rigid = paper_models()
    inp = KernelInputs(rigid)
    pm = pinocchio_model_from(rigid)
    pd = pm.createData()
    q, v = pinocchio_configuration(inp.state), pinocchio_velocity(inp.state)
    tau = np.concatenate([np.zeros(6), inp.tau])
    fext = pin.StdVec_Force()
    for _ in range(pm.njoints):
        fext.append(pin.Force.Zero())
    fext[1] = body_wrench_force(inp.f_body)

    reference = uvms.forward_dynamics(rigid, inp.state, joint_torques=inp.tau, body_wrench=inp.f_body)
    error = np.abs(generalized_from_pinocchio(pin.aba(pm, pd, q, v, tau, fext)) - reference.generalized).max()
    t = time_side_by_side({
        "uvms_python": python_loop(uvms.forward_dynamics, rigid, inp.state, joint_torques=inp.tau,
                                   body_wrench=inp.f_body),
        "uvms_python_tau": python_loop(uvms.forward_dynamics, rigid, inp.state, joint_torques=inp.tau),
        "uvms_compiled": inp.aba_batch,
        "pinocchio": python_loop(pin.aba, pm, pd, q, v, tau),
        "pinocchio_fext": python_loop(pin.aba, pm, pd, q, v, tau, fext)}, settings)
    uvms_python, uvms_compiled = t["uvms_python"], t["uvms_compiled"]
    sec.figures["pinocchio_aba_us"] = t["pinocchio"]
    sec.figures["pinocchio_aba_fext_us"] = t["pinocchio_fext"]
    sec.figures["uvms_forward_dynamics_rigid_us"] = uvms_python
    sec.figures["uvms_forward_dynamics_tau_rigid_us"] = t["uvms_python_tau"]
    sec.figures["uvms_aba_compiled_rigid_us"] = uvms_compiled
    sec.figures["max_abs_difference"] = float(error)
    p = sec.figures["pinocchio_aba_us"]
    sec.rows = [
        ["pinocchio.aba(q, v, tau)", p, "1.00"],
        ["pinocchio.aba(q, v, tau, fext)", sec.figures["pinocchio_aba_fext_us"], ""],
        ["uvms.forward_dynamics(state, joint_torques=tau)", t["uvms_python_tau"],
         f"{t['uvms_python_tau'] / p:.2f}"],
        ["uvms.forward_dynamics(..., body_wrench=f) vs aba(..., fext)", uvms_python,
         f"{uvms_python / sec.figures['pinocchio_aba_fext_us']:.2f}"],
        ["uvms aba (compiled loop)", uvms_compiled, f"{uvms_compiled / p:.2f}"],
    ]
    sec.notes.append(f"same state, same result: max |uvms - pinocchio| = {error:.1e}")
    return sec


def mjcf_from(model: Model, *, fluid: bool = True, timestep: float = 0.001, integrator: str = "RK4") -> str:
    """An MJCF of the bodies of ``model``: the vehicle as a free box, the links as cylinders on hinge joints
    placed per the modified-DH rows; MuJoCo's ellipsoid fluid model when ``fluid``. Gravity is ``model.gravity``
    (the uvms world frame, z down), so MuJoCo's buoyancy points up in that frame too."""

    def inertial(i: int) -> str:
        J = np.array(model.inertia_com[i], dtype=float) + MIN_INERTIA * np.eye(3)
        c = model.com[i]
        return (f'<inertial pos="{c[0]:.17g} {c[1]:.17g} {c[2]:.17g}" mass="{model.mass[i]:.17g}" '
                f'fullinertia="{J[0, 0]:.17g} {J[1, 1]:.17g} {J[2, 2]:.17g} {J[0, 1]:.17g} {J[0, 2]:.17g} '
                f'{J[1, 2]:.17g}"/>')

    box = 0.5 * np.array(model.vehicle_box, dtype=float)
    density = model.density if fluid else 0.0
    g = model.gravity
    lines = [
        f'<mujoco model="{model.name}">',
        (f'  <option density="{density:g}" viscosity="0" integrator="{integrator}" timestep="{timestep:g}" '
         f'gravity="{g[0]:g} {g[1]:g} {g[2]:g}"/>'),
        '  <default><geom contype="0" conaffinity="0" fluidshape="ellipsoid"/></default>',
        '  <worldbody>',
        '    <body name="vehicle">',
        '      <freejoint name="vehicle"/>',
        f'      {inertial(0)}',
        f'      <geom type="box" size="{box[0]:g} {box[1]:g} {box[2]:g}"/>',
    ]
    indent = "      "
    for i in range(model.n_joints):
        R = np.array(model.joint_rotation[i], dtype=float) @ rotz(float(model.theta_offset[i]))
        w, x, y, z = quaternion_from_rotation(R)
        p = model.joint_position[i]
        L, r = model.link_length[i], model.link_radius[i]
        lines += [
            (f'{indent}<body name="link{i + 1}" pos="{p[0]:.17g} {p[1]:.17g} {p[2]:.17g}" '
             f'quat="{w:.17g} {x:.17g} {y:.17g} {z:.17g}">'),
            f'{indent}  <joint name="joint{i + 1}" type="hinge" axis="0 0 1"/>',
            f'{indent}  {inertial(i + 1)}',
            f'{indent}  <geom type="cylinder" fromto="0 0 0 {L:g} 0 0" size="{r:g}"/>',
        ]
        indent += "  "
    e = model.ee_position
    lines.append(f'{indent}<site name="end_effector" pos="{e[0]:.17g} {e[1]:.17g} {e[2]:.17g}"/>')
    for _ in range(model.n_joints):
        indent = indent[:-2]
        lines.append(f"{indent}</body>")
    lines += ["    </body>", "  </worldbody>", "</mujoco>"]
    return "\n".join(lines)


def mujoco_rigid_check(mujoco, model: Model) -> float:
    """Max |qacc difference| between MuJoCo (fluid off) and uvms on the rigid model with MuJoCo's inertia floor."""
    rigid = model.with_effects(added_mass=False, drag=False, buoyancy=False)
    mm = mujoco.MjModel.from_xml_string(mjcf_from(rigid, fluid=False))
    md = mujoco.MjData(mm)
    rigid = rigid.replace(inertia_com=np.array(rigid.inertia_com) + MIN_INERTIA * np.eye(3))   # as in the MJCF
    inp = KernelInputs(rigid)
    s, R = inp.state, inp.R0
    omega, v = s.nu[:3], s.nu[3:]
    md.qpos[:] = np.concatenate([s.position, s.quaternion, s.q])
    md.qvel[:] = np.concatenate([R @ v, omega, s.qd])          # free joint: world linear, local angular
    md.qfrc_applied[:] = np.concatenate([np.zeros(6), inp.tau])
    mujoco.mj_forward(mm, md)
    acc = uvms.forward_dynamics(rigid, s, joint_torques=inp.tau)
    classical = R @ (acc.nu_dot[3:] + np.cross(omega, v))       # world acceleration of the vehicle origin
    expected = np.concatenate([classical, acc.nu_dot[:3], acc.qdd])
    return float(np.abs(md.qacc - expected).max())


def bench_mujoco(settings: Settings) -> Section:
    """(d) MuJoCo on a matching MJCF with its ellipsoid fluid model: ``mj_step`` (RK4) and ``mj_forward``."""
    sec = Section("mujoco", "MuJoCo, paper bodies, ellipsoid fluid model", ["call", "us/call", "ratio"])
    try:
        import mujoco
    except ImportError:
        sec.notes.append("skipped: mujoco is not installed")
        return sec
    hydro, _ = paper_models()
    inp = KernelInputs(hydro)
    s = inp.state
    variants = {}
    for fluid in (True, False):
        mm = mujoco.MjModel.from_xml_string(mjcf_from(hydro, fluid=fluid))
        md = mujoco.MjData(mm)
        qpos = np.concatenate([s.position, s.quaternion, s.q])
        qvel = np.concatenate([inp.R0 @ s.nu[3:], s.nu[:3], s.qd])
        variants[fluid] = (mm, md, qpos, qvel)

    def stepper(fluid: bool, fn):
        mm, md, qpos, qvel = variants[fluid]

        def batch(calls: int) -> None:
            md.qpos[:], md.qvel[:] = qpos, qvel
            md.qfrc_applied[:] = np.concatenate([np.zeros(6), inp.tau])
            for _ in range(calls):
                fn(mm, md)
        return batch

    f = sec.figures
    f.update(time_side_by_side({
        "mj_step_rk4_fluid_us": stepper(True, mujoco.mj_step),
        "mj_forward_fluid_us": stepper(True, mujoco.mj_forward),
        "mj_step_rk4_no_fluid_us": stepper(False, mujoco.mj_step),
        "mj_forward_no_fluid_us": stepper(False, mujoco.mj_forward),
        "uvms_aba_compiled_hydro_us": inp.aba_batch}, settings))
    f["rigid_check_max_abs_qacc_difference"] = mujoco_rigid_check(mujoco, hydro)
    four = 4 * f["uvms_aba_compiled_hydro_us"]
    sec.rows = [
        ["mj_step, RK4, fluid", f["mj_step_rk4_fluid_us"], f["mj_step_rk4_fluid_us"] / four],
        ["mj_forward, fluid", f["mj_forward_fluid_us"], f["mj_forward_fluid_us"] / f["uvms_aba_compiled_hydro_us"]],
        ["mj_step, RK4, no fluid", f["mj_step_rk4_no_fluid_us"], f["mj_step_rk4_no_fluid_us"] / four],
        ["mj_forward, no fluid", f["mj_forward_no_fluid_us"],
         f["mj_forward_no_fluid_us"] / f["uvms_aba_compiled_hydro_us"]],
        ["uvms aba hydro, compiled (x4 = RK4 step)", f["uvms_aba_compiled_hydro_us"], 1.0],
    ]
    sec.notes += [
        "ratio: mj_step against 4 uvms hydrodynamic aba evaluations, mj_forward against one",
        ("MuJoCo called from a Python loop (includes ~0.1-0.3 us call overhead per call); "
         "its fluid model is not the paper's hydrodynamics, so only the cost is comparable"),
        f"MJCF check (fluid off): max |qacc_mujoco - qacc_uvms| = {f['rigid_check_max_abs_qacc_difference']:.1e}",
    ]
    return sec


def bench_scaling(settings: Settings) -> Section:
    """(e) ABA against CRBA + RNEA + solve on random hydrodynamic chains, all compiled; Pinocchio for scale."""
    try:
        import pinocchio as pin

        from uvms.interop.pinocchio_model import pinocchio_configuration, pinocchio_model_from, pinocchio_velocity
    except ImportError:
        pin = None
    sec = Section("scaling", "ABA vs CRBA + RNEA + solve, random chains, compiled loops (us per evaluation)",
                  ["links", "aba hydro", "aba rigid", "crba+rnea+chol", "crba+rnea+lapack", "pinocchio.aba rigid",
                   "chol / aba", "lapack / aba"])
    rng = np.random.default_rng(2026)
    for n in SCALING_LINKS:
        model = random_chain(rng, n, hydro=True)
        rigid = model.with_effects(added_mass=False, drag=False, buoyancy=False)
        inp = KernelInputs(model)
        inp.crba_batch(False)(1)
        x_chol = inp.x.copy()
        inp.aba_batch(1)
        disagreement = np.abs(x_chol - np.concatenate([inp.nu_dot, inp.qdd])).max()
        if disagreement > 1e-8 * max(1.0, np.abs(x_chol).max()):
            sec.notes.append(f"n={n}: ABA and CRBA+RNEA+solve disagree by {disagreement:.1e}")
        batches = {"aba": inp.aba_batch, "rigid": KernelInputs(rigid).aba_batch, "chol": inp.crba_batch(False),
                   "lapack": inp.crba_batch(True)}
        if pin is not None:
            pm = pinocchio_model_from(rigid)
            pd = pm.createData()
            q, v = pinocchio_configuration(inp.state), pinocchio_velocity(inp.state)
            tau = np.concatenate([np.zeros(6), inp.tau])
            batches["pin"] = python_loop(pin.aba, pm, pd, q, v, tau)
        t = time_side_by_side(batches, settings)
        t_aba, t_rigid, t_chol, t_lapack = t["aba"], t["rigid"], t["chol"], t["lapack"]
        t_pin = t.get("pin", float("nan"))
        sec.rows.append([n, t_aba, t_rigid, t_chol, t_lapack, t_pin, t_chol / t_aba, t_lapack / t_aba])
        sec.figures.update({f"aba_hydro_n{n}_us": t_aba, f"aba_rigid_n{n}_us": t_rigid,
                            f"crba_rnea_cholesky_n{n}_us": t_chol, f"crba_rnea_lapack_n{n}_us": t_lapack,
                            f"pinocchio_aba_rigid_n{n}_us": t_pin})
    if pin is None:
        sec.notes.append("pinocchio column skipped: pinocchio is not installed")
    sec.notes.append("lapack = numpy.linalg.solve inside @njit (allocates); chol = dense Cholesky, no allocation; "
                     "pinocchio.aba is called from Python")
    return sec


def bench_simulation(settings: Settings) -> Section:
    """(f) a whole RK4 step and whole runs: uvms's compiled RK4 loop against MuJoCo's RK4 ``mj_step`` (fluid
    model on) and ``mujoco.rollout`` in the same run; the paper's case 2 (released, no control) and case 3
    (``smc-ab``, 60 % model error) over 10 s at 1 ms: wall time and real-time factor."""
    from uvms.control.registry import make_controller
    from uvms.dynamics.plant import build_plant, fluid_table, held_inputs
    from uvms.sim.inputs import paper_torques
    from uvms.sim.integrate import pack, rk4, samples
    from uvms.sim.run import simulate

    sec = Section("simulation", "RK4 step and whole runs, paper model", ["what", "value", "unit / ratio"])
    hydro, _ = paper_models()
    inp = KernelInputs(hydro)
    plant, _ = build_plant(hydro, fluid=fluid_table([0.0], [np.zeros(3)], [np.zeros(3)]))
    held = held_inputs(hydro.n_joints, 0)
    held.joint_torques[:] = inp.tau
    x0 = pack(inp.state)
    record = samples(1, x0.size, 1 << 60)

    def rk4_batch(calls: int) -> None:
        x = x0.copy()
        rk4(plant, held, x, 0.0, 1e-3, calls, 0, record)

    f = sec.figures
    batches: dict[str, Callable[[int], object]] = {"uvms_rk4_step_us": rk4_batch}
    try:
        import mujoco

        mm = mujoco.MjModel.from_xml_string(mjcf_from(hydro, fluid=True))
        md = mujoco.MjData(mm)
        s = inp.state
        qpos = np.concatenate([s.position, s.quaternion, s.q])
        qvel = np.concatenate([inp.R0 @ s.nu[3:], s.nu[:3], s.qd])

        def mj_batch(calls: int) -> None:
            md.qpos[:], md.qvel[:] = qpos, qvel
            md.qfrc_applied[:] = np.concatenate([np.zeros(6), inp.tau])
            for _ in range(calls):
                mujoco.mj_step(mm, md)

        batches["mujoco_mj_step_rk4_fluid_us"] = mj_batch
        try:
            from mujoco import rollout

            state0 = np.zeros((1, mujoco.mj_stateSize(mm, mujoco.mjtState.mjSTATE_FULLPHYSICS)))
            md.qpos[:], md.qvel[:] = qpos, qvel
            mujoco.mj_getState(mm, md, state0[0], mujoco.mjtState.mjSTATE_FULLPHYSICS)

            def rollout_batch(calls: int) -> None:
                rollout.rollout(mm, md, state0, nstep=calls)

            rollout_batch(1)
            batches["mujoco_rollout_step_us"] = rollout_batch
        except Exception as exc:  # rollout API differs between versions
            sec.notes.append(f"mujoco.rollout skipped: {exc}")
    except ImportError:
        sec.notes.append("MuJoCo skipped: not installed")
    f.update(time_side_by_side(batches, settings))
    sec.rows.append(["uvms RK4 step (compiled loop, full hydrodynamics)", f["uvms_rk4_step_us"], "us"])
    for key, label in (("mujoco_mj_step_rk4_fluid_us", "MuJoCo mj_step RK4 + ellipsoid fluid (Python loop)"),
                       ("mujoco_rollout_step_us", "MuJoCo rollout (C loop) per RK4 step, fluid")):
        if key in f:
            sec.rows.append([label, f[key], f"{f[key] / f['uvms_rk4_step_us']:.2f} x uvms"])
    sec.notes.append("the RK4 steps are timed side by side (batches take turns in every repeat)")

    def wall(fn) -> tuple[float, float]:
        """(statistic, best) of ``settings.repeats`` whole runs [s], after one warm-up run."""
        fn()
        times = []
        for _ in range(settings.repeats):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
        return (min(times) if settings.statistic == "min" else statistics.median(times)), min(times)

    def run_row(key: str, label: str, fn) -> None:
        f[key], best = wall(fn)
        f[key.replace("_wall_s", "_best_wall_s")] = best
        f[key.replace("_wall_s", "_real_time_factor")] = 10.0 / f[key]
        sec.rows.append([label, f[key], f"s wall, {10.0 / f[key]:.0f} x real time (best {10.0 / best:.0f} x)"])

    model = uvms.load_model("paper")
    run_row("case2_10s_wall_s", "paper case 2 (released, no control), 10 s at 1 ms",
            lambda: simulate(model, duration=10.0, step=1e-3, joint_torques=paper_torques()))

    def closed_loop():
        c = make_controller("smc-ab", model, period=0.01, parameters={"hydro_scale": 0.4})
        return simulate(model, duration=10.0, step=1e-3, joint_torques=paper_torques(), controller=c)

    run_row("case3_smc_ab_10s_wall_s", "paper case 3 (smc-ab every 10 ms), 10 s at 1 ms", closed_loop)
    return sec


def bench_flow(settings: Settings) -> Section:
    """(g) the RK4 step in each kind of water (:mod:`uvms.hydro.flow`), side by side: a uniform current (the
    step of section (f)), a depth profile, and 50-component irregular waves (Pierson-Moskowitz amplitudes,
    Hs 0.5 m, Tp 4 s, random phases and directions, 20 m deep), on the paper model and the BlueROV2 Heavy +
    Alpha 5, each body evaluated at its own position in every stage. Issue 27's targets: <= 1.1 x and
    <= 1.5 x the uniform step."""
    from types import SimpleNamespace

    from uvms.dynamics.plant import build_plant, held_inputs
    from uvms.hydro.flow import Flow
    from uvms.sim.integrate import pack, rk4, samples

    sec = Section("flow", "RK4 step in each kind of water", ["model", "water", "us per step", "x uniform"])
    rng = np.random.default_rng(27)
    omega = np.linspace(0.8, 4.0, 50) + rng.uniform(-0.02, 0.02, 50)
    wp, hs = 2 * np.pi / 4.0, 0.5
    spectrum = 5 / 16 * hs**2 * wp**4 * omega**-5 * np.exp(-1.25 * (wp / omega) ** 4)
    amplitude = np.sqrt(2 * spectrum * np.gradient(omega))
    k = np.array([_deep_or_finite_k(w, 20.0) for w in omega])
    waves = SimpleNamespace(amplitude=amplitude, omega=omega, wavenumber=k, direction=rng.uniform(-0.5, 0.5, 50),
                            phase=rng.uniform(0, 2 * np.pi, 50), water_depth=20.0)
    profile = SimpleNamespace(depth=np.array([0.0, 2.0, 5.0, 10.0, 30.0]),
                              velocity=np.array([[0.5, 0.1, 0], [0.4, 0.1, 0], [0.3, 0.0, 0], [0.1, 0, 0], [0, 0, 0]]))
    current = [0.2, 0.1, 0.0]
    waters = {"uniform": Flow.constant(current), "profile": Flow.constant(current, profile=profile),
              "waves50": Flow.constant(current, waves=waves)}
    for name in ("paper", "bluerov2_heavy_alpha5"):
        model = uvms.load_model(name)
        n = model.n_joints
        state = uvms.State.from_euler(model, position=[0, 0, 3.0], q=np.full(n, 0.3), qd=np.full(n, 0.1))
        x0 = pack(state)
        batches: dict[str, Callable[[int], object]] = {}
        for water, flow in waters.items():
            plant, _ = build_plant(model, fluid=flow.compiled(model.convention))
            held = held_inputs(n, 0)
            record = samples(1, x0.size, 1 << 60)

            def batch(calls: int, plant=plant, held=held, record=record) -> None:
                x = x0.copy()
                rk4(plant, held, x, 0.0, 1e-3, calls, 0, record)

            batches[f"{name}_{water}_us"] = batch
        times = time_side_by_side(batches, settings)
        sec.figures.update(times)
        base = times[f"{name}_uniform_us"]
        for water in waters:
            value = times[f"{name}_{water}_us"]
            sec.figures[f"{name}_{water}_ratio"] = value / base
            sec.rows.append([name, water, value, f"{value / base:.2f}"])
    sec.notes.append("the three waters are timed side by side per model (batches take turns in every repeat)")
    _flow_points(sec, waters, settings)
    return sec


@njit(cache=True)
def _water_at_points(flow, t, points, v, a, grad, calls):
    """``fluid_at`` at every row of ``points`` (the drag strips' 16 Gauss points of a link), ``calls`` times."""
    for j in range(calls):
        for p in range(points.shape[0]):
            fluid_at(flow, t + j * 1e-4, points[p], v, a, grad)


@njit(cache=True)
def _sin_cos_libm(x, s, c):
    for i in range(x.shape[0]):
        s[i] = np.sin(x[i])
        c[i] = np.cos(x[i])


def _flow_points(sec: Section, waters: dict, settings: Settings) -> None:
    """Where the time goes: the water at one point (``fluid_at``, call included) per kind, what evaluating it
    at the 16 Gauss points of every link's drag strips instead of once per link would add to an RK4 step (15
    more points per link and stage), and the elementary functions' throughput per element of a long array."""
    from uvms.hydro.elementary import exp_pair_reduced_array, sin_cos_reduced_array

    points = np.zeros((16, 3))
    points[:, 0] = np.linspace(0.0, 0.2, 16)
    points[:, 2] = 3.0
    v, a, grad = np.zeros(3), np.zeros(3), np.zeros((3, 3))
    batches: dict[str, Callable[[int], object]] = {}
    for water in ("profile", "waves50"):
        data = waters[water].compiled("ned")
        batches[f"point_{water}_ns"] = lambda calls, data=data: _water_at_points(data, 1.0, points, v, a, grad, calls)
    x = np.random.default_rng(3).uniform(-100.0, 100.0, 5600)
    s, c = np.empty(5600), np.empty(5600)
    elementary = {"sin_cos_poly": sin_cos_reduced_array, "exp_pair_poly": exp_pair_reduced_array,
                  "sin_cos_libm": _sin_cos_libm}
    times = time_side_by_side(batches, settings)
    for name, fn in elementary.items():
        times.update(time_side_by_side({name: lambda calls, fn=fn: [fn(x, s, c) for _ in range(calls)]}, settings,
                                       calls=max(settings.calls // 20, 1)))
    links = {"paper": 3, "bluerov2_heavy_alpha5": 4}
    for water in ("profile", "waves50"):
        per_point = times[f"point_{water}_ns"] / 16 * 1e3
        sec.figures[f"point_{water}_ns"] = per_point
        strips = {name: per_point * 15 * n * 4 / 1e3 for name, n in links.items()}
        sec.figures.update({f"{name}_{water}_strips_extra_us": value for name, value in strips.items()})
        sec.notes.append(f"{water}: {per_point:.0f} ns per point; at every link's 16 drag-strip points instead of "
                         f"one: +{strips['paper']:.1f} us per step (paper), +{strips['bluerov2_heavy_alpha5']:.1f} us "
                         "(BlueROV2 Heavy + Alpha 5)")
    per_element = {name: times[name] / x.size * 1e3 for name in elementary}
    sec.figures.update({f"{name}_ns_per_element": value for name, value in per_element.items()})
    sec.notes.append(f"per element of {x.size} (vectorised throughput): " + ", ".join(
        f"{name} {value:.1f} ns" for name, value in per_element.items()))


def _deep_or_finite_k(omega: float, h: float) -> float:
    """The finite-depth wave number (Newton on omega^2 = g k tanh(k h), from the deep-water value)."""
    g = 9.81
    k = omega**2 / g
    for _ in range(50):
        f = g * k * np.tanh(k * h) - omega**2
        df = g * np.tanh(k * h) + g * k * h / np.cosh(k * h) ** 2
        k -= f / df
    return float(k)


BENCHMARKS: dict[str, Callable[[Settings], Section]] = {
    "python": bench_python,
    "compiled": bench_compiled,
    "pinocchio": bench_pinocchio,
    "mujoco": bench_mujoco,
    "scaling": bench_scaling,
    "simulation": bench_simulation,
    "flow": bench_flow,
}


# -- report ---------------------------------------------------------------------------------------------------

def _cell(value) -> str:
    if isinstance(value, float):
        return "-" if np.isnan(value) else f"{value:.2f}"
    return str(value)


def print_section(sec: Section) -> None:
    try:
        from rich.console import Console
        from rich.table import Table
    except ImportError:
        print(f"\n{sec.title}\n  " + " | ".join(sec.columns))
        for row in sec.rows:
            print("  " + " | ".join(_cell(v) for v in row))
        for note in sec.notes:
            print(f"  note: {note}")
        return
    table = Table()
    for i, col in enumerate(sec.columns):
        table.add_column(col, justify="left" if i == 0 else "right")
    for row in sec.rows:
        table.add_row(*(_cell(v) for v in row))
    console = Console(width=None if sys.stdout.isatty() else 120)
    console.print(f"\n[bold]{sec.title}[/bold]")
    console.print(table)
    for note in sec.notes:
        console.print(f"  [dim]{note}[/dim]")


def _json_safe(value):
    """NaN (a skipped measurement) as ``null``; NumPy scalars as Python numbers."""
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return None if np.isnan(value) else float(value)
    if isinstance(value, np.integer):
        return int(value)
    return value


def versions() -> dict[str, str]:
    import numba

    out = {"python": platform.python_version(), "numpy": np.__version__, "numba": numba.__version__,
           "uvms": uvms.__version__}
    for module, name in (("pinocchio", "pinocchio"), ("mujoco", "mujoco")):
        try:
            out[name] = __import__(module).__version__
        except ImportError:
            out[name] = "missing"
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", metavar="FILE", help="also write the figures to FILE as JSON")
    parser.add_argument("--repeats", type=int, default=Settings.repeats, help="batches per figure (median)")
    parser.add_argument("--calls", type=int, default=Settings.calls, help="calls per batch")
    parser.add_argument("--statistic", choices=["median", "min"], default="median",
                        help="statistic over the batches (min is steadier on a busy machine)")
    parser.add_argument("--only", nargs="+", choices=sorted(BENCHMARKS), help="run only these sections")
    args = parser.parse_args(argv)
    settings = Settings(repeats=args.repeats, calls=args.calls, statistic=args.statistic)

    t0 = time.perf_counter()
    hydro, _ = paper_models()
    uvms.forward_dynamics(hydro, uvms.State.zero(hydro))
    first_call = time.perf_counter() - t0

    sections = []
    for name in args.only or list(BENCHMARKS):
        sec = BENCHMARKS[name](settings)
        print_section(sec)
        sections.append(sec)
    print(f"\nload model + first forward_dynamics call: {first_call:.2f} s; {settings.statistic} of "
          f"{settings.repeats} batches x {settings.calls} calls; {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}")

    if args.json:
        report = {"settings": asdict(settings), "versions": versions(), "platform": platform.platform(),
                  "cpus": os.cpu_count(), "load_average": os.getloadavg()[0], "first_call_s": first_call,
                  "sections": {s.key: {"title": s.title, "figures": s.figures, "columns": s.columns, "rows": s.rows,
                                       "notes": s.notes} for s in sections}}
        with open(args.json, "w") as fh:
            json.dump(_json_safe(report), fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
