"""`clip`: depth clips (.npz, the interchange format of docs/architecture.md), with their ground truth."""
from __future__ import annotations

import zipfile
from functools import cached_property
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict

from host import DepthFrame, Intrinsics, Side, Source, Truth
from host.errors import UserError
from host.options import ProfilePath

BODY_JOINTS = ("head", "torso", "left_shoulder", "right_shoulder")  # the clip's spine joint is the torso


def frame_rate(timestamps: np.ndarray) -> float:
    """Frames per second from the median step between timestamps (30 when they do not say)."""
    if len(timestamps) < 2:
        return 30.0
    step = float(np.median(np.diff(timestamps)))
    return 1.0 / step if step > 0 else 30.0


class ClipOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    path: ProfilePath
    loop: bool = False


class Clip:
    """A whole clip in memory, checked against the format once, with one clear error."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        try:
            if self.path.exists() and not zipfile.is_zipfile(self.path):  # np.load would call it a pickle
                raise UserError(f"{self.path}: not a readable .npz depth clip (not a zip archive of arrays; "
                                "see docs/architecture.md, Depth clip)")
            with np.load(self.path, allow_pickle=False) as z:
                arrays = {k: z[k] for k in z.files}
        except FileNotFoundError:
            raise UserError(f"{self.path}: no such depth clip") from None
        except (OSError, ValueError, zipfile.BadZipFile, EOFError) as error:
            raise UserError(f"{self.path}: not a readable .npz depth clip ({error})") from None
        for key in ("depth", "timestamps", "intrinsics"):
            if key not in arrays:
                raise UserError(f"{self.path}: depth clip has no `{key}` array (see docs/architecture.md, Depth clip)")
        self.depth = arrays["depth"]
        if self.depth.ndim != 3 or self.depth.dtype != np.uint16:
            raise UserError(f"{self.path}: `depth` must be uint16 (N, H, W), got {self.depth.dtype} {self.depth.shape}")
        self.timestamps = np.asarray(arrays["timestamps"], dtype=np.float64)
        if len(self.timestamps) != len(self.depth):
            raise UserError(f"{self.path}: {len(self.timestamps)} timestamps for {len(self.depth)} depth frames")
        self.intrinsics = Intrinsics(*map(float, arrays["intrinsics"][:4]))
        self.mirrored = bool(arrays.get("mirrored", True))
        self.hands = arrays.get("hands")
        self.hand_names = [str(n) for n in arrays.get("hand_names", ["left", "right"])]
        self.body = arrays.get("body")
        self.label = str(arrays["label"]) if "label" in arrays else None

    def __len__(self) -> int:
        return len(self.depth)

    @cached_property
    def fps(self) -> float:
        return frame_rate(self.timestamps)

    def truth(self, i: int) -> Truth | None:
        if self.hands is None and self.body is None:
            return None
        hands: dict[Side, tuple[float, float, float]] = {}
        if self.hands is not None:
            for name, p in zip(self.hand_names, self.hands[i]):
                if np.all(np.isfinite(p)) and name in ("left", "right"):
                    hands[Side(name)] = (float(p[0]), float(p[1]), float(p[2]))
        body = {}
        if self.body is not None:
            body = {n: tuple(map(float, p)) for n, p in zip(BODY_JOINTS, self.body[i]) if np.all(np.isfinite(p))}
        return Truth(hands=hands, body=body)

    def frame(self, i: int, frame_id: int, offset: float = 0.0) -> DepthFrame:
        return DepthFrame(self.depth[i], self.intrinsics, frame_id=frame_id,
                          timestamp=float(self.timestamps[i]) + offset, mirrored=self.mirrored,
                          truth=self.truth(i))


class ClipSource(Source):
    """Plays a depth clip; the host paces it in real time unless asked to run as fast as possible."""

    name = "clip"
    Options = ClipOptions

    def __init__(self, options: ClipOptions) -> None:
        super().__init__(options)
        self.clip: Clip | None = None
        self._played = 0

    def open(self) -> None:
        self.clip = Clip(self.options.path)
        self.fps = self.clip.fps
        self.intrinsics = self.clip.intrinsics
        self._played = 0

    def read(self) -> DepthFrame | None:
        assert self.clip is not None, "open() the source first"
        if len(self.clip) == 0:
            return None
        passes, i = divmod(self._played, len(self.clip))
        if passes and not self.options.loop:
            return None
        # Looping keeps time running forwards: each pass starts one frame after the last one.
        span = float(self.clip.timestamps[-1] - self.clip.timestamps[0]) + 1.0 / self.clip.fps
        frame = self.clip.frame(i, self._played, offset=passes * span)
        self._played += 1
        return frame
