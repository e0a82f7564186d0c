"""Hostile Gazebo files (issue 26): an SDF or a URDF with UUV Simulator's tags is data. Entity expansion
("billion laughs"), external entities and a xacro evaluating ``__import__`` inside a plugin block are refused
by the CLI in well under a second, one line, exit 2, and nothing runs (the payloads would create a file)."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from uvms.cli import main

SRC = Path(__file__).resolve().parents[2] / "src"
LAUGHS = ('<?xml version="1.0"?><!DOCTYPE lolz [<!ENTITY lol "lol">'
          + "".join(f'<!ENTITY lol{k} "{("&lol" + (str(k - 1) if k > 1 else "") + ";") * 10}">' for k in range(1, 10))
          + ']>')
EXTERNAL = '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY secret SYSTEM "file:///etc/passwd">]>'
PLUGIN = ('<gazebo><plugin name="uuv_plugin" filename="libuuv_underwater_object_ros_plugin.so">'
          '<fluid_density>{rho}</fluid_density><link name="base"><volume>0.1</volume></link></plugin></gazebo>')
BASE = ('<link name="base"><inertial><mass value="10"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" '
        'izz="1"/></inertial></link>')

FILES = {
    "laughs.sdf": LAUGHS + '<sdf version="1.9"><model name="m"><link name="a"><pose>&lol9; 0 0 0 0 0</pose>'
                           '</link></model></sdf>',
    "external.sdf": EXTERNAL + '<sdf version="1.9"><model name="&secret;"><link name="a"/></model></sdf>',
    "laughs.urdf": LAUGHS + f'<robot name="r">{BASE}{PLUGIN.format(rho="&lol9;")}</robot>',
    "external.urdf": EXTERNAL + f'<robot name="r">{BASE}{PLUGIN.format(rho="&secret;")}</robot>',
    "import.urdf.xacro": ('<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">' + BASE
                          + PLUGIN.format(rho="${__import__('os').system('touch PWNED')}") + "</robot>"),
}


@pytest.fixture(scope="module", autouse=True)
def _commands_imported(tmp_path_factory):
    """The command's modules imported once (the first command of a session pays for the imports, not the
    refusal)."""
    folder = tmp_path_factory.mktemp("warm")
    (folder / "ok.sdf").write_text('<sdf version="1.9"><model name="m"></model></sdf>')
    main(["validate", str(folder / "ok.sdf")])


@pytest.mark.parametrize("name", sorted(FILES))
def test_hostile_gazebo_file_refused_at_once_exit_2(tmp_path, capsys, name, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / name).write_text(FILES[name])
    start = time.perf_counter()
    code = main(["validate", str(tmp_path / name)])
    elapsed = time.perf_counter() - start
    err = capsys.readouterr().err.strip()
    assert code == 2 and elapsed < 1.0
    assert len(err.splitlines()) == 1 and name in err and "Traceback" not in err
    assert not (tmp_path / "PWNED").exists()


def test_hostile_sdf_through_a_fresh_process(tmp_path):
    """The installed command, not only the function: exit 2, one line on stderr."""
    (tmp_path / "laughs.sdf").write_text(FILES["laughs.sdf"])
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    run = subprocess.run([sys.executable, "-m", "uvms", "validate", "laughs.sdf"], cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and len(run.stderr.strip().splitlines()) == 1 and "DTD or entity" in run.stderr


@pytest.mark.parametrize("name", sorted(FILES))
def test_hostile_file_refused_before_the_kernels_are_imported(tmp_path, name):
    """A fresh ``uvms validate`` refuses a hostile file before it imports numba (the compiled kernels' import
    costs most of a fresh process's second): the refusal's time is the loader's imports and the parse alone."""
    (tmp_path / name).write_text(FILES[name])
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    script = ("import sys; from uvms.cli import main; code = main(['validate', sys.argv[1]]); "
              "print(code, 'numba' in sys.modules)")
    run = subprocess.run([sys.executable, "-c", script, name], cwd=tmp_path, env=env, capture_output=True,
                         text=True, timeout=120)
    assert run.stdout.split() == ["2", "False"], run.stdout + run.stderr
    assert not (tmp_path / "PWNED").exists()
