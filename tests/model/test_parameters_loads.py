"""Point-load and disturbance parameters (uvms.model.parameters): setting one equals building the model from a
file with the new value; their frame signs are those of ``Model.in_frame``; bad names are one line."""

from importlib.resources import files

import numpy as np
import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.model.parameters import AXES, frame_sign, parameter, with_parameters

PAPER = (files("uvms") / "model" / "models" / "paper.yaml").read_text()


def _loads(foam=(0.5, 0.0, (0.1, 0.02, -0.1)), ballast=(0.4, 0.0, (0.05, 0.0, 0.01))) -> str:
    """A ``point_loads`` block: a foam block (buoyancy) on the vehicle and a ballast weight on link2."""
    (fm, fb, fp), (bm, bb, bp) = foam, ballast
    return ("\npoint_loads:\n"
            f"  - {{name: foam, body: vehicle, position: {list(fp)}, mass: {fm!r}, buoyancy: {fb!r}}}\n"
            f"  - {{name: ballast, body: link2, position: {list(bp)}, mass: {bm!r}, buoyancy: {bb!r}}}\n")


def _model(tmp_path, name: str, loads: str, extra: str = ""):
    path = tmp_path / f"{name}.yaml"
    path.write_text(PAPER + loads + extra)
    return uvms.load_model(path)


FIELDS = ("mass", "com", "inertia_com", "buoyancy_mass", "cob", "weight_mass", "weight_center")


def _assert_same_bodies(a, b):
    for f in FIELDS:
        np.testing.assert_allclose(getattr(a, f), getattr(b, f), rtol=0.0, atol=1e-12, err_msg=f)


def test_the_built_model_remembers_its_point_loads(tmp_path):
    model = _model(tmp_path, "m", _loads())
    foam, ballast = model.point_loads
    assert (foam.name, foam.body, foam.mass, foam.fluid_mass, foam.inertial) == ("foam", 0, 0.5, 0.0, True)
    assert ballast.name == "ballast" and ballast.body == model.body_names.index("link2")
    np.testing.assert_array_equal(foam.position, [0.1, 0.02, -0.1])


@pytest.mark.parametrize("values, foam, ballast", [
    ({"point_load:foam.fluid_mass": 1.3}, (0.5, 1.3, (0.1, 0.02, -0.1)), None),
    ({"point_load:foam.mass": 0.1, "point_load:foam.fluid_mass": 0.7}, (0.1, 0.7, (0.1, 0.02, -0.1)), None),
    ({"point_load:foam.x": -0.15, "point_load:foam.z": 0.05}, (0.5, 0.0, (-0.15, 0.02, 0.05)), None),
    ({"point_load:ballast.mass": 0.0, "point_load:foam.y": -0.03},
     (0.5, 0.0, (0.1, -0.03, -0.1)), (0.0, 0.0, (0.05, 0.0, 0.01))),
])
def test_setting_a_point_load_equals_building_the_model_with_the_new_value(tmp_path, values, foam, ballast):
    """First moments and the inertia about the origin are linear in the point mass: folding the old load out
    with a negative mass and the new one in gives the model built from the file with the new load, to 1e-12."""
    base = _model(tmp_path, "base", _loads())
    expected = _model(tmp_path, "expected", _loads(foam, ballast or (0.4, 0.0, (0.05, 0.0, 0.01))))
    changed = with_parameters(base, values)
    _assert_same_bodies(changed, expected)
    for p in values:
        assert parameter(changed, p).value(changed) == values[p]
    for a, b in zip(changed.point_loads, expected.point_loads):
        assert (a.name, a.body, a.inertial) == (b.name, b.body, b.inertial)
        np.testing.assert_allclose([a.mass, a.fluid_mass, *a.position], [b.mass, b.fluid_mass, *b.position],
                                   rtol=0, atol=1e-15)


