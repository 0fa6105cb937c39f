"""`depth-images`: a folder of 16-bit depth images (PNG or TIFF) as a depth source.

What camera tools and datasets write: one image per frame, each pixel a depth count in the
camera's depth unit (1 mm for Kinect/OpenNI PNGs and RealSense D4xx at its default scale, 0.125 mm
for the SR305, 0.2 mm for TUM RGB-D's factor 5000). Frames are either

- every `*.png` / `*.tif` / `*.tiff` in the folder, in natural name order (`30.png` before
  `110.png`, as the numbered files of camera tools are meant), `i / fps` seconds apart; or
- listed in a text file (`path` names the file), TUM RGB-D style: `timestamp filename` per line,
  `#` comments, file names relative to the list's folder; timestamps are seconds.

Depth unit, intrinsics and frame rate come from the profile, else from a description beside the
images (in their folder, then its parent): a JSON file with any of `depth_unit_mm`,
`intrinsics` ([fx, fy, cx, cy]) and `fps`, or a text file of `key = value` lines (`depth unit =
0.125 mm`, `focal length = 476.007`, `principal point = (313.683, 242.755)`, `fx`, `fy`, `cx`,
`cy`, `fps`), as the SR305 dataset's readme.txt is written. What neither says: 1 mm, 30 fps, and a
58 x 45 degree field of view (a typical structured-light camera).
"""
from __future__ import annotations

import json
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from pydantic import BaseModel, ConfigDict, Field, field_validator

from host import DepthFrame, Intrinsics, Source
from host.errors import UserError
from host.options import ProfilePath
from sources.clip import frame_rate

IMAGE_SUFFIXES = (".png", ".tif", ".tiff")
DEFAULT_FOV_DEG = (58.0, 45.0)
DEFAULT_UNIT_MM, DEFAULT_FPS = 1.0, 30.0
_NUMBER = r"[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?"
_UNITS_MM = {"mm": 1.0, "m": 1000.0, "cm": 10.0, "um": 0.001, "µm": 0.001, "": 1.0}


class DepthImagesOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    path: ProfilePath = Field(description="a folder of 16-bit PNG/TIFF depth images, or a TUM-style list file")
    depth_unit_mm: float | None = Field(None, gt=0, description="millimetres per pixel count (SR305: 0.125)")
    intrinsics: list[float] | None = Field(None, description="[fx, fy, cx, cy] in pixels")
    fps: float | None = Field(None, gt=0, le=1000, description="frame rate when the list has no timestamps")
    loop: bool = Field(False, description="start again after the last image")
    mirrored: bool = Field(False, description="camera tools write the camera's view, not a mirror image")

    @field_validator("intrinsics")
    @classmethod
    def _four(cls, value: list[float] | None) -> list[float] | None:
        if value is not None and (len(value) != 4 or min(value[:2]) <= 0):
            raise ValueError("expected [fx, fy, cx, cy] in pixels, fx and fy above 0")
        return value


@dataclass(frozen=True)
class Described:
    """What a description file beside the images says (None: it does not say)."""

    depth_unit_mm: float | None = None
    intrinsics: tuple[float, float, float, float] | None = None
    fps: float | None = None
    sources: tuple[Path, ...] = ()  # the files that said it


def natural_key(name: str) -> list:
    """`30.png` < `110.png`: digit runs compare as numbers."""
    return [int(part) if part.isdigit() else part.lower() for part in re.split(r"(\d+)", name)]


def list_folder(folder: Path) -> list[Path]:
    images = sorted((p for p in folder.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES),
                    key=lambda p: natural_key(p.name))
    if not images:
        raise UserError(f"{folder}: no depth images (*.png, *.tif, *.tiff) in this folder")
    return images


