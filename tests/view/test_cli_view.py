"""``uvms show`` and ``uvms animate`` from the command line: the files they write (checked for size and
content), and one-line errors naming the option for bad input."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from uvms.output import MARKER

from .conftest import run_cli

VEHICLE_RGB = np.array([0xF2, 0xB7, 0x05]) / 255


def _non_background(image: np.ndarray) -> float:
    """Fraction of pixels that differ from the corner (background) colour."""
    rgb = image[..., :3].astype(float)
    rgb = rgb / 255 if rgb.max() > 1 else rgb
    return float(np.mean(np.abs(rgb - rgb[0, 0]).sum(axis=-1) > 0.05))


def _yellowish(image: np.ndarray) -> int:
    """Pixels in the vehicle's yellow (red and green well above blue): the translucent box was drawn."""
    rgb = image[..., :3].astype(float)
    rgb = rgb / 255 if rgb.max() > 1 else rgb
    return int(np.sum((rgb[..., 0] > 0.6) & (rgb[..., 1] > 0.45) & (rgb[..., 2] < rgb[..., 0] - 0.25)))


def test_show_png_is_a_drawn_picture(tmp_path):
    from matplotlib.image import imread

    out = tmp_path / "paper.png"
    code, stdout, err = run_cli(["show", "paper", "-o", out])
    assert code == 0, err
    assert "paper drawn to" in stdout
    image = imread(out)
    assert image.shape[0] > 600 and image.shape[1] > 600
    assert _non_background(image) > 0.1 and _yellowish(image) > 5000
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]    # no temporary file left behind


def test_show_html_is_self_contained(tmp_path):
    out = tmp_path / "paper.html"
    code, _, err = run_cli(["show", "paper", "--q", "0", "-1.5708", "0", "-o", out])
    assert code == 0, err
    text = out.read_text()
    assert "<script src=\"http" not in text and "cdn.plot.ly" not in text.split("/*")[0]
    assert len(text) > 3_000_000           # plotly.js is inside the page
    assert "Plotly.newPlot" in text


