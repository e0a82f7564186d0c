"""Model files: schema, loading and the frozen :class:`Model` (body 0 = vehicle, bodies 1..n = links).

``load_model``, ``bundled_models`` and ``build_model`` are imported on first use, so that ``import uvms``
does not pay for pydantic and PyYAML.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from uvms.model.model import Model

if TYPE_CHECKING:
    from uvms.model.build import build_model
    from uvms.model.load import bundled_models, load_model

__all__ = ["Model", "build_model", "bundled_models", "load_model"]


def __getattr__(name: str) -> Any:
    if name == "build_model":
        from uvms.model.build import build_model

        return build_model
    if name in ("load_model", "bundled_models"):
        from uvms.model import load

        return getattr(load, name)
    raise AttributeError(f"module 'uvms.model' has no attribute {name!r}")
