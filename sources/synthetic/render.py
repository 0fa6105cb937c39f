"""Depth rasterisation: capsules and ellipsoids into a z-buffer, plus the room.

Each shape is ray-cast only inside its own screen bounding box, with numpy over the box, so a
performer costs a few thousand pixels per limb instead of full-frame passes. Rays leave the
camera centre through pixel (u, v) with direction (xn, yn, 1), xn = (u - cx) / fx and
yn = (cy - v) / fy (docs/architecture.md's pixel <-> world formulas), so a ray's parameter is its depth z.
Ellipsoids are exact. A capsule is drawn as an impostor: each pixel takes the nearest
point of the capsule's projected axis, and the surface lies sqrt(r^2 - d^2) in front of that
point's depth, d being the pixel's distance from the axis in millimetres at that depth. Where a
limb points at the camera that would show its far part, so its nearer end is added as an exact
sphere. A ray that misses a shape gets NaN (the square root of a negative number), which
np.fmin ignores: no masks needed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from host import Intrinsics

NEAR_MM = 100.0  # shapes closer than this to the camera are not drawn
Box = tuple[int, int, int, int]  # rows v0:v1, columns u0:u1


@dataclass(frozen=True)
class Capsule:
    """A limb: the points within `radius` of the segment a-b."""

    a: np.ndarray
    b: np.ndarray
    radius: float


@dataclass(frozen=True)
class Ellipsoid:
    """`axes`: three orthonormal rows; `radii`: the semi-axis along each, mm."""

    centre: np.ndarray
    axes: np.ndarray
    radii: tuple[float, float, float]


Shape = Capsule | Ellipsoid


def union(a: Box | None, b: Box | None) -> Box | None:
    if a is None or b is None:
        return a or b
    return (min(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), max(a[3], b[3]))


def separate(boxes: list[Box | None]) -> list[Box]:
    """The boxes with every overlapping group replaced by its union: performers far apart keep
    their own small boxes, overlapping ones share one."""
    out: list[Box] = []
    for box in filter(None, boxes):
        while (hit := next((b for b in out if b[0] < box[1] and box[0] < b[1] and b[2] < box[3] and box[2] < b[3]),
                           None)) is not None:
            out.remove(hit)
            box = union(box, hit)
        out.append(box)
    return out


class Raster:
    """Draws shapes into a float32 z-buffer (millimetres, inf = nothing there)."""

    def __init__(self, width: int, height: int, intrinsics: Intrinsics) -> None:
        self.width, self.height = width, height
        self.k = intrinsics
        self.xn = ((np.arange(width) - intrinsics.cx) / intrinsics.fx).astype(np.float32)
        self.yn = ((intrinsics.cy - np.arange(height)) / intrinsics.fy).astype(np.float32)

    def room(self, floor_y: float, wall_z: float | None) -> np.ndarray:
        """The empty stage: a floor `floor_y` mm below the camera and a back wall at `wall_z`."""
        zbuf = np.full((self.height, self.width), np.inf, np.float32)
        if wall_z is None:
            return zbuf
        with np.errstate(divide="ignore"):
            floor = np.where(self.yn < 0, floor_y / self.yn, np.inf).astype(np.float32)
        zbuf[:] = np.minimum(floor, wall_z)[:, None]
        return zbuf

    def draw(self, zbuf: np.ndarray, shapes: list[Shape]) -> Box | None:
        """Draws every shape, nearest wins; returns the box of pixels they may have touched."""
        region: Box | None = None
        with np.errstate(invalid="ignore"):
            for shape in shapes:
                region = union(region, self._shape(zbuf, shape))
        return region

    def draw_labelled(self, zbuf: np.ndarray, shapes: list[Shape], scratch: np.ndarray, labels: np.ndarray,
                      label: int) -> Box | None:
        """Draws one body over what `zbuf` holds, nearest wins, and writes `label` into `labels`
        where it does. `scratch` (all inf, the z-buffer's size) is used and left all inf again."""
        region = self.draw(scratch, shapes)
        if region is None:
            return None
        v0, v1, u0, u1 = region
        own, target = scratch[v0:v1, u0:u1], zbuf[v0:v1, u0:u1]
        nearer = own < target
        np.copyto(target, own, where=nearer)
        np.copyto(labels[v0:v1, u0:u1], label, where=nearer)
        own.fill(np.inf)
        return region

    def _shape(self, zbuf: np.ndarray, shape: Shape) -> Box | None:
        if isinstance(shape, Capsule):
            return self._capsule(zbuf, shape)
        return self._ellipsoid(zbuf, shape)

    def _box(self, centre: np.ndarray, radius: float) -> Box | None:
        """Screen box of a sphere, conservatively (its silhouette is within r / (z - r) of the centre)."""
        return self._clip(self._extent(centre, radius))

    def _extent(self, centre: np.ndarray, radius: float) -> Box | None:
        """A sphere's screen box, not yet clipped to the image (None: too near to draw)."""
        x, y, z = centre
        if z - radius < NEAR_MM:
            return None
        k = self.k
        u, v = k.cx + k.fx * x / z, k.cy - k.fy * y / z
        hu, hv = k.fx * radius / (z - radius), k.fy * radius / (z - radius)
        return (int(v - hv), int(v + hv) + 2, int(u - hu), int(u + hu) + 2)

    def _clip(self, box: Box | None) -> Box | None:
        if box is None:
            return None
        v0, v1, u0, u1 = max(box[0], 0), min(box[1], self.height), max(box[2], 0), min(box[3], self.width)
        return (v0, v1, u0, u1) if u0 < u1 and v0 < v1 else None

    def _sphere(self, zbuf: np.ndarray, c: np.ndarray, r: float) -> Box | None:
        box = self._box(c, r)
        if box is None:
            return None
        v0, v1, u0, u1 = box
        xs, ys = self.xn[u0:u1], self.yn[v0:v1]
        cx, cy, cz = map(float, c)  # Python floats keep the arithmetic in float32
        # |s d - c|^2 = r^2 with d = (xn, yn, 1): s^2 |d|^2 - 2 s (d.c) + |c|^2 - r^2 = 0
        dd = (xs * xs)[None, :] + (ys * ys + 1)[:, None]
        dc = (xs * cx)[None, :] + (ys * cy + cz)[:, None]
        disc = dc * dc - dd * float(c @ c - r * r)
        target = zbuf[v0:v1, u0:u1]
        np.fmin(target, (dc - np.sqrt(disc)) / dd, out=target)
        return box

    def _ellipsoid(self, zbuf: np.ndarray, e: Ellipsoid) -> Box | None:
        box = self._box(e.centre, max(e.radii))
        if box is None:
            return None
        v0, v1, u0, u1 = box
        xs, ys = self.xn[u0:u1], self.yn[v0:v1]
        scaled = e.axes / np.asarray(e.radii)[:, None]  # A: maps a point to unit-sphere coordinates
        b = (scaled @ e.centre).tolist()
        # |s A d - A c|^2 = 1, solved per pixel for the nearer root s
        a = [(r0 * xs)[None, :] + (r1 * ys + r2)[:, None] for r0, r1, r2 in scaled.tolist()]
        aa = a[0] * a[0] + a[1] * a[1] + a[2] * a[2]
        ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
        disc = ab * ab - aa * (b[0] ** 2 + b[1] ** 2 + b[2] ** 2 - 1.0)
        target = zbuf[v0:v1, u0:u1]
        np.fmin(target, (ab - np.sqrt(disc)) / aa, out=target)
        return box

    def _capsule(self, zbuf: np.ndarray, c: Capsule) -> Box | None:
        r = c.radius
        if min(c.a[2], c.b[2]) - r < NEAR_MM:
            return None
        box = self._clip(union(self._extent(c.a, r), self._extent(c.b, r)))  # a limb may leave the image
        if box is None:
            return None
        (xa, ya, za), (xb, yb, zb) = map(float, c.a), map(float, c.b)
        ax, ay = xa / za, ya / za
        ex, ey = xb / zb - ax, yb / zb - ay
        length2 = max(ex * ex + ey * ey, 1e-12)
        v0, v1, u0, u1 = box
        px, py = self.xn[u0:u1] - ax, self.yn[v0:v1] - ay
        t = (px * (ex / length2))[None, :] + (py * (ey / length2))[:, None]
        np.clip(t, 0.0, 1.0, out=t)
        dx = px[None, :] - t * ex
        dy = py[:, None] - t * ey
        z = 1.0 / (1.0 / za + t * (1.0 / zb - 1.0 / za))  # perspective-correct depth along the axis
        d2 = (dx * dx + dy * dy) * (z * z)
        target = zbuf[v0:v1, u0:u1]
        np.fmin(target, z - np.sqrt(r * r - d2), out=target)
        if abs(za - zb) > 0.5 * float(np.linalg.norm(c.a - c.b)):  # pointing at (or away from) the camera
            self._sphere(zbuf, c.a if za < zb else c.b, r)
        return box
