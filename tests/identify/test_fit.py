"""Output-error identification (uvms.identify) recovers parameters that made synthetic logs, within the
uncertainties it reports; held-out experiments are scored, never fitted; the fitted model file loads."""

import numpy as np
import pytest

import uvms
from tests.identify.synthetic import noisy_experiments
from uvms.errors import UvmsInputError
from uvms.identify import Experiment, identify
from uvms.identify.experiment import signal_values
from uvms.identify.write import write_fitted_model
from uvms.model.parameters import with_parameters

NOISE_DEG = 0.1
NOISE_M = 0.001
SCALE = {"roll": np.radians(NOISE_DEG), "pitch": np.radians(NOISE_DEG), "depth": NOISE_M}


def _experiments(truth, starts, seed, duration=6.0):
    """Logs that ``truth`` made from tilted starts, with white noise of known size added."""
    return noisy_experiments(truth, starts, seed, duration, SCALE)


@pytest.fixture(scope="module")
def fitted():
    base = uvms.load_model("paper")
    truth = with_parameters(base, {"cob.z": base.cob[0, 2] - 0.01, "buoyancy": base.buoyancy_mass[0] * 1.02})
    fit = _experiments(truth, [(0.15, 0.1, 0.0), (-0.1, 0.2, 0.3)], seed=1)
    held = _experiments(truth, [(0.05, -0.2, 0.1)], seed=2)
    result = identify(base, fit, ["cob.z", "buoyancy"], held_out=held, signals=("roll", "pitch", "depth"),
                      scale=SCALE, threads=2)
    return base, truth, result


def test_recovers_the_parameters_that_made_the_logs_within_its_uncertainty(fitted):
    base, truth, result = fitted
    true_values = np.array([truth.cob[0, 2], truth.buoyancy_mass[0]])
    start = np.array([base.cob[0, 2], base.buoyancy_mass[0]])
    assert result.converged, result.message
    assert np.all(np.abs(start - true_values) > 100 * result.std)          # the start was far off
    assert np.all(np.abs(result.values - true_values) <= 3.0 * result.std), (result.values, result.std)
    assert np.all(result.std >= result.std_white)
    assert result.at_bound == ()


def test_the_fitted_residual_is_the_noise_and_held_out_trials_are_scored_apart(fitted):
    _, _, result = fitted
    roles = [s["role"] for s in result.scores]
    assert roles == ["fit", "fit", "held_out"]
    for s in result.scores:
        # white noise of NOISE_DEG has an RMSE of NOISE_DEG: the fitted model leaves only the noise
        assert s["pitch_rmse_deg_after"] == pytest.approx(NOISE_DEG, rel=0.25)
        assert s["roll_rmse_deg_after"] == pytest.approx(NOISE_DEG, rel=0.25)
        assert s["pitch_rmse_deg_before"] > 10 * NOISE_DEG
    record = result.to_dict()
    assert record["held_out"] == ["trial2-0"] and record["fitted_on"] == ["trial1-0", "trial1-1"]


def test_the_fitted_model_file_loads_with_the_fitted_values_and_its_record(fitted, tmp_path):
    base, _, result = fitted
    path = write_fitted_model(result, base.source, tmp_path / "sub" / "paper_fit.yaml", logs=["a.yaml"])
    model = uvms.load_model(path)
    assert model.name == "paper_fit"
    assert model.cob[0, 2] == result.values[0] and model.buoyancy_mass[0] == result.values[1]
    np.testing.assert_array_equal(model.mass, base.mass)
    text = path.read_text()
    assert "held_out:" in text and "trial2-0" in text and "a.yaml" in text


def test_a_bound_that_stops_the_fit_is_named():
    base = uvms.load_model("paper")
    truth = with_parameters(base, {"cob.z": base.cob[0, 2] - 0.01})
    fit = _experiments(truth, [(0.15, 0.1, 0.0)], seed=3, duration=3.0)
    result = identify(base, fit, [f"cob.z={base.cob[0, 2] - 0.005}:0.0"], scale=SCALE, threads=2)
    assert result.at_bound == ("cob.z",)
    assert result.values[0] == pytest.approx(base.cob[0, 2] - 0.005)


def test_a_fit_stopped_early_says_so_and_keeps_the_best_point_it_evaluated():
    """Issue 25, bad input: a fit that does not converge says so and keeps the best point. Every residual
    evaluation's cost is seen through ``progress``; the point kept is the cheapest of them."""
    base = uvms.load_model("paper")
    truth = with_parameters(base, {"cob.z": base.cob[0, 2] - 0.01, "cob.x": base.cob[0, 0] + 0.004})
    fit = _experiments(truth, [(0.15, 0.1, 0.0)], seed=4, duration=3.0)
    costs = []
    result = identify(base, fit, ["cob.z", "cob.x"], scale=SCALE, threads=2, max_evaluations=3,
                      progress=lambda evaluations, cost: costs.append(cost))
    assert not result.converged and "maximum number of function evaluations" in result.message
    assert result.evaluations == len(costs) == 3
    assert result.cost[0] == costs[0]                 # the first evaluation is the start
    assert result.cost[1] == min(costs) < costs[0]    # the point kept is the best evaluated, better than the start


@pytest.mark.parametrize("parameters, message", [
    (["cob.q"], "unknown parameter"),
    (["cob.z=1:0"], "lower < upper"),
    (["cob.z", "cob.z"], "given twice"),
])
def test_bad_fits_are_one_line(parameters, message):
    base = uvms.load_model("paper")
    e = Experiment("e", uvms.State.zero(base), 1.0, np.array([0.0, 1.0]), {"roll": [0, 0], "pitch": [0, 0]})
    with pytest.raises(UvmsInputError, match=message):
        identify(base, [e], parameters)
    with pytest.raises(UvmsInputError, match="both fitted and held out"):
        identify(base, [e], ["cob.z"], held_out=[e])
    for step in (0.0, float("nan")):
        with pytest.raises(UvmsInputError, match="step: expected a positive, finite number"):
            Experiment("e", uvms.State.zero(base), 1.0, np.array([0.0, 1.0]), {"roll": [0, 0]}, step=step)
    for option, words in (({"max_evaluations": 0}, "max_evaluations: expected a whole number >= 1"),
                          ({"threads": 0}, "threads: expected a whole number >= 1"),
                          ({"threads": 2.5}, "threads: expected a whole number >= 1"),
                          ({"loss": "l1"}, "loss: expected one of linear, soft_l1")):
        with pytest.raises(UvmsInputError, match=words):
            identify(base, [e], ["cob.z"], **option)


def test_signals_by_hand():
    times = np.array([0.0, 1.0, 2.0])
    position = np.array([[0.0, 0.0, 1.0], [0.1, 0.2, 1.5], [0.2, 0.4, 0.5]])
    euler = np.array([[0.1, 0.2, 3.1], [0.1, 0.2, -3.1], [0.1, 0.2, -3.0]])
    np.testing.assert_allclose(signal_values("depth", times, position, euler, "ned"), [0.0, 0.5, -0.5])
    np.testing.assert_allclose(signal_values("depth", times, position, euler, "enu"), [0.0, -0.5, 0.5])
    np.testing.assert_allclose(signal_values("yaw", times, position, euler), [0.0, 2 * np.pi - 6.2, 2 * np.pi - 6.1])
