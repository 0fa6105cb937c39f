"""`fakenect`: libfreenect's fakenect dump folders (made by `fakenect-record`) as a depth source.

A folder holds `INDEX.txt`, one file name per line in capture order: `d-<time>-<timestamp>.pgm`
depth images, `r-...ppm` colour images and `a-...dump` accelerometer states (only depth is used).
`<time>` is the recording machine's clock in seconds. A depth file is a one-line header
`P5 640 480 65535` and a newline, then 640x480 raw 11-bit disparities as little-endian uint16 (the
sensor's bytes as they came, not PGM's big-endian), 2047 meaning no reading.

Disparity d becomes millimetres with the standard Kinect v1 fit (OpenKinect wiki, S. Magnenat):

    z = 123.6 mm * tan(d / 2842.5 + 1.1863)

Readings where the fit leaves the sensor's range (z <= 0 or z > 10 m) and d = 2047 become 0 (no
reading). The geometry is Kinect v1's: 57 x 43 degree field of view. `device.json` registration
data, written by newer fakenect-record versions for colour registration, is not needed and not used.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from host import DepthFrame, Intrinsics, Source
from host.errors import UserError
from host.options import ProfilePath
from sources.clip import frame_rate

KINECT_V1_FOV_DEG = (57.0, 43.0)
NO_READING = 2047
MAX_RANGE_MM = 10_000
_DEPTH_FILE = re.compile(r"^d-(?P<time>\d+(?:\.\d*)?)-(?P<stamp>\d+)\.pgm$")


def _disparity_lut() -> np.ndarray:
    d = np.arange(NO_READING + 1, dtype=np.float64)
    z = 123.6 * np.tan(d / 2842.5 + 1.1863)
    z[(z <= 0) | (z > MAX_RANGE_MM) | (d >= NO_READING)] = 0
    return np.round(z).astype(np.uint16)


DISPARITY_TO_MM = _disparity_lut()


def disparity_to_mm(raw: np.ndarray) -> np.ndarray:
    """Kinect v1 11-bit disparities (uint16) -> millimetres, 0 = no reading (see the module doc)."""
    return DISPARITY_TO_MM[raw]


class FakenectOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    path: ProfilePath = Field(description="the dump folder (holding INDEX.txt)")
    loop: bool = False
    mirrored: bool = Field(False, description="libfreenect images are the camera's view, not mirrored")


@dataclass(frozen=True)
class _Entry:
    time: float
    path: Path


def read_pgm(path: Path) -> np.ndarray:
    """One fakenect depth file -> uint16 disparities (H, W), checked against the format."""
    try:
        content = path.read_bytes()
    except OSError as error:
        raise UserError(f"{path}: cannot read the depth image: {error.strerror or error}") from None
    head, sep, data = content.partition(b"\n")
    fields = head.split()
    if not sep or len(fields) != 4 or fields[0] != b"P5" or not all(f.isdigit() for f in fields[1:]):
        raise UserError(f"{path}: not a fakenect depth image (expected a `P5 640 480 65535` header line)")
    w, h = int(fields[1]), int(fields[2])
    if len(data) != w * h * 2:
        raise UserError(f"{path}: {len(data)} bytes of pixels, expected {w * h * 2} for {w}x{h} 16-bit")
    raw = np.frombuffer(data, dtype="<u2").reshape(h, w)
    if raw.max(initial=0) > NO_READING:
        raise UserError(f"{path}: values up to {raw.max()} are not 11-bit disparities (0..2047); "
                        f"record in FREENECT_DEPTH_11BIT mode")
    return raw


def read_index(folder: Path) -> list[_Entry]:
    index = folder / "INDEX.txt"
    try:
        lines = index.read_text(encoding="ascii").splitlines()
    except FileNotFoundError:
        what = "no such folder" if not folder.is_dir() else "not a fakenect dump folder (no INDEX.txt)"
        raise UserError(f"{folder}: {what}; record one with libfreenect's `fakenect-record DIR`") from None
    except (OSError, UnicodeDecodeError) as error:
        raise UserError(f"{index}: cannot read it: {error}") from None
    entries = []
    for number, line in enumerate(lines, 1):
        name = line.strip()
        if not name or name[0] in "ra":  # colour images and accelerometer states
            continue
        match = _DEPTH_FILE.match(name)
        if match is None:
            raise UserError(f"{index}:{number}: expected a depth file name like d-1294873002.535302-2018436839.pgm, "
                            f"got {name!r}")
        entries.append(_Entry(float(match["time"]), folder / name))
    if not entries:
        raise UserError(f"{index}: lists no depth images (d-*.pgm)")
    return entries


class FakenectSource(Source):
    name = "fakenect"
    Options = FakenectOptions

    def open(self) -> None:
        self.entries = read_index(Path(self.options.path))
        h, w = read_pgm(self.entries[0].path).shape
        self.intrinsics = Intrinsics.from_fov(w, h, *KINECT_V1_FOV_DEG)
        times = np.array([e.time for e in self.entries])
        self.fps = frame_rate(times)
        self._span = float(times[-1] - times[0]) + 1.0 / self.fps  # one pass, for looping
        self._played = 0

    def read(self) -> DepthFrame | None:
        n = len(self.entries)
        passes, i = divmod(self._played, n)
        if passes and not self.options.loop:
            return None
        entry = self.entries[i]
        depth = disparity_to_mm(read_pgm(entry.path))
        t = entry.time - self.entries[0].time + passes * self._span
        frame = DepthFrame(depth, self.intrinsics, frame_id=self._played, timestamp=t,
                           mirrored=self.options.mirrored)
        self._played += 1
        return frame
