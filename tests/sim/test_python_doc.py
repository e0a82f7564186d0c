"""Every ``python`` block of ``docs/python.md`` runs, in order, in one namespace (its asserts are the checks)."""

from __future__ import annotations

import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[2] / "docs" / "python.md"


def test_every_example_of_the_python_page_runs():
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S)
    assert len(blocks) >= 5
    namespace: dict = {}
    for k, body in enumerate(blocks):
        exec(compile(body, f"{DOC}:block{k}", "exec"), namespace)
