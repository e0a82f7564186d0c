"""The compiled controllers' numberings live in one place (:mod:`uvms.control.kinds`) and every builder uses it."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

import uvms
from uvms.control import kinds
from uvms.control.registry import make_controller

SRC = Path(__file__).resolve().parents[2] / "src" / "uvms"


def test_no_other_module_numbers_the_controller_kinds():
    names = r"(NONE|SLIDING|PID|AB|VEHICLE|NE|CONSTANT|SCHEDULE|COMPUTED_TORQUE|PD)"
    number = re.compile(r"^" + names + r"\b[\w, ]*=\s*\d")
    offending = [f"{path.relative_to(SRC)}:{n}: {line.strip()}"
                 for path in sorted((SRC / "control").rglob("*.py")) if path.name != "kinds.py"
                 for n, line in enumerate(path.read_text().splitlines(), 1) if number.search(line)]
    assert not offending, offending
    assert len({kinds.NONE, kinds.SLIDING, kinds.PID}) == 3 and len({kinds.AB, kinds.VEHICLE, kinds.NE}) == 3
    assert len({kinds.CONSTANT, kinds.SCHEDULE, kinds.COMPUTED_TORQUE, kinds.PD}) == 4


@pytest.mark.parametrize("name, kind, predictor", [("smc-ab", kinds.SLIDING, kinds.AB),
                                                   ("smc-vehicle", kinds.SLIDING, kinds.VEHICLE),
                                                   ("smc-ne", kinds.SLIDING, kinds.NE),
                                                   ("pid", kinds.PID, kinds.AB)])
def test_each_controller_is_built_with_its_kind_and_predictor(name, kind, predictor):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # the paper's b bounds miss the paper model (a warning of its own)
        data = make_controller(name, uvms.load_model("paper")).compiled(10)
    assert (data.kind, data.predictor) == (kind, predictor)