def read_list(path: Path) -> tuple[list[Path], np.ndarray]:
    """A TUM-style list: `timestamp filename` lines -> the files and their times (s)."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as error:
        raise UserError(f"{path}: cannot read the image list: {error}") from None
    files, times = [], []
    for number, line in enumerate(lines, 1):
        fields = line.split("#", 1)[0].split()
        if not fields:
            continue
        try:
            if len(fields) != 2:
                raise ValueError
            times.append(float(fields[0]))
        except ValueError:
            raise UserError(f"{path}:{number}: expected `timestamp filename` (TUM RGB-D depth.txt), "
                            f"got {line.strip()!r}") from None
        files.append(path.parent / fields[1])
    if not files:
        raise UserError(f"{path}: lists no images (lines of `timestamp filename`)")
    return files, np.array(times)


def read_depth_image(path: Path) -> np.ndarray:
    """One 16-bit single-channel PNG or TIFF -> its raw counts (H, W) uint16."""
    raw = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if raw is None:
        what = "no such file" if not path.exists() else "not a readable PNG or TIFF image"
        raise UserError(f"{path}: {what}")
    if raw.dtype != np.uint16 or raw.ndim != 2:
        channels = 1 if raw.ndim == 2 else raw.shape[2]
        raise UserError(f"{path}: a {channels}-channel {raw.dtype} image; depth images must be 16-bit "
                        f"single-channel (a colour or 8-bit image is a visualisation, not depth)")
    return raw


def _parse_text(path: Path) -> Described:
    """`key = value` / `key: value` lines as camera tools and dataset readmes write them."""
    values: dict[str, str] = {}
    for line in path.read_text(encoding="utf-8", errors="replace").splitlines():
        match = re.match(r"\s*([^=:]+?)\s*[=:]\s*(.+)$", line)
        if match:
            values[re.sub(r"[\s_-]+", " ", match[1].lower()).strip()] = match[2]
    numbers = {k: [float(n) for n in re.findall(_NUMBER, v)] for k, v in values.items()}
    fps = next((numbers[k][0] for k in ("fps", "frame rate") if numbers.get(k)), None)
    return Described(_text_unit(values, numbers), _text_intrinsics(numbers), fps, (path,))


def _text_unit(values: dict[str, str], numbers: dict[str, list[float]]) -> float | None:
    """The depth unit in mm, from a number and its unit ("depth unit: 0.1 mm", "depth scale mm = 1")."""
    for key in ("depth unit", "depth unit mm", "depth scale mm"):
        if numbers.get(key):
            suffix = re.sub(_NUMBER, "", values[key]).strip().lower()
            return numbers[key][0] * _UNITS_MM.get(suffix, 1.0)
    return None


def _text_intrinsics(numbers: dict[str, list[float]]) -> tuple[float, float, float, float] | None:
    """(fx, fy, cx, cy) from fx/fy/cx/cy lines, or "focal length" and "principal point" pairs."""
    f = numbers.get("focal length") or []
    pp = numbers.get("principal point") or []
    fx = (numbers.get("fx") or f[:1] or [None])[0]
    fy = (numbers.get("fy") or f[1:2] or f[:1] or [None])[0]
    cx = (numbers.get("cx") or pp[:1] or [None])[0]
    cy = (numbers.get("cy") or pp[1:2] or [None])[0]
    return (fx, fy, cx, cy) if None not in (fx, fy, cx, cy) else None


def _parse_json(path: Path) -> Described:
    """A JSON description; a JSON file beside depth images that is broken, or gives one of our
    keys a wrong value, is an error (it was surely meant to describe them)."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise UserError(f"{path}: not valid JSON ({error}); it should hold depth_unit_mm, intrinsics, fps") from None
    if not isinstance(data, dict):
        return Described()
    unit, k, fps = data.get("depth_unit_mm"), data.get("intrinsics"), data.get("fps")
    numbers = (int, float)
    if unit is not None and not (isinstance(unit, numbers) and unit > 0):
        raise UserError(f"{path}: depth_unit_mm must be a number of millimetres above 0, got {unit!r}")
    if k is not None and not (isinstance(k, list) and len(k) == 4 and all(isinstance(v, numbers) for v in k)):
        raise UserError(f"{path}: intrinsics must be [fx, fy, cx, cy] in pixels, got {k!r}")
    if fps is not None and not (isinstance(fps, numbers) and fps > 0):
        raise UserError(f"{path}: fps must be a number above 0, got {fps!r}")
    return Described(unit and float(unit), k and tuple(map(float, k)), fps and float(fps), (path,))


