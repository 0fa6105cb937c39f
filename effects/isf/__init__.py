"""The `isf` effect: ISF 2.0 shaders on the stage (see effect.py), and the `issv isf` command."""
from effects.isf.effect import Isf, IsfOptions, check_bindings
from effects.isf.header import IsfError
from effects.isf.shader import IsfShader

__all__ = ["Isf", "IsfError", "IsfOptions", "IsfShader", "check_bindings"]