def test_a_disturbance_parameter_sets_the_wrench_and_the_file_key_builds_it(tmp_path):
    base = uvms.load_model("paper")
    np.testing.assert_array_equal(base.disturbance_wrench, np.zeros(6))
    changed = with_parameters(base, {"disturbance.surge": 2.5, "disturbance.pitch": -0.4})
    np.testing.assert_array_equal(changed.disturbance_wrench, [0.0, -0.4, 0.0, 2.5, 0.0, 0.0])
    assert parameter(base, "disturbance.pitch").unit == "N m" and parameter(base, "disturbance.heave").unit == "N"
    from_file = _model(tmp_path, "d", "", "\ndisturbance_wrench: [0, -0.4, 0, 2.5, 0, 0]\n")
    np.testing.assert_array_equal(from_file.disturbance_wrench, changed.disturbance_wrench)


def test_frame_signs_are_those_of_in_frame(tmp_path):
    """``frame_sign`` against the model rewritten in the other convention (``Model.in_frame``): the vehicle's
    cob.y/z, a vehicle load's y/z and the disturbance's pitch, yaw, sway, heave flip; a link's own frame does not."""
    model = with_parameters(_model(tmp_path, "m", _loads(ballast=(0.4, 0.2, (0.05, 0.03, 0.01)))),
                            {f"disturbance.{a}": 1.0 + k for k, a in enumerate(AXES)})
    enu = model.in_frame("enu")
    names = ([f"disturbance.{a}" for a in AXES] + ["cob.y", "cob.z", "link2:cob.y", "link2:cob.z"]
             + [f"point_load:{n}.{q}" for n in ("foam", "ballast") for q in ("mass", "fluid_mass", "x", "y", "z")])
    flipped = []
    for name in names:
        p = parameter(model, name)
        sign = frame_sign(p, "ned", "enu")
        assert p.value(enu) == pytest.approx(sign * p.value(model), abs=1e-15), name
        if sign < 0:
            flipped.append(name)
    assert flipped == ["disturbance.pitch", "disturbance.yaw", "disturbance.sway", "disturbance.heave", "cob.y",
                       "cob.z", "point_load:foam.y", "point_load:foam.z"]
    assert parameter(model, "cob.z").value(model) != 0.0 and parameter(model, "point_load:foam.z").value(model) != 0


@pytest.mark.parametrize("values, message", [
    ({"point_load:nope.mass": 1.0}, "no point load 'nope' in model"),
    ({"point_load:foam.volume": 1.0}, "unknown parameter 'point_load:foam.volume'"),
    ({"point_load:foam.mass": -0.1}, "expected a value >= 0 kg"),
    ({"link2:disturbance.surge": 1.0}, "a disturbance wrench acts on the vehicle only"),
    ({"disturbance.forward": 1.0}, "unknown parameter 'disturbance.forward'"),
])
def test_bad_point_load_and_disturbance_parameters_are_one_line(tmp_path, values, message):
    model = _model(tmp_path, "m", _loads())
    with pytest.raises(UvmsInputError, match=message) as info:
        with_parameters(model, values)
    assert "\n" not in str(info.value)


def test_a_disturbance_on_a_link_in_a_model_file_is_one_line_naming_the_file(tmp_path):
    (tmp_path / "bad.yaml").write_text(PAPER + _loads() + "\nidentified:\n  parameters: {link2:disturbance.yaw: 1}\n")
    with pytest.raises(UvmsInputError, match=r"bad.yaml: identified.parameters: .*vehicle only"):
        uvms.load_model(tmp_path / "bad.yaml")


def test_validate_reports_a_disturbance_only_when_there_is_one():
    from uvms.analysis.report import model_report

    base = uvms.load_model("paper")
    assert "disturbance" not in model_report(base).table()
    assert "disturbance_wrench_KMN_Nm_XYZ_N" not in model_report(base).to_dict()
    report = model_report(with_parameters(base, {"disturbance.surge": 2.5, "disturbance.yaw": -0.5}))
    assert "disturbance wrench:     (0, 0, -0.5) N m (K, M, N), (2.5, 0, 0) N (X, Y, Z)" in report.table()
    assert report.to_dict()["disturbance_wrench_KMN_Nm_XYZ_N"] == [0.0, 0.0, -0.5, 2.5, 0.0, 0.0]
