"""``uvms identify`` fits a point load's fluid mass and a constant disturbance wrench (a surge force and a pitch
moment) to noisy synthetic logs made by uvms, recovering them within the uncertainties it reports; the fitted
model file holds them; a bad name is one line, exit 2."""

from importlib.resources import files

import numpy as np
import pytest

import uvms
from tests.identify.synthetic import noisy_experiments
from tests.replays.synthetic import write_log
from uvms.cli import main
from uvms.identify import identify
from uvms.identify.fit import Bounds, parse_parameter
from uvms.identify.write import write_fitted_model
from uvms.model.parameters import with_parameters

PAPER = (files("uvms") / "model" / "models" / "paper.yaml").read_text()
FOAM = "\npoint_loads:\n  - {name: foam, body: vehicle, position: [0.12, 0.03, -0.1], buoyancy: 0.5}\n"
SIGNALS = ("roll", "pitch", "depth", "x")
SCALE = {"roll": np.radians(0.1), "pitch": np.radians(0.1), "depth": 0.001, "x": 0.001}
NAMES = ["point_load:foam.fluid_mass", "disturbance.surge", "disturbance.pitch"]
TRUTH = {"point_load:foam.fluid_mass": 0.65, "disturbance.surge": 3.0, "disturbance.pitch": -0.4}


def _experiments(truth, starts, seed, duration=5.0):
    return noisy_experiments(truth, starts, seed, duration, SCALE)


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    path = tmp_path_factory.mktemp("foam") / "foam.yaml"
    path.write_text(PAPER.replace("name: paper", "name: paper_foam", 1) + FOAM)
    base = uvms.load_model(path)
    truth = with_parameters(base, TRUTH)
    fit = _experiments(truth, [(0.15, 0.1, 0.0), (-0.1, 0.2, 0.3)], seed=3)
    held = _experiments(truth, [(0.05, -0.2, 0.1)], seed=4)
    return base, identify(base, fit, NAMES, held_out=held, signals=SIGNALS, scale=SCALE, threads=2)


def test_recovers_a_point_load_fluid_mass_and_a_disturbance_within_its_uncertainty(fitted):
    base, result = fitted
    true_values = np.array([TRUTH[n] for n in NAMES])
    start = np.array([0.5, 0.0, 0.0])
    assert result.converged, result.message
    np.testing.assert_array_equal(result.initial, start)
    assert np.all(np.abs(start - true_values) > 30 * result.std)          # the start was far off
    assert np.all(np.abs(result.values - true_values) <= 3.0 * result.std), (result.values, result.std)
    assert result.at_bound == ()
    held = next(s for s in result.scores if s["role"] == "held_out")
    assert held["pitch_rmse_deg_after"] == pytest.approx(0.1, rel=0.3)


def test_the_fitted_model_file_holds_the_point_load_and_the_disturbance(fitted, tmp_path):
    base, result = fitted
    path = write_fitted_model(result, base.source, tmp_path / "paper_foam_fit.yaml", logs=["a.yaml"])
    model = uvms.load_model(path)
    foam = model.point_loads[0]
    assert foam.fluid_mass == result.values[0]
    assert model.disturbance_wrench[3] == result.values[1] and model.disturbance_wrench[1] == result.values[2]
    expected = with_parameters(base, dict(zip(NAMES, result.values)))
    np.testing.assert_allclose(model.buoyancy_mass, expected.buoyancy_mass, rtol=0, atol=1e-12)
    np.testing.assert_allclose(model.cob, expected.cob, rtol=0, atol=1e-12)


@pytest.mark.parametrize("fit, message", [
    ("point_load:ballast.mass", "no point load 'ballast' in model 'paper'"),
    ("link2:disturbance.surge", "a disturbance wrench acts on the vehicle only"),
])
def test_a_bad_point_load_or_disturbance_name_exits_2_in_one_line(tmp_path, capsys, fit, message):
    path, _ = write_log(tmp_path / "log", uvms.load_model("paper"), seconds=2.0)
    out = tmp_path / "fit.yaml"
    assert main(["identify", "paper", str(path), "--fit", fit, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_the_fit_form_takes_point_load_names_and_negative_bounds():
    assert parse_parameter("point_load:foam.x=-0.2:0.1") == ("point_load:foam.x", Bounds(-0.2, 0.1))
    assert parse_parameter("disturbance.surge=-5:5") == ("disturbance.surge", Bounds(-5.0, 5.0))
