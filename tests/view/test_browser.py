"""The HTML pages in a real browser (headless chromium, software WebGL, network off): the 3-D canvas is drawn,
moving the time slider moves the robot, and nothing is fetched from the internet.

Skipped only when no chromium is installed (CI installs Debian's ``chromium``, so they run there)."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from .conftest import run_cli
from .test_cli_view import _non_background, _yellowish

CHROMIUM = next((p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None)
pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed (CI installs Debian's "
                                                          "chromium); the browser tests need it")]

OFFLINE = ["--proxy-server=127.0.0.1:9", "--proxy-bypass-list=<-loopback>", "--host-resolver-rules=MAP * ~NOTFOUND"]


def screenshot(url: str, out, profile) -> np.ndarray:
    """A 1000x800 screenshot of ``url`` by headless chromium with the network disabled, after the page's
    scripts have run (virtual time)."""
    from matplotlib.image import imread

    args = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
            "--hide-scrollbars", "--no-first-run", "--disable-extensions", f"--user-data-dir={profile}",
            "--window-size=1000,800", "--virtual-time-budget=10000", f"--screenshot={out}", *OFFLINE, url]
    done = subprocess.run(args, capture_output=True, text=True, timeout=180)
    assert done.returncode == 0 and out.is_file(), done.stderr[-2000:]
    return imread(out)


@pytest.fixture(scope="module")
def pages(synthetic_run, tmp_path_factory):
    """The paper model's page and the synthetic run's replay page (plus one opening at its last frame)."""
    tmp = tmp_path_factory.mktemp("pages")
    for argv in (["show", "paper", "-o", tmp / "paper.html"],
                 ["animate", synthetic_run[0], "-o", tmp / "run.html", "--fps", "10"],
                 ["animate", synthetic_run[0], "-o", tmp / "run_end.html", "--fps", "10", "--start", "2"]):
        code, _, err = run_cli(argv)
        assert code == 0, err
    return tmp


def test_network_is_really_off_for_the_browser(tmp_path):
    """Control: an image from the internet fails to load under the same flags (the page turns red)."""
    page = tmp_path / "control.html"
    page.write_text("<html><body style='background:white'><img src='https://example.com/logo.png' "
                    "onerror=\"document.body.style.background='rgb(255,0,0)'\"></body></html>")
    image = screenshot(page.as_uri(), tmp_path / "control.png", tmp_path / "profile")
    rgb = image[400, 500, :3]
    assert rgb[0] > 0.9 and rgb[1] < 0.1 and rgb[2] < 0.1


def test_model_page_draws_the_3d_canvas_offline(pages, tmp_path):
    image = screenshot((pages / "paper.html").as_uri(), tmp_path / "paper.png", tmp_path / "profile")
    assert _non_background(image) > 0.15      # axes planes, grid, shapes
    assert _yellowish(image) > 5000           # the vehicle box (WebGL drew the meshes)


def test_time_slider_moves_the_robot(pages, tmp_path):
    """Frames 0 and 20 (t = 0 and 2 s; the vehicle moved 0.4 m and yawed 90 degrees, joint 1 turned by pi)
    differ; the same frame twice does not (so the difference is the robot, not noise). The page opened at
    ``--start 2`` shows frame 20."""
    url = (pages / "run.html").as_uri()
    a = screenshot(url + "#frame=0", tmp_path / "a.png", tmp_path / "profile")
    a2 = screenshot(url + "#frame=0", tmp_path / "a2.png", tmp_path / "profile")
    b = screenshot(url + "#frame=20", tmp_path / "b.png", tmp_path / "profile")
    end = screenshot((pages / "run_end.html").as_uri(), tmp_path / "end.png", tmp_path / "profile")

    def changed(x, y):
        return float(np.mean(np.abs(x[..., :3] - y[..., :3]).sum(axis=-1) > 0.1))

    assert _yellowish(a) > 3000 and _yellowish(b) > 3000
    assert changed(a, a2) < 0.002
    assert changed(a, b) > 0.01
    assert changed(b, end) < 0.002
