"""Every example of ``docs/linearize_trim.md`` runs: its ``python`` blocks in order in one namespace, its ``console``
blocks (``$ uvms ...`` then the expected output) through the command line, whose output must be the one shown
line by line (on stderr with exit status 2 for an error, on stdout with status 0 otherwise)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

from uvms.cli import main

DOC = Path(__file__).resolve().parents[2] / "docs" / "linearize_trim.md"
BLOCK = re.compile(r"```(?P<lang>\w+)\n(?P<body>.*?)```", re.S)


def blocks() -> list[tuple[str, str]]:
    return [(m["lang"], m["body"]) for m in BLOCK.finditer(DOC.read_text(encoding="utf-8"))]


def test_every_example_runs_and_shows_its_output(capsys):
    found = blocks()
    assert [lang for lang, _ in found].count("python") >= 3 and [lang for lang, _ in found].count("console") >= 3
    namespace: dict = {}
    for lang, body in found:
        if lang == "python":
            exec(compile(body, f"{DOC}:python", "exec"), namespace)
            capsys.readouterr()
        elif lang == "console":
            command, *expected = body.rstrip("\n").split("\n")
            assert command.startswith("$ uvms "), command
            status = main(shlex.split(command[len("$ uvms "):]))
            out, err = capsys.readouterr()
            failing = bool(expected) and expected[0].startswith("uvms: error:")
            assert status == (2 if failing else 0), command
            shown = err if failing else out
            assert [line.rstrip() for line in shown.rstrip("\n").split("\n")] == expected, command
