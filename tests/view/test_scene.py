"""The scene of a model at a pose, checked against poses worked out by hand from the paper model's Table 1
(modified DH, ``docs/conventions.md``) and the NED world frame; frame sampling of replays; the drawn orientation
(z down on the screen, and the picture not mirrored)."""

from __future__ import annotations

import numpy as np
import pytest

from uvms.state import State
from uvms.view import picture, pose_scene, scene_from_model, show
from uvms.view.animate import frame_samples, replay
from uvms.view.scene import Primitive, body_poses

from .conftest import synthetic_result

L1 = 0.22          # link length and DH a_prev of the paper model [m] (Table 1)
R_LINK = 0.0125    # link radius [m]


def snapshot(model, **state):
    scene = scene_from_model(model)
    R, p = body_poses(model, State.from_euler(model, **state))
    return scene, pose_scene(scene, R, p)


def test_paper_scene_reads_the_model_file(paper):
    scene = scene_from_model(paper)
    kinds = [(p.kind, p.body) for p in scene.primitives]
    assert kinds == [("box", 0), ("cylinder", 1), ("cylinder", 2), ("cylinder", 3)]
    assert scene.primitives[0].size == pytest.approx((0.596, 0.596, 0.596))
    assert all(p.size == pytest.approx((R_LINK, L1)) for p in scene.primitives[1:])
    assert [t.name for t in scene.thrusters] == ["surge_port", "surge_starboard", "heave", "sway"]
    assert scene.body_names[1:] == ("link1", "link2", "link3")


def test_arm_bent_down_by_hand(paper):
    """q = (0, -pi/2, 0): joint 2's axis is RotX(-pi/2) e_z = +y, link 2 turns from +x to +z (down), so link 3
    runs from (0.22, 0, 0.22) to the end effector at (0.22, 0, 0.44): below the vehicle, not above it."""
    _, snap = snapshot(paper, q=[0.0, -np.pi / 2, 0.0])
    assert snap.end_effector == pytest.approx([L1, 0.0, 2 * L1], abs=1e-12)
    V, _ = snap.meshes[3]                                   # link 3's cylinder
    assert np.abs(V[:, 0] - L1).max() <= R_LINK + 1e-12
    assert np.abs(V[:, 1]).max() <= R_LINK + 1e-12
    assert V[:, 2].min() == pytest.approx(L1) and V[:, 2].max() == pytest.approx(2 * L1)
    a, b = snap.joint_axis[1]                               # joint 2, centred on its joint, along world y
    assert 0.5 * (a + b) == pytest.approx([L1, 0.0, 0.0], abs=1e-12)
    d = (b - a) / np.linalg.norm(b - a)
    assert abs(d[1]) == pytest.approx(1.0)


def test_vehicle_box_centres_and_thrusters_by_hand(paper):
    """Vehicle at (1, 2, 3) m, yaw +90 degrees (nose east): the port thruster (body y = -0.15 m) is then north
    of the centre and pushes east; the box is the 0.596 m cube around (1, 2, 3); the centre of buoyancy
    (body z = -0.0254 m) is above the centre of mass (smaller z)."""
    p0 = np.array([1.0, 2.0, 3.0])
    scene, snap = snapshot(paper, position=p0, euler=[0.0, 0.0, np.pi / 2])
    V, _ = snap.meshes[0]
    assert V.min(axis=0) == pytest.approx(p0 - 0.298) and V.max(axis=0) == pytest.approx(p0 + 0.298)
    port = [t.name for t in scene.thrusters].index("surge_port")
    assert snap.thruster_base[port] == pytest.approx(p0 + [0.15, 0.0, 0.0], abs=1e-12)
    assert snap.thruster_tip[port] - snap.thruster_base[port] == pytest.approx(
        [0.0, scene.arrow_length, 0.0], abs=1e-12)
    assert snap.cob[0] == pytest.approx(p0 + [0.0, 0.0, -0.0254], abs=1e-12)
    assert snap.com[0] == pytest.approx(p0, abs=1e-12)
    # joint 1 at the vehicle's centre, link 1 along the nose (east), its CoM 0.11 m out
    assert snap.com[1] == pytest.approx(p0 + [0.0, 0.11, 0.0], abs=1e-12)


@pytest.mark.parametrize("prim, check", [
    (Primitive("sphere", 0, (0.3,), position=(1, 0, 0)),
     lambda V: np.allclose(np.linalg.norm(V - [1, 0, 0], axis=1), 0.3)),
    (Primitive("ellipsoid", 0, (0.1, 0.2, 0.3)),
     lambda V: np.allclose(((V / [0.1, 0.2, 0.3]) ** 2).sum(axis=1), 1.0)),
    (Primitive("box", 0, (0.2, 0.4, 0.6)),
     lambda V: np.allclose(np.abs(V), [0.1, 0.2, 0.3])),
    (Primitive("cylinder", 0, (0.05, 0.5)),
     lambda V: np.allclose(np.abs(V[:, 2]), 0.25) and np.hypot(V[:, 0], V[:, 1]).max() == pytest.approx(0.05)),
])
def test_primitives_tessellate_to_their_size(prim, check):
    V, F = prim.local_mesh()
    assert check(V)
    assert F.min() >= 0 and F.max() < len(V)


