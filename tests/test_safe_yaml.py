"""Hostile YAML is refused quickly with one line, in every command that reads YAML (issue: hardening, class 3)."""

from __future__ import annotations

import subprocess
import sys
import time

import pytest

from uvms.errors import UvmsInputError
from uvms.safe_yaml import MAX_DEPTH, read_yaml


def _laughs(levels: int, width: int = 9) -> str:
    """The "billion laughs" document: each level names the previous one ``width`` times."""
    text = "l0: &l0 [" + ", ".join(["lol"] * width) + "]\n"
    for i in range(1, levels + 1):
        text += f"l{i}: &l{i} [" + ", ".join([f"*l{i - 1}"] * width) + "]\n"
    return text


HOSTILE = {
    "billion_laughs": (_laughs(9), "aliases expand"),
    "alias_mapping_bomb": ("a: &a {x: 1, y: 2, z: 3}\n" + "".join(
        f"b{i}: &b{i} {{p: *{'a' if i == 0 else f'b{i - 1}'}, q: *{'a' if i == 0 else f'b{i - 1}'}}}\n"
        for i in range(40)), "aliases expand"),
    "deep_flow": ("x: " + "[" * 5000 + "]" * 5000 + "\n", "nested more than"),
    "deep_block": ("x:\n" + "".join(" " * i + "- \n" for i in range(1000)), "nested more than"),
    "deep_mapping": ("".join("  " * i + f"k{i}:\n" for i in range(200)) + "  " * 200 + "v: 1\n", "nested more than"),
    "huge_int": ("mass: " + "9" * 400 + "\n", "does not fit in 64 bits"),
    "huge_negative_int": ("name: x\nvehicle: {mass: -" + "1" * 60 + "}\n", "does not fit in 64 bits"),
    "huge_hex_int": ("seed: 0x" + "f" * 300 + "\n", "does not fit in 64 bits"),
    "int_just_past_64_bits": (f"seed: {2**63}\n", "does not fit in 64 bits"),
    "int_of_5000_digits": ("seed: " + "7" * 5000 + "\n", "does not fit in 64 bits"),
}


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_hostile_yaml_refused_fast_with_one_line(tmp_path, name):
    text, expected = HOSTILE[name]
    path = tmp_path / f"{name}.yaml"
    path.write_text(text)
    start = time.perf_counter()
    with pytest.raises(UvmsInputError, match=expected) as info:
        read_yaml(path)
    assert time.perf_counter() - start < 1.0     # a refusal bound, not a speed benchmark
    message = str(info.value)
    assert message.startswith(str(path)) and "\n" not in message and len(message) < 300


def test_large_file_refused_without_parsing(tmp_path):
    path = tmp_path / "big.yaml"
    path.write_text("x: [" + "1, " * 1_500_000 + "1]\n")
    with pytest.raises(UvmsInputError, match="larger than"):
        read_yaml(path)


def test_limits_leave_ordinary_documents_alone(tmp_path):
    nested = "".join("  " * i + f"k{i}:\n" for i in range(MAX_DEPTH - 1)) + "  " * (MAX_DEPTH - 1) + "v: 1\n"
    path = tmp_path / "ok.yaml"
    path.write_text(nested)
    value = read_yaml(path)
    for i in range(MAX_DEPTH - 1):
        value = value[f"k{i}"]
    assert value == {"v": 1}
    path.write_text(f"big: {2**63 - 1}\nsmall: {-(2**63)}\nexp: 1e2\nanchors: [&a 1, *a, *a]\n")
    assert read_yaml(path) == {"big": 2**63 - 1, "small": -(2**63), "exp": 100.0, "anchors": [1, 1, 1]}


def test_merge_keys_follow_yaml_and_repeated_keys_are_refused(tmp_path):
    path = tmp_path / "merge.yaml"
    path.write_text("defaults: &d {mass: 1.0, volume: 2.0}\nlink:\n  <<: *d\n  volume: 3.0\n"
                    "both:\n  <<: [*d, {extra: 1}]\n")
    assert read_yaml(path) == {"defaults": {"mass": 1.0, "volume": 2.0}, "link": {"mass": 1.0, "volume": 3.0},
                               "both": {"mass": 1.0, "volume": 2.0, "extra": 1}}
    path.write_text("link:\n  mass: 1\n  volume: 2\n  mass: 3\n")
    with pytest.raises(UvmsInputError, match=r"line 4, column 3: invalid YAML: duplicate key 'mass'"):
        read_yaml(path)


@pytest.mark.parametrize("command", [["validate"], ["run"], ["sweep", "-o", "{out}"]])
def test_every_command_refuses_an_alias_bomb_with_one_line(tmp_path, command):
    path = tmp_path / "bomb.yaml"
    path.write_text(_laughs(9))
    args = [part.format(out=tmp_path / "out") for part in command]
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "uvms", args[0], str(path), *args[1:]], capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "aliases expand" in proc.stderr and str(path) in proc.stderr
    assert not (tmp_path / "out").exists()
    assert time.perf_counter() - start < 30   # the process start-up dominates; an expansion never ends


@pytest.mark.parametrize("content", ["secret-token-123456\n", "- secret-token-123456\n- b\n", "123456789\n",
                                     "\n"])
def test_a_model_path_pointing_at_any_file_echoes_the_path_not_the_content(tmp_path, content):
    from uvms.sim.scenario import load_scenario

    private = tmp_path / "private.txt"
    private.write_text(content)
    scenario = tmp_path / "scenario.yaml"
    scenario.write_text(f"name: s\nmodel: {private}\nduration: 0.1\nstep: 0.001\n")
    with pytest.raises(UvmsInputError, match="is this a uvms file|empty file") as info:
        load_scenario(scenario)
    assert str(private) in str(info.value) and "secret" not in str(info.value) and "123456" not in str(info.value)
