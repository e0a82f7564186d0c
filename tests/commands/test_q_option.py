"""``--q`` is one option with one parser (:mod:`uvms.commands._options`) in every command that takes it: numbers
in the model's joint order or ``NAME=VALUE`` by joint name, the same pose either way; mixing the forms, unknown
joint names and malformed items are one line naming ``--q`` (exit 2)."""

from __future__ import annotations

import json

import pytest

from uvms.cli import main

COMMANDS_WITH_Q = ("show", "validate", "trim")
ALPHA5 = ("axis_e", "axis_d", "axis_c", "axis_b")      # bluerov2_heavy_alpha5's joints, in order


def test_every_command_with_q_uses_the_one_parser():
    """Each subcommand's ``--q`` is registered by ``add_q_argument`` (strings, repeatable), not its own."""
    from uvms.cli import build_parser

    subparsers = next(a for a in build_parser()._actions if a.dest == "command").choices
    with_q = sorted(name for name, sub in subparsers.items() if any("--q" in a.option_strings for a in sub._actions))
    assert with_q == sorted(COMMANDS_WITH_Q)
    for name in with_q:
        action = next(a for a in subparsers[name]._actions if "--q" in a.option_strings)
        assert action.type is None and action.nargs == "+" and type(action).__name__ == "_ExtendAction"
        assert "NAME=VALUE" in action.help and "joint order" in action.help


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("command", ["validate", "trim"])
def test_numbers_and_names_give_the_same_pose(capsys, command):
    by_order = _json(capsys, [command, "bluerov2_heavy_alpha5", "--q", "0", "0.4", "0.4", "0", "--json"])
    by_name = _json(capsys, [command, "bluerov2_heavy_alpha5", "--q", "axis_d=0.4", "axis_c=0.4", "--json"])
    assert by_order == by_name
    assert by_name["q"] == {"axis_e": 0.0, "axis_d": 0.4, "axis_c": 0.4, "axis_b": 0.0}


def test_show_takes_both_forms(tmp_path, monkeypatch):
    import uvms.view

    poses, original = [], uvms.view.state_at
    monkeypatch.setattr(uvms.view, "state_at", lambda model, state=None, *, q=None: (
        q is None or poses.append(list(q)), original(model, state, q=q))[1])
    a, b = tmp_path / "order.html", tmp_path / "names.html"
    assert main(["show", "paper", "--q", "0", "-1.5708", "0", "-o", str(a)]) == 0
    assert main(["show", "paper", "--q", "joint2=-1.5708", "-o", str(b)]) == 0
    assert poses == [[0.0, -1.5708, 0.0]] * 2
    assert "q = [0, -1.57, 0] rad" in a.read_text() and "q = [0, -1.57, 0] rad" in b.read_text()


def test_library_parser_returns_values_in_joint_order():
    import uvms
    from uvms.commands._options import q_option, split_q_items

    model = uvms.load_model("bluerov2_heavy_alpha5")
    assert tuple(model.joint_names) == ALPHA5
    assert q_option(model, None) is None
    assert q_option(model, ["axis_b=0.1", "axis_e=-0.2"]).tolist() == [-0.2, 0.0, 0.0, 0.1]
    assert q_option(model, ["1", "2", "3", "-4e-1"]).tolist() == [1.0, 2.0, 3.0, -0.4]
    assert split_q_items(["0.5", "1"]) == [0.5, 1.0] and split_q_items(["a=1"]) == {"a": 1.0}


@pytest.mark.parametrize("command", COMMANDS_WITH_Q)
@pytest.mark.parametrize("q, expected", [
    (["0", "axis_d=0.4"], "--q: give every joint value as a number (in joint order) or every one as NAME=VALUE, "
                          "not both; found '0' and 'axis_d=0.4'"),
    (["axis_d=0.4", "0", "0", "0"], "--q: give every joint value as a number"),
    (["axis_z=1"], "--q: model 'bluerov2_heavy_alpha5' has no joint 'axis_z'; joints: axis_e, axis_d, axis_c, axis_b"),
    (["axis_d"], "--q: expected NAME=VALUE (a joint name and a number) or numbers in joint order, found 'axis_d'"),
    (["axis_d=x"], "--q: expected NAME=VALUE (a joint name and a number) or numbers in joint order, found 'axis_d=x'"),
    (["=1"], "--q: expected NAME=VALUE"),
    (["axis_d=1", "axis_d=2"], "--q: joint 'axis_d' is given twice"),
    (["0", "0"], "--q: expected 4 joint values (joints: axis_e, axis_d, axis_c, axis_b), found 2"),
    (["axis_d=nan"], "--q: expected finite joint values"),
    (["0", "inf", "0", "0"], "--q: expected finite joint values"),
])
def test_bad_q_is_one_line_naming_the_option(tmp_path, monkeypatch, capsys, command, q, expected):
    monkeypatch.chdir(tmp_path)
    argv = [command, "bluerov2_heavy_alpha5", "--q", *q] + (["-o", "x.html"] if command == "show" else [])
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.startswith("uvms: error: " + expected) and err.count("\n") == 1
    assert not list(tmp_path.iterdir())