def describe(folder: Path, skip: Path | None = None) -> Described:
    """What the files beside the images say: JSON files, then text files, in the images' folder,
    then its parent. Each value comes from the first file that gives it."""
    found: dict[str, tuple] = {}
    for place in (folder, folder.parent):
        for path in sorted(place.glob("*.json")) + sorted(place.glob("*.txt")):
            if path == skip:
                continue
            try:
                described = _parse_json(path) if path.suffix == ".json" else _parse_text(path)
            except OSError:
                continue  # unreadable: not ours to judge
            for key in ("depth_unit_mm", "intrinsics", "fps"):
                if getattr(described, key) is not None and key not in found:
                    found[key] = (getattr(described, key), path)
    return Described(*(found.get(k, (None,))[0] for k in ("depth_unit_mm", "intrinsics", "fps")),
                     sources=tuple(sorted({p for _, p in found.values()})))


def mm_table(unit_mm: float) -> np.ndarray | None:
    """Raw count -> millimetres (rounded, clipped to uint16) as a lookup table; None for 1 mm."""
    if unit_mm == 1.0:
        return None
    counts = np.arange(65536, dtype=np.float64)
    return np.clip(np.round(counts * unit_mm), 0, 65535).astype(np.uint16)


class DepthImagesSource(Source):
    """A folder of 16-bit depth images (PNG/TIFF) or a TUM-style list, paced by the host from their timestamps."""

    name = "depth-images"
    Options = DepthImagesOptions

    def open(self) -> None:
        path = Path(self.options.path)
        if path.is_dir():
            self.files, times, folder, skip = list_folder(path), None, path, None
        elif path.is_file():
            (self.files, times), folder, skip = read_list(path), path.parent, path
        else:
            raise UserError(f"{path}: no such folder or image list")
        described = describe(folder, skip)
        o = self.options
        self.depth_unit_mm = o.depth_unit_mm or described.depth_unit_mm or DEFAULT_UNIT_MM
        self._table = mm_table(self.depth_unit_mm)
        first = read_depth_image(self.files[0])
        self.height, self.width = first.shape
        given = o.intrinsics or described.intrinsics
        self.intrinsics = (Intrinsics(*map(float, given)) if given
                           else Intrinsics.from_fov(self.width, self.height, *DEFAULT_FOV_DEG))
        if times is not None:
            self.fps = o.fps or frame_rate(times)
            self.times = times - times[0]
        else:
            self.fps = o.fps or described.fps or DEFAULT_FPS
            self.times = np.arange(len(self.files)) / self.fps
        if described.sources:
            print(f"issv: depth-images: depth unit {self.depth_unit_mm:g} mm, intrinsics "
                  f"{self.intrinsics.as_list()}, {self.fps:g} fps (the profile, else "
                  f"{', '.join(map(str, described.sources))})", file=sys.stderr)
        self._played = 0

    def to_mm(self, raw: np.ndarray) -> np.ndarray:
        return raw if self._table is None else np.take(self._table, raw)  # take: twice as fast as indexing

    def read(self) -> DepthFrame | None:
        n = len(self.files)
        passes, i = divmod(self._played, n)
        if passes and not self.options.loop:
            return None
        raw = read_depth_image(self.files[i])
        if raw.shape != (self.height, self.width):
            raise UserError(f"{self.files[i]}: {raw.shape[1]}x{raw.shape[0]}, but the first image "
                            f"{self.files[0].name} is {self.width}x{self.height}; one folder, one size")
        span = float(self.times[-1]) + 1.0 / self.fps
        frame = DepthFrame(self.to_mm(raw), self.intrinsics, frame_id=self._played,
                           timestamp=float(self.times[i]) + passes * span, mirrored=self.options.mirrored)
        self._played += 1
        return frame
