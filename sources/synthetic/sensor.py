"""What a Kinect v1 does to a perfect depth image: disparity noise, quantisation and holes.

The Kinect v1 triangulates: an IR projector 75 mm beside the IR camera (focal length ~580 px at
640x480) casts a dot pattern, and depth comes from the pattern's disparity d = f b / z, measured
in 1/8 pixel steps (Khoshelham & Elberink 2012, "Accuracy and resolution of Kinect depth data").
So noise and quantisation live in disparity: a random disparity error sigma_d gives a depth error
sigma_z = z^2 sigma_d / (f b), growing with the square of distance. sigma_d = 0.06 px plus the
1/8 px quantisation gives sigma_z ~ 1.6 mm at 1 m, 10 mm at 2.5 m, 26 mm at 4 m, as measured by
Nguyen, Izadi & Lovell 2012 ("Modeling Kinect sensor noise": 1.2 + 1.9 (z - 0.4 m)^2 mm).

Holes (0 = no reading), each with its physical cause:
- the projector's shadow: background the camera sees but the projector cannot light, a band
  f b (1/z_near - 1/z_far) pixels wide beside every foreground object, on the side away from
  the projector (the image's left on a raw Kinect image, its right once mirrored);
- silhouette edges: pixels straddling a depth jump mix two surfaces and often read nothing;
- sparse random dropouts, and everything outside the sensor's 0.5-8 m range.
"""
from __future__ import annotations

import numpy as np

from sources.synthetic.render import Box

BASELINE_MM = 75.0
FOCAL_PX = 580.0  # the IR camera's focal length at 640x480
SUBPIXEL = 8  # disparity steps per pixel
DISPARITY_SIGMA_PX = 0.06
MIN_RANGE_MM, MAX_RANGE_MM = 500.0, 8000.0
EDGE_JUMP_MM = 100.0  # a depth step this large between neighbours is a silhouette edge
EDGE_DROP = 0.5  # share of silhouette-edge pixels that read nothing (holes = 1)
RANDOM_DROP = 0.002  # share of all pixels that read nothing (holes = 1)
DISPARITY_UNITS = SUBPIXEL * FOCAL_PX * BASELINE_MM  # depth mm * disparity steps


class KinectModel:
    """Turns a z-buffer (float32 mm, inf = nothing) into a uint16 Kinect-like depth image.

    `noise` and `holes` scale the effects (1 = a Kinect v1, 0 = none); `fx` is the focal length
    of the output image, which sets the shadow width in its pixels.
    """

    def __init__(self, width: int, height: int, fx: float, mirrored: bool, noise: float, holes: float,
                 rng: np.random.Generator) -> None:
        self.size = width * height
        self.fx, self.mirrored, self.holes, self.rng = fx, mirrored, holes, rng
        self.columns = np.arange(width, dtype=np.float32)
        self.noise = noise
        # Scratch buffers reused every frame: fresh megabyte arrays cost page faults each time.
        self._work = np.empty((height, width), np.float32)
        self._steps = np.empty((height, width), np.int32)
        if noise > 0:
            # Normal draws cost more than the rest of a frame, so each frame reads a pool drawn once
            # at a random offset: the noise field moves from frame to frame like fresh noise.
            sigma = noise * DISPARITY_SIGMA_PX * SUBPIXEL
            self.pool = (rng.standard_normal(2 * self.size, dtype=np.float32) * sigma).astype(np.float32)
            # Disparity step -> millimetres; steps outside the sensor's range read 0.
            steps = np.arange(int(DISPARITY_UNITS / MIN_RANGE_MM) + 2, dtype=np.float64)
            with np.errstate(divide="ignore"):
                lut = np.rint(DISPARITY_UNITS / steps)
            lut[(lut < MIN_RANGE_MM) | (lut > MAX_RANGE_MM)] = 0
            self.lut = lut.astype(np.uint16)

    def capture(self, zbuf: np.ndarray, regions: list[Box]) -> np.ndarray:
        """The depth image the sensor reports; `zbuf` is consumed (holes are written into it).
        `regions`: disjoint boxes holding everything in front of the room (shadows and silhouette
        edges are looked for there)."""
        if self.holes > 0:
            for region in regions:
                self._shadow(zbuf, region)
            for region in regions:
                self._edges(zbuf, region)
            self._dropouts(zbuf)
        return self._measure(zbuf)

    def _measure(self, z: np.ndarray) -> np.ndarray:
        work = self._work
        if self.noise <= 0:
            out = np.zeros(z.shape, np.uint16)
            np.add(z, 0.5, out=work)
            np.copyto(out, work, casting="unsafe", where=(z >= MIN_RANGE_MM) & (z <= MAX_RANGE_MM))
            return out
        with np.errstate(divide="ignore"):
            np.divide(DISPARITY_UNITS, z, out=work)  # nothing there (inf) -> 0 steps -> no reading
        start = int(self.rng.integers(0, self.size))
        work += self.pool[start:start + self.size].reshape(z.shape)
        work += 0.5
        np.copyto(self._steps, work, casting="unsafe")  # the nearest disparity step
        return np.take(self.lut, self._steps, mode="clip")  # noise may push 0 below 0: clipped, no reading

    def _shadow(self, z: np.ndarray, region: Box) -> None:
        """Blank the projector's shadow beside the performer (computed on a raw, unmirrored view)."""
        v0, v1, u0, u1 = region
        nearest = float(np.min(z[v0:v1, u0:u1]))
        if not np.isfinite(nearest):
            return
        raw = z
        if self.mirrored:
            raw = z[:, ::-1]
            u0, u1 = z.shape[1] - u1, z.shape[1] - u0
        reach = int(self.fx * BASELINE_MM / nearest) + 2  # widest possible shadow, pixels
        a = max(u0 - reach, 0)
        block = raw[v0:v1, a:u1]
        # A pixel is in shadow when a nearer pixel to its right (raw image) takes its projector ray:
        # its projector column j - f b / z_j lies at or left of this pixel's, i - f b / z_i.
        projector = self.columns[a:u1] - (self.fx * BASELINE_MM) / block
        ahead = np.minimum.accumulate(projector[:, ::-1], axis=1)[:, ::-1]
        shadow = ahead[:, 1:] < projector[:, :-1] - 0.5
        block[:, :-1][shadow] = np.inf

    def _edges(self, z: np.ndarray, region: Box) -> None:
        v0, v1, u0, u1 = region
        v0, u0 = max(v0 - 1, 0), max(u0 - 1, 0)
        block = z[v0:v1 + 1, u0:u1 + 1]
        with np.errstate(invalid="ignore"):
            across = np.abs(np.diff(block, axis=1)) > EDGE_JUMP_MM
            down = np.abs(np.diff(block, axis=0)) > EDGE_JUMP_MM
        edge = np.zeros(block.shape, bool)
        edge[:, 1:] |= across
        edge[:, :-1] |= across
        edge[1:, :] |= down
        edge[:-1, :] |= down
        rows, cols = np.nonzero(edge)
        drop = self.rng.random(len(rows)) < min(EDGE_DROP * self.holes, 1.0)
        block[rows[drop], cols[drop]] = np.inf

    def _dropouts(self, z: np.ndarray) -> None:
        count = self.rng.binomial(self.size, min(RANDOM_DROP * self.holes, 1.0))
        z.reshape(-1)[self.rng.integers(0, self.size, count)] = np.inf
