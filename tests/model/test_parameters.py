"""Named model parameters (uvms.model.parameters) and a model file's ``identified:`` block."""

import numpy as np
import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.model.parameters import AXES, parameter, quantities, with_parameters


def test_each_quantity_sets_exactly_its_entry_and_nothing_else():
    model = uvms.load_model("bluerov2_heavy_alpha5")
    fields = ("buoyancy_mass", "cob", "damping_linear", "damping_quadratic", "added_mass")
    for q in quantities():
        p = parameter(model, q)
        changed = with_parameters(model, {q: 0.123})
        assert p.value(changed) == 0.123
        for f in fields:
            before, after = np.asarray(getattr(model, f)), np.asarray(getattr(changed, f))
            mask = np.zeros(before.shape, dtype=bool)
            if f == p.field:
                mask[(p.body, *p.index)] = True
            np.testing.assert_array_equal(after[~mask], before[~mask])


def test_axis_order_is_angular_then_linear_and_bodies_are_named():
    model = uvms.load_model("paper")
    assert AXES.index("pitch") == 1 and AXES.index("heave") == 5
    p = parameter(model, "damping.linear.heave")
    assert (p.field, p.index, p.unit) == ("damping_linear", (5, 5), "N s/m")
    link = model.body_names[2]
    assert parameter(model, f"{link}:buoyancy").body == 2


@pytest.mark.parametrize("values, message", [
    ({"buoyancy.z": 1.0}, "unknown parameter 'buoyancy.z'"),
    ({"nobody:buoyancy": 1.0}, "no body 'nobody'"),
    ({"buoyancy": float("nan")}, "expected a finite number"),
    ({"damping.linear.roll": -1.0}, "expected a value >= 0"),
    ({"buoyancy": "heavy"}, "expected a number"),
])
def test_bad_parameters_are_one_line(values, message):
    with pytest.raises(UvmsInputError, match=message):
        with_parameters(uvms.load_model("paper"), values)


def test_a_model_file_identified_block_sets_the_parameters(tmp_path):
    from importlib.resources import files

    text = (files("uvms") / "model" / "models" / "paper.yaml").read_text()
    base = uvms.load_model("paper")
    (tmp_path / "fit.yaml").write_text(text + "\nidentified:\n  parameters: {buoyancy: 51.5, cob.z: -0.02}\n"
                                       "  record: {method: test}\n")
    fitted = uvms.load_model(tmp_path / "fit.yaml")
    assert fitted.buoyancy_mass[0] == 51.5 and fitted.cob[0, 2] == -0.02
    np.testing.assert_array_equal(fitted.buoyancy_mass[1:], base.buoyancy_mass[1:])
    (tmp_path / "bad.yaml").write_text(text + "\nidentified:\n  parameters: {cob.w: 1.0}\n")
    with pytest.raises(UvmsInputError, match=r"bad.yaml: identified.parameters: unknown parameter 'cob.w'"):
        uvms.load_model(tmp_path / "bad.yaml")
