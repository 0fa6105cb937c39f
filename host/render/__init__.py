"""Rendering: effects draw layers with moderngl, the host composites, warps and outputs them.

moderngl is imported only by `make_renderer`, so shows that draw nothing never load GL.
"""
from __future__ import annotations

from typing import Any


def make_renderer(output: Any, stage: Any) -> Any:
    """The renderer for a profile's `output`; puts the GL context on `stage.ctx` for the effects."""
    from host.render.renderer import Renderer
    return Renderer.create(output, stage)
