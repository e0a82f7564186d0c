"""Issue 17: a model whose link has zero inertia about its joint axis is refused when it is built.

``uvms validate`` used to accept it and ``uvms run`` then died with ``ZeroDivisionError``: the articulated-body
algorithm divides by ``d_i = S_i^T I^A_i S_i``. The check (rigid + added inertia of each link about its joint
axis through the joint origin, parallel-axis term included) is sufficient for ``d_i > 0``: the tests check that
bound against the ``d_i`` the compiled ABA itself computes.
"""

from __future__ import annotations

import copy
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
import yaml

import uvms
from tests.conftest import random_model
from uvms.checks import joint_axis_inertia
from uvms.cli import main
from uvms.dynamics.aba import aba
from uvms.dynamics.kernel_model import make_workspace
from uvms.dynamics.plant import fluid_table, kernel_model
from uvms.errors import UvmsInputError

PAPER = yaml.safe_load(Path(str(files("uvms.model") / "models" / "paper.yaml")).read_text())


def _write(tmp_path, mutate) -> Path:
    data = copy.deepcopy(PAPER)
    mutate(data["arm"]["links"])
    path = tmp_path / "model.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def _point_on_axis(links, j=2):
    """Link j: a point mass on its joint axis (no inertia about the axis), no added inertia about it."""
    links[j]["com"] = [0.0, 0.0, 0.05]
    links[j]["inertia"] = {"diagonal": [0.0, 0.0, 0.0], "about": "com"}
    links[j]["added_mass"] = {"diagonal": [0.0017, 0.0017, 0.0, 0.1, 0.1, 0.1], "about": "joint"}


def _thin_rod_on_axis(links, j=0):
    """Link j: inertia about the joint only about x and y, centre of mass at the joint."""
    links[j]["com"] = [0.0, 0.0, 0.0]
    links[j]["buoyancy"]["center"] = [0.0, 0.0, 0.0]
    links[j]["inertia"] = {"diagonal": [0.01, 0.01, 0.0], "about": "joint"}
    links[j]["added_mass"] = {"diagonal": [0.001, 0.001, 0.0, 0.1, 0.1, 0.1], "about": "joint"}


def _point_above_the_joint(links, j=1):
    """Link j: 1 kg at 0.5 m along the joint axis, given about the joint (m d^2 about x and y, none about z)."""
    links[j]["com"] = [0.0, 0.0, 0.5]
    links[j]["inertia"] = {"diagonal": [0.25, 0.25, 0.0], "about": "joint"}
    links[j]["added_mass"] = {"diagonal": [0.0] * 6, "about": "joint"}


@pytest.mark.parametrize("mutate, link", [(_point_on_axis, 2), (_thin_rod_on_axis, 0), (_point_above_the_joint, 1)])
def test_zero_inertia_about_a_joint_axis_is_refused_with_the_file_and_field(tmp_path, mutate, link):
    path = _write(tmp_path, mutate)
    with pytest.raises(UvmsInputError) as info:
        uvms.load_model(path)
    message = str(info.value)
    assert message.startswith(f"{path}: arm.links[{link}].inertia: expected a positive rotational inertia about "
                              "the joint axis")
    assert "found 0 kg m^2" in message and "\n" not in message


def test_validate_refuses_it_in_one_line(tmp_path, capsys):
    path = _write(tmp_path, _point_on_axis)
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{path}: arm.links[2].inertia: expected a positive" in err


@pytest.mark.parametrize("mutate", [
    lambda links: links[2].update(inertia={"diagonal": [0.0, 0.0, 0.0], "about": "com"}),   # m d^2 only
    lambda links: (_point_on_axis(links), links[2].update(added_mass={"diagonal": [0.0, 0.0, 1e-4, 0, 0, 0],
                                                                      "about": "joint"})),  # added inertia only
])
def test_an_axis_inertia_from_the_offset_mass_or_the_added_mass_alone_is_enough(tmp_path, mutate):
    model = uvms.load_model(_write(tmp_path, mutate))
    acc = uvms.forward_dynamics(model, uvms.State.zero(model), joint_torques=[0.0, 0.0, 0.1])
    assert np.all(np.isfinite(acc.qdd)) and acc.qdd[2] > 0


def test_axis_inertia_is_the_parallel_axis_sum(tmp_path):
    """Hand-computed for the paper's links: I_zz about the CoM 0.0016 + m d^2 = 1 * 0.11^2 + added 0.0017."""
    model = uvms.load_model("paper")
    axis, _ = joint_axis_inertia(model.mass, model.com, model.inertia_com, model.added_mass)
    np.testing.assert_allclose(axis, [0.0016 + 0.0121 + 0.0017] * 3, rtol=1e-12)


def test_the_bound_holds_for_the_articulated_inertia_the_aba_computes(rng):
    """``d_i >= `` the link's own axis inertia, with equality for the outermost link (no outboard bodies)."""
    for n in (1, 3, 6):
        model = random_model(rng, n)
        axis, _ = joint_axis_inertia(model.mass, model.com, model.inertia_com, model.added_mass)
        for _ in range(5):
            ws = make_workspace(model.n_bodies)
            R0 = uvms.State.from_euler(model, euler=rng.uniform(-1, 1, 3)).rotation
            aba(kernel_model(model), ws, R0, np.zeros(3), rng.normal(size=6), rng.uniform(-3, 3, n), rng.normal(size=n),
                np.zeros(n), np.zeros(6), np.zeros(6), fluid_table([0.0], [np.zeros(3)], [np.zeros(3)]), 0.0, False,
                np.zeros(6), np.zeros(n))
            assert np.all(ws.d[1:] >= axis * (1 - 1e-12))
            np.testing.assert_allclose(ws.d[n], axis[-1], rtol=1e-12)


def test_a_model_built_directly_is_checked_too(rng):
    model = random_model(rng, 3)
    inertia = model.inertia_com.copy()
    inertia[2] = np.diag([1e-3, 1e-3, 0.0])
    com = model.com.copy()
    com[2] = [0.0, 0.0, 0.1]
    added = model.added_mass.copy()
    added[2] = np.diag([1e-3, 1e-3, 0.0, 0.1, 0.1, 0.1])
    with pytest.raises(UvmsInputError, match=r"^link 'b2' \(body 2\): expected a positive rotational inertia"):
        model.replace(inertia_com=inertia, com=com, added_mass=added)
    with pytest.raises(UvmsInputError, match=r"^link 'b2' \(body 2\)"):
        model.replace(inertia_com=inertia, com=com, added_mass=added * 0.0)
