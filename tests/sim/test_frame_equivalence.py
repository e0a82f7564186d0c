"""Issue 25's acceptance for frames: the same robot written z down (ned, the bundled files) and z up (enu: files
written here in ``tmp_path`` with every number given in the vehicle frame or the world turned by the half turn
about x, ``H = diag(1, -1, -1)``, by hand from the file's own numbers, not by ``Model.in_frame``) gives the same
motion to 1e-12 after the frame change: ``p -> H p``, ``[w, x, y, z] -> [w, x, -y, -z]``, ``nu -> H6 nu``,
``(roll, pitch, yaw) -> (roll, -pitch, -yaw)``, ``q``, ``qd`` and the thrusters' states unchanged."""

from pathlib import Path

import numpy as np
import pytest
import yaml

import uvms
from uvms import frames

pytestmark = pytest.mark.filterwarnings("ignore:.*crossed its position limit")
from uvms.control.registry import make_controller
from uvms.model.load import resolve_model_path
from uvms.rotations import euler_from_rotation, rotation_from_euler
from uvms.sim.options import Actuation
from uvms.state import State

H = np.diag([1.0, -1.0, -1.0])


def flip(v):
    """A vehicle-frame or world vector written in the other convention (``H v``), as a plain list."""
    return [float(x) for x in H @ np.asarray(v, dtype=float)]


def write_paper_enu(folder: Path) -> Path:
    """The bundled paper model (modified DH) written z up: vehicle numbers turned, the arm mounted by the half
    turn (its DH frames are its own and stay), gravity along -z."""
    spec = yaml.safe_load(resolve_model_path("paper").read_text())
    spec["frame"] = "enu"
    spec["environment"]["gravity"] = flip(spec["environment"]["gravity"])
    vehicle = spec["vehicle"]
    vehicle["com"] = flip(vehicle["com"])
    vehicle["buoyancy"]["center"] = flip(vehicle["buoyancy"]["center"])
    # diagonal inertia and added mass about the CoM: H I H and H6 M H6 leave a diagonal as it is
    spec["arm"]["mount"] = {"position": [0.0, 0.0, 0.0], "rotation_rpy": [float(np.pi), 0.0, 0.0]}
    for t in spec["thrusters"]:
        t["position"], t["direction"] = flip(t["position"]), flip(t["direction"])
    path = folder / "paper_enu.yaml"
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def write_bluerov_enu(folder: Path) -> Path:
    """The bundled BlueROV2 Heavy + Alpha 5 (URDF + additions) written z up: base_link forward-left-up (its
    inertia is diagonal at the origin: unchanged), the arm mount's origin turned (``H p``, ``H R``), the
    additions' vehicle numbers and thrusters turned, gravity along -z."""
    yaml_path = resolve_model_path("bluerov2_heavy_alpha5")
    urdf = (yaml_path.parent / "bluerov2_heavy_alpha5.urdf").read_text()
    old = '<origin xyz="0.22 0 0.13" rpy="0 1.5707963267948966 0"/>'
    assert urdf.count(old) == 1
    rpy = euler_from_rotation(H @ rotation_from_euler(np.array([0.0, np.pi / 2, 0.0])))
    urdf = urdf.replace(old, f'<origin xyz="0.22 0 -0.13" rpy="{float(rpy[0])!r} {float(rpy[1])!r} {float(rpy[2])!r}"/>')
    (folder / "rov_enu.urdf").write_text(urdf)
    spec = yaml.safe_load(yaml_path.read_text())
    spec["urdf"] = "rov_enu.urdf"
    spec["frame"] = "enu"
    spec["environment"]["gravity"] = flip(spec["environment"]["gravity"])
    vehicle = spec["vehicle"]
    vehicle["buoyancy"]["center"] = flip(vehicle["buoyancy"]["center"])
    # diagonal added mass and damping (no cross terms): unchanged by H6 M H6
    assert all("|" not in k or k.split("|")[0][2] == k.split("|")[1] for k in vehicle["damping"]["coefficients"])
    for t in spec["thrusters"]:
        t["position"], t["direction"] = flip(t["position"]), flip(t["direction"])
        if t.get("model") == "table" and not Path(str(t["table"])).suffix:
            pass                                    # a bundled table name: no file to copy
    path = folder / "rov_enu.yaml"
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def assert_same_motion(ned, enu, atol=1e-12):
    """Two results equal after the frame change (module docstring), row by row."""
    assert ned.complete and enu.complete
    np.testing.assert_array_equal(ned.time, enu.time)
    np.testing.assert_allclose(frames.convert_vectors(ned.position, "ned", "enu"), enu.position, rtol=0, atol=atol)
    np.testing.assert_allclose(frames.convert_quaternions(ned.quaternion, "ned", "enu"), enu.quaternion, rtol=0,
                               atol=atol)
    np.testing.assert_allclose(frames.convert_twists(ned.nu, "ned", "enu"), enu.nu, rtol=0, atol=atol)
    np.testing.assert_allclose(ned.q, enu.q, rtol=0, atol=atol)
    np.testing.assert_allclose(ned.qd, enu.qd, rtol=0, atol=atol)
    np.testing.assert_allclose(ned.actuator, enu.actuator, rtol=0, atol=atol * np.abs(ned.actuator).max(initial=1.0))
    np.testing.assert_allclose(frames.convert_vectors(ned.end_effector, "ned", "enu"), enu.end_effector, rtol=0,
                               atol=atol)
    a, b = ned.columns(), enu.columns()
    for column, sign in (("roll_rad", 1.0), ("pitch_rad", -1.0), ("yaw_rad", -1.0)):
        np.testing.assert_allclose(sign * np.asarray(a[column]), np.asarray(b[column]), rtol=0, atol=atol)
    assert np.ptp(ned.position, axis=0).max() > 1e-3 and np.ptp(ned.q, axis=0).max() > 0.1   # it moved


