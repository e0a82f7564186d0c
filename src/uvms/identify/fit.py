"""Output-error identification: fit named model parameters to logged trials by least squares on the simulation
error (``docs/logs.md``, "Identification").

For parameters ``p`` (:mod:`uvms.model.parameters`), the residuals stack, over the fitted experiments ``e`` and
the chosen signals ``s``, the simulation error at the measurement times, each signal divided by its scale
``sigma_s`` (its noise level, :data:`~uvms.identify.experiment.DEFAULT_SCALE`)::

    r(p) = [ (y_sim,e,s(p; t) - y_log,e,s(t)) / sigma_s ]        minimised: 1/2 |r(p)|^2

solved by ``scipy.optimize.least_squares`` (trust-region reflective, with bounds). The Jacobian is a forward
difference of whole simulations, all perturbed runs of one evaluation simulated at once in threads
(:func:`uvms.sim.batch.run_plans`, the compiled loops release the GIL).

Uncertainty (Ljung, *System Identification*, 2nd ed., 1999, sec. 9.2; Bard, *Nonlinear Parameter Estimation*,
1974, ch. 7): ``cov = s^2 (J^T J)^-1`` with ``s^2 = |r|^2 / (m - k)``. The residuals of a time series are
correlated, so that figure is optimistic; the reported standard deviations are inflated by
``sqrt((1 + rho_1) / (1 - rho_1))``, the variance factor of an AR(1) sequence with the residuals' mean lag-one
autocorrelation ``rho_1`` (Bayley & Hammersley 1946, the effective number of independent samples). Both are
reported. Held-out experiments are never part of ``r``: they are scored alone, before and after.
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from uvms.errors import UvmsInputError
from uvms.identify.experiment import DEFAULT_SCALE, SIGNALS, Experiment, difference, result_signals
from uvms.model.parameters import MAX_PARAMETERS, Parameter, frame_sign, parameter, with_parameters

MAX_EXPERIMENTS = 200
"""Most experiments (fitted and held out) of one identification."""

PENALTY = 1e3
"""Scaled residual given to every sample after a run stopped early (diverged): large against a fitted
residual of order 1, finite so that the solver can step back."""


@dataclass(frozen=True)
class Bounds:
    """Lower and upper bound of one parameter [its unit]."""

    lower: float
    upper: float


def default_bounds(p: Parameter, value: float) -> Bounds:
    """Bounds when none are given: a buoyancy or a point load's mass or fluid mass within 50 % of its value
    (0 to 1 kg when it is zero), a centre or a point load's position within 0.1 m, a disturbance within 10 N m or
    10 N of its value, a damping or added-mass entry between 0 and ten times its value (or 10 when it is zero)."""
    if p.field in ("buoyancy_mass", "point_load.mass", "point_load.fluid_mass"):
        return Bounds(0.5 * value, 1.5 * value) if value > 0 else Bounds(0.0, 1.0)
    if p.field in ("cob", "point_load.position"):
        return Bounds(value - 0.1, value + 0.1)
    if p.field == "disturbance_wrench":
        return Bounds(value - 10.0, value + 10.0)
    return Bounds(0.0, 10.0 * value if value > 0 else 10.0)


def parse_parameter(text: str) -> tuple[str, Bounds | None]:
    """``name`` or ``name=lower:upper`` (the ``--fit`` form) as ``(name, bounds or None)``."""
    name, eq, rest = str(text).partition("=")
    if not eq:
        return name.strip(), None
    lo, colon, hi = rest.partition(":")
    try:
        bounds = Bounds(float(lo), float(hi))
    except ValueError:
        bounds = None
    if not colon or bounds is None or not (np.isfinite(bounds.lower) and np.isfinite(bounds.upper)) \
            or bounds.lower >= bounds.upper:
        raise UvmsInputError(f"--fit {text!r}: expected name or name=lower:upper with lower < upper")
    return name.strip(), bounds


@dataclass(frozen=True, eq=False)
class Identification:
    """The labelled outcome of :func:`identify`.

    Attributes:
        parameters: the fitted parameters (:class:`~uvms.model.parameters.Parameter`), in order.
        initial: (k,) their values in the starting model.
        values: (k,) the fitted values (the best point found).
        std: (k,) standard deviations, inflated for correlated residuals (module docstring).
        std_white: (k,) the same assuming white residuals.
        correlation: (k, k) correlation matrix of the estimates.
        bounds: the bounds used, per parameter.
        at_bound: names of the parameters that stopped at a bound.
        converged: whether the solver met a tolerance.
        message: the solver's message.
        evaluations: residual evaluations (each simulating every fitted experiment).
        cost: ``1/2 |r|^2`` at the start and at the end.
        scores: one dict per experiment: name, role (``fit`` or ``held_out``), RMSE per signal before and after
            [deg for angles, m for positions].
        model: the fitted model.
        wall_time_s: seconds taken.
    """

    parameters: tuple[Parameter, ...]
    initial: np.ndarray
    values: np.ndarray
    std: np.ndarray
    std_white: np.ndarray
    correlation: np.ndarray
    bounds: tuple[Bounds, ...]
    at_bound: tuple[str, ...]
    converged: bool
    message: str
    evaluations: int
    cost: tuple[float, float]
    scores: tuple[dict, ...]
    model: Any = field(repr=False)
    signals: tuple[str, ...] = ("roll", "pitch")
    wall_time_s: float = 0.0

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    def in_frame(self, target: str, source: str) -> "Identification":
        """This identification with its values (and bounds) written in frame convention ``target``, the fit
        having been made in ``source`` (:func:`uvms.model.parameters.frame_sign`: ``cob.y`` and ``cob.z``
        change sign under the half turn, the diagonals do not)."""
        from dataclasses import replace

        from uvms.model.parameters import frame_sign

        signs = np.array([frame_sign(p, source, target) for p in self.parameters])
        box = tuple(b if s > 0 else Bounds(-b.upper, -b.lower) for b, s in zip(self.bounds, signs))
        return replace(self, initial=signs * self.initial, values=signs * self.values, bounds=box,
                       correlation=self.correlation * np.outer(signs, signs))

    def table(self):
        """The parameters as a pandas DataFrame: name, unit, initial, value, std, std_white, bounds, at bound."""
        import pandas as pd

        return pd.DataFrame([{"parameter": p.name, "unit": p.unit, "initial": a, "value": v, "std": s,
                              "std_white": w, "lower": b.lower, "upper": b.upper, "at_bound": p.name in self.at_bound}
                             for p, a, v, s, w, b in zip(self.parameters, self.initial, self.values, self.std,
                                                         self.std_white, self.bounds)])

    def to_dict(self) -> dict:
        """Plain data for JSON/YAML (the record written into a fitted model file)."""
        return {
            "method": "output-error least squares (scipy.optimize.least_squares, trf), forward-difference Jacobian "
                      "of whole simulations",
            "signals": list(self.signals),
            "parameters": {p.name: {"unit": p.unit, "initial": float(a), "value": float(v), "std": float(s),
                                    "std_white": float(w), "bounds": [float(b.lower), float(b.upper)]}
                           for p, a, v, s, w, b in zip(self.parameters, self.initial, self.values, self.std,
                                                       self.std_white, self.bounds)},
            "correlation": np.round(self.correlation, 4).tolist(),
            "at_bound": list(self.at_bound),
            "converged": bool(self.converged),
            "message": self.message,
            "evaluations": int(self.evaluations),
            "cost": [float(self.cost[0]), float(self.cost[1])],
            "fitted_on": [s["name"] for s in self.scores if s["role"] == "fit"],
            "held_out": [s["name"] for s in self.scores if s["role"] == "held_out"],
            "scores": [dict(s) for s in self.scores],
            "wall_time_s": round(float(self.wall_time_s), 2),
        }


def _plans(models, experiments: Sequence[Experiment]):
    from uvms.sim.run import prepare

    return [prepare(m, e.initial_state, duration=e.duration, step=e.step, inputs=e.inputs,
                    actuation=e.actuation, record_period=e.record_period())
            for m in models for e in experiments]


def simulate_experiments(models, experiments: Sequence[Experiment], *, threads: int | None = None):
    """Run every experiment with every model (models outer), in threads: a list of lists of results. Joint
    limits crossed are left in each result's metadata, not warned: a logged motion crosses them in every run
    alike (``uvms replay`` of that log says so once)."""
    import os
    import warnings

    from uvms.model.limits import JointLimitWarning
    from uvms.sim.batch import run_plans

    if not experiments:
        return [[] for _ in models]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", JointLimitWarning)
        results = run_plans(_plans(models, experiments), threads=threads or os.cpu_count() or 1)
    n = len(experiments)
    return [list(results[i * n:(i + 1) * n]) for i in range(len(models))]


def _residuals(results, experiments, signals, scale) -> np.ndarray:
    parts = []
    for result, e in zip(results, experiments):
        sim = result_signals(result, e.times, signals, e.frame)
        alive = e.times <= result.time[-1] + 1e-12 if not result.complete else np.ones(e.times.size, bool)
        for s in signals:
            r = difference(s, sim[s], e.measured[s]) / scale[s]
            parts.append(np.where(alive, r, PENALTY))
    return np.concatenate(parts)


def rmse(result, e: Experiment, signals) -> dict[str, float]:
    """RMSE of each signal of ``result`` against experiment ``e`` (degrees for angles, metres otherwise)."""
    sim = result_signals(result, e.times, signals, e.frame)
    out = {}
    for s in signals:
        v = float(np.sqrt(np.mean(difference(s, sim[s], e.measured[s]) ** 2)))
        out[s] = float(np.degrees(v)) if s in ("roll", "pitch", "yaw") else v
    return out


@dataclass(frozen=True)
class FitOptions:
    """How :func:`identify` fits.

    Attributes:
        signals: the compared signals (:data:`~uvms.identify.experiment.SIGNALS`).
        scale: residual scale per signal (default :data:`~uvms.identify.experiment.DEFAULT_SCALE`).
        bounds: ``{name: (lower, upper)}``, overriding :func:`default_bounds` and ``name=lower:upper``.
        loss: ``least_squares``'s loss (``"linear"``, or ``"soft_l1"`` for outliers).
        max_evaluations: most residual evaluations (each a simulation of every fitted experiment).
        threads: simulation threads (default: the machine's cores).
    """

    signals: tuple[str, ...] = ("roll", "pitch")
    scale: Mapping[str, float] | None = None
    bounds: Mapping[str, tuple[float, float]] | None = None
    loss: str = "linear"
    max_evaluations: int = 30
    threads: int | None = None


def identify(model, experiments: Sequence[Experiment], parameters: Sequence[str], *,
             held_out: Sequence[Experiment] = (), options: FitOptions | None = None,
             progress: Callable[[int, float], None] | None = None, **keywords) -> Identification:
    """Fit ``parameters`` of ``model`` to ``experiments`` (module docstring).

    Args:
        parameters: parameter names (:mod:`uvms.model.parameters`), or ``name=lower:upper``.
        held_out: experiments scored before and after, never fitted.
        options: a :class:`FitOptions`, or its fields as keywords (``signals=``, ``scale=``, ``bounds=``,
            ``loss=``, ``max_evaluations=``, ``threads=``).
        progress: ``progress(evaluations, cost)`` after each evaluation.

    The experiments may be in either frame convention (all in one): the model is fitted in theirs and the
    values, bounds and fitted model are reported in the model's own (:func:`uvms.model.parameters.frame_sign`).
    """
    from scipy.optimize import least_squares

    from dataclasses import replace

    wall0 = _time.perf_counter()
    options = replace(options or FitOptions(), **keywords)
    signals, bounds, threads = tuple(options.signals), options.bounds, options.threads
    _check_options(options)
    experiments, held_out = list(experiments), list(held_out)
    if not experiments:
        raise UvmsInputError("identify: expected at least one experiment to fit")
    if len(experiments) + len(held_out) > MAX_EXPERIMENTS:
        raise UvmsInputError(f"identify: expected at most {MAX_EXPERIMENTS} experiments, got "
                             f"{len(experiments) + len(held_out)}")
    conventions = sorted({e.frame for e in experiments + held_out})
    if len(conventions) > 1:
        raise UvmsInputError(f"identify: expected experiments in one frame convention, found "
                             f"{' and '.join(conventions)}")
    own, frame = model.convention, conventions[0]
    model = model.in_frame(frame)                  # fitted in the experiments' convention, reported in the model's
    names = {e.name for e in experiments}
    overlap = sorted(names & {e.name for e in held_out})
    if overlap:
        raise UvmsInputError(f"identify: {overlap[0]!r} is both fitted and held out")
    for s in signals:
        if s not in SIGNALS:
            raise UvmsInputError(f"identify: unknown signal {s!r}; expected one of {', '.join(SIGNALS)}")
        for e in experiments + held_out:
            if s not in e.measured:
                raise UvmsInputError(f"identify: experiment {e.name!r} has no measured {s!r}")
    scale = {**DEFAULT_SCALE, **(options.scale or {})}
    if not 0 < len(parameters) <= MAX_PARAMETERS:
        raise UvmsInputError(f"identify: expected 1 to {MAX_PARAMETERS} parameters, got {len(parameters)}")
    params, box = [], []
    for text in parameters:
        name, given = parse_parameter(text)
        p = parameter(model, name, "--fit")
        if any(q.name == p.name for q in params):
            raise UvmsInputError(f"--fit: parameter {p.name!r} given twice")
        b = Bounds(*map(float, bounds[p.name])) if bounds and p.name in bounds else given
        if b is not None and frame_sign(p, own, frame) < 0:      # given in the model's convention
            b = Bounds(-b.upper, -b.lower)
        b = b or default_bounds(p, p.value(model))
        if not b.lower < b.upper:
            raise UvmsInputError(f"--fit {p.name}: expected lower < upper, got {b.lower:g}, {b.upper:g}")
        params.append(p)
        box.append(b)
    lower = np.array([b.lower for b in box])
    upper = np.array([b.upper for b in box])
    x_initial = np.array([p.value(model) for p in params])
    x0 = np.clip(x_initial, lower + 1e-6 * (upper - lower), upper - 1e-6 * (upper - lower))
    widths = upper - lower
    cache: dict[bytes, np.ndarray] = {}
    count = [0]

    def model_at(x):
        return with_parameters(model, {p.name: float(v) for p, v in zip(params, x)})

    def evaluate(xs: list[np.ndarray]) -> list[np.ndarray]:
        todo = [x for x in xs if x.tobytes() not in cache]
        if todo:
            runs = simulate_experiments([model_at(x) for x in todo], experiments, threads=threads)
            for x, results in zip(todo, runs):
                cache[x.tobytes()] = _residuals(results, experiments, signals, scale)
        return [cache[x.tobytes()] for x in xs]

    def fun(x):
        r = evaluate([np.array(x, dtype=float)])[0]
        count[0] += 1
        if progress is not None:
            progress(count[0], 0.5 * float(r @ r))
        return r

    def steps(x):
        h = 1e-4 * widths
        return np.where(x + h <= upper, h, -h)

    def jac(x):
        x = np.array(x, dtype=float)
        h = steps(x)
        shifted = []
        for j in range(x.size):
            xj = x.copy()
            xj[j] += h[j]
            shifted.append(xj)
        r0, *rs = evaluate([x] + shifted)
        return np.column_stack([(r - r0) / hj for r, hj in zip(rs, h)])

    r_start = evaluate([x0])[0]
    solution = least_squares(fun, x0, jac=jac, bounds=(lower, upper), x_scale="jac", loss=options.loss,
                             max_nfev=int(options.max_evaluations), method="trf")
    x = np.array(solution.x, dtype=float)
    r = evaluate([x])[0]
    J = jac(x)
    m, k = r.size, x.size
    s2 = float(r @ r) / max(1, m - k)
    cov = s2 * np.linalg.pinv(J.T @ J)
    std_white = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    inflation = np.sqrt(_ar1_factor(r, len(experiments) * len(signals)))
    d = np.where(std_white > 0, std_white, 1.0)
    correlation = cov / np.outer(d, d)
    at_bound = tuple(p.name for p, v, lo, hi in zip(params, x, lower, upper)
                     if min(v - lo, hi - v) <= 1e-3 * (hi - lo))
    fitted = model_at(x)
    scores = _scores(model, fitted, experiments, held_out, signals, threads)
    result = Identification(
        parameters=tuple(params), initial=x_initial, values=x, std=std_white * inflation, std_white=std_white,
        correlation=correlation, bounds=tuple(box), at_bound=at_bound, converged=bool(solution.status > 0),
        message=str(solution.message), evaluations=int(solution.nfev), cost=(0.5 * float(r_start @ r_start),
                                                                              0.5 * float(r @ r)),
        scores=scores, model=fitted, signals=signals, wall_time_s=_time.perf_counter() - wall0)
    if own == frame:
        return result
    from dataclasses import replace as replace_dataclass

    return replace_dataclass(result.in_frame(own, frame), model=fitted.in_frame(own))


LOSSES = ("linear", "soft_l1", "huber", "cauchy", "arctan")
"""The losses of ``scipy.optimize.least_squares``."""


def _check_options(options: FitOptions) -> None:
    """One line for options ``least_squares`` or the thread pool would refuse with a traceback."""
    from uvms import checks
    from uvms.sim.batch import MAX_THREADS

    checks.count(options.max_evaluations, "max_evaluations", minimum=1)
    if options.threads is not None and checks.count(options.threads, "threads", minimum=1) > MAX_THREADS:
        raise checks.fail("threads", f"expected at most {MAX_THREADS} threads, got {options.threads}")
    if options.loss not in LOSSES:
        raise UvmsInputError(f"expected one of {', '.join(LOSSES)}, got {options.loss!r}", path="loss")


def _ar1_factor(r: np.ndarray, pieces: int) -> float:
    """``(1 + rho_1) / (1 - rho_1)`` for the mean lag-one autocorrelation of the residual pieces (>= 1)."""
    rhos = []
    for piece in np.array_split(r, max(1, pieces)):
        piece = piece - piece.mean()
        denom = float(piece @ piece)
        if piece.size > 2 and denom > 0:
            rhos.append(float(piece[1:] @ piece[:-1]) / denom)
    rho = float(np.clip(np.mean(rhos), 0.0, 0.99)) if rhos else 0.0
    return (1.0 + rho) / (1.0 - rho)


def _scores(before, after, experiments, held_out, signals, threads) -> tuple[dict, ...]:
    every = experiments + held_out
    runs = simulate_experiments([before, after], every, threads=threads)
    out = []
    for k, e in enumerate(every):
        row: dict[str, Any] = {"name": e.name, "role": "fit" if k < len(experiments) else "held_out"}
        for label, results in (("before", runs[0]), ("after", runs[1])):
            for s, v in rmse(results[k], e, signals).items():
                row[f"{s}_rmse_{'deg' if s in ('roll', 'pitch', 'yaw') else 'm'}_{label}"] = round(v, 6)
        out.append(row)
    return tuple(out)
