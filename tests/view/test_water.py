"""The drawn water (``uvms.view.water``): the surface is the wave elevation written out (a cos(k x - w t) for a
regular wave, flipped into a z-down world), the arrows are the given current at its knots or nodes plus the
uniform current at the frame's time, and ``uvms show --scenario`` and the replay figure carry them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uvms.hydro.currents import current_field, current_profile
from uvms.hydro.waves import regular_waves
from uvms.view.water import water_drawing

from .conftest import run_cli, synthetic_result


def parts(waves=None, profile=None, field=None, surface=0.0, times=(0.0,), velocity=((0.0, 0.0, 0.0),)):
    v = np.array(velocity, dtype=float)
    return dict(times=np.array(times, dtype=float), velocity=v, acceleration=np.zeros_like(v), profile=profile,
                field=field, waves=waves, surface=surface)


@pytest.mark.parametrize("convention, sign", [("ned", -1.0), ("enu", 1.0)])
def test_surface_is_the_regular_wave_elevation_in_either_world(convention, sign):
    wave = regular_waves(0.6, 5.0, water_depth=30.0)
    k, w = wave.wavenumber[0], wave.omega[0]
    water = water_drawing(parts(waves=wave, surface=1.0), convention, [0.0, 1.3], [[0, 0, 3.0], [1, 2, 3.0]])
    X = water.x[None, :] * np.ones((water.y.size, 1))
    for frame, t in enumerate((0.0, 1.3)):
        assert np.allclose(water.heights[frame], 1.0 + sign * 0.3 * np.cos(k * X - w * t), atol=1e-12)
    assert water.x[0] <= 0.0 and water.x[-1] >= 1.0 and water.x[-1] - water.x[0] >= 4.0 - 1e-12
    assert water.starts.shape == (0, 3)


def test_profile_arrows_at_its_knots_plus_the_uniform_current():
    profile = current_profile([0.0, 2.0, 4.0, 50.0], [[0.3, 0, 0], [0.2, 0, 0], [0.1, 0.1, 0], [0, 0, 0]])
    flow = parts(profile=profile, surface=-1.0, times=(0.0, 10.0), velocity=((0.0, 0.0, 0.0), (0.0, 1.0, 0.0)))
    water = water_drawing(flow, "ned", [0.0, 5.0], [[0.0, 0.0, 2.0]])      # 3 m below a surface at z = -1
    assert np.allclose(water.starts[:, 2], -1.0 + np.array([0.0, 2.0, 4.0]))   # knots down to 3 m + 1 m
    assert np.allclose(water.velocities[0], profile.velocity[:3])
    assert np.allclose(water.velocities[1], profile.velocity[:3] + [0.0, 0.5, 0.0])   # uniform at t = 5: 0.5
    assert np.all(water.heights == -1.0)                                   # no waves: the flat mean surface
    fastest = np.linalg.norm(water.velocities, axis=-1).max()
    assert water.scale * fastest == pytest.approx(0.4 * 0.5 * (water.x[-1] - water.x[0]))


def test_field_arrows_at_its_nodes_at_the_nearest_time():
    x, y, z, t = np.array([0.0, 1.0]), np.array([0.0]), np.array([1.0, 2.0]), np.array([0.0, 10.0])
    velocity = np.zeros((2, 2, 1, 2, 3))
    velocity[1, ..., 0] = 1.0                                              # +x at t = 10 only
    field = current_field(x, y, z, t, velocity, "hold")
    water = water_drawing(parts(field=field), "enu", [2.0, 8.0], [[0.0, 0.0, -1.0]])
    assert water.starts.shape == (4, 3)
    assert {tuple(p) for p in water.starts} == {(a, 0.0, c) for a in x for c in z}
    assert np.all(water.velocities[0] == 0.0) and np.all(water.velocities[1] == [1.0, 0.0, 0.0])


def test_show_with_a_wave_scenario_draws_the_surface(tmp_path):
    out = tmp_path / "w.html"
    code, _, err = run_cli(["show", "bluerov2_heavy_alpha5", "--position", 0, 0, 3, "--scenario",
                            "bluerov2_heavy_alpha5_waves", "-o", out])
    assert code == 0, err
    text = out.read_text()
    assert '"type":"surface"' in text and "free surface" in text and "current" in text
    code, _, err = run_cli(["show", "bluerov2_heavy_alpha5", "--position", 0, 0, 3, "--scenario",
                            "bluerov2_heavy_alpha5_waves", "-o", tmp_path / "w.png"])
    assert code == 0, err
    assert (tmp_path / "w.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_replay_figure_animates_the_surface(paper):
    from uvms.view.animate import replay, replay_figure

    result = synthetic_result(paper)
    wave = regular_waves(0.4, 2.0)
    rp = replay(result, paper, max_frames=10, flow=parts(waves=wave, profile=current_profile([0.0], [[0.2, 0, 0]])))
    fig = replay_figure(rp)
    surfaces = [k for k, trace in enumerate(fig.data) if trace.type == "surface"]
    assert len(surfaces) == 1 and len(fig.frames) == len(rp.times)
    k, w = wave.wavenumber[0], wave.omega[0]
    X = rp.water.x[None, :] * np.ones((rp.water.y.size, 1))
    for n, frame in enumerate(fig.frames):
        drawn = [d for d in frame.data if d.type == "surface"]
        assert len(drawn) == 1 and surfaces[0] in frame.traces
        assert np.allclose(np.array(drawn[0].z), -0.2 * np.cos(k * X - w * rp.times[n]), atol=1e-12)   # ned
    assert not math.isclose(rp.times[0], rp.times[-1])


def test_animate_reads_a_runs_field_file_where_the_scenario_was(tmp_path, monkeypatch):
    """A run's ``scenario.yaml`` copy names its field file relative to the scenario's folder, not to the run
    folder: ``uvms animate`` (run from elsewhere) finds it there and draws its arrows."""
    import yaml

    from importlib.resources import files

    data = yaml.safe_load((files("uvms") / "scenarios" / "paper_case2_released.yaml").read_text())
    data.update(name="field", duration=0.3, environment={"current": {"field": {"file": "flow.csv", "outside": "hold"}}})
    folder = tmp_path / "case"
    folder.mkdir()
    rows = ["x,y,z,t,u,v,w"] + [f"{x},{y},{z},0.0,{0.1 * z},0.0,0.0" for z in (0.0, 5.0) for y in (-3.0, 3.0)
                                for x in (-3.0, 3.0)]
    (folder / "flow.csv").write_text("\n".join(rows) + "\n")
    (folder / "case.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    code, _, err = run_cli(["run", folder / "case.yaml", "-o", tmp_path / "run"])
    assert code == 0, err
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    code, out, err = run_cli(["animate", tmp_path / "run", "-o", tmp_path / "a.html", "--max-frames", "5"])
    assert code == 0, err
    assert "current" in (tmp_path / "a.html").read_text()


def test_a_gif_of_a_wave_run_draws_the_surface_of_each_frame(paper, tmp_path, monkeypatch):
    """The .gif/.mp4 writer draws frame k's water (surface and arrows at frame k's time) on frame k, and its
    axes hold the drawn surface."""
    from uvms.view import png
    from uvms.view.animate import replay, write_video

    rp = replay(synthetic_result(paper), paper, max_frames=4, flow=parts(waves=regular_waves(0.4, 2.0)))
    drawn, draw = [], png.draw_water
    monkeypatch.setattr(png, "draw_water", lambda ax, water, k=0: (drawn.append((water, k)), draw(ax, water, k)))
    path = write_video(rp, tmp_path / "w.gif")
    assert path.read_bytes()[:6] in (b"GIF87a", b"GIF89a")
    assert [k for _, k in drawn] == list(range(len(rp.snaps))) and all(w is rp.water for w, _ in drawn)
    lo, hi = rp.ranges()[:, 0], rp.ranges()[:, 1]
    corners = rp.water.points()
    assert np.all(corners >= lo - 1e-9) and np.all(corners <= hi + 1e-9)
