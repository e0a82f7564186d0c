"""Robot descriptions: every input has a documented limit checked before the work (docs/models.md, "Limits"),
hostile XML is refused at once, numbers that are not numbers are refused by name, and an impossible inertia
can be accepted only on request (``balance_inertia``, MuJoCo's ``balanceinertia``)."""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.model import urdf as urdf_module
from uvms.model import xacro as xacro_module

X = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
INERTIA = '<inertia ixx="{a}" iyy="{b}" izz="{c}" ixy="0" ixz="0" iyz="0"/>'


def _chain(n: int) -> str:
    parts = ['<robot name="chain">', '<link name="l0"><inertial><mass value="10"/>'
             + INERTIA.format(a=1, b=1, c=1) + '</inertial></link>']
    for i in range(1, n):
        parts.append(f'<link name="l{i}"><inertial><origin xyz="0.05 0 0"/><mass value="1"/>'
                     + INERTIA.format(a=0.01, b=0.01, c=0.01) + '</inertial></link>')
        parts.append(f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/><child link="l{i}"/>'
                     '<origin xyz="0.1 0 0"/><axis xyz="0 0 1"/>'
                     '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint>')
    return "\n".join(parts) + "</robot>"


def _refused_fast(path, match: str) -> str:
    start = time.perf_counter()
    with pytest.raises(UvmsInputError, match=match) as info:
        uvms.load_model(path)
    assert time.perf_counter() - start < 1.0, "refused, but not at once"
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path))
    return message


def test_a_urdf_of_more_links_than_the_limit_is_refused_at_once(tmp_path):
    path = tmp_path / "chain.urdf"
    path.write_text(_chain(10_000))
    _refused_fast(path, f"more than {urdf_module.MAX_LINKS:,} <link>")


def test_a_model_at_the_link_limit_loads_in_linear_time(tmp_path):
    warm = tmp_path / "warm.urdf"
    warm.write_text(_chain(3))
    uvms.load_model(warm)                       # imports done before timing
    times = {}
    for n in (250, urdf_module.MAX_LINKS):
        path = tmp_path / f"chain{n}.urdf"
        path.write_text(_chain(n))
        runs = []
        for _ in range(3):           # the fastest of three: a test running beside it (pytest-xdist) only slows one
            start = time.perf_counter()
            model = uvms.load_model(path)
            runs.append(time.perf_counter() - start)
        times[n] = min(runs)
        assert len(model.body_names) == n
    assert times[urdf_module.MAX_LINKS] < 15.0
    assert times[urdf_module.MAX_LINKS] < 4 * times[250] * 2.5     # linear (x4 links), with slack for noise


def test_a_huge_urdf_file_is_refused_before_it_is_read(tmp_path):
    path = tmp_path / "huge.urdf"
    with path.open("wb") as f:                  # 1 GiB, sparse: nothing to read unless uvms reads it
        f.truncate(1 << 30)
    _refused_fast(path, "over the limit")


def test_a_huge_xacro_file_is_refused_before_it_is_read(tmp_path):
    path = tmp_path / "huge.xacro"
    with path.open("wb") as f:
        f.truncate(xacro_module.MAX_FILE_BYTES + 1)
    _refused_fast(path, "over the limit")


def test_entity_expansion_in_a_urdf_is_refused_at_once(tmp_path):
    levels = "".join(f'<!ENTITY e{k} "{f"&e{k - 1};" * 10}">' for k in range(1, 10))
    path = tmp_path / "laughs.urdf"
    path.write_text(f'<?xml version="1.0"?><!DOCTYPE robot [<!ENTITY e0 "lol">{levels}]>'
                    '<robot name="r"><link name="&e9;"/></robot>')
    _refused_fast(path, "DTD or entity")
    external = tmp_path / "external.urdf"
    external.write_text('<?xml version="1.0"?><!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
                        '<robot name="r"><link name="&x;"/></robot>')
    assert "root:" not in _refused_fast(external, "DTD or entity")


def _xacro(tmp_path: Path, name: str, body: str) -> Path:
    path = tmp_path / name
    path.write_text(f'<robot name="r" {X}>{body}<link name="base"/></robot>')
    return path


def test_macros_that_double_are_refused_at_once(tmp_path):
    doubling = '<xacro:macro name="m0"><link name="x"/></xacro:macro>' + "".join(
        f'<xacro:macro name="m{i}"><xacro:m{i - 1}/><xacro:m{i - 1}/></xacro:macro>' for i in range(1, 41))
    path = _xacro(tmp_path, "double.xacro", doubling + "<xacro:m40/>")
    assert path.stat().st_size < 4096
    _refused_fast(path, "more than 20,000 XML elements")


