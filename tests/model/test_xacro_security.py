"""A xacro file is data, not a program (docs/models.md, "What a xacro may do").

Every way a xacro could run code, read a file outside its folder or read the environment is refused with one
line naming the file, exit code 2 from the CLI, and nothing runs (the payloads would create a marker file);
ordinary xacro (properties, math, conditionals, macros with blocks, arguments, includes and YAML inside the
model's folder, ``$(find pkg)`` of a package the user names) still expands.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.model.xacro import XacroOptions, evaluate, expand

SRC = Path(__file__).resolve().parents[2] / "src"
HEAD = '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
BODY = ('<link name="base"><inertial><mass value="{mass}"/>'
        '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>')


def _robot(folder: Path, middle: str, mass: str = "2.0", name: str = "robot.urdf.xacro") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    path.write_text(HEAD + middle + BODY.format(mass=mass) + "</robot>")
    return path


def _uvms(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    return subprocess.run([sys.executable, "-m", "uvms", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=120)


MARKER = "PWNED"
ATTACKS = {
    "python_vars_chain": "${python.vars(int.mro()[1])['__getattribute__'](xacro.load_yaml, '__globals__')"
                         "['os'].system('touch PWNED')}",
    "dunder_import": "${__import__('os').system('touch PWNED')}",
    "getattr_string": "${python.getattr(xacro.load_yaml, '__glo' + 'bals__')['os'].system('touch PWNED')}",
    "dunder_attribute": "${''.__class__.__mro__[1].__subclasses__()}",
    "attribute_of_builtin": "${int.mro()}",
    "string_method": "${'touch PWNED'.split()}",
    "open_file": "${open('/etc/passwd').read()}",
    "lambda": "${(lambda: 1)()}",
    "comprehension": "${[c for c in 'ab']}",
    "generator": "${sum(x for x in [1, 2])}",
    "walrus": "${(x := 2)}",
    "fstring": "${f'x'}",
    "keyword_call": "${round(number=1.5)}",
    "eval_substitution": "$(eval __import__)",
    "eval_substitution_comprehension": "$(eval [c for c in 'ab'])",
    "eval_substitution_lambda": "$(eval lambda: 1)",
    "load_yaml_absolute": "${xacro.load_yaml('/etc/passwd')}",
    "env": "$(env HOME)",
    "optenv": "$(optenv HOME nothing)",
    "cwd": "$(cwd)",
    "find_unnamed_package": "$(find some_package)",
    "unknown_substitution": "$(anon x)",
}


@pytest.mark.parametrize("name", sorted(ATTACKS))
def test_a_xacro_expression_that_reaches_outside_is_refused_and_runs_nothing(tmp_path, monkeypatch, name):
    monkeypatch.chdir(tmp_path)
    path = _robot(tmp_path / "model", f'<xacro:property name="p" value="{ATTACKS[name]}"/>',
                  mass="${p}" if "$(" not in ATTACKS[name] else ATTACKS[name])
    start = time.perf_counter()
    with pytest.raises(UvmsInputError) as info:
        uvms.load_model(path)
    assert time.perf_counter() - start < 1.0
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path))
    assert not (tmp_path / MARKER).exists() and not (tmp_path / "model" / MARKER).exists()
    assert "root:" not in message               # no line of /etc/passwd in the message


def test_the_issue_payload_is_refused_by_the_cli_with_exit_2_and_nothing_runs(tmp_path):
    path = _robot(tmp_path, f'<xacro:property name="p" value="{ATTACKS["python_vars_chain"]}"/>', mass="${p}",
                  name="x.xacro")
    (tmp_path / "model.yaml").write_text("urdf: x.xacro\n")
    for target in ("x.xacro", "model.yaml"):
        done = _uvms("validate", target, cwd=tmp_path)
        assert done.returncode == 2, done.stderr
        lines = done.stderr.strip().splitlines()
        assert len(lines) == 1 and str(path.name) in lines[0] and "Traceback" not in done.stderr
        assert not (tmp_path / MARKER).exists()


def test_includes_and_yaml_outside_the_model_folder_are_refused(tmp_path):
    secret = tmp_path / "secret.xacro"
    secret.write_text(HEAD + '<link name="TOKEN_abc123"/></robot>')
    (tmp_path / "secret.yaml").write_text("token: TOKEN_abc123\n")
    model = tmp_path / "model"
    cases = {
        "absolute include": f'<xacro:include filename="{secret}"/>',
        "parent include": '<xacro:include filename="../secret.xacro"/>',
        "parent yaml": '<xacro:property name="s" value="${xacro.load_yaml(\'../secret.yaml\')}"/>',
        "wildcard include": '<xacro:include filename="../*.xacro"/>',
    }
    for what, middle in cases.items():
        path = _robot(model, middle, mass="${s.token}" if "yaml" in what else "2.0")
        with pytest.raises(UvmsInputError, match="outside the model's folder|wildcard") as info:
            uvms.load_model(path)
        assert "TOKEN_abc123" not in str(info.value), what
    link = model / "inside.xacro"
    link.symlink_to(secret)                     # a symbolic link inside the folder that points outside
    path = _robot(model, '<xacro:include filename="inside.xacro"/>')
    with pytest.raises(UvmsInputError, match="outside the model's folder"):
        uvms.load_model(path)


def test_environment_is_read_only_when_allowed(tmp_path, monkeypatch):
    monkeypatch.setenv("UVMS_TEST_MASS", "3.5")
    path = _robot(tmp_path, "", mass="$(env UVMS_TEST_MASS)")
    with pytest.raises(UvmsInputError, match="allow_environment"):
        uvms.load_model(path)
    assert uvms.load_model(path, allow_environment=True).mass[0] == 3.5
    (tmp_path / "m.yaml").write_text(f"urdf: {path.name}\nallow_environment: true\n")
    with pytest.raises(UvmsInputError, match="a model file cannot allow") as info:   # a file cannot grant itself
        uvms.load_model(tmp_path / "m.yaml")
    assert info.value.path == "allow_environment"
    assert uvms.load_model(tmp_path / "m.yaml", allow_environment=True).mass[0] == 3.5    # the caller can


def test_a_model_file_cannot_name_package_folders_outside_its_own(tmp_path):
    path = _ordinary(tmp_path / "model")
    outside = tmp_path / "model" / "m.yaml"
    outside.write_text("urdf: robot.urdf.xacro\npackage_paths: {tool_pkg: ../pkg}\n")
    with pytest.raises(UvmsInputError, match="outside this file's folder") as info:
        uvms.load_model(outside)
    assert info.value.path == "package_paths.tool_pkg"
    result = _uvms("validate", str(outside), cwd=tmp_path)
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    # the caller may name it, from Python or through ROS_PACKAGE_PATH
    assert uvms.load_model(outside, package_paths={"tool_pkg": tmp_path / "pkg"}).joint_names == ("j1",)
    assert uvms.load_model(path, package_paths={"tool_pkg": tmp_path / "pkg"}).joint_names == ("j1",)


def test_find_uses_the_users_ros_package_path(tmp_path, monkeypatch):
    path = _ordinary(tmp_path / "model")
    workspace = tmp_path / "ws" / "src"
    (workspace / "deeper").mkdir(parents=True)
    (tmp_path / "pkg").rename(workspace / "deeper" / "tool_pkg")
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(workspace))
    with pytest.raises(UvmsInputError, match="ROS_PACKAGE_PATH"):   # a folder named so, without package.xml
        uvms.load_model(path)
    (workspace / "deeper" / "tool_pkg" / "package.xml").write_text(
        "<package format='2'><name>tool_pkg</name></package>")
    model = uvms.load_model(path)
    assert "tool" in [f.name for f in model.frames]


def test_dtd_and_entities_are_refused_in_a_xacro_and_its_includes(tmp_path):
    bomb = ('<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;">'
            '<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;"><!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;">]>')
    top = tmp_path / "bomb.xacro"
    top.write_text(bomb + HEAD + BODY.format(mass="&d;") + "</robot>")
    external = tmp_path / "ext.xacro"
    external.write_text('<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
                        + HEAD + '<link name="&x;"/>' + BODY.format(mass="1") + "</robot>")
    (tmp_path / "inc.xacro").write_text(bomb + HEAD + "</robot>")
    includer = _robot(tmp_path, '<xacro:include filename="inc.xacro"/>', name="includer.xacro")
    for path in (top, external, includer):
        start = time.perf_counter()
        with pytest.raises(UvmsInputError, match="DTD or entity") as info:
            uvms.load_model(path)
        assert time.perf_counter() - start < 1.0
        assert "root:" not in str(info.value)


def _ordinary(folder: Path) -> Path:
    """A xacro with the ordinary constructs: properties, math, conditionals, macros with parameters and
    blocks, arguments, an include and a YAML file inside its folder, $(find) of a named package."""
    (folder / "parts").mkdir(parents=True)
    (folder / "parts" / "arm.xacro").write_text(
        HEAD + '<xacro:macro name="arm" params="parent">'
        '<joint name="j1" type="revolute"><parent link="${parent}"/><child link="l1"/>'
        '<origin xyz="${L} 0 0" rpy="0 ${radians(90)} ${-pi/2}"/><axis xyz="0 0 1"/>'
        '<limit lower="${-pi/2}" upper="$(eval pi/2)" effort="${2*5}" velocity="1"/></joint>'
        '</xacro:macro></robot>')
    (folder / "config.yaml").write_text("link:\n  mass: 1.5\n  length: 0.4\n")
    package = folder.parent / "pkg"
    (package / "urdf").mkdir(parents=True)
    (package / "urdf" / "tool.xacro").write_text(
        HEAD + '<xacro:macro name="tool"><link name="tool"/><joint name="jt" type="fixed"><parent link="l1"/>'
        '<child link="tool"/></joint></xacro:macro></robot>')
    middle = (
        '<xacro:arg name="base_mass" default="20"/>'
        '<xacro:property name="cfg" value="${xacro.load_yaml(\'config.yaml\')}"/>'
        '<xacro:property name="L" value="${cfg.link.length}"/>'
        '<xacro:property name="with_tool" value="true"/>'
        '<xacro:include filename="parts/arm.xacro"/>'
        '<xacro:include filename="$(find tool_pkg)/urdf/tool.xacro"/>'
        '<xacro:macro name="cylinder_link" params="name mass *origin">'
        '<link name="${name}"><inertial><xacro:insert_block name="origin"/><mass value="${mass}"/>'
        '<inertia ixx="${mass*L*L/12}" iyy="${mass*L*L/12}" izz="${mass*0.001}" ixy="0" ixz="0" iyz="0"/>'
        '</inertial></link></xacro:macro>'
        '<xacro:cylinder_link name="l1" mass="${cfg[\'link\'][\'mass\']}"><origin xyz="${L/2} 0 0"/>'
        '</xacro:cylinder_link>'
        '<xacro:arm parent="base"/>'
        '<xacro:if value="${with_tool}"><xacro:tool/></xacro:if>'
        '<xacro:unless value="${with_tool}"><link name="no_tool"/></xacro:unless>'
    )
    return _robot(folder, middle, mass="$(arg base_mass)")


def test_ordinary_xacro_still_expands(tmp_path, capfd):
    path = _ordinary(tmp_path / "model")
    package = {"tool_pkg": tmp_path / "pkg"}
    with pytest.raises(UvmsInputError, match="package 'tool_pkg' is not named"):
        uvms.load_model(path)
    model = uvms.load_model(path, package_paths=package)
    assert model.body_names == ("base", "l1") and model.joint_names == ("j1",)
    assert model.mass.tolist() == [20.0, 1.5]
    np.testing.assert_allclose(model.joint_limits[0], [-np.pi / 2, np.pi / 2, 10.0, 1.0])
    assert "tool" in [f.name for f in model.frames]
    assert uvms.load_model(path, package_paths=package, xacro_args={"base_mass": "30"}).mass[0] == 30.0
    import shutil

    shutil.copytree(tmp_path / "pkg", tmp_path / "model" / "pkg")    # a package inside the model file's folder
    (tmp_path / "model" / "m.yaml").write_text("urdf: robot.urdf.xacro\npackage_paths: {tool_pkg: pkg}\n"
                                               "xacro_args: {base_mass: '25'}\n")
    assert uvms.load_model(tmp_path / "model" / "m.yaml").mass[0] == 25.0
    out, err = capfd.readouterr()
    assert out == "" and err == ""              # xacro's own warnings and notes stay off the terminal


def _example_robot_data() -> Path:
    """The ``robots`` folder of example-robot-data (installed by cmeel next to pinocchio), or skip."""
    import site

    for base in map(Path, site.getsitepackages()):
        candidate = base / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if candidate.is_dir():
            return candidate
    pytest.skip("example-robot-data is not installed")


def test_a_published_xacro_expands_quietly(capfd):
    path = _example_robot_data() / "hector_description" / "robots" / "quadrotor_base.urdf.xacro"
    text = expand(path)
    assert "quadrotor_base_macro" not in text and "<robot" in text
    out, err = capfd.readouterr()
    assert out == "" and err == ""


@pytest.mark.parametrize("expression, message", [
    ("2**2**40", "bits"),
    ("'x'*3000000000", "longer than"),
    ("3000000000*'x'", "longer than"),
    ("[0]*10**9", "longer than"),
    ("10**100000", "bits"),
    ("round(1, -10**9)", "ndigits"),
    ("'%0999999999d' % 1", "string"),
    ("1 << 100000", "not allowed"),
    ("(" * 1000 + "1" + ")" * 1000, "nested|invalid"),
    ("1 +" * 5000 + "1", "nested|invalid|longer"),
])
def test_runaway_expressions_are_refused_at_once(expression, message):
    from uvms.model import xacro as module

    start = time.perf_counter()
    with pytest.raises(UvmsInputError, match=message):
        evaluate(expression, module._ROOT)
    assert time.perf_counter() - start < 1.0


def test_the_evaluator_keeps_ordinary_arithmetic():
    symbols = {"a": 2.0, "b": 3, "name": "arm", "cfg": {"m": [1, 2]}, "pi": np.pi}
    from uvms.model import xacro as module

    symbols.update(module._ROOT)
    assert evaluate("a*b + 1", symbols) == 7.0
    assert evaluate("pi/2", symbols) == np.pi / 2
    assert evaluate("math.radians(180)", symbols) == pytest.approx(np.pi)
    assert evaluate("name + '_link'", symbols) == "arm_link"
    assert evaluate("'x' if b > 2 and not a > 5 else 'y'", symbols) == "x"
    assert evaluate("cfg['m'][1] + cfg.m[0]", symbols) == 3
    assert evaluate("2**10 - -3 // 2 % 5", symbols) == 2**10 - -3 // 2 % 5
    assert evaluate("max(1, 2, 3) + abs(-1) + len('ab') + int('4') + float(1)", symbols) == 11.0
    assert evaluate("'%s' == str(1)", symbols) is False


def test_xacro_state_is_restored_after_an_expansion(tmp_path):
    import xacro

    before = (xacro.safe_eval, xacro.eval_extension, xacro.parse, xacro.eval_all, xacro._global_symbols)
    path = _robot(tmp_path, '<xacro:property name="p" value="${__import__(\'os\')}"/>', mass="${p}")
    with pytest.raises(UvmsInputError):
        expand(path)
    expand(_robot(tmp_path, "", name="ok.xacro"), XacroOptions())
    assert (xacro.safe_eval, xacro.eval_extension, xacro.parse, xacro.eval_all, xacro._global_symbols) == before


def test_a_missing_include_is_an_error_unless_optional(tmp_path):
    path = _robot(tmp_path, '<xacro:include filename="nothing.xacro"/>')
    with pytest.raises(UvmsInputError, match="no such file"):
        uvms.load_model(path)
    path = _robot(tmp_path, '<xacro:include filename="nothing.xacro" optional="true"/>', name="opt.xacro")
    assert uvms.load_model(path).body_names == ("base",)


def test_a_file_that_is_not_a_regular_file_is_not_read(tmp_path):
    os.mkfifo(tmp_path / "pipe.xacro")          # reading a FIFO would wait forever
    path = _robot(tmp_path, '<xacro:include filename="pipe.xacro"/>')
    start = time.perf_counter()
    with pytest.raises(UvmsInputError, match="not a regular file"):
        uvms.load_model(path)
    assert time.perf_counter() - start < 1.0


def test_xacro_warnings_become_at_most_one_line(tmp_path, capfd):
    path = _robot(tmp_path, '<xacro:property name="a" value="1" bogus="x"/>'
                            '<xacro:property name="b" value="2" other="y"/>')
    with pytest.warns(UserWarning) as caught:
        uvms.load_model(path)
    lines = [str(w.message) for w in caught]
    assert len(lines) == 1 and "unknown attribute" in lines[0] and "and 1 more" in lines[0]
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_expansions_in_several_threads_do_not_mix(tmp_path):
    from concurrent.futures import ThreadPoolExecutor

    good = _ordinary(tmp_path / "model")
    bad = _robot(tmp_path / "bad", '<xacro:property name="p" value="${__import__(\'os\')}"/>', mass="${p}")
    options = XacroOptions(package_paths={"tool_pkg": tmp_path / "pkg"})

    def one(k: int) -> str:
        try:
            return expand(good if k % 2 == 0 else bad, options)
        except UvmsInputError as exc:
            return str(exc)

    with ThreadPoolExecutor(4) as pool:
        results = list(pool.map(one, range(16)))
    assert all("<robot" in r for r in results[0::2])
    assert all("'__import__' is not allowed" in r for r in results[1::2])


def test_an_unnamed_package_near_the_file_is_named_in_the_refusal(tmp_path, monkeypatch):
    """Issue 26: ``$(find pkg)`` of a package lying beside the model (a checked-out workspace) is still refused,
    but the one line names the folder and the ROS_PACKAGE_PATH entry that would grant it."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    shared = tmp_path / "ws" / "uuv_simulator" / "uuv_descriptions"
    (shared / "urdf").mkdir(parents=True)
    (shared / "urdf" / "common.xacro").write_text(HEAD + "</robot>")
    path = _robot(tmp_path / "ws" / "rov" / "robots",
                  '<xacro:include filename="$(find uuv_descriptions)/urdf/common.xacro"/>')
    with pytest.raises(UvmsInputError, match=r"is not named.*ROS_PACKAGE_PATH=\S*uuv_simulator or package_paths="
                       r"\{'uuv_descriptions': '\S*uuv_descriptions'\}") as info:
        uvms.load_model(path)
    assert "\n" not in str(info.value)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "ws" / "uuv_simulator"))
    (shared / "package.xml").write_text("<package><name>uuv_descriptions</name></package>")
    assert uvms.load_model(path).mass[0] == 2.0