@pytest.fixture(scope="module")
def enu_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("enu")
    return {"paper": write_paper_enu(folder), "bluerov2_heavy_alpha5": write_bluerov_enu(folder)}


@pytest.mark.parametrize("name", ["paper", "bluerov2_heavy_alpha5"])
def test_z_up_file_loads_as_the_z_down_model_turned(name, enu_files):
    ned, enu = uvms.load_model(name), uvms.load_model(enu_files[name])
    assert (ned.convention, enu.convention) == ("ned", "enu")
    np.testing.assert_allclose(enu.gravity, [0.0, 0.0, -9.81])
    turned = ned.in_frame("enu")                   # the in-memory conversion agrees with the hand-written file
    for field in ("com", "cob", "inertia_com", "added_mass", "gravity", "joint_rotation", "joint_position",
                  "damping_linear", "damping_quadratic", "shape_drag", "mass", "buoyancy_mass"):
        np.testing.assert_allclose(getattr(enu, field), getattr(turned, field), rtol=0, atol=1e-15, err_msg=field)
    for a, b in zip(enu.thrusters, turned.thrusters, strict=True):
        np.testing.assert_allclose(a.position, b.position, atol=1e-15)
        np.testing.assert_allclose(a.direction, b.direction, atol=1e-15)
    assert turned.in_frame("ned").convention == "ned"
    np.testing.assert_array_equal(turned.in_frame("ned").joint_rotation, ned.joint_rotation)


def _start(model, q):
    rng = np.random.default_rng(25)
    return State.from_euler(model, position=[0.3, -0.2, 1.5], euler=[0.1, -0.05, 0.4], nu=0.05 * rng.normal(size=6),
                            q=q, qd=0.1 * rng.normal(size=model.n_joints))


@pytest.mark.parametrize("name, q, tau", [("paper", [0.0, 0.3, -0.2], [2.5, 0.3, -0.1]),
                                          ("bluerov2_heavy_alpha5", [0.05, 0.4, 0.4, 0.05], [0.02, 0.1, -0.05, 0.001])])
def test_released_arm_moves_the_same_in_both_frames(name, q, tau, enu_files):
    """Uncontrolled: the vehicle released, joint torques applied, every thruster idle."""
    ned, enu = uvms.load_model(name), uvms.load_model(enu_files[name])
    start = _start(ned, q)
    runs = [uvms.simulate(m, s, duration=1.0, step=1e-3, joint_torques=np.array(tau), record_period=0.01)
            for m, s in ((ned, start), (enu, start.in_frame("ned", "enu")))]
    assert_same_motion(*runs)


@pytest.mark.parametrize("name, q", [("paper", [0.0, 0.3, -0.2]), ("bluerov2_heavy_alpha5", [0.05, 0.4, 0.4, 0.05])])
def test_controlled_run_with_a_converted_set_point_is_the_same(name, q, enu_files):
    """Six-axis smc-ab through the model's thrusters, toward a set point (a waypoint) given in each model's
    frame: x, y, z by ``H``, roll, pitch, yaw by ``(roll, -pitch, -yaw)``."""
    ned, enu = uvms.load_model(name), uvms.load_model(enu_files[name])
    start = _start(ned, q)
    target_p, target_e = np.array([0.35, -0.1, 1.45]), np.array([0.0, 0.02, 0.3])
    runs = []
    for model, frame, state in ((ned, "ned", start), (enu, "enu", start.in_frame("ned", "enu"))):
        p = frames.convert_vectors(target_p, "ned", frame)
        e = frames.convert_euler(target_e, "ned", frame)
        controller = make_controller("smc-ab", model, parameters={"axes": "all",
                                                                  "waypoints": [[0.2, *p, *e]]})
        runs.append(uvms.simulate(model, state, duration=1.0, step=1e-3, controller=controller,
                                  actuation=Actuation.named("model", model), joint_torques=np.zeros(model.n_joints),
                                  record_period=0.01))
    assert_same_motion(*runs)
