"""Option types for plugin authors: validated in the profile, with messages artists understand."""
from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

from pydantic import BeforeValidator, ValidationInfo, WrapValidator
from pydantic_core import PydanticCustomError


def _color(value: Any) -> tuple[float, float, float]:
    ok = (isinstance(value, (list, tuple)) and len(value) == 3
          and all(isinstance(c, (int, float)) and not isinstance(c, bool) and 0 <= c <= 1 for c in value))
    if not ok:
        raise PydanticCustomError("color", "expected 3 numbers from 0 to 1")
    return (float(value[0]), float(value[1]), float(value[2]))


Color = Annotated[tuple[float, float, float], BeforeValidator(_color)]
"""An RGB colour: three numbers from 0 to 1, e.g. [1.0, 0.5, 0.0]."""


def _profile_path(value: Any, handler, info: ValidationInfo) -> str:
    text = handler(value)
    base = (info.context or {}).get("base_dir")
    path = Path(text).expanduser()
    return str(path if path.is_absolute() or base is None else Path(base) / path)


ProfilePath = Annotated[str, WrapValidator(_profile_path)]
"""A file path; relative paths are relative to the profile file that names them."""