def test_blocks_and_recursive_macros_that_double_are_refused_at_once(tmp_path):
    blocks = '<xacro:macro name="m0" params="*b"><xacro:insert_block name="b"/></xacro:macro>' + "".join(
        f'<xacro:macro name="m{i}" params="*b"><xacro:m{i - 1}><g><xacro:insert_block name="b"/>'
        f'<xacro:insert_block name="b"/></g></xacro:m{i - 1}></xacro:macro>' for i in range(1, 41))
    _refused_fast(_xacro(tmp_path, "blocks.xacro", blocks + '<xacro:m40><link name="y"/></xacro:m40>'),
                  "more than")
    recursive = ('<xacro:macro name="r" params="n"><xacro:if value="${n > 0}"><xacro:r n="${n-1}"/>'
                 '<xacro:r n="${n-1}"/></xacro:if><link name="a"/></xacro:macro><xacro:r n="40"/>')
    _refused_fast(_xacro(tmp_path, "recursive.xacro", recursive), "more than")
    endless = '<xacro:macro name="r"><xacro:r/></xacro:macro><xacro:r/>'
    _refused_fast(_xacro(tmp_path, "endless.xacro", endless), "nested deeper than 50")


def test_runaway_values_in_a_xacro_are_refused_at_once(tmp_path):
    for k, expression in enumerate(("${2**2**40}", "${'x'*3000000000}", "${'x'*1000000 + 'y'}")):
        path = _xacro(tmp_path, f"v{k}.xacro", f'<link name="{expression}"/>')
        _refused_fast(path, "bits|longer than")
    doubling = '<xacro:property name="p0" value="xxxxxxxxxx"/>' + "".join(
        f'<xacro:property name="p{i}" value="${{p{i - 1}}}${{p{i - 1}}}"/>' for i in range(1, 41))
    _refused_fast(_xacro(tmp_path, "text.xacro", doubling + '<link name="${p40}"/>'), "longer than")


# ------------------------------------------------------------------------------------------ numbers

def _one_joint(joint_extra: str = "", origin: str = 'xyz="0.1 0 0"', inertial_origin: str = 'xyz="0.05 0 0"',
               limit: str = 'lower="-1" upper="1" effort="10" velocity="1"') -> str:
    return ('<robot name="r"><link name="base"><inertial><mass value="10"/>' + INERTIA.format(a=1, b=1, c=1)
            + '</inertial></link><link name="arm"><inertial>'
            f'<origin {inertial_origin}/><mass value="1"/>' + INERTIA.format(a=0.01, b=0.01, c=0.01)
            + '</inertial></link><joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>'
            f'<origin {origin}/><axis xyz="0 0 1"/><limit {limit}/>{joint_extra}</joint></robot>')


@pytest.mark.parametrize("what, text, match", [
    ("nan joint origin", _one_joint(origin='xyz="nan 0 0"'), "joint 'j1': expected a finite <origin"),
    ("inf joint rpy", _one_joint(origin='xyz="0 0 0" rpy="0 inf 0"'), "joint 'j1': expected a finite <origin"),
    ("nan centre of mass", _one_joint(inertial_origin='xyz="0 nan 0"'), "link 'arm': inertial: expected a finite"),
    ("nan damping", _one_joint('<dynamics damping="nan"/>'), "joint 'j1': expected finite damping"),
    ("inf friction", _one_joint('<dynamics friction="inf"/>'), "joint 'j1': expected finite damping"),
    ("nan lower", _one_joint(limit='lower="nan" upper="1" effort="1" velocity="1"'), "limit lower>, found NaN"),
    ("nan effort", _one_joint(limit='lower="0" upper="1" effort="nan" velocity="1"'), "limit effort>, found NaN"),
    ("inf velocity", _one_joint(limit='lower="0" upper="1" effort="1" velocity="inf"'), "finite <limit velocity"),
    ("lower > upper", _one_joint(limit='lower="1" upper="-1" effort="1" velocity="1"'),
     "lower 1 > upper -1"),
])
def test_numbers_that_are_not_numbers_are_refused_by_name(tmp_path, what, text, match):
    path = tmp_path / "r.urdf"
    path.write_text(text)
    with pytest.raises(UvmsInputError, match=match):
        uvms.load_model(path)


