"""Checks shared by several test modules (imported as ``tests.helpers``)."""

from __future__ import annotations

import pytest

import uvms
from uvms.cli import main
from uvms.errors import UvmsInputError


def assert_model_file_refused(path, field: str) -> None:
    """Loading the model file ``path`` fails with one line naming the file and ``field``, and ``uvms validate``
    on it exits with 2."""
    with pytest.raises(UvmsInputError) as info:
        uvms.load_model(path)
    text = str(info.value)
    assert "\n" not in text and str(path) in text and field in text, text
    assert main(["validate", str(path)]) == 2
