"""Where camera points land on the stage: homographies for calibration and keystone (numpy only).

Two mappings, applied in this order (docs/architecture.md, Outputs and the stage):
- camera -> stage: a 3x3 homography from depth-image pixels (u, v) to stage pixels (x right,
  y down, origin top-left of the composited image). The profile's `output.calibration`; without
  one, the depth image is stretched over the whole output (what `depth-view` shows).
- stage -> projector: the keystone, four corners (top-left, top-right, bottom-right, bottom-left)
  in output fractions (0..1, y down) where the composited image's corners land.

Calibrating measures camera -> stage through the keystone in force, so both stay consistent.
"""
from __future__ import annotations

import csv
from pathlib import Path
from typing import Callable

import numpy as np

from host.errors import UserError
from host.model import DepthFrame, Intrinsics, Vec3

UNIT_SQUARE = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))


def homography(src, dst) -> np.ndarray:
    """The 3x3 H with dst ~ H @ (src, 1), least squares over >= 4 point pairs (normalised DLT)."""
    src, dst = np.asarray(src, np.float64), np.asarray(dst, np.float64)
    if src.shape != dst.shape or src.ndim != 2 or src.shape[1] != 2 or len(src) < 4:
        raise ValueError(f"need >= 4 matching 2-D point pairs, got {src.shape} and {dst.shape}")
    ts, td = _normaliser(src), _normaliser(dst)
    s, d = apply(ts, src), apply(td, dst)
    rows = []
    for (x, y), (u, v) in zip(s, d):
        rows.append([-x, -y, -1, 0, 0, 0, u * x, u * y, u])
        rows.append([0, 0, 0, -x, -y, -1, v * x, v * y, v])
    _, sing, vt = np.linalg.svd(np.asarray(rows))
    if sing[-2] < 1e-9:
        raise ValueError("the points are degenerate (three or more on one line, or repeated)")
    h = np.linalg.inv(td) @ vt[-1].reshape(3, 3) @ ts
    return h / h[2, 2]


def _normaliser(points: np.ndarray) -> np.ndarray:
    """Hartley normalisation: centroid to the origin, mean distance sqrt(2)."""
    centre = points.mean(axis=0)
    scale = np.sqrt(2) / max(np.mean(np.linalg.norm(points - centre, axis=1)), 1e-12)
    return np.array([[scale, 0, -scale * centre[0]], [0, scale, -scale * centre[1]], [0, 0, 1]])


def apply(h: np.ndarray, points) -> np.ndarray:
    """Maps (N, 2) points through a homography."""
    p = np.asarray(points, np.float64).reshape(-1, 2)
    q = np.c_[p, np.ones(len(p))] @ np.asarray(h, np.float64).T
    return q[:, :2] / q[:, 2:3]


def depth_to_stage_matrix(depth_size: tuple[int, int], stage_size: tuple[int, int],
                          calibration=None) -> np.ndarray:
    """3x3 from depth pixels to stage pixels: the calibration, else a stretch of the image."""
    if calibration is not None:
        return np.asarray(calibration, np.float64)
    (dw, dh), (sw, sh) = depth_size, stage_size
    return np.diag([sw / dw, sh / dh, 1.0])


def project(position: Vec3, depth: DepthFrame, stage_size: tuple[int, int], calibration=None) -> tuple[float, float]:
    """A camera point (mm) -> stage pixels, through the depth image it was seen in."""
    u, v, _ = depth.intrinsics.world_to_depth(*position)
    m = depth_to_stage_matrix((depth.width, depth.height), stage_size, calibration)
    x, y = apply(m, [(u, v)])[0]
    return float(x), float(y)


def keystone_matrix(corners, size: tuple[int, int]) -> np.ndarray:
    """3x3 from stage pixels to output pixels for keystone corners given in output fractions."""
    corners = check_keystone(corners)
    w, h = size
    square = np.array(UNIT_SQUARE) * (w, h)
    return homography(square, np.asarray(corners) * (w, h))


def check_keystone(corners) -> list[tuple[float, float]]:
    """Four corners forming a convex quad in the order TL, TR, BR, BL; one clear error otherwise."""
    where = "output.keystone"
    try:
        pts = np.asarray(corners, np.float64)
    except (TypeError, ValueError):
        raise UserError(f"{where}: expected 4 [x, y] pairs (fractions of the output), got {corners!r}") from None
    if pts.shape != (4, 2) or not np.all(np.isfinite(pts)):
        raise UserError(f"{where}: expected 4 [x, y] pairs (top-left, top-right, bottom-right, "
                        f"bottom-left, fractions of the output), got {corners!r}")
    edges = np.roll(pts, -1, axis=0) - pts
    turns = edges[:, 0] * np.roll(edges, -1, axis=0)[:, 1] - edges[:, 1] * np.roll(edges, -1, axis=0)[:, 0]
    if not (np.all(turns > 0) or np.all(turns < 0)):
        raise UserError(f"{where}: the corners {pts.tolist()} do not form a convex quad in the order "
                        "top-left, top-right, bottom-right, bottom-left")
    return [(float(x), float(y)) for x, y in pts]


def check_calibration(matrix) -> np.ndarray:
    try:
        m = np.asarray(matrix, np.float64)
    except (TypeError, ValueError):
        m = np.zeros(0)
    if m.shape != (3, 3) or not np.all(np.isfinite(m)) or abs(np.linalg.det(m)) < 1e-12:
        raise UserError(f"output.calibration: expected an invertible 3x3 matrix (rows of 3 numbers; "
                        f"`issv calibrate` writes it), got {matrix!r}")
    return m


def read_points(path: str | Path, intrinsics: Callable[[], Intrinsics | None]) -> tuple[np.ndarray, np.ndarray]:
    """A calibration points file: header `u,v,stage_x,stage_y` (depth pixels) or
    `x,y,z,stage_x,stage_y` (camera mm, projected with the source's intrinsics, which `intrinsics()`
    gives: asked only then, as it may open the camera); >= 4 rows."""
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
            header = set(rows[0]) if rows else set()
    except FileNotFoundError:
        raise UserError(f"{path}: no such points file") from None
    except (OSError, UnicodeDecodeError, csv.Error) as error:
        raise UserError(f"{path}: cannot read the points file: {error}") from None
    mm = {"x", "y", "z"} <= header
    if not ({"stage_x", "stage_y"} <= header and (mm or {"u", "v"} <= header)):
        raise UserError(f"{path}: expected a header `u,v,stage_x,stage_y` (depth pixels) or "
                        f"`x,y,z,stage_x,stage_y` (camera mm), got {','.join(rows[0]) if rows else 'an empty file'}")
    camera = intrinsics() if mm else None
    if mm and camera is None:
        raise UserError(f"{path}: camera mm need the source's intrinsics; give depth pixels u,v instead")
    cam, stage = [], []
    for line, row in enumerate(rows, start=2):
        try:
            if mm:
                u, v, _ = camera.world_to_depth(float(row["x"]), float(row["y"]), float(row["z"]))
            else:
                u, v = float(row["u"]), float(row["v"])
            cam.append((u, v))
            stage.append((float(row["stage_x"]), float(row["stage_y"])))
        except (TypeError, ValueError, ZeroDivisionError):
            raise UserError(f"{path}:{line}: expected numbers, got {dict(row)}") from None
    if len(cam) < 4:
        raise UserError(f"{path}: a calibration needs at least 4 point pairs, got {len(cam)}")
    return np.asarray(cam), np.asarray(stage)
