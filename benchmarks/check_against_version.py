"""Check that the dynamics of this checkout agree with those of another commit (the physics must not move).

Run ``python benchmarks/check_against_version.py [--ref cbb0ffd] [--states 200] [--tolerance 1e-12]``.

A temporary ``git worktree`` of ``--ref`` is created; then this script runs itself twice as a worker, once
with ``PYTHONPATH`` on the reference's ``src`` and once on this checkout's ``src`` (each with its own empty
``NUMBA_CACHE_DIR``). Each worker evaluates the same random states (a seeded generator) of the paper model and
``bluerov2_heavy_alpha5`` with their hydrodynamics on: ``uvms.forward_dynamics`` (random joint torques, body
and end-effector wrenches, current and fluid acceleration; free and clamped vehicle),
``uvms.inverse_dynamics`` (random accelerations, end-effector wrench, current) and ``uvms.mass_matrix``.

For every output array the relative difference is ``max |new - ref| / max |ref|``; the script prints the
largest over all states and outputs and exits with status 1 if it exceeds the tolerance.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

MODELS = ("paper", "bluerov2_heavy_alpha5")
REPO = Path(__file__).resolve().parents[1]


def evaluate(n_states: int, seed: int) -> dict[str, np.ndarray]:
    """Outputs of the three entry points at ``n_states`` random states per model (the worker's job)."""
    import uvms

    out: dict[str, np.ndarray] = {}
    for name in MODELS:
        model = uvms.load_model(name)
        n = model.n_joints
        rng = np.random.default_rng(seed)
        rows: dict[str, list] = {k: [] for k in ("nu_dot", "qdd", "nu_dot_fixed", "qdd_fixed", "f0", "tau", "M")}
        for _ in range(n_states):
            state = uvms.State.from_euler(model, position=rng.normal(size=3), euler=rng.uniform(-1.5, 1.5, 3),
                                          nu=rng.normal(scale=0.5, size=6), q=rng.uniform(-np.pi, np.pi, n),
                                          qd=rng.normal(scale=1.0, size=n))
            rest = uvms.State.from_euler(model, position=state.position, euler=rng.uniform(-1.5, 1.5, 3),
                                         q=state.q, qd=state.qd)
            current, fluid_acc = rng.normal(scale=0.5, size=3), rng.normal(scale=0.2, size=3)
            tau, f_body, f_ee = rng.normal(scale=2.0, size=n), rng.normal(scale=20.0, size=6), rng.normal(size=6)
            acc = uvms.forward_dynamics(model, state, joint_torques=tau, body_wrench=f_body, ee_wrench=f_ee,
                                        current=current, fluid_acceleration=fluid_acc)
            fixed = uvms.forward_dynamics(model, rest, joint_torques=tau, ee_wrench=f_ee, fixed_base=True,
                                          current=current, fluid_acceleration=fluid_acc)
            f0, tau_id = uvms.inverse_dynamics(model, state, nu_dot=rng.normal(size=6), qdd=rng.normal(size=n),
                                               ee_wrench=rng.normal(size=6), current=rng.normal(scale=0.5, size=3),
                                               fluid_acceleration=rng.normal(scale=0.2, size=3))
            for key, value in (("nu_dot", acc.nu_dot), ("qdd", acc.qdd), ("nu_dot_fixed", fixed.nu_dot),
                               ("qdd_fixed", fixed.qdd), ("f0", f0), ("tau", tau_id),
                               ("M", uvms.mass_matrix(model, state))):
                rows[key].append(np.array(value, dtype=float))
        for key, values in rows.items():
            out[f"{name}/{key}"] = np.stack(values)
    return out


def largest_relative_difference(ref: dict, new: dict) -> tuple[float, str]:
    """``max |new - ref| / max |ref|`` per state and output, the largest over all and where it is."""
    worst, where = 0.0, ""
    for key in ref:
        a, b = ref[key], new[key]
        if a.shape != b.shape:
            return float("inf"), f"{key}: shapes {a.shape} and {b.shape}"
        for k in range(a.shape[0]):
            scale = np.max(np.abs(a[k]))
            diff = np.max(np.abs(b[k] - a[k]))
            rel = diff / scale if scale > 0 else diff
            if not np.isfinite(rel) or rel > worst:
                worst, where = (float("inf") if not np.isfinite(rel) else float(rel)), f"{key}, state {k}"
    return worst, where


def run_worker(src: Path, cache: Path, output: Path, n_states: int, seed: int) -> None:
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache))
    subprocess.run([sys.executable, str(Path(__file__).resolve()), "--worker", str(output), "--states",
                    str(n_states), "--seed", str(seed)], env=env, check=True)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ref", default="cbb0ffd", help="reference commit (default cbb0ffd)")
    parser.add_argument("--states", type=int, default=200, help="random states per model (default 200)")
    parser.add_argument("--seed", type=int, default=20261130)
    parser.add_argument("--tolerance", type=float, default=1e-12)
    parser.add_argument("--worker", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker is not None:
        np.savez(args.worker, **evaluate(args.states, args.seed))
        return 0
    with tempfile.TemporaryDirectory(prefix="uvms-check-") as tmp:
        tmp = Path(tmp)
        tree = tmp / "ref"
        subprocess.run(["git", "-C", str(REPO), "worktree", "add", "--detach", "--quiet", str(tree), args.ref],
                       check=True)
        try:
            run_worker(tree / "src", tmp / "cache-ref", tmp / "ref.npz", args.states, args.seed)
            run_worker(REPO / "src", tmp / "cache-new", tmp / "new.npz", args.states, args.seed)
        finally:
            subprocess.run(["git", "-C", str(REPO), "worktree", "remove", "--force", str(tree)], check=False)
        with np.load(tmp / "ref.npz") as r, np.load(tmp / "new.npz") as n:
            ref, new = dict(r), dict(n)
    worst, where = largest_relative_difference(ref, new)
    count = sum(v.shape[0] for v in ref.values())
    print(f"{args.states} states per model x {len(MODELS)} models ({count} outputs): largest relative difference "
          f"against {args.ref} = {worst:.3e} ({where}); tolerance {args.tolerance:.0e}")
    if not worst <= args.tolerance:
        print("FAILED: the dynamics moved")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
