"""The renderer the show loop drives: effects -> stage (blend, opacity, keystone) -> HUD -> outputs.

The loop calls `render(show, frame)` once per tick and `close()` at the end; `wants_stop` turns
True when the window is closed. A render effect that raises is disabled with one message and the
other layers keep rendering.
"""
from __future__ import annotations

import sys
import time
from array import array
from pathlib import Path
from typing import Any

from host.render.calibration import check_calibration, check_keystone, keystone_matrix
from host.render.compositor import Compositor, pixels_to_clip
from host.render.context import Headless, Window, open_surface
from host.render.gputime import LayerTimes
from host.render.hud import Hud
from host.render.outputs import VideoOutput, check_folder, save_snapshot
from host.render.textures import FrameTextures
from host.render.warp import Keystone


class Renderer:
    """Owns the surface, the shared sensor textures, the stage, the HUD and the output files."""

    def __init__(self, surface: Headless | Window, output: Any, keystone=None) -> None:
        self.surface = surface
        self.ctx = surface.ctx
        self.size = surface.size
        self.textures = FrameTextures(self.ctx)
        self.compositor = Compositor(self.ctx, self.size, self.textures)
        self.corners = keystone
        self.keystone: Keystone | None = None  # the warp pass, only for effects that need it
        self.hud = Hud(self.ctx, self.size) if output.hud else None
        self.layer_times = LayerTimes(self.ctx) if output.hud else None
        self.video = VideoOutput(output.video, self.size, output.fps) if output.video else None
        self.snapshot = output.snapshot
        self.frame_ms = array("d")  # time spent in each render() call, for bench/render.py
        self._start: float | None = None
        self._last = 0.0
        self._planned: tuple = ()
        self._groups: dict[int, tuple[int, int]] = {}  # profile index -> the layer group it is drawn in

    @classmethod
    def create(cls, output: Any, stage: Any) -> "Renderer":
        """Checks the profile's stage settings, opens the surface and hands the context to `stage`."""
        keystone = check_keystone(output.keystone) if output.keystone is not None else None
        calibration = check_calibration(output.calibration) if output.calibration is not None else None
        if output.snapshot:
            check_folder(Path(output.snapshot), "snapshot")
        surface = open_surface(output.mode, tuple(output.size), output.monitor)
        stage.ctx = surface.ctx
        stage.size = tuple(surface.size)  # fullscreen: the monitor's size
        stage.calibration = calibration
        return cls(surface, output, keystone)

    @property
    def wants_stop(self) -> bool:
        return self.surface.closing

    def render(self, show: Any, frame: Any) -> None:
        t0 = time.perf_counter()
        self._start = t0 if self._start is None else self._start
        now, dt = t0 - self._start, (t0 - self._start) - self._last
        self._last = now
        self.textures.frame = frame
        drawing = tuple(s.effect for s in show.effects if s.effect.renders)
        if drawing != self._planned:  # the first frame, or a live reload changed the stack
            self._plan(drawing, show.effects)
        stage = self.keystone.stage if self.keystone else self.surface.fbo
        self.compositor.begin(stage, frame, now, dt)
        for index, slot in enumerate(show.effects):
            group = self._groups.get(index)
            if group is not None and group[0] == index:
                self.compositor.open_group(*group)
            self._draw(show, slot)
            if group is not None and group[1] == index:
                self.compositor.close_group()
        if self.keystone is not None:
            self.keystone.draw(self.surface.fbo)
        if self.hud is not None:
            self.hud.draw(show.metrics, self.surface.fbo, self.layer_times.line())
        self.surface.present()  # waits for the frame with the GIL released: read it back after
        if self.layer_times is not None:
            self.layer_times.collect()
        if self.video is not None:
            self.video.write(self.surface.fbo)
        self.frame_ms.append((time.perf_counter() - t0) * 1000.0)

    def _draw(self, show: Any, slot: Any) -> None:
        if not (slot.enabled and slot.effect.renders):
            return
        target = self.compositor.before(slot.blend, slot.opacity)
        try:
            if self.layer_times is None:
                slot.effect.render(target)
            else:
                with self.layer_times.query(f"{slot.where.removeprefix('effects')}{slot.effect.name}"):
                    slot.effect.render(target)
        except Exception as error:
            show.disable(slot, "render", error)
            return
        self.compositor.after(slot.blend, slot.opacity)

    def _plan(self, drawing: tuple, effects: list) -> None:
        """Layer groups other effects read (`captures`: (first, last) profile indices) are drawn
        apart; keystone in the effects' own matrix when they all draw through it, else a warp pass."""
        self._planned = drawing
        self._groups = {}
        for reader, slot in enumerate(effects):
            for first, last in getattr(slot.effect, "captures", ()) if slot.effect.renders else ():
                if first <= reader <= last or last >= len(effects):
                    print(f"issv: {slot.where}: reads effects[{first}..{last}], which must be other effects of "
                          f"the profile (0..{len(effects) - 1}, not itself); it sees nothing there", file=sys.stderr)
                    continue
                self._groups.update({i: (first, last) for i in range(first, last + 1)})
        if not self.corners:
            return
        if all(getattr(effect, "keystone_aware", False) for effect in drawing):
            self.compositor.target.to_clip = pixels_to_clip(self.size, keystone_matrix(self.corners, self.size))
            if self.keystone is not None:
                self.keystone.release()
                self.keystone = None
        else:
            self.compositor.target.to_clip = pixels_to_clip(self.size)
            self.keystone = self.keystone or Keystone(self.ctx, self.size, self.corners)

    def close(self) -> None:
        try:
            if self.snapshot and self.frame_ms:
                save_snapshot(self.snapshot, self.surface.fbo)
        finally:
            if self.video is not None:
                self.video.close()
            if self.keystone is not None:
                self.keystone.release()
            self.textures.release()
            self.compositor.release()
            if self.hud is not None:
                self.hud.release()
                self.layer_times.release()
            self.surface.close()