def test_default_show_output_is_named_after_the_model(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = run_cli(["show", "paper"])
    assert code == 0, err
    assert (tmp_path / "paper.html").is_file()


@pytest.mark.parametrize("argv, message", [
    (["show", "nosuchmodel", "-o", "x.html"], "nosuchmodel"),
    (["show", "paper", "--q", "0.1", "-o", "x.html"], "--q: expected 3 joint values (joints: joint1, joint2, joint3), found 1"),
    (["show", "paper", "-o", "x.txt"], "x.txt: --output: expected a .html, .png, .pdf, .svg or .jpg file name"),
    (["show", "paper", "--q", "nan", "0", "0", "-o", "x.html"], "--q: expected finite joint values"),
    (["show", "paper", "-o", ""], "--output: expected a file name"),
    (["show", "paper", "--position", "0", "inf", "0", "-o", "x.png"], "--position: expected finite numbers"),
])
def test_show_bad_input_is_one_line(tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    code, _, err = run_cli(argv)
    assert code == 2
    assert err.count("\n") == 1 and message in err and "Traceback" not in err
    assert not list(tmp_path.iterdir())    # nothing written


def test_show_refuses_a_folder_as_output(tmp_path):
    code, _, err = run_cli(["show", "paper", "-o", tmp_path])
    assert code == 2 and "--output" in err


def test_animate_html_default_goes_into_the_run_folder(synthetic_run, tmp_path):
    folder = tmp_path / "run"
    shutil.copytree(synthetic_run[0], folder)
    (folder / MARKER).write_text('{"written_by": "uvms", "kind": "run", "files": ["result.csv", "result.json", '
                                 '"scenario.yaml"]}')
    code, stdout, err = run_cli(["animate", folder, "--fps", "10"])
    assert code == 0, err
    assert "21 frames at 10 fps" in stdout
    assert (folder / "animation.html").stat().st_size > 3_000_000
    assert "animation.html" in (folder / MARKER).read_text()     # the run folder may still be replaced


def test_animate_gif(synthetic_run, tmp_path):
    from PIL import Image

    out = tmp_path / "run.gif"
    code, _, err = run_cli(["animate", synthetic_run[0], "-o", out, "--fps", "3"])
    assert code == 0, err
    with Image.open(out) as gif:
        assert gif.n_frames == 7           # 2 s at 3 frames per second: t = 0, 1/3, ..., 2
        assert gif.size[0] >= 600
        gif.seek(0)
        first = np.asarray(gif.convert("RGB"))
        gif.seek(6)
        last = np.asarray(gif.convert("RGB"))
    assert _non_background(first) > 0.1 and _yellowish(first) > 3000
    assert np.mean(np.abs(first.astype(int) - last.astype(int)).sum(axis=-1) > 30) > 0.005   # the robot moved


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg is not installed (CI installs it)")
def test_animate_mp4(short_run, tmp_path):
    import json
    import subprocess

    out = tmp_path / "run.mp4"
    code, _, err = run_cli(["animate", short_run, "-o", out, "--fps", "8"])
    assert code == 0, err
    assert out.stat().st_size > 10_000
    if shutil.which("ffprobe"):
        probe = json.loads(subprocess.run(
            ["ffprobe", "-v", "error", "-count_frames", "-show_entries", "stream=codec_name,nb_read_frames,width",
             "-of", "json", str(out)], capture_output=True, text=True, check=True).stdout)["streams"][0]
        assert probe["codec_name"] == "h264" and int(probe["nb_read_frames"]) == 9 and probe["width"] >= 600


def test_mp4_without_ffmpeg_is_one_line(synthetic_run, tmp_path, monkeypatch):
    import uvms.view.animate as anim

    monkeypatch.setattr(anim, "ffmpeg_available", lambda: False)
    code, _, err = run_cli(["animate", synthetic_run[0], "-o", tmp_path / "x.mp4"])
    assert code == 2 and err.count("\n") == 1
    assert "x.mp4: --output: writing .mp4 needs the ffmpeg program" in err
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("case, message", [
    ("no_scenario", "no scenario.yaml here, so the model of the run is unknown"),
    ("bad_extension", "--output: expected a .html, .mp4 or .gif file name"),
    ("no_folder", "no such run directory"),
    ("bad_fps", "--fps: expected a positive frame rate, found 0.0"),
    ("bad_speed", "--speed: expected a positive playback speed, found -1.0"),
    ("wrong_model", "the run has 3 joints, its model"),
])
def test_animate_bad_input_is_one_line(synthetic_run, tmp_path, case, message):
    folder = tmp_path / "run"
    shutil.copytree(synthetic_run[0], folder)
    argv = ["animate", folder, "-o", tmp_path / "out.html"]
    if case == "no_scenario":
        (folder / "scenario.yaml").unlink()
    elif case == "bad_extension":
        argv[-1] = tmp_path / "out.avi"
    elif case == "no_folder":
        argv[1] = tmp_path / "missing"
    elif case == "bad_fps":
        argv += ["--fps", "0"]
    elif case == "bad_speed":
        argv += ["--speed", "-1"]
    elif case == "wrong_model":
        model = tmp_path / "two.yaml"
        import yaml
        from importlib.resources import files

        data = yaml.safe_load((files("uvms") / "model" / "models" / "paper.yaml").read_text())
        data["arm"]["links"] = data["arm"]["links"][:2]
        model.write_text(yaml.safe_dump(data))
        (folder / "scenario.yaml").write_text(f"name: x\nmodel: {model}\nduration: 2.0\n")
    code, _, err = run_cli(argv)
    assert code == 2, err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err
    assert not (tmp_path / "out.html").exists()


def test_video_title_fits_the_frame(synthetic_run, tmp_path, monkeypatch):
    """A long title (run name, model, thrust note) is broken into lines that fit the frame's width, not cut."""
    import matplotlib

    matplotlib.use("Agg")
    import uvms.view.animate as animate
    from uvms.view import png

    fig, _ = png.new_figure(size=(7.2, 6.4))
    text = "a_rather_long_run_name_of_a_sweep (model bluerov2_heavy_alpha5), played at 2x; arrows: commanded " \
           "thrust, longest 51.8 N"
    title = animate.fitted_title(fig, text)
    assert title.replace("\n", " ") == text and title.count("\n") >= 1
    renderer = fig.canvas.get_renderer()
    shown = fig.text(0, 0, title, fontsize="medium")
    assert shown.get_window_extent(renderer).width <= fig.get_figwidth() * fig.dpi
    titles = []
    real = png.style_axes
    monkeypatch.setattr(png, "style_axes", lambda ax, ranges, t, *scene: (titles.append(t), real(ax, ranges, t, *scene))[1])
    code, _, err = run_cli(["animate", synthetic_run[0], "-o", tmp_path / "run.gif", "--fps", "1"])
    assert code == 0, err
    assert titles and all(len(t.splitlines()) >= 2 for t in titles)
    head = titles[0].rsplit("\n", 1)[0]
    assert animate.fitted_title(fig, head.replace("\n", " ")) == head     # what was drawn is the fitted title
