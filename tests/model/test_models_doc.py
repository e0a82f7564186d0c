"""Every example of ``docs/models.md`` runs: the files it shows (a block after ``<!-- file: NAME -->``) are written
to a temporary folder first, then its ``python`` blocks run there in order in one namespace and its ``console``
blocks (``$ uvms ...``) through the command line, which must succeed."""

from __future__ import annotations

import re
import shlex
import warnings
from pathlib import Path

from uvms.cli import main

DOC = Path(__file__).resolve().parents[2] / "docs" / "models.md"
BLOCK = re.compile(r"(?:<!-- file: (?P<file>\S+) -->\n)?```(?P<lang>\w+)\n(?P<body>.*?)```", re.S)


def blocks() -> list[tuple[str | None, str, str]]:
    return [(m["file"], m["lang"], m["body"]) for m in BLOCK.finditer(DOC.read_text(encoding="utf-8"))]


def test_doc_has_examples():
    kinds = [lang for _, lang, _ in blocks()]
    assert kinds.count("python") >= 3 and "console" in kinds and "xml" in kinds and "yaml" in kinds


def test_every_example_in_models_md_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    found = blocks()
    for file, _, body in found:
        if file is not None:
            (tmp_path / file).write_text(body, encoding="utf-8")
    namespace: dict = {}
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # the examples load without a warning
        for file, lang, body in found:
            if file is not None:
                continue
            if lang == "python":
                exec(compile(body, f"{DOC}:python", "exec"), namespace)
            elif lang == "console":
                for line in body.splitlines():
                    assert line.startswith("$ uvms "), line
                    assert main(shlex.split(line[len("$ uvms "):])) == 0, line
    assert "bluerov_arm: valid" in capsys.readouterr().out