class _WithVisuals:
    """The paper model plus shapes a model may carry later (``visuals``: a URDF's meshes)."""

    def __init__(self, model, visuals):
        self._model, self.visuals = model, visuals

    def __getattr__(self, name):
        return getattr(self._model, name)


def test_mesh_visuals_load_with_trimesh_and_missing_files_are_left_out(paper, tmp_path):
    import trimesh

    stl = tmp_path / "gripper.stl"
    trimesh.creation.box(extents=(0.1, 0.2, 0.3)).export(stl)
    model = _WithVisuals(paper, [
        {"kind": "mesh", "body": 3, "filename": str(stl), "position": (L1, 0.0, 0.0), "name": "gripper"},
        {"kind": "mesh", "body": 3, "filename": str(tmp_path / "missing.stl")},
        {"kind": "sphere", "body": 0, "radius": 0.05, "position": (0.0, 0.0, 0.4)},
    ])
    scene = scene_from_model(model)
    assert [p.kind for p in scene.primitives[4:]] == ["mesh", "sphere"]
    R, p = body_poses(paper, State.zero(paper))
    snap = pose_scene(scene, R, p)
    # at q = 0 link 3 ends at x = 3 L1 (the box is centred there); link 2's alpha_prev = -pi/2 turns the frames
    # of links 2 and 3: their y axis is world -z and their z axis world +y (RotX(-pi/2))
    V, _ = snap.meshes[4]
    assert V.min(axis=0) == pytest.approx([3 * L1 - 0.05, -0.15, -0.1], abs=1e-6)
    assert V.max(axis=0) == pytest.approx([3 * L1 + 0.05, 0.15, 0.1], abs=1e-6)


def test_frame_samples_follow_fps_speed_and_the_frame_limit():
    t = np.round(np.arange(0, 10001) * 1e-3, 9)          # 10 s at 1 ms
    idx, fps = frame_samples(t, fps=20, speed=1, max_frames=1000)
    assert (len(idx), fps) == (201, 20) and t[idx] == pytest.approx(np.arange(201) * 0.05)
    idx, fps = frame_samples(t, fps=20, speed=2, max_frames=1000)    # twice as fast: 5 s, 101 frames
    assert (len(idx), fps) == (101, 20) and t[idx] == pytest.approx(np.arange(101) * 0.1)
    idx, fps = frame_samples(t, fps=20, speed=1, max_frames=51)      # capped: same 10 s at 5 fps
    assert (len(idx), fps) == (51, pytest.approx(5.0)) and t[idx][-1] == pytest.approx(10.0)


def test_thrust_arrows_scale_with_the_commanded_thrust(paper):
    """The synthetic run's surge_port command ramps -10 -> 20 N, the largest of the run: its arrow is half the
    full length, reversed, at the start, and full length forward at the end (the vehicle yawed 90 degrees:
    forward is then east)."""
    from uvms.thrusters.layouts import layout

    rp = replay(synthetic_result(paper), paper, fps=10, speed=1, max_frames=100, thrusters=layout("paper-sway"))
    assert rp.peak_thrust == pytest.approx(20.0)
    first, last = rp.snaps[0], rp.snaps[-1]
    full = rp.scene.arrow_length
    assert first.thruster_tip[0] - first.thruster_base[0] == pytest.approx([-0.5 * full, 0, 0], abs=1e-12)
    assert last.thruster_tip[0] - last.thruster_base[0] == pytest.approx([0, full, 0], abs=1e-9)
    assert last.thruster_tip[2] - last.thruster_base[2] == pytest.approx([0, 0, 0.25 * full], abs=1e-9)  # heave 5 N
    assert rp.vehicle_path[-1] == pytest.approx([0.4, 0.0, 0.0])


def test_plotly_view_has_z_down_and_is_not_mirrored(paper):
    """y and z reversed: a rotation by 180 degrees about x (z grows downwards on the screen, no mirror image);
    z alone reversed would mirror the world."""
    fig = show(paper)
    scene = fig.layout.scene
    reversed_axes = [a for a in "xyz" if scene[f"{a}axis"].range[0] > scene[f"{a}axis"].range[1]]
    assert reversed_axes == ["y", "z"]
    assert scene.aspectmode == "cube"
    labels = [scene[f"{a}axis"].title.text for a in "xyz"]
    assert labels == ["x north [m]", "y east [m]", "z down [m]"]