def test_infinite_position_limits_mean_none(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(_one_joint(limit='lower="-inf" upper="inf" effort="1" velocity="1"'))
    np.testing.assert_array_equal(uvms.load_model(path).joint_limits[0], [-np.inf, np.inf, 1.0, 1.0])


# ------------------------------------------------------------------------------------ balance_inertia

IMPOSSIBLE = ('<robot name="r"><link name="base"><inertial><mass value="10"/>' + INERTIA.format(a=1, b=1, c=1)
              + '</inertial></link><link name="finger"><inertial><origin xyz="0.05 0 0"/><mass value="0.1"/>'
              + INERTIA.format(a="2e-6", b="3e-6", c="7e-6") + '</inertial></link>'
              '<joint name="j1" type="revolute"><parent link="base"/><child link="finger"/>'
              '<axis xyz="0 0 1"/></joint></robot>')


def test_an_impossible_inertia_is_refused_by_name_with_the_way_out(tmp_path):
    path = tmp_path / "hand.urdf"
    path.write_text(IMPOSSIBLE)
    with pytest.raises(UvmsInputError, match="link 'finger'.*triangle inequality.*balance_inertia"):
        uvms.load_model(path)


def test_balance_inertia_sets_the_principal_moments_to_their_mean_with_one_warning(tmp_path):
    path = tmp_path / "hand.urdf"
    path.write_text(IMPOSSIBLE)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = uvms.load_model(path, balance_inertia=True)
    lines = [str(w.message) for w in caught]
    assert len(lines) == 1 and "\n" not in lines[0]
    assert "'finger'" in lines[0] and "[2e-06, 3e-06, 7e-06] -> 4e-06" in lines[0]
    np.testing.assert_allclose(model.inertia_com[1], 4e-6 * np.eye(3), rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(model.inertia_com[0], np.eye(3))       # a valid inertia is left alone
    (tmp_path / "hand.yaml").write_text("urdf: hand.urdf\nbalance_inertia: true\n")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        np.testing.assert_allclose(uvms.load_model(tmp_path / "hand.yaml").inertia_com[1], 4e-6 * np.eye(3),
                                   atol=1e-18)


def test_balance_inertia_does_not_accept_a_negative_moment(tmp_path):
    path = tmp_path / "bad.urdf"
    path.write_text(IMPOSSIBLE.replace('izz="7e-6"', 'izz="-7e-6"'))
    with pytest.raises(UvmsInputError, match="positive semi-definite"):
        uvms.load_model(path, balance_inertia=True)


def test_the_allegro_hand_is_refused_by_name_and_loads_balanced():
    import site

    bases = [Path(b) / "cmeel.prefix" / "share" / "example-robot-data" / "robots" for b in site.getsitepackages()]
    found = [b / "allegro_hand_description" / "urdf" / "allegro_right_hand.urdf" for b in bases]
    found = [p for p in found if p.exists()]
    if not found:
        pytest.skip("example-robot-data is not installed")
    with pytest.raises(UvmsInputError, match="link 'link_3.0'.*triangle"):
        uvms.load_model(found[0])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        uvms.load_model(found[0], balance_inertia=True)
    assert len(caught) == 1 and "'link_3.0'" in str(caught[0].message)


def test_parsing_a_urdf_prints_nothing(tmp_path, capfd):
    path = tmp_path / "chain.urdf"
    path.write_text(_chain(5))
    uvms.load_model(path)
    out, err = capfd.readouterr()
    assert out == "" and err == ""


@pytest.mark.parametrize("text, match", [
    ('<robot><link name="base"/></robot>', "expected a name attribute on <robot>"),
    ('<robot name="r"><link/></robot>', "expected a name attribute on <link>"),
    ('<robot name="r"><link name="a"/><joint name="j" type="fixed"><parent link="a"/></joint></robot>',
     "joint 'j': expected a <child link=...> element"),
    ('<robot name="r"><link name="a"/><joint name="j"><parent link="a"/><child link="a"/></joint></robot>',
     "joint 'j': expected a type attribute"),
])
def test_missing_required_parts_are_named(tmp_path, text, match, capfd):
    path = tmp_path / "r.urdf"
    path.write_text(text)
    with pytest.raises(UvmsInputError, match=match):
        uvms.load_model(path)
    out, err = capfd.readouterr()
    assert out == "" and err == ""