def _screen_jacobian(ax):
    from mpl_toolkits.mplot3d import proj3d

    ax.figure.canvas.draw()
    M = ax.get_proj()
    origin = np.array(proj3d.proj_transform(0.0, 0.0, 0.0, M))
    cols = [np.array(proj3d.proj_transform(*(0.1 * np.eye(3)[k]), M)) - origin for k in range(3)]
    return np.column_stack(cols), origin


def test_matplotlib_picture_has_z_down_and_is_not_mirrored(paper):
    """Down (+z) is lower on the page, and world-to-screen keeps the handedness of an untouched right-handed
    3-D axes (a mirror image would flip the sign of the Jacobian's determinant)."""
    from matplotlib.figure import Figure

    fig = picture(paper)
    J, _ = _screen_jacobian(fig.axes[0])
    assert J[1, 2] < 0                     # +z (down) moves a point down the screen
    plain = Figure().add_subplot(projection="3d")
    J_ref, _ = _screen_jacobian(plain)
    assert np.sign(np.linalg.det(J)) == np.sign(np.linalg.det(J_ref)) != 0


def test_models_without_arm_or_thrusters_are_drawn(paper):
    """The vehicle alone (no joints) and a random 5-link chain without thrusters (tests/conftest.py)."""
    from ..conftest import random_model

    alone = paper.vehicle_only()
    fig = show(alone)
    assert {"vehicle", "thrusters"} <= {t.name for t in fig.data} and "links" not in {t.name for t in fig.data}
    assert picture(alone).axes
    chain = random_model(np.random.default_rng(3), 5)
    fig = show(chain, q=np.ones(5))
    assert "thrusters" not in {t.name for t in fig.data}
    joints = next(t for t in fig.data if t.name == "joint axes")
    assert np.isfinite(np.asarray(joints.x, dtype=float)).sum() == 10     # 5 segments, 2 ends each


def test_slow_motion_frames_keep_distinct_names_and_labels(paper):
    """Played at 1/100 speed, frames lie 0.5 ms apart: every frame still has its own name and slider label."""
    from uvms.view.animate import replay_figure

    rp = replay(synthetic_result(paper, K=801, duration=0.4), paper, fps=20, speed=0.01, max_frames=40)
    fig = replay_figure(rp)
    names = [f.name for f in fig.frames]
    labels = [s.label for s in fig.layout.sliders[0].steps]
    assert len(set(names)) == len(names) == 40 and len(set(labels)) == 40


def test_animation_frames_move_the_same_points_as_the_drawn_traces(paper):
    """A frame carries only points (:func:`moving_points`); they must be those of the styled traces, in order."""
    from uvms.view.plotly_html import moving_points, moving_traces

    rp = replay(synthetic_result(paper), paper, fps=2, speed=1, max_frames=10)
    for snap in rp.snaps:
        traces, points = moving_traces(rp.scene, snap), moving_points(rp.scene, snap)
        assert len(traces) == len(points)
        for trace, p in zip(traces, points):
            drawn = np.column_stack([np.asarray(trace[a], dtype=float) for a in "xyz"])
            assert drawn == pytest.approx(p, abs=1e-6, nan_ok=True), trace.name


def test_hydrodynamic_shapes_are_drawn_where_the_model_puts_them(tmp_path):
    """A vehicle sphere and a link cylinder along the link's y axis (shapes of the model file) become
    primitives of their bodies at their poses; the cylinder primitive's axis (its local z) lies along y."""
    import copy
    from importlib.resources import files

    import yaml

    import uvms
    from uvms.view.scene import scene_from_model

    data = copy.deepcopy(yaml.safe_load((files("uvms.model") / "models" / "paper.yaml").read_text()))
    data["vehicle"]["shapes"] = [{"type": "sphere", "radius": 0.1, "drag_coefficient": 0.5,
                                  "position": [0.2, 0.0, 0.1]}]
    data["arm"]["links"][1]["shapes"] = [{"type": "cylinder", "radius": 0.03, "length": 0.2,
                                          "drag_coefficient": 1.0, "position": [0.1, 0.05, 0.0],
                                          "rotation_rpy": [0.0, 0.0, np.pi / 2]}]
    path = tmp_path / "shapes.yaml"
    path.write_text(yaml.safe_dump(data))
    scene = scene_from_model(uvms.load_model(path))
    spheres = [p for p in scene.primitives if p.kind == "sphere"]
    cylinders = [p for p in scene.primitives if p.kind == "cylinder" and p.body == 2 and p.size == (0.03, 0.2)]
    assert len(spheres) == 1 and spheres[0].body == 0 and spheres[0].size == (0.1,)
    np.testing.assert_allclose(spheres[0].position, [0.2, 0.0, 0.1])
    assert len(cylinders) == 1
    np.testing.assert_allclose(cylinders[0].position, [0.1, 0.05, 0.0])
    np.testing.assert_allclose(np.abs(np.asarray(cylinders[0].rotation) @ [0.0, 0.0, 1.0]), [0.0, 1.0, 0.0],
                               atol=1e-12)
